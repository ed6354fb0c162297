//! The crate's layering, checked: no module of `volley-sim` imports a module of a higher layer
//! (the order `lib.rs` states). A `use crate::x` or a `crate::x::` path outside comments and
//! outside `#[cfg(test)]` code counts as an import.

use std::path::Path;

/// The layers, bottom up; a module may use its own layer and those below.
const LAYERS: &[&[&str]] = &[
    &["body", "instant", "rng", "simd"],
    &["atmosphere", "drag", "forces"],
    &["exact"],
    &["integrate"],
    &["contact"],
    &["scene"],
    &["world"],
    &["step"],
    &["command", "hash", "clock"],
    &["sim_loop", "draw"],
    &[
        "table",
        "replay",
        "study",
        "stability",
        "firing",
        "timeline",
        "pacing",
    ],
    &["synctest"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The top-level modules that `text` names through `crate::`, outside comments and tests.
fn imports(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for line in text.lines() {
        let code = line.trim_start();
        if code.starts_with("#[cfg(test)]") {
            break;
        }
        if code.starts_with("//") {
            continue;
        }
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            rest = &rest[at + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            // `crate::World` and other re-exports at the root name no module.
            if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
                found.push(name);
            }
        }
    }
    found
}

fn files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_module_imports_a_higher_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut all = Vec::new();
    files(&src, &mut all);
    all.sort();
    let mut checked = 0;
    let mut wrong = Vec::new();
    for path in &all {
        let rel = path.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = top.trim_end_matches(".rs");
        if module == "lib" {
            continue;
        }
        let own = layer_of(module).unwrap_or_else(|| panic!("{module} is in no layer"));
        for used in imports(&std::fs::read_to_string(path).unwrap()) {
            let theirs = layer_of(&used).unwrap_or_else(|| panic!("{used} is in no layer"));
            checked += 1;
            if theirs > own {
                wrong.push(format!("{} uses crate::{used}", rel.display()));
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} imports found: is the scan broken?"
    );
    assert!(wrong.is_empty(), "imports from a higher layer: {wrong:#?}");
}

/// The scan itself: it sees paths and `use` lines, and skips comments and test code.
#[test]
fn the_scan_finds_imports_and_skips_comments_and_tests() {
    let text = "use crate::world::World;\n// crate::replay in a comment\nfn f() { crate::hash::state_hash(w); crate::World::new(s); }\n#[cfg(test)]\nmod tests { use crate::study; }\n";
    assert_eq!(imports(text), ["world", "hash"]);
}
