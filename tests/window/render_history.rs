//! What the renderer reads from the loop: the interpolated positions, the trail ring and the
//! closed-form references. No GPU needed.

use std::time::Duration;

use glam::DVec3;
use volley::clock::VirtualClock;
use volley::render::reference::ReferenceEnd;
use volley::render::trails::TRAIL_SAMPLES;
use volley::render::{BodyError, TickHistory};
use volley::{Command, SimLoop, World, scene};

/// A body moving at 4 m/s along x with no forces, at h = 62.5 ms: every position is a multiple
/// of 0.25 m, exact in binary, so drawn positions can be compared with `==`.
fn drifting() -> World {
    let text = "Scene(dt: 0.0625, integrator: SemiImplicitEuler,
                      bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((4, 0, 0)))])";
    World::new(&scene::parse(text, "drift.ron", "drift").unwrap())
}

fn drawn(history: &TickHistory, world: &World, alpha: f64) -> Vec<DVec3> {
    let mut out = Vec::new();
    history.interpolate(world, alpha, |_, p| out.push(p));
    out
}

#[test]
fn a_frame_of_several_ticks_interpolates_from_the_state_before_its_last_tick() {
    let mut sim = SimLoop::new(drifting());
    let mut history = TickHistory::new(&sim.world, DVec3::ZERO);
    // 3.5 ticks of time (under the 250 ms clamp): ticks 0 -> 3 run in this one frame, half a
    // tick stays behind.
    let ticks = sim
        .frame(Duration::from_micros(218_750), &mut history)
        .unwrap();
    assert_eq!((ticks.steps, ticks.alpha), (3, 0.5));
    assert_eq!(history.previous_tick(), 2);
    // Between tick 2 (x = 0.5) and tick 3 (x = 0.75), not between the frame's first and last.
    assert_eq!(
        drawn(&history, &sim.world, ticks.alpha),
        [DVec3::new(0.625, 0.0, 0.0)]
    );
}

#[test]
fn a_frame_with_no_tick_keeps_interpolating_between_the_same_two_states() {
    let mut sim = SimLoop::new(drifting());
    let mut history = TickHistory::new(&sim.world, DVec3::ZERO);
    sim.frame(Duration::from_micros(62_500), &mut history)
        .unwrap();
    let ticks = sim
        .frame(Duration::from_micros(46_875), &mut history)
        .unwrap();
    assert_eq!((ticks.steps, ticks.alpha), (0, 0.75));
    assert_eq!(
        drawn(&history, &sim.world, ticks.alpha),
        [DVec3::new(0.1875, 0.0, 0.0)]
    );
}

#[test]
fn a_body_the_snapshot_never_saw_is_drawn_at_its_current_position() {
    let mut world = drifting();
    let history = TickHistory::new(&world, DVec3::ZERO);
    world
        .apply(&Command::Spawn(volley::scene::BodySpec {
            mass: 1.0,
            radius: 0.1,
            position: DVec3::new(5.0, 0.0, 0.0),
            velocity: DVec3::new(0.0, 4.0, 0.0),
            spin: Default::default(),
        }))
        .unwrap();
    world.step().unwrap();
    let positions = drawn(&history, &world, 0.5);
    assert_eq!(positions[0], DVec3::new(0.125, 0.0, 0.0), "interpolated");
    assert_eq!(
        positions[1],
        DVec3::new(5.0, 0.25, 0.0),
        "current, no previous position"
    );
}

#[test]
fn the_trail_ring_holds_one_sample_per_tick_up_to_its_length() {
    let mut sim = SimLoop::new(drifting());
    let mut history = TickHistory::new(&sim.world, DVec3::new(1.0, 0.0, 0.0));
    assert_eq!(history.trails.count(0), 1, "the starting position");
    sim.run_until(
        3,
        &mut VirtualClock::Steady(Duration::from_micros(62_500)),
        &mut history,
    )
    .unwrap();
    assert_eq!(history.trails.count(0), 4);
    // Newest first, relative to the origin (1, 0, 0): x = 0.75 - 1, then 0.5 - 1.
    assert_eq!(history.trails.sample(0, 0), [-0.25, 0.0, 0.0, 0.0]);
    assert_eq!(history.trails.sample(0, 1), [-0.5, 0.0, 0.0, 0.0]);
    let far = TRAIL_SAMPLES as u64 + 10;
    sim.run_until(
        far,
        &mut VirtualClock::Steady(Duration::from_micros(62_500)),
        &mut history,
    )
    .unwrap();
    assert_eq!(history.trails.count(0), TRAIL_SAMPLES as u32);
}

#[test]
fn a_reset_restarts_every_trail_and_reference() {
    let mut sim = SimLoop::new(drifting());
    let mut history = TickHistory::new(&sim.world, DVec3::ZERO);
    let mut clock = VirtualClock::Steady(Duration::from_micros(62_500));
    sim.run_until(5, &mut clock, &mut history).unwrap();
    sim.push(Command::Reset);
    sim.run_until(6, &mut clock, &mut history).unwrap();
    // The reset body is a new id: its reference starts at tick 5, where it was spawned, and its
    // trail with the first tick it ran (one sample, after tick 6), not where the old one was.
    assert_eq!(history.trails.count(0), 1);
    assert_eq!(history.trails.sample(0, 0), [0.25, 0.0, 0.0, 0.0]);
    let id = sim.world.bodies().ids()[0];
    assert_eq!(history.references.get(id).unwrap().spawn_tick, 5);
    assert_eq!(
        history.references.all().len(),
        1,
        "the old body's reference is gone"
    );
}

/// The seed's projectile under explicit Euler at h = 0.2 s.
fn seed() -> (SimLoop, TickHistory) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/seed.ron");
    let sim = SimLoop::new(World::new(&scene::load(&path).unwrap()));
    let history = TickHistory::new(&sim.world, DVec3::ZERO);
    (sim, history)
}

#[test]
fn explicit_euler_drifts_from_the_closed_form_by_g_n_h_squared_over_two() {
    let (mut sim, mut history) = seed();
    let mut clock = VirtualClock::Steady(Duration::from_millis(200));
    for n in 1..=5u64 {
        sim.run_until(n, &mut clock, &mut history).unwrap();
        let BodyError::Measured { position, velocity } = history.references.error(&sim.world, 0)
        else {
            panic!("no error measured at tick {n}");
        };
        // Under constant force explicit Euler ends g T h / 2 = g n h^2 / 2 high and its velocity
        // is exact (0.1962 m per tick at h = 0.2, the seed's truncation error). The positions
        // are about 10 m: rounding leaves differences of a few 1e-15 m.
        let expected = 9.81 * n as f64 * 0.2 * 0.2 / 2.0;
        assert!(
            (position - expected).abs() < 1e-12,
            "tick {n}: {position} vs {expected}"
        );
        assert!(velocity < 1e-12, "tick {n}: velocity error {velocity}");
    }
}

#[test]
fn a_reference_ends_at_the_first_impact() {
    let (mut sim, mut history) = seed();
    let mut clock = VirtualClock::Steady(Duration::from_millis(200));
    // Step until the projectile first hits the ground (explicit Euler's arc, above the exact
    // one, lands after tick 27).
    let impact = (1..200)
        .find_map(|n| {
            sim.run_until(n, &mut clock, &mut history).unwrap();
            sim.world.events().iter().find_map(|e| match e.kind {
                volley::EventKind::Impact { .. } => Some((e.tick, e.time)),
                _ => None,
            })
        })
        .expect("the projectile lands");
    assert_eq!(
        history.references.error(&sim.world, 0),
        BodyError::Ended(ReferenceEnd::Contact {
            tick: impact.0,
            time: impact.1
        })
    );
}

#[test]
fn switching_a_force_ends_the_references() {
    let (mut sim, mut history) = seed();
    let mut clock = VirtualClock::Steady(Duration::from_millis(200));
    sim.run_until(2, &mut clock, &mut history).unwrap();
    sim.push(Command::SetForce {
        kind: volley::ForceKind::Gravity,
        enabled: false,
    });
    sim.run_until(3, &mut clock, &mut history).unwrap();
    assert_eq!(
        history.references.error(&sim.world, 0),
        BodyError::Ended(ReferenceEnd::ForcesChanged { tick: 2 })
    );
}
