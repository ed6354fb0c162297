//! `volley record` and `volley replay` as a user runs them: output lines, exit codes, and a
//! recording killed mid-run.

use std::path::PathBuf;
use std::process::{Command, Output};

use crate::replay_support::*;

fn volley(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .output()
        .unwrap()
}

/// A fresh path in the temp dir for this test process.
fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("volley-replay-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn record_then_verify_prints_the_ticks_and_the_final_hash() {
    let file = temp("seed.vrec");
    let out = volley(&["record", "seed", "-o", file.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // The seed's pinned hash after its 27 ticks (tests/determinism.rs).
    assert!(text(&out.stdout).ends_with("final hash 0xe02a9ef4a1ddb321\n"));
    let out = volley(&["replay", file.to_str().unwrap(), "--verify"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.starts_with("verified 27 ticks, final hash 0xe02a9ef4a1ddb321 (ticks 0..=27: 28"),
        "{stdout}"
    );
    // Every 10th tick: 0, 10, 20, and the last tick's hash in the footer; both lines count 4.
    let out = volley(&[
        "record",
        "seed",
        "--hash-every",
        "10",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(
        text(&out.stdout).contains(", 4 hashes,"),
        "{}",
        text(&out.stdout)
    );
    let out = volley(&["replay", file.to_str().unwrap(), "--verify"]);
    assert!(
        text(&out.stdout).contains("(ticks 0..=27: 4 hashes"),
        "{}",
        text(&out.stdout)
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn replay_prints_the_same_table_as_the_run_it_recorded() {
    let file = temp("table.vrec");
    let (scene, script) = (
        "tests/data/replay_scene.ron",
        "tests/data/replay_commands.txt",
    );
    let run_args = ["--commands", script, "--ticks", "120"];
    let run = volley(&[&["headless", scene, "--format", "csv"][..], &run_args].concat());
    let rec = volley(
        &[
            &["record", scene, "-o", file.to_str().unwrap()][..],
            &run_args,
        ]
        .concat(),
    );
    assert!(rec.status.success(), "{}", text(&rec.stderr));
    let play = volley(&["replay", file.to_str().unwrap(), "--format", "csv"]);
    assert!(play.status.success(), "{}", text(&play.stderr));
    assert!(text(&run.stdout).lines().count() > 120 * 27);
    assert_eq!(text(&play.stdout), text(&run.stdout));
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_divergent_recording_exits_1_naming_tick_body_and_field() {
    let file = temp("nudged.vrec");
    let scene = coverage_scene();
    let mut sim = volley::SimLoop::new(volley::World::new(&scene));
    let mut source = volley::clock::VirtualClock::Steady(scene.timestep());
    let mut recorder =
        volley::replay::Recorder::start(Vec::new(), &sim.world, options(1, 10)).unwrap();
    sim.run_until(20, &mut source, &mut recorder).unwrap();
    let mut s = sim.world.snapshot();
    s.bodies.mv.z[0] = s.bodies.mv.z[0].next_down();
    sim.world.restore(&s).unwrap();
    sim.run_until(40, &mut source, &mut recorder).unwrap();
    std::fs::write(&file, recorder.finish(&sim.world).unwrap().0).unwrap();

    let out = volley(&["replay", file.to_str().unwrap(), "--verify"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    assert!(
        stdout.starts_with("first divergence at tick 21: state hash recorded 0x"),
        "{stdout}"
    );
    assert!(
        stdout.contains("the state matched at tick 20\n"),
        "{stdout}"
    );
    assert!(stdout.contains("\n  body 0 mV.z: recorded "), "{stdout}");
    assert_eq!(
        text(&out.stderr),
        format!(
            "error: {}: the replay parts from the recording at tick 21\n",
            file.display()
        )
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn damaged_or_foreign_recordings_exit_2_with_one_line() {
    let good = record(&coverage_scene(), 40, &[], options(1, 10));
    let mut magic = good.clone();
    magic[0] = b'{';
    let mut newer = good.clone();
    newer[8] = 9;
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x10;
    let mut bad_scene = frames(&good);
    let mut header: serde_json::Value = serde_json::from_slice(&bad_scene[0].payload).unwrap();
    header["scene_source"] = "Scene(dt: 0.01, integrator: Warp9, bodies: [])".into();
    bad_scene[0].payload = serde_json::to_vec(&header).unwrap();
    let cases = [
        ("magic", magic, "not a Volley recording"),
        ("newer", newer, "format version 9 is newer"),
        ("flipped", flipped, "(damaged file)"),
        ("cut", good[..100].to_vec(), "ends before the header"),
        (
            "scene",
            assemble(&bad_scene),
            "the embedded scene no longer parses",
        ),
    ];
    for (name, bytes, expected) in cases {
        let file = temp(&format!("{name}.vrec"));
        std::fs::write(&file, bytes).unwrap();
        for verify in [true, false] {
            let mut args = vec!["replay", file.to_str().unwrap()];
            args.extend(verify.then_some("--verify"));
            let out = volley(&args);
            let stderr = text(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
            assert!(
                stderr.starts_with(&format!("error: {}", file.display())),
                "{stderr}"
            );
            assert!(stderr.contains(expected), "{name}: {stderr}");
        }
        let _ = std::fs::remove_file(&file);
    }
    let out = volley(&["replay", "/nonexistent/run.vrec"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_recording_killed_mid_run_opens_truncated_and_verifies() {
    let file = temp("killed.vrec");
    let mut child = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args([
            "record",
            "seed",
            "--ticks",
            "100000000",
            "-o",
            file.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait until the recorder has flushed a few thousand ticks, then kill it (SIGKILL: no
    // chance to write a footer or flush a buffer).
    while std::fs::metadata(&file).map_or(0, |m| m.len()) < 100_000 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the recording ended early"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.kill().unwrap();
    child.wait().unwrap();

    let rec = volley::replay::Recording::open(&file).unwrap();
    assert!(rec.footer().is_none() && rec.truncated_at().is_some());
    let end = rec.end_tick();
    assert!(end > 3000, "{end}");
    let out = volley(&["replay", file.to_str().unwrap(), "--verify"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains(&format!("truncated after tick {end}")));
    assert!(text(&out.stdout).starts_with(&format!("verified {end} ticks")));
    let _ = std::fs::remove_file(&file);
}

/// A game's own force term, which only this test process has: the `volley` binary does not.
#[derive(Debug)]
struct GamePush;

impl volley::forces::ForceTerm for GamePush {
    fn name(&self) -> &str {
        "test-game/push"
    }
    fn version(&self) -> u32 {
        3
    }
    fn force(&self, i: &volley::forces::ForceInput) -> glam::DVec3 {
        glam::DVec3::new(i.m * i.t, 0.0, 0.0)
    }
}

#[test]
fn a_recording_with_a_games_own_term_names_it_and_is_refused_without_it() {
    let terms = volley::forces::ForceTerms::new().with(GamePush);
    let scene = volley::parse_scene_with(
        "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81)), \
         Custom(name: \"test-game/push\", version: 3)], \
         bodies: [(mass: 1, position: (0, 0, 5), launch: Velocity((1, 0, 2)))])",
        "game.ron",
        "game",
        &terms,
    )
    .unwrap();
    let file = temp("game-term.vrec");
    std::fs::write(&file, record(&scene, 30, &[], options(1, 10))).unwrap();
    let out = volley(&["replay", file.to_str().unwrap(), "--verify"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stdout));
    let err = text(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(
            "custom force term `test-game/push` (version 3) is not in this program's terms"
        ),
        "{err}"
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_replay_lists_the_declared_events_the_run_had() {
    // tests/data/declared_events.ron: "10 m up" in tick 59 and "30.5 m out" in tick 153.
    let dir = crate::support::scratch_dir("replay_declared_events");
    let file = dir.join("events.vrec");
    let scene = crate::support::ws("tests/data/declared_events.ron");
    let rec = crate::support::volley_output(
        &[
            "record",
            scene.to_str().unwrap(),
            "--ticks",
            "200",
            "-o",
            file.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        rec.status.success(),
        "{}",
        String::from_utf8_lossy(&rec.stderr)
    );
    let run = crate::support::volley_stdout(
        &["headless", scene.to_str().unwrap(), "--ticks", "200"],
        &[],
    );
    let replay =
        crate::support::volley_stdout(&["replay", file.to_str().unwrap(), "--headless"], &[]);
    let declared = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("event ") && (l.contains("m up") || l.contains("m out")))
            .map(str::to_string)
            .collect()
    };
    let seen = declared(&replay);
    assert_eq!(seen.len(), 2, "{replay}");
    assert!(seen[0].starts_with("event tick 59 ") && seen[0].contains("10 m up rising"));
    assert!(seen[1].starts_with("event tick 153 ") && seen[1].contains("30.5 m out rising"));
    assert_eq!(
        seen,
        declared(&run),
        "the replay lists what the run printed"
    );
}
