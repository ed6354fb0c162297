//! What the simulation's test binaries share: paths into the workspace.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `rel` under the workspace root (`assets/scenes/seed.ron`, `tests/data/...`): the bundled
/// scenes and the test data live beside the `volley` package, two folders up from this crate.
pub fn ws(rel: impl AsRef<Path>) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}
