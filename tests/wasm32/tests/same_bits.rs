//! The same bits on wasm32 and aarch64: the determinism suite ([`volley_wasm32::suite`]: every
//! bundled scene under every integrator, contacts, divergences, and the golden recording's verify
//! with every kind of command) run natively, as a wasm32-unknown-unknown build in Node and as an
//! aarch64-unknown-linux-gnu build under qemu-aarch64 must print the same lines, hash for hash.
//! A platform math function, a signed zero, a fused multiply-add or an iteration order that
//! differs between them shows here as the first line that differs.
//!
//! Needs Debian's rustc-web toolchain (scripts/wasm32 and scripts/aarch64 install it with
//! apt-get when they can), Node for wasm32, and Debian's aarch64 cross gcc and qemu-user for
//! aarch64 (scripts/aarch64 installs them). Under `CI=true` a missing tool fails the test;
//! elsewhere the test says loudly that it did not run and passes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Not run here: fails in CI, says so loudly elsewhere. `target` names the check.
fn unavailable(target: &str, why: &str) {
    assert!(
        !in_ci(),
        "the {target} determinism check cannot run under CI=true: {why}"
    );
    eprintln!("\n*** NOT RUN: the {target} determinism check: {why} ***\n");
}

/// The suite's lines on this machine, computed once for every comparison.
fn native_lines() -> &'static [String] {
    static LINES: OnceLock<Vec<String>> = OnceLock::new();
    LINES.get_or_init(volley_wasm32::suite)
}

/// This machine's architecture as the failure messages name it.
fn native_name() -> &'static str {
    match std::env::consts::ARCH {
        "x86_64" => "x86-64",
        arch => arch,
    }
}

/// Runs a build script (`scripts/wasm32`, `scripts/aarch64`) with `args`. `Err` holds why the
/// check cannot run here (the script could not install its toolchain); a failed compile panics.
fn build(script: &str, args: &[&str]) -> Result<(), String> {
    let root = root();
    let build = Command::new(root.join(script))
        .args(args)
        .current_dir(&root)
        .output()
        .unwrap_or_else(|e| panic!("{script} does not run: {e}"));
    if build.status.success() {
        return Ok(());
    }
    let log = String::from_utf8_lossy(&build.stderr);
    let tail: Vec<&str> = log.lines().rev().take(30).collect();
    let tail: Vec<&str> = tail.into_iter().rev().collect();
    if log.contains("apt-get") && !log.contains("error[") && !log.contains("error:") {
        return Err(tail.join("\n"));
    }
    panic!("{script} {} failed:\n{}", args.join(" "), tail.join("\n"));
}

/// The report a run printed, one line per run; panics naming `what` if the run failed.
fn report(what: &str, run: Output) -> Vec<String> {
    assert!(
        run.status.success(),
        "{what} failed ({}): {}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    String::from_utf8(run.stdout)
        .expect("the report is UTF-8")
        .lines()
        .map(str::to_string)
        .collect()
}

/// Requires `other`, the report of the build for `target`, to equal this machine's, line for
/// line; fails with the count and the first lines that differ.
fn require_same_lines(target: &str, other: &[String]) {
    let native = native_lines();
    let here = native_name();
    let differing: Vec<String> = native
        .iter()
        .zip(other)
        .filter(|(n, o)| n != o)
        .map(|(n, o)| format!("{here}: {n}\n{target}: {o}"))
        .collect();
    assert!(
        differing.is_empty() && native.len() == other.len(),
        "{} of {} lines differ ({target} printed {} lines); the first ones:\n{}",
        differing.len(),
        native.len(),
        other.len(),
        differing
            .iter()
            .take(10)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn the_native_suite_verifies_the_golden_recording() {
    // The suite's anchor: its golden line is the pinned verdict of tests/cli/determinism.rs
    // (301 hashes, 7 keyframes, final hash 0xa3bb4937f154ea1f), so the comparisons below
    // compare a suite that checks what the determinism tests check.
    let lines = native_lines();
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
        return unavailable("wasm32", "node is not installed");
    }
    if let Err(why) = build("scripts/wasm32", &["-p", "volley-wasm32"]) {
        return unavailable("wasm32", &why);
    }
    let root = root();
    let wasm = root.join("target/wasm32/wasm32-unknown-unknown/debug/volley_wasm32.wasm");
    let run = Command::new("node")
        .arg(root.join("tests/wasm32/run.mjs"))
        .arg(&wasm)
        .output()
        .expect("node runs");
    let what = format!("node tests/wasm32/run.mjs {}", wasm.display());
    require_same_lines("wasm32", &report(&what, run));
}

/// The suite's example (examples/suite.rs) built for aarch64-unknown-linux-gnu by
/// scripts/aarch64 and run under qemu-aarch64 with the cross glibc as its root. Built in the dev
/// profile, as the wasm32 module is: the determinism tests pin the same hashes in both profiles.
#[test]
fn aarch64_gives_the_same_hashes_as_this_machine() {
    let args = ["-p", "volley-wasm32", "--example", "suite"];
    if let Err(why) = build("scripts/aarch64", &args) {
        return unavailable("aarch64", &why);
    }
    let exe = root().join("target/aarch64/aarch64-unknown-linux-gnu/debug/examples/suite");
    let run = match Command::new("qemu-aarch64")
        .args(["-L", "/usr/aarch64-linux-gnu"])
        .arg(&exe)
        .output()
    {
        Ok(run) => run,
        Err(e) => return unavailable("aarch64", &format!("qemu-aarch64 does not run: {e}")),
    };
    let what = format!("qemu-aarch64 -L /usr/aarch64-linux-gnu {}", exe.display());
    require_same_lines("aarch64", &report(&what, run));
}
