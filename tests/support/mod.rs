//! What the GPU and window tests share: finding an adapter or a display, or saying why not.
//!
//! Outside CI a machine without an adapter (or without Xvfb) skips these tests with a printed
//! reason; with `CI=true` the same absence fails them, so CI cannot pass by not drawing.

#![allow(dead_code)]

use std::path::PathBuf;

use volley::render::Gpu;

mod ci;
#[allow(unused_imports)] // each test crate uses some of them
pub use ci::{has, in_ci, unavailable};

/// A headless device, or `None` after reporting why there is none.
pub fn gpu(test: &str) -> Option<Gpu> {
    match Gpu::headless() {
        Ok(gpu) => Some(gpu),
        Err(e) => {
            unavailable(test, &e.to_string());
            None
        }
    }
}

/// A fresh, empty folder for one test's files.
pub fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("volley-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the temp folder is writable");
    dir
}

/// Path of a file in the crate.
pub fn crate_path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// `volley ARGS` with extra environment variables: its output, whatever the exit status.
pub fn volley_output(args: &[&str], envs: &[(&str, &str)]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .expect("the volley binary runs")
}

/// `volley ARGS`' stdout; the run must succeed.
pub fn volley_stdout(args: &[&str], envs: &[(&str, &str)]) -> String {
    let out = volley_output(args, envs);
    assert!(
        out.status.success(),
        "volley {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

/// The one line of `stderr` that starts with `prefix` (the program's own message among the
/// drivers' chatter); fails unless there is exactly one.
pub fn only_line<'a>(stderr: &'a str, prefix: &str) -> &'a str {
    let ours: Vec<&str> = stderr.lines().filter(|l| l.starts_with(prefix)).collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    ours[0]
}

/// `rel` under the workspace root, which is this package's folder (the name the simulation
/// crate's shared test helpers use).
pub fn ws(rel: impl AsRef<std::path::Path>) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)
}
