//! The same bits on wasm32: the determinism suite ([`volley_wasm32::suite`]: every bundled scene
//! under every integrator, contacts, divergences, and the golden recording's verify with every
//! kind of command) run natively and as a wasm32-unknown-unknown build in Node must print the
//! same lines, hash for hash. A platform math function, a signed zero or an iteration order
//! that differs between the two shows here as the first line that differs.
//!
//! Needs Debian's rustc-web toolchain (scripts/wasm32 installs it with apt-get when it can) and
//! Node. Under `CI=true` a missing tool fails the test; elsewhere the test says loudly that it
//! did not run and passes.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Not run here: fails in CI, says so loudly elsewhere.
fn unavailable(why: &str) {
    assert!(
        !in_ci(),
        "the wasm32 determinism check cannot run under CI=true: {why}"
    );
    eprintln!("\n*** NOT RUN: the wasm32 determinism check: {why} ***\n");
}

#[test]
fn the_native_suite_verifies_the_golden_recording() {
    // The suite's anchor: its golden line is the pinned verdict of tests/cli/determinism.rs
    // (301 hashes, 7 keyframes, final hash 0xa3bb4937f154ea1f), so the comparison below
    // compares a suite that checks what the determinism tests check.
    let lines = volley_wasm32::suite();
    let golden = lines.last().expect("the golden line");
    assert_eq!(
        golden,
        "golden.vrec verified hashes=301 keyframes=7 final=0xa3bb4937f154ea1f \
         footer=0xa3bb4937f154ea1f"
    );
    // The seed scene's pinned hash after its 27 ticks under its own integrator.
    assert!(
        lines
            .iter()
            .any(|l| l == "seed explicit-euler ticks=27 hash=0xe02a9ef4a1ddb321"),
        "{lines:#?}"
    );
    // The level golden recording (tests/data/levels_golden.vrec), pinned by the sim crate's
    // replay test: the line before the golden one.
    assert_eq!(
        lines[lines.len() - 2],
        "levels_golden.vrec verified hashes=301 keyframes=7 final=0x9e55116e738644b6 \
         footer=0x9e55116e738644b6"
    );
    // Every integrator on every scene: refusals and divergences are lines too.
    let scenes = volley_wasm32::SCENES.len();
    assert_eq!(lines.len(), scenes * volley_sim::Integrator::ALL.len() + 2);
}

#[test]
fn wasm32_gives_the_same_hashes_as_this_machine() {
    if Command::new("node").arg("--version").output().is_err() {
        return unavailable("node is not installed");
    }
    let root = root();
    let build = Command::new(root.join("scripts/wasm32"))
        .args(["-p", "volley-wasm32"])
        .current_dir(&root)
        .output()
        .expect("scripts/wasm32 runs");
    if !build.status.success() {
        let log = String::from_utf8_lossy(&build.stderr);
        let tail: Vec<&str> = log.lines().rev().take(30).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        if log.contains("apt-get") && !log.contains("error[") && !log.contains("error:") {
            return unavailable(&tail.join("\n"));
        }
        panic!(
            "scripts/wasm32 -p volley-wasm32 failed:\n{}",
            tail.join("\n")
        );
    }
    let wasm = root.join("target/wasm32/wasm32-unknown-unknown/debug/volley_wasm32.wasm");
    let run = Command::new("node")
        .arg(root.join("tests/wasm32/run.mjs"))
        .arg(&wasm)
        .output()
        .expect("node runs");
    assert!(
        run.status.success(),
        "node tests/wasm32/run.mjs {} failed: {}",
        wasm.display(),
        String::from_utf8_lossy(&run.stderr)
    );
    let wasm_lines: Vec<String> = String::from_utf8(run.stdout)
        .expect("the report is UTF-8")
        .lines()
        .map(str::to_string)
        .collect();
    let native = volley_wasm32::suite();
    let differing: Vec<String> = native
        .iter()
        .zip(&wasm_lines)
        .filter(|(n, w)| n != w)
        .map(|(n, w)| format!("x86-64: {n}\nwasm32: {w}"))
        .collect();
    assert!(
        differing.is_empty() && native.len() == wasm_lines.len(),
        "{} of {} lines differ (wasm32 printed {} lines); the first ones:\n{}",
        differing.len(),
        native.len(),
        wasm_lines.len(),
        differing
            .iter()
            .take(10)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}
