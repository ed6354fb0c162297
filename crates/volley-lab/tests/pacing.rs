//! The loop lab's policies and displays, driven through the real loop: what a policy may change
//! (ticks per frame, where a frame is drawn) and what it may not (any tick's state).

#[path = "../../volley-sim/tests/support/mod.rs"]
mod support;

use std::time::Duration;

use volley_lab::pacing::{DisplayModel, DrawMode, RunConfig, Subject, run};
use volley_sim::internals::clock::LoopPolicy;
use volley_sim::internals::hash;
use volley_sim::internals::sim_loop::TickObserver;
use volley_sim::{Integrator, ObserverError, SimLoop, World};

const H60: Duration = Duration::from_nanos(16_666_667);

/// Every tick's hash, in order.
struct Hashes(Vec<u64>);

impl TickObserver for Hashes {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.0.push(hash::state_hash(world));
        Ok(())
    }
}

fn policies(refresh: Duration) -> Vec<LoopPolicy> {
    LoopPolicy::NAMES
        .iter()
        .map(|n| LoopPolicy::from_name(n, refresh).unwrap())
        .collect()
}

#[test]
fn every_policy_computes_the_same_state_at_every_tick() {
    let timing = DisplayModel::fixed(60_000.0 / 1001.0).timing("59.94", 10.0);
    let scene = Subject::Orbit.scene(60.0, Integrator::VelocityVerlet);
    let mut runs = Vec::new();
    for policy in policies(H60) {
        let mut sim = SimLoop::new(World::new(&scene));
        sim.clock.set_policy(policy);
        let mut hashes = Hashes(Vec::new());
        for delta in timing.deltas(Duration::ZERO) {
            sim.frame(delta, &mut hashes).unwrap();
        }
        runs.push((policy.name(), hashes.0));
    }
    let shortest = runs.iter().map(|r| r.1.len()).min().unwrap();
    // 10 s at 60 Hz, less what the policies hold back at the end (at most a few ticks).
    assert!(shortest > 590, "{shortest}");
    for (name, hashes) in &runs[1..] {
        assert_eq!(hashes[..shortest], runs[0].1[..shortest], "{name}");
    }
}

#[test]
fn every_draw_mode_leaves_every_tick_as_it_was() {
    // A draw reads the world and changes nothing a tick computes: the subjects with surfaces
    // and commands and the bundled scenes with a ground and walls, drawn every frame in each
    // mode (swept meets the surfaces), step to the same hashes as with no draw at all, and
    // leave the world's generator where it was.
    use volley_sim::{Draw, bundled_scene};
    let timing = DisplayModel::fixed(144.0).timing("144", 4.0);
    let mut scenes: Vec<(String, volley_sim::Scene, Vec<volley_sim::Stamped>)> = [
        Subject::Bounce,
        Subject::BounceHalf,
        Subject::Wall,
        Subject::Command,
        Subject::Target,
    ]
    .into_iter()
    .map(|s| {
        let scene = s.scene(60.0, Integrator::VelocityVerlet);
        (s.name().to_string(), scene, s.commands(60.0, 4.0))
    })
    .collect();
    for name in ["bounce", "volley", "hard/tunnelling"] {
        scenes.push((name.to_string(), bundled_scene(name).unwrap(), Vec::new()));
    }
    for (name, scene, commands) in &scenes {
        let run = |mode: Option<DrawMode>| {
            let mut sim = SimLoop::new(World::new(scene));
            sim.schedule(commands.clone());
            let mut draw = Draw::new(&sim.world, mode.unwrap_or(DrawMode::Current));
            // The target subject's shots stop on the target where they strike it.
            if name == "target" {
                draw.set_at_targets(volley_sim::AtTargets::Stop);
            }
            let mut hashes = Hashes(Vec::new());
            let mut drawn = 0usize;
            for delta in timing.deltas(Duration::ZERO) {
                let ticks = match mode {
                    Some(_) => sim.frame(delta, &mut (&mut hashes, &mut draw)).unwrap(),
                    None => sim.frame(delta, &mut hashes).unwrap(),
                };
                if mode.is_some() {
                    draw.frame(delta);
                    draw.positions(&sim.world, ticks.alpha, |_, p| {
                        assert!(p.is_finite());
                        drawn += 1;
                    });
                }
            }
            (hashes.0, sim.world.rng(), drawn)
        };
        let (plain, rng, _) = run(None);
        assert!(plain.len() > 200, "{name}");
        for mode in DrawMode::ALL {
            let (hashes, after, drawn) = run(Some(mode));
            assert!(drawn > 0, "{name}");
            assert_eq!(hashes, plain, "{name}: {}", mode.name());
            assert_eq!(after, rng, "{name}: {}", mode.name());
        }
    }
}

fn config(policy: LoopPolicy, phase: f64) -> RunConfig {
    RunConfig {
        subject: Subject::Orbit,
        rate: 60.0,
        integrator: Integrator::VelocityVerlet,
        policy,
        phase,
    }
}

#[test]
fn a_60_hz_loop_on_a_steady_59_94_hz_display_runs_a_two_tick_frame_about_every_16_7_s() {
    // No wake-up noise: the display is 1001/1000 slower than the loop, so the accumulator gains
    // 1/1000 of a tick a frame and runs a frame of 2 ticks every 1000 frames, 16.68 s.
    let display = DisplayModel::Fixed {
        hz: 60_000.0 / 1001.0,
        wake: Duration::ZERO,
        cost: Duration::from_millis(4),
        miss_every: 0,
        seed: 1,
    };
    let timing = display.timing("59.94", 60.0);
    let m = run(&config(LoopPolicy::Accumulator, 0.5), &timing).unwrap();
    // The one 0-tick frame is the first: it carries only the half tick of the phase.
    assert_eq!(m.histogram[0], 1);
    assert!((3..=4).contains(&m.histogram[2]), "{:?}", m.histogram);
}

#[test]
fn on_a_noisy_60_hz_clock_at_a_tick_boundary_the_accumulator_swings_and_snapping_does_not() {
    // Wake-up noise up to 0.15 ms: the deltas stay within Glaiel's 0.2 ms snapping tolerance.
    let display = DisplayModel::Fixed {
        hz: 60.0,
        wake: Duration::from_micros(150),
        cost: Duration::from_millis(4),
        miss_every: 0,
        seed: 7,
    };
    let timing = display.timing("60", 20.0);
    let plain = run(&config(LoopPolicy::Accumulator, 0.0), &timing).unwrap();
    assert!(plain.swings_per_s > 5.0, "{}", plain.swings_per_s);
    let snapped = run(&config(LoopPolicy::glaiel(H60), 0.0), &timing).unwrap();
    assert_eq!(snapped.swings_per_s, 0.0, "{}", snapped.cadence);
}

#[test]
fn the_hysteresis_policy_keeps_game_time_within_its_bound_of_wall_time() {
    // Godot's jitter fix bounds |game - wall| by jitter_fix ticks (0.5 here, 8.3 ms at 60 Hz),
    // on every bundled fixed-refresh display.
    for hz in [60.0, 60_000.0 / 1001.0, 144.0] {
        let timing = DisplayModel::fixed(hz).timing("fixed", 30.0);
        let m = run(&config(LoopPolicy::godot(), 0.0), &timing).unwrap();
        assert!(
            m.drift_worst <= 0.5 * 1e3 / 60.0 + 1e-6,
            "{hz}: {}",
            m.drift_worst
        );
    }
}

#[test]
fn interpolation_draws_one_tick_behind_and_extrapolation_does_not() {
    let timing = DisplayModel::fixed(60.0).timing("60", 10.0);
    let m = run(&config(LoopPolicy::Accumulator, 0.5), &timing).unwrap();
    let lag = |mode| m.mode(mode).lag;
    // The difference of the two lags is one tick exactly (16.667 ms), up to rounding in the
    // millisecond conversions.
    let tick = 1e3 / 60.0;
    assert!((lag(DrawMode::Interpolate) - lag(DrawMode::Extrapolate) - tick).abs() < 1e-6);
}

#[test]
fn a_hitch_is_recovered_as_the_clock_documents() {
    // The clock's doc: a frame's delta is clamped to 250 ms, at most 8 ticks run, and whole ticks
    // beyond the cap are dropped, not carried. A 300 ms render on a 60 Hz display makes one
    // delta of whole refreshes, D; the clamp drops D - 250 ms, the 250 ms left owe 15 ticks
    // (plus an accumulator under one tick), 8 run and 7 are dropped. The next frame is back to
    // one tick: recovery is one frame, and the drift the policy causes stays at zero.
    let (_, model) = DisplayModel::bundled()
        .into_iter()
        .find(|(n, _)| *n == "60-hitch")
        .unwrap();
    let timing = model.timing("60-hitch", 20.0);
    let longest = timing.deltas(Duration::ZERO).max().unwrap().as_secs_f64();
    let m = run(&config(LoopPolicy::Accumulator, 0.5), &timing).unwrap();
    let tick = 1e3 / 60.0;
    let expected = (longest - 0.25) * 1e3 + 7.0 * tick;
    assert!(
        (m.dropped - expected).abs() < 1e-3,
        "dropped {} ms, expected {expected} ms",
        m.dropped
    );
    assert_eq!(m.histogram[3], 1, "one frame of 8 ticks: {:?}", m.histogram);
    let recovery = m.recovery.expect("the hitch is found");
    assert!((recovery - tick).abs() < 0.1, "recovery {recovery} ms");
    assert!(m.drift_kept < 1e-3, "{}", m.drift_kept);
}

#[test]
fn pacing_default_is_the_sweeps_choice() {
    // Volley's defaults are what the loop lab's ranking over every subject puts first
    // (docs/pacing/report.md): the bundled display models and the shipped PresentMon capture,
    // every policy, every subject at 60 Hz under velocity Verlet, both phases.
    use volley_lab::pacing::{
        DEFAULT_DRAW, DEFAULT_POLICY, Sweep, SweepDisplay, choose_all, read_capture, sweep,
    };
    let path = "assets/captures/presentmon_test_case_4.csv";
    let text =
        std::fs::read_to_string(format!("{}/../../{path}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let capture = read_capture(&text, path, None).unwrap();
    let mut displays = Sweep::bundled_displays(sweep::SECONDS);
    displays.push(SweepDisplay::capture(&capture.name.clone(), capture));
    let mut lab = Sweep::bundled(displays);
    lab.rates = vec![60.0];
    lab.integrators = vec![Integrator::VelocityVerlet];
    assert_eq!(lab.subjects, Subject::ALL.to_vec());
    let rows = lab.run().unwrap();
    let ranking = choose_all(&rows, 60.0, Integrator::VelocityVerlet);
    let best = &ranking[0];
    assert!(best.admissible, "{ranking:?}");
    assert_eq!(
        (best.policy, best.mode),
        (DEFAULT_POLICY.name(), DEFAULT_DRAW),
        "the sweep chose {} with {}; update pacing::DEFAULT_POLICY and DEFAULT_DRAW",
        best.policy,
        best.mode.name()
    );
    // What the defaults' docs and issue 40's goals claim, display by display (models and the
    // capture), with the plain accumulator; each figure the worse of the phases.
    use volley_lab::pacing::ModeMetrics;
    for subject in Subject::ALL {
        let mut displays: Vec<(&str, bool, bool)> = Vec::new();
        for r in rows.iter().filter(|r| r.subject == subject) {
            if !displays.iter().any(|(d, ..)| *d == r.display) {
                displays.push((&r.display, r.metrics.recovery.is_some(), r.capture));
            }
        }
        for (name, hitch, capture) in displays {
            let worst = |mode, f: fn(&ModeMetrics) -> f64| {
                rows.iter()
                    .filter(|r| r.subject == subject && r.display == name)
                    .filter(|r| r.policy == "accumulator")
                    .map(|r| f(r.metrics.mode(mode)))
                    .fold(0.0, f64::max)
            };
            let what = format!("{} on {name}", subject.name());
            // Never a frame drawn inside a surface.
            let inside = |mode| worst(mode, |m| m.inside_frames as f64);
            assert_eq!(inside(DEFAULT_DRAW), 0.0, "{what}");
            let (p99, near) = (
                |m: &ModeMetrics| m.error.p99,
                |m: &ModeMetrics| m.error_near.p99,
            );
            match subject {
                // Smooth motion: no worse than predict by more than 5 % (it is predict there),
                // and better than interpolation on every model.
                Subject::Orbit | Subject::Shot => {
                    assert!(
                        worst(DEFAULT_DRAW, p99) <= 1.05 * worst(DrawMode::Predict, p99),
                        "{what}"
                    );
                    if !capture {
                        assert!(
                            worst(DEFAULT_DRAW, p99) < worst(DrawMode::Interpolate, p99),
                            "{what}"
                        );
                    }
                }
                // Through impacts: the frames around each one at most half predict's p99
                // error, except on a display with a hitch (a frame over four times the median,
                // `Metrics::recovery`: 60-hitch and the capture), whose frames near an impact
                // are off by the hitch for every draw (metres): there no worse than predict.
                Subject::Bounce | Subject::BounceHalf | Subject::Wall | Subject::Target => {
                    // The models run a minute and reach it; a capture may be too short to.
                    assert!(
                        capture || inside(DrawMode::Predict) > 0.0,
                        "{what}: must reach a surface"
                    );
                    let (ours, predict) =
                        (worst(DEFAULT_DRAW, near), worst(DrawMode::Predict, near));
                    let limit = if hitch { predict } else { 0.5 * predict };
                    assert!(
                        ours <= limit,
                        "{what}: {} vs predict's {} mm",
                        ours * 1e3,
                        predict * 1e3
                    );
                }
                // An input cannot be foreseen: it mispredicts as predict does.
                Subject::Command => {
                    assert_eq!(
                        worst(DEFAULT_DRAW, near),
                        worst(DrawMode::Predict, near),
                        "{what}"
                    );
                }
            }
        }
    }
}

/// A small sweep: two displays, two rates, every policy, one integrator and subject, both
/// phases (40 jobs).
fn small_sweep() -> volley_lab::pacing::Sweep {
    use volley_lab::pacing::{Sweep, SweepDisplay};
    let displays = ["59.94", "144"]
        .iter()
        .map(|n| SweepDisplay::model(n, &DisplayModel::named(n).unwrap(), 5.0))
        .collect();
    let mut sweep = Sweep::bundled(displays);
    sweep.rates = vec![60.0, 64.0];
    sweep.integrators = vec![Integrator::VelocityVerlet];
    sweep.subjects = vec![Subject::Orbit];
    sweep
}

#[test]
fn a_sweep_in_shards_merges_to_the_one_machine_rows() {
    use volley_lab::pacing::shard::{PacingShard, merge};
    use volley_lab::study::Shard;
    let sweep = small_sweep();
    let whole = sweep.run().unwrap();
    assert_eq!(whole.len(), 2 * 2 * 5 * 2);
    // Three shards of 40 jobs, through their files' text (every float back to the bit).
    let parts: Vec<(String, PacingShard)> = (0..3)
        .map(|index| {
            let part = PacingShard::run(&sweep, Shard { index, count: 3 }).unwrap();
            let name = format!("p{index}.json");
            let back = PacingShard::from_json(&part.to_json(), &name).unwrap();
            assert_eq!(back, part);
            (name, back)
        })
        .collect();
    // In any order.
    let shuffled = vec![parts[2].clone(), parts[0].clone(), parts[1].clone()];
    assert_eq!(merge(&shuffled).unwrap(), whole);
    let err = merge(&[parts[0].clone(), parts[2].clone()]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "missing shard 1/3: the files given hold shards 0, 2 of 3 (numbered from 0)"
    );
    let err = merge(&[parts[0].clone(), parts[0].clone()]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "p0.json: shard 0/3 given twice (also p0.json)"
    );
    // A row moved to another job's number is refused by the reader, naming the job.
    let mut forged = parts[1].1.clone();
    forged.rows[0].1.policy = "snap".into();
    let err = PacingShard::from_json(&forged.to_json(), "forged.json").unwrap_err();
    assert!(
        err.to_string()
            .starts_with("forged.json: rows: job 1 should be 59.94 at 60 Hz"),
        "{err}"
    );
}
