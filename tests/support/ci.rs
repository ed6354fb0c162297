//! Whether a test may skip: std only, so a crate that cannot link the renderer (volley-bevy's
//! tests include this file by path) shares it with the root's GPU and window tests.

use std::process::Command;

/// Whether the tests run in CI (`CI=true`).
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// Skips (outside CI) or fails (in CI) a test that cannot run here, with the reason.
pub fn unavailable(test: &str, why: &str) {
    assert!(!in_ci(), "{test}: {why} (CI=true requires it)");
    eprintln!("skipping {test}: {why}");
}

/// Whether `program` is on the PATH.
pub fn has(program: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {program}")])
        .output()
        .is_ok_and(|o| o.status.success())
}
