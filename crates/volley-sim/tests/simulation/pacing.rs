//! The loop lab's policies and displays, driven through the real loop: what a policy may change
//! (ticks per frame, where a frame is drawn) and what it may not (any tick's state).

use std::time::Duration;

use volley_sim::clock::LoopPolicy;
use volley_sim::pacing::{DisplayModel, DrawMode, RunConfig, Subject, run};
use volley_sim::sim_loop::TickObserver;
use volley_sim::{Integrator, ObserverError, SimLoop, World, hash};

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
