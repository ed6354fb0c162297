//! `volley scenes`: the bundled scenes, one line each.

use std::io::Write;
use std::path::{Path, PathBuf};

use volley::scene;

use super::{EXIT_ENVIRONMENT, Failure, fail, scene_dirs};

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
            Ok(s) => format!("{name:<28} {}", s.description),
            Err(e) => format!("{name:<28} (does not load: {e})"),
        };
        writeln!(out, "{line}").map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    }
    Ok(())
}

/// Every `.ron` file under `dir`, recursively, into `out`.
pub fn collect_ron(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect_ron(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "ron") {
            out.push(path);
        }
    }
    Ok(())
}
