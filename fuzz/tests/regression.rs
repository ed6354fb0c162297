//! Replays every file of `fuzz/regression/<target>/` through its fuzz target's property with the
//! stable toolchain and no fuzzer, so each input a fuzzing run found (a crash, a hang, an
//! allocation past the limit) stays fixed in CI. `scripts/fuzz` copies new findings here; each
//! file is named for what it found. Beside the findings, a file named `valid-*` is an input the
//! target's reader must accept and one named `malformed-*` an input it must refuse: the targets
//! with no finding yet hold one of each, so their property runs on a file that gets past the
//! reader and on one that does not. A directory with no input at all fails its test.

use std::path::{Path, PathBuf};

/// Most force evaluations one input may cost: about a second of the fuzz harness's work in
/// release, a tenth of libFuzzer's 10 s limit. A hang found by fuzzing costs orders of magnitude
/// more (the first recording that hung spent about 10^9), so counting the work catches it
/// again exactly, without timing anything.
const MAX_INPUT_EVALS: u64 = 50_000_000;

/// The inputs of `regression/<target>`, sorted; fails if there is none, so a test can never
/// replay an empty directory and pass.
fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("regression")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep"))
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "{}: no input, so the test would replay nothing",
        dir.display()
    );
    files
}

/// Runs `property` on every file of `regression/<target>`; returns how many there were.
fn replay(target: &str, property: fn(&[u8])) -> usize {
    let files = inputs(target);
    for file in &files {
        let data = std::fs::read(file).unwrap();
        volley_fuzz::take_evals();
        property(&data);
        let evals = volley_fuzz::take_evals();
        eprintln!("{}: {evals} force evaluations", file.display());
        assert!(
            evals <= MAX_INPUT_EVALS,
            "{}: {evals} force evaluations, more than {MAX_INPUT_EVALS}: it hangs again",
            file.display()
        );
    }
    files.len()
}

#[test]
fn scene_regressions() {
    // The two saved-setup findings of the first run stay in the corpus, beside a Mach drag
    // with every field the reader accepts and one it must refuse.
    reader_sorts("scene", |text, name| {
        volley_sim::internals::scene::parse(text, name, "fuzz").is_ok()
    });
    assert!(replay("scene", volley_fuzz::scene) >= 4);
}

/// Checks that the reader `reads` (true when it accepts the text) accepts every `valid-*` input
/// of `regression/<target>` and refuses every `malformed-*` one, and that there is at least one
/// of each.
fn reader_sorts(target: &str, reads: fn(&str, &str) -> bool) {
    let (mut valid, mut malformed) = (0, 0);
    for file in inputs(target) {
        let name = file.file_name().unwrap().to_str().unwrap().to_owned();
        let text = std::fs::read_to_string(&file).unwrap();
        if name.starts_with("valid-") {
            assert!(reads(&text, &name), "{}: refused", file.display());
            valid += 1;
        } else if name.starts_with("malformed-") {
            assert!(!reads(&text, &name), "{}: accepted", file.display());
            malformed += 1;
        }
    }
    assert!(
        valid > 0 && malformed > 0,
        "regression/{target}: {valid} valid-* and {malformed} malformed-* inputs, one of each at least"
    );
}

#[test]
fn command_regressions() {
    reader_sorts("commands", |text, name| {
        volley_sim::internals::command::parse_script(text, name).is_ok()
    });
    replay("commands", volley_fuzz::commands);
}

#[test]
fn recording_regressions() {
    // The contact-work hang and the overflowing count.
    assert!(replay("recording", volley_fuzz::recording) >= 2);
}

#[cfg(feature = "window")]
#[test]
fn window_script_regressions() {
    reader_sorts("window_script", |text, name| {
        volley::app::script::parse(text, name).is_ok()
    });
    replay("window_script", volley_fuzz::window_script);
}

#[test]
fn shard_regressions() {
    reader_sorts("shard", |text, name| {
        volley_lab::study::shard::ShardResult::from_json(text, name).is_ok()
    });
    replay("shard", volley_fuzz::shard);
}

#[test]
fn pacing_shard_regressions() {
    reader_sorts("pacing_shard", |text, name| {
        volley_lab::pacing::shard::PacingShard::from_json(text, name).is_ok()
    });
    replay("pacing_shard", volley_fuzz::pacing_shard);
}

/// [`reader_sorts`] for a binary reader.
fn reader_sorts_bytes(target: &str, reads: fn(&[u8]) -> bool) {
    let (mut valid, mut malformed) = (0, 0);
    for file in inputs(target) {
        let name = file.file_name().unwrap().to_str().unwrap().to_owned();
        let data = std::fs::read(&file).unwrap();
        if name.starts_with("valid-") {
            assert!(reads(&data), "{}: refused", file.display());
            valid += 1;
        } else if name.starts_with("malformed-") {
            assert!(!reads(&data), "{}: accepted", file.display());
            malformed += 1;
        }
    }
    assert!(
        valid > 0 && malformed > 0,
        "regression/{target}: {valid} valid-* and {malformed} malformed-* inputs, one of each at least"
    );
}

#[test]
fn obj_regressions() {
    reader_sorts_bytes("obj", |data| {
        volley_sim::internals::scene::read_obj(data, "fuzz.obj").is_ok()
    });
    replay("obj", volley_fuzz::obj);
}

#[test]
fn gltf_regressions() {
    reader_sorts_bytes("gltf", |data| {
        let mut none = |uri: &str| {
            Err(volley_sim::internals::scene::LevelError::new(
                uri, "no files",
            ))
        };
        volley_sim::internals::scene::read_gltf(data, "fuzz.glb", &mut none).is_ok()
    });
    replay("gltf", volley_fuzz::gltf);
}

#[test]
fn heightmap_regressions() {
    reader_sorts_bytes("heightmap", |data| {
        volley_sim::internals::scene::read_heightmap_png(data, "fuzz.png", 0.001).is_ok()
    });
    replay("heightmap", volley_fuzz::heightmap);
}

#[test]
fn capture_regressions() {
    // The shipped capture trimmed to its first rows, and a malformed one.
    assert!(replay("capture", volley_fuzz::capture) >= 2);
}

/// The properties pass on the inputs they are seeded from: every bundled scene, the replay
/// tests' data, the golden recording, the shipped capture. A property that refused everything (or panicked on valid
/// input) would fail here.
#[test]
fn properties_hold_on_the_valid_seeds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for (name, text) in volley_sim::internals::scene::BUNDLED {
        let scene = volley_sim::internals::scene::parse(text, name, name).unwrap();
        volley_fuzz::take_evals();
        volley_fuzz::scene(text.as_bytes());
        let stepped = volley_fuzz::take_evals() > 0;
        // Larger worlds are validated, not built (the harness's bound); the closed form
        // evaluates no force.
        let built = scene.body_count() <= volley_fuzz::MAX_FUZZ_BODIES && scene.duration() > 0.0;
        let evaluates = scene.integrator() != volley_sim::Integrator::Exact;
        assert_eq!(stepped, built && evaluates, "{name} stepped");
    }
    let commands = std::fs::read(root.join("tests/data/replay_commands.txt")).unwrap();
    volley_fuzz::commands(&commands);
    assert!(
        volley_fuzz::take_evals() > 0,
        "the command script's world was stepped"
    );
    let golden = std::fs::read(root.join("tests/data/golden.vrec")).unwrap();
    assert_eq!(
        volley_fuzz::fix_checksums(&golden),
        golden,
        "a valid file's checksums are kept"
    );
    volley_fuzz::recording(&golden);
    assert!(
        volley_fuzz::take_evals() > 0,
        "the golden recording was replayed"
    );
    let capture =
        std::fs::read_to_string(root.join("assets/captures/presentmon_test_case_4.csv")).unwrap();
    volley_lab::pacing::read_capture(&capture, "presentmon_test_case_4.csv", None)
        .expect("the shipped capture reads");
    volley_fuzz::capture(capture.as_bytes());
}
