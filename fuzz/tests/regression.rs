//! Replays every file of `fuzz/regression/<target>/` through its fuzz target's property with the
//! stable toolchain and no fuzzer, so each input a fuzzing run found (a crash, a hang, an
//! allocation past the limit) stays fixed in CI. `scripts/fuzz` copies new findings here; each
//! file is named for what it found.

use std::path::{Path, PathBuf};

/// Runs `property` on every file of `regression/<target>`; returns how many there were.
fn replay(target: &str, property: fn(&[u8])) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("regression")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep"))
        .collect();
    files.sort();
    for file in &files {
        let data = std::fs::read(file).unwrap();
        let started = std::time::Instant::now();
        property(&data);
        // Not a timing assertion on the property: a report of an input that got slow again.
        eprintln!("{}: {:?}", file.display(), started.elapsed());
    }
    files.len()
}

#[test]
fn scene_regressions() {
    replay("scene", volley_fuzz::scene);
}

#[test]
fn command_regressions() {
    replay("commands", volley_fuzz::commands);
}

#[test]
fn recording_regressions() {
    replay("recording", volley_fuzz::recording);
}

#[test]
fn window_script_regressions() {
    replay("window_script", volley_fuzz::window_script);
}

#[test]
fn shard_regressions() {
    replay("shard", volley_fuzz::shard);
}

/// The properties pass on the inputs they are seeded from: every bundled scene, the replay
/// tests' data, the golden recording. A property that refused everything (or panicked on valid
/// input) would fail here.
#[test]
fn properties_hold_on_the_valid_seeds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for (name, text) in volley_sim::scene::BUNDLED {
        assert!(
            volley_sim::scene::parse(text, name, name).is_ok(),
            "{name} is a valid seed"
        );
        volley_fuzz::scene(text.as_bytes());
    }
    let commands = std::fs::read(root.join("tests/data/replay_commands.txt")).unwrap();
    volley_fuzz::commands(&commands);
    let golden = std::fs::read(root.join("tests/data/golden.vrec")).unwrap();
    assert_eq!(
        volley_fuzz::fix_checksums(&golden),
        golden,
        "a valid file's checksums are kept"
    );
    volley_fuzz::recording(&golden);
}
