//! `volley synctest` as CI runs it: every bundled scene passes, over command scripts and
//! recordings; a mismatch prints the report and exits 1 with one error line; bad input exits 2.

use std::process::{Command, Output};

use volley::scene::BUNDLED;

fn volley(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn data(file: &str) -> String {
    format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_bundled_scene_passes() {
    // 120 ticks of each in the dev profile (scripts/test runs each scene's whole duration in
    // release); the stiff springs diverge on their own integrator, reproduced by the re-runs.
    for (name, _) in BUNDLED {
        let out = volley(&["synctest", name, "--ticks", "120"]);
        let stdout = text(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{name}: {}{stdout}",
            text(&out.stderr)
        );
        assert!(
            stdout.starts_with("sync test passed: `"),
            "{name}: {stdout}"
        );
        assert_eq!(stdout.lines().count(), 1, "{name}: {stdout}");
        if name.starts_with("hard/stiff_spring") {
            assert!(stdout.contains("and the re-run reproduced it"), "{stdout}");
        } else {
            assert!(stdout.contains("ticks 0..=120,"), "{name}: {stdout}");
        }
    }
}

#[test]
fn the_seed_passes_with_its_pinned_hash_and_a_frame_of_48_bytes_a_body() {
    let out = volley(&["synctest", "seed"]);
    assert_eq!(
        text(&out.stdout),
        "sync test passed: `seed`: ticks 0..=27, each re-run from up to 7 ticks back (27 \
         checks, 168 ticks re-run), frames of 48 bytes a body; final hash 0xe02a9ef4a1ddb321\n"
    );
}

#[test]
fn the_golden_recording_and_its_command_script_pass_to_the_golden_hash() {
    let golden = "final hash 0xa3bb4937f154ea1f\n";
    let out = volley(&["synctest", &data("golden.vrec")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).ends_with(golden), "{}", text(&out.stdout));
    let script = data("replay_commands.txt");
    let scene = data("replay_scene.ron");
    let args = ["synctest", &scene, "--commands", &script, "--ticks", "300"];
    for extra in [
        &[][..],
        &[
            "--stage-hashes",
            "--rerun-threads",
            "2",
            "--check-distance",
            "3",
        ],
    ] {
        let out = volley(&[&args[..], extra].concat());
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        assert!(text(&out.stdout).ends_with(golden), "{}", text(&out.stdout));
    }
}

#[test]
fn a_mismatch_prints_the_report_and_exits_1_with_one_error_line() {
    let out = volley(&["synctest", "seed", "--inject-restore-fault", "mV.z"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    assert!(
        stdout.starts_with(
            "sync test mismatch at tick 0: the check of tick 1, which restored tick 0"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("first differing stage: restore\n"),
        "{stdout}"
    );
    // The field, both values and their bit patterns.
    assert!(
        stdout.contains(
            "  body 0 mV.z: saved 72.5001065488924 (0x40522001bee60088), restored \
             62.6901065488924 (0x404f585569511fc8)"
        ),
        "{stdout}"
    );
    let stderr = text(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr
            .starts_with("error: `seed`: sync test mismatch at tick 0, stage restore: body 0 mV.z"),
        "{stderr}"
    );
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let golden = data("golden.vrec");
    let cases: [(&[&str], &str); 5] = [
        (
            &["synctest", "seed", "--check-distance", "0"],
            "--check-distance",
        ),
        (
            &["synctest", "seed", "--check-distance", "257"],
            "--check-distance",
        ),
        (
            &["synctest", "no_such_scene"],
            "no scene file `no_such_scene`",
        ),
        (&["synctest", &golden, "--dt", "0.1"], "--dt: "),
        (
            &["synctest", "seed", "--inject-restore-fault", "mass"],
            "unknown column `mass`",
        ),
    ];
    for (args, expected) in cases {
        let out = volley(args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

#[test]
fn a_command_that_fails_is_bad_input() {
    let dir = std::env::temp_dir().join(format!("volley-synctest-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("despawn.txt");
    std::fs::write(&script, "3: despawn 9\n").unwrap();
    let out = volley(&["synctest", "seed", "--commands", script.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        "error: command `3: despawn 9` failed: despawn: there is no body 9\n"
    );
}
