//! `volley scenes`: the bundled scenes, one line each.

use std::io::Write;

use volley::scene;

use super::{EXIT_ENVIRONMENT, Failure, collect_ron, fail, scene_dirs};

/// Lists every `.ron` file under the bundled scene folder with its description.
pub fn run() -> Result<(), Failure> {
    let dir = scene_dirs()
        .into_iter()
        .find(|d| d.is_dir())
        .ok_or_else(|| fail(EXIT_ENVIRONMENT, "no assets/scenes folder found"))?;
    let mut files = Vec::new();
    collect_ron(&dir, &mut files)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", dir.display())))?;
    files.sort();
    let mut out = std::io::stdout().lock();
    for path in files {
        let name = path
            .strip_prefix(&dir)
            .unwrap_or(&path)
            .with_extension("")
            .display()
            .to_string();
        let line = match scene::load(&path) {
            Ok(s) => format!("{name:<28} {}", s.description()),
            Err(e) => format!("{name:<28} (does not load: {e})"),
        };
        writeln!(out, "{line}").map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    }
    Ok(())
}
