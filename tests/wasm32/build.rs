//! Embeds every bundled scene (assets/scenes/*.ron and assets/scenes/hard/*.ron; not the bench
//! scenes, which are sized for timing) so the wasm build, which has no file system, steps the
//! same inputs as the native one. A scene added to those folders joins the suite by itself.

use std::fmt::Write;
use std::path::{Path, PathBuf};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
    let mut files: Vec<PathBuf> = Vec::new();
    for dir in [root.clone(), root.join("hard")] {
        println!("cargo::rerun-if-changed={}", dir.display());
        for entry in std::fs::read_dir(&dir).expect("assets/scenes is readable") {
            let path = entry.expect("a directory entry").path();
            if path.extension().is_some_and(|e| e == "ron") {
                files.push(path);
            }
        }
    }
    files.sort();
    let mut out = String::from(
        "/// Every bundled scene: its name as `volley scenes` lists it, and its text.\n",
    );
    out.push_str("pub const SCENES: &[(&str, &str)] = &[\n");
    for path in &files {
        let name = path
            .strip_prefix(&root)
            .expect("under assets/scenes")
            .with_extension("")
            .to_string_lossy()
            .replace('\\', "/");
        let full = path.canonicalize().expect("a scene file");
        writeln!(out, "    ({name:?}, include_str!({:?})),", full.display()).unwrap();
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("scenes.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}
