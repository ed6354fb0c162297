//! Determinism pins: these tests run in the dev profile *and* in release (`scripts/test`), so
//! passing both means both profiles produce the same bits.

use crate::support;

use std::path::Path;

use volley::clock::VirtualClock;
use volley::hash::{hex, state_hash};
use volley::{SimLoop, World, scene};

/// The seed scene after its 27 ticks (t = 5.0 to 10.4). A physics change that alters any bit of
/// the result must update this on purpose.
const SEED_HASH_AT_27: &str = "0xe02a9ef4a1ddb321";

#[test]
fn seed_scene_hash_is_pinned() {
    let scene = scene::load(Path::new("assets/scenes/seed.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.run_until(27, &mut VirtualClock::Steady(scene.timestep()), &mut ())
        .unwrap();
    assert_eq!(hex(state_hash(&sim.world)), SEED_HASH_AT_27);
}

#[test]
fn headless_checks_a_pinned_final_hash() {
    let run = |hash: &str| {
        let out = support::volley_output(
            &["headless", "seed", "--no-table", "--expect-hash", hash],
            &[],
        );
        let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
        (out.status.code(), text(&out.stdout), text(&out.stderr))
    };
    let (code, stdout, stderr) = run(SEED_HASH_AT_27);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.contains(&format!("hash={SEED_HASH_AT_27}")),
        "{stdout}"
    );
    // Any other hash (here the last digit changed, and upper case) fails after the summary.
    let other = SEED_HASH_AT_27
        .replace("321", "322")
        .to_uppercase()
        .replace("0X", "0x");
    let (code, stdout, stderr) = run(&other);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stdout.contains("summary: ticks=27"), "{stdout}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!(
            "final hash {SEED_HASH_AT_27} at tick 27, expected {}",
            other.to_lowercase()
        )),
        "{stderr}"
    );
}

/// Final hash of the golden recording, tests/data/golden.vrec: the replay coverage scene and
/// script (a seeded volley, bounces, a wall, a target, a spring, drag toggled on and off, every
/// kind of command, velocity Verlet's carried force) over 300 ticks, a hash every tick and a
/// keyframe every 50. Re-simulating it must match every stored hash and keyframe, in debug and in
/// release. A physics change that alters any bit must regenerate the file and update this on
/// purpose (see docs/replays.md, "The golden recording"):
/// `cargo run -- record tests/data/replay_scene.ron --commands tests/data/replay_commands.txt
/// --ticks 300 --keyframe-every 50 -o tests/data/golden.vrec`
const GOLDEN_REPLAY_FINAL_HASH: &str = "0xa3bb4937f154ea1f";

#[test]
fn golden_replay_verifies_every_tick_and_its_final_hash_is_pinned() {
    use volley::replay::{Recording, Replay};
    let recording = Recording::open(Path::new("tests/data/golden.vrec")).unwrap();
    let footer = recording
        .footer()
        .copied()
        .expect("the golden file is complete");
    let mut replay = Replay::start(recording, None).unwrap();
    replay.run_to(u64::MAX, &mut ()).unwrap();
    if let Some(d) = replay.first_divergence() {
        panic!("the golden replay diverged:\n{}", d.report(Some(20)));
    }
    assert_eq!(
        (replay.hashes_checked(), replay.keyframes_checked()),
        (301, 7)
    );
    assert_eq!(hex(state_hash(replay.world())), GOLDEN_REPLAY_FINAL_HASH);
    assert_eq!(hex(footer.final_hash), GOLDEN_REPLAY_FINAL_HASH);
}

/// The three integrators added after the golden recording, each pinned on the replay coverage
/// scene (a seeded volley, bounces, a wall, a target, a spring and drag) after 300 ticks: the
/// carried force of Forest-Ruth, Dormand-Prince's step choice and its counted evaluations, and
/// implicit midpoint's split forms all decide these bits, in debug and in release.
const NEW_INTEGRATOR_HASHES: [(volley::Integrator, &str); 3] = [
    (volley::Integrator::ForestRuth, "0xb504a903c8cb2e84"),
    (volley::Integrator::Dopri5, "0x304b95f800869c35"),
    (volley::Integrator::ImplicitMidpoint, "0x15074ff363cd3325"),
];

#[test]
fn the_new_integrators_hashes_are_pinned() {
    let mut got = Vec::new();
    for (integrator, _) in NEW_INTEGRATOR_HASHES {
        let mut scene = scene::load(Path::new("tests/data/replay_scene.ron")).unwrap();
        scene.set_integrator(integrator).unwrap();
        let mut sim = SimLoop::new(World::new(&scene));
        sim.run_until(300, &mut VirtualClock::Steady(scene.timestep()), &mut ())
            .unwrap();
        got.push((integrator, hex(state_hash(&sim.world))));
    }
    let want: Vec<_> = NEW_INTEGRATOR_HASHES
        .iter()
        .map(|(i, h)| (*i, h.to_string()))
        .collect();
    assert_eq!(got, want);
}
