//! The fixed-timestep clock, driven by hand: every call's whole resulting state is asserted,
//! with no sleeping and no window (the habit of bevy_time's tests).

use std::time::Duration;

use volley_sim::internals::clock::{FixedClock, FrameSource, FrameTicks, VirtualClock};
use volley_sim::internals::hash::state_hash;
use volley_sim::internals::scene;
use volley_sim::internals::world::SplitMix64;
use volley_sim::{SimLoop, World};

const MS: Duration = Duration::from_millis(1);

/// The clock's observable state: (tick, accumulator, dropped, alpha).
fn state(c: &FixedClock) -> (u64, Duration, Duration, f64) {
    (c.tick(), c.accumulator(), c.dropped(), c.alpha())
}

#[test]
fn whole_steps_come_out_and_the_fraction_stays() {
    let mut c = FixedClock::new(10 * MS);
    assert_eq!(state(&c), (0, Duration::ZERO, Duration::ZERO, 0.0));
    let f = c.advance(25 * MS);
    assert_eq!(
        f,
        FrameTicks {
            steps: 2,
            alpha: 0.5,
            dropped: Duration::ZERO
        }
    );
    assert_eq!(state(&c), (2, 5 * MS, Duration::ZERO, 0.5));
    let f = c.advance(4 * MS);
    assert_eq!(
        f,
        FrameTicks {
            steps: 0,
            alpha: 0.9,
            dropped: Duration::ZERO
        }
    );
    assert_eq!(state(&c), (2, 9 * MS, Duration::ZERO, 0.9));
    let f = c.advance(MS);
    assert_eq!(
        f,
        FrameTicks {
            steps: 1,
            alpha: 0.0,
            dropped: Duration::ZERO
        }
    );
    assert_eq!(state(&c), (3, Duration::ZERO, Duration::ZERO, 0.0));
    assert_eq!(c.elapsed(), 30 * MS);
}

#[test]
fn a_five_second_hitch_is_clamped_then_capped_and_the_loss_is_counted() {
    let mut c = FixedClock::new(10 * MS);
    c.advance(5 * MS);
    // 5 s is clamped to 250 ms (4.75 s dropped); 255 ms is 25 steps, the cap runs 8 and drops
    // 17 whole steps (170 ms); the 5 ms fraction stays for interpolation.
    let f = c.advance(Duration::from_secs(5));
    assert_eq!(f.steps, 8);
    assert_eq!(f.dropped, Duration::from_millis(4750 + 170));
    assert_eq!(state(&c), (8, 5 * MS, Duration::from_millis(4920), 0.5));
    // No spiral: the next normal frame runs the normal number of steps.
    let f = c.advance(10 * MS);
    assert_eq!((f.steps, f.dropped), (1, Duration::ZERO));
    assert_eq!(state(&c), (9, 5 * MS, Duration::from_millis(4920), 0.5));
}

#[test]
fn clamp_and_cap_are_settings() {
    let mut c = FixedClock::new(10 * MS);
    c.max_frame_delta = Duration::from_secs(1);
    c.max_steps_per_frame = 100;
    let f = c.advance(Duration::from_millis(999));
    assert_eq!((f.steps, f.dropped), (99, Duration::ZERO));
    assert_eq!(state(&c), (99, 9 * MS, Duration::ZERO, 0.9));
}

#[test]
fn pause_ignores_frame_time_and_single_step_runs_exactly_one_tick() {
    let mut c = FixedClock::new(10 * MS);
    c.advance(15 * MS);
    c.pause();
    assert!(c.is_paused());
    let f = c.advance(Duration::from_secs(3));
    assert_eq!((f.steps, f.dropped), (0, Duration::ZERO));
    assert_eq!(state(&c), (1, 5 * MS, Duration::ZERO, 0.5));
    c.single_step();
    assert_eq!(c.advance(Duration::ZERO).steps, 1);
    assert_eq!(c.advance(100 * MS).steps, 0, "one request, one tick");
    assert_eq!(state(&c), (2, 5 * MS, Duration::ZERO, 0.5));
    c.resume();
    assert_eq!(c.advance(5 * MS).steps, 1);
    assert_eq!(state(&c), (3, Duration::ZERO, Duration::ZERO, 0.0));
}

#[test]
fn single_step_while_running_pauses_first() {
    let mut c = FixedClock::new(10 * MS);
    c.single_step();
    assert!(c.is_paused());
    assert_eq!(c.advance(50 * MS).steps, 1);
}

#[test]
fn time_scale_stretches_frame_time_and_rejects_nonsense() {
    let mut c = FixedClock::new(10 * MS);
    c.set_time_scale(0.5).unwrap();
    assert_eq!(c.advance(30 * MS).steps, 1);
    assert_eq!(state(&c), (1, 5 * MS, Duration::ZERO, 0.5));
    c.set_time_scale(2.0).unwrap();
    assert_eq!(c.advance(10 * MS).steps, 2);
    assert_eq!(state(&c), (3, 5 * MS, Duration::ZERO, 0.5));
    for bad in [-1.0, f64::NAN, f64::INFINITY, 1000.0] {
        let err = c.set_time_scale(bad).unwrap_err();
        assert!(
            matches!(err, volley_sim::internals::clock::ClockError::TimeScale(x) if x.to_bits() == bad.to_bits()),
            "{bad}"
        );
        assert_eq!(err.to_string(), "time scale must be a number from 0 to 100");
    }
    assert_eq!(c.time_scale(), 2.0);
}

#[test]
fn sim_time_is_exactly_tick_times_dt_after_ten_million_ticks() {
    // 1/60 s in whole nanoseconds. An f32 running sum of 1/60 would be off by seconds here.
    let dt = Duration::from_nanos(16_666_667);
    let mut c = FixedClock::new(dt);
    for _ in 0..10_000_000u32 {
        c.advance(dt);
    }
    assert_eq!(c.tick(), 10_000_000);
    assert_eq!(c.elapsed(), Duration::from_nanos(16_666_667 * 10_000_000));
    assert_eq!(c.accumulator(), Duration::ZERO);

    let text = "Scene(dt: 0.016666666666666666, integrator: Exact)";
    let scene = scene::parse(text, "inline.ron", "inline").unwrap();
    let mut world = World::new(&scene);
    for _ in 0..10_000_000u32 {
        world.step().unwrap();
    }
    assert_eq!(world.tick(), 10_000_000);
    // One multiplication of the exact tick count by h: the same bits as computing it directly.
    assert_eq!(world.time(), 10_000_000.0 * 16_666_667e-9);
}

/// The bounce scene has impacts, rests and a wall: everything a tick can do.
fn hash_after(ticks: u64, source: &mut impl FrameSource) -> (u64, u64) {
    let scene = scene::load(&crate::support::ws("assets/scenes/bounce.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.run_until(ticks, source, &mut ()).unwrap();
    (sim.world.tick(), state_hash(&sim.world))
}

#[test]
fn the_state_after_n_ticks_does_not_depend_on_the_frame_deltas() {
    let ticks = 700;
    let reference = hash_after(ticks, &mut VirtualClock::display(60.0));
    let sources = [
        ("144 Hz", VirtualClock::display(144.0)),
        ("30 Hz", VirtualClock::display(30.0)),
        (
            "jitter",
            VirtualClock::Jitter {
                base: 12 * MS,
                spread: 11 * MS,
                rng: SplitMix64(99),
            },
        ),
        (
            "one 5 s hitch",
            VirtualClock::Hitch {
                base: Duration::from_nanos(16_666_667),
                at: 100,
                length: Duration::from_secs(5),
                frame: 0,
            },
        ),
        (
            "script",
            VirtualClock::Script {
                deltas: vec![Duration::ZERO, 70 * MS, 3 * MS, 250 * MS],
                next: 0,
            },
        ),
    ];
    for (name, mut source) in sources {
        assert_eq!(hash_after(ticks, &mut source), reference, "{name}");
    }
}

#[test]
fn a_run_stops_exactly_at_its_tick_and_keeps_the_rest_for_later() {
    let scene = scene::load(&crate::support::ws("assets/scenes/bounce.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    // 250 ms frames grant 8 ticks at a time (the cap); stopping at 20 returns 4 of the third.
    sim.run_until(20, &mut VirtualClock::Steady(250 * MS), &mut ())
        .unwrap();
    assert_eq!(sim.world.tick(), 20);
    assert_eq!(sim.clock.tick(), 20);
}

#[test]
fn a_frame_stopped_by_a_failing_command_gives_back_the_ticks_it_did_not_run() {
    let scene = scene::load(&crate::support::ws("assets/scenes/bounce.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(
        volley_sim::internals::command::parse_script("2: despawn 99\n", "script.txt").unwrap(),
    );
    // One 250 ms frame is 14 whole 1/60 s ticks: the cap grants 8 (dropping 6) and the command
    // due before the third fails.
    let err = sim.frame(250 * MS, &mut ()).unwrap_err();
    assert!(
        matches!(err, volley_sim::LoopError::Command { tick: 2, .. }),
        "{err}"
    );
    assert_eq!(sim.world.tick(), 2);
    assert_eq!(
        sim.clock.tick(),
        2,
        "the six unrun ticks are back in the accumulator"
    );
    assert_eq!(
        sim.clock.dropped(),
        6 * scene.timestep(),
        "only the cap's drop; the failure drops nothing"
    );
}
