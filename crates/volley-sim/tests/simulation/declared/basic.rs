//! One behaviour each: the times and states against closed forms.

use super::*;
use volley_sim::Integrator;

/// The schemes exact under constant force, which the 1e-9 s goal is for.
const EXACT_UNDER_GRAVITY: [Integrator; 7] = [
    Integrator::VelocityVerlet,
    Integrator::Midpoint,
    Integrator::Rk4,
    Integrator::Exact,
    Integrator::ForestRuth,
    Integrator::Dopri5,
    Integrator::ImplicitMidpoint,
];

/// A shot at 20 m/s up and 10 m/s across from z = 0 under g = 9.81, at 60 Hz.
fn shot(integrator: Integrator, events: &str) -> Scene {
    parse(&format!(
        "Scene(dt: 0.016666667, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
               bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((10, 0, 20)))],
               events: [{events}])"
    ))
}

#[test]
fn an_altitude_is_crossed_up_and_down_at_the_roots_of_its_quadratic() {
    // z = 20 t - 4.905 t^2 = 15: t = (20 -+ sqrt(400 - 4 * 4.905 * 15)) / (2 * 4.905).
    let (g, vz, z) = (9.81f64, 20.0f64, 15.0f64);
    let disc = (vz * vz - 2.0 * g * z).sqrt();
    let roots = [(vz - disc) / g, (vz + disc) / g];
    for integrator in EXACT_UNDER_GRAVITY {
        let seen = run(&shot(integrator, "(when: Altitude(15.0))"), 300);
        assert_eq!(seen.len(), 2, "{integrator}: {seen:?}");
        for (s, t) in seen.iter().zip(roots) {
            assert!((s.time - t).abs() < 1e-9, "{integrator}: {} vs {t}", s.time);
            assert!(
                (s.state.p.z - 15.0).abs() < 1e-9,
                "{integrator}: {:?}",
                s.state
            );
        }
        assert_eq!(seen[0].direction, EventDirection::Rising);
        assert_eq!(seen[1].direction, EventDirection::Falling);
    }
}

#[test]
fn the_apex_is_at_vz_over_g() {
    for integrator in EXACT_UNDER_GRAVITY {
        let seen = run(&shot(integrator, "(when: Apex)"), 300);
        assert_eq!(seen.len(), 1, "{integrator}: {seen:?}");
        let t = 20.0 / 9.81;
        assert!(
            (seen[0].time - t).abs() < 1e-9,
            "{integrator}: {}",
            seen[0].time
        );
        assert_eq!(seen[0].direction, EventDirection::Falling);
        let top = 20.0 * 20.0 / (2.0 * 9.81);
        assert!((seen[0].state.p.z - top).abs() < 1e-9);
    }
}

#[test]
fn two_crossings_inside_one_tick_are_both_found() {
    // At dt = 5 s the whole flight is one tick: z = 15 is crossed at 0.93 s and 3.15 s.
    let (g, vz, z) = (9.81f64, 20.0f64, 15.0f64);
    let disc = (vz * vz - 2.0 * g * z).sqrt();
    let roots = [(vz - disc) / g, (vz + disc) / g];
    for integrator in EXACT_UNDER_GRAVITY {
        let scene = parse(&format!(
            "Scene(dt: 5.0, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
                   bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((10, 0, 20)))],
                   events: [(when: Altitude(15.0))])"
        ));
        let seen = run(&scene, 1);
        assert_eq!(seen.len(), 2, "{integrator}: {seen:?}");
        for (s, t) in seen.iter().zip(roots) {
            assert_eq!(s.tick, 1);
            assert!((s.time - t).abs() < 1e-9, "{integrator}: {} vs {t}", s.time);
        }
    }
}

#[test]
fn a_root_exactly_on_a_tick_boundary_is_reported_once_by_the_tick_ending_on_it() {
    // 64 m/s at 64 Hz, no force: x = 64 t is exact in binary, and x = 9 m at 9/64 s, the end of
    // tick 9, exactly.
    for integrator in Integrator::ALL {
        let scene = parse(&format!(
            "Scene(dt: 0.015625, integrator: {integrator:?},
                   bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((64, 0, 0)))],
                   events: [(when: Plane(point: (9, 0, 0), normal: (1, 0, 0)))])"
        ));
        let seen = run(&scene, 20);
        assert_eq!(seen.len(), 1, "{integrator}: {seen:?}");
        assert!(
            (seen[0].time - 9.0 / 64.0).abs() <= 1e-15,
            "{integrator}: {seen:?}"
        );
        assert_eq!(seen[0].direction, EventDirection::Rising);
        // The tick that ends on it, or (a step ending an ulp short) the next.
        assert!([9, 10].contains(&seen[0].tick), "{integrator}: {seen:?}");
    }
}

#[test]
fn an_event_whose_function_is_zero_at_the_spawn_is_reported_once_at_the_spawn() {
    // Downrange 0 m is the muzzle; a level shot's apex is its first instant.
    for integrator in Integrator::ALL {
        let scene = parse(&format!(
            "Scene(dt: 0.01, start_time: 2.0, integrator: {integrator:?},
                   forces: [Gravity((0, 0, -9.81))],
                   bodies: [(mass: 1, position: (0, 0, 1), launch: Velocity((100, 0, 0)))],
                   events: [(when: Downrange(0.0)), (when: Apex)])"
        ));
        let seen = run(&scene, 30);
        assert_eq!(seen.len(), 2, "{integrator}: {seen:?}");
        for s in &seen {
            assert_eq!((s.tick, s.time), (1, 2.0), "{integrator}: {s:?}");
            assert!(!s.graze);
        }
        assert_eq!(seen[0].direction, EventDirection::Rising); // out past the muzzle
        assert_eq!(seen[1].direction, EventDirection::Falling); // over the top
    }
}

#[test]
fn a_tangent_graze_is_reported_once_where_the_path_touches() {
    // Up at 8 m/s under 16 m/s^2: the apex is z = 2 m at 0.5 s, exactly the altitude asked
    // for. Ticks of 0.3 s put the touch inside a tick, of 0.25 s on a boundary.
    for dt in [0.3, 0.25, 0.0625, 0.1] {
        for integrator in EXACT_UNDER_GRAVITY {
            let scene = parse(&format!(
                "Scene(dt: {dt}, integrator: {integrator:?}, forces: [Gravity((0, 0, -16))],
                       bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((1, 0, 8)))],
                       events: [(when: Altitude(2.0))])"
            ));
            let seen = run(&scene, (1.0 / dt) as u64 + 1);
            assert_eq!(seen.len(), 1, "{integrator} at {dt}: {seen:?}");
            assert!(
                (seen[0].time - 0.5).abs() < 1e-9,
                "{integrator} at {dt}: {seen:?}"
            );
            assert!((seen[0].state.p.z - 2.0).abs() < 1e-12);
        }
    }
}

#[test]
fn a_body_stopped_by_its_event_leaves_the_world_there() {
    let scene = parse(
        "Scene(dt: 0.01, integrator: Rk4,
               bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((10, 0, 0))),
                        (mass: 1, position: (0, 0, 0), launch: Velocity((-10, 0, 0)))],
               launcher: (position: (0, 0, 0), speed: 10, elevation_deg: 0, azimuth_deg: 0),
               events: [(when: Downrange(1.0), stop: Body(1)), (when: Downrange(2.0))])",
    );
    let mut world = World::new(&scene);
    let mut seen = Vec::new();
    for _ in 0..40 {
        world.step().unwrap();
        seen.extend(world.events().iter().filter_map(declared));
    }
    // Body 0 crosses 1 m at 0.1 s and is gone: it never reaches 2 m; body 1 flies on.
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert!((seen[0].time - 0.1).abs() < 1e-12);
    assert_eq!(world.bodies().ids(), [volley_sim::BodyId(1)]);
    assert!(world.stopped().is_none());
}

#[test]
fn the_run_stops_at_the_nth_occurrence_and_the_count_is_state() {
    // A ball bouncing elastically: its third apex stops the run.
    let text = "Scene(dt: 0.01, integrator: VelocityVerlet, forces: [Gravity((0, 0, -9.81))],
                      ground: (restitution: 1.0),
                      bodies: [(mass: 1, radius: 0.1, position: (0, 0, 2))],
                      events: [(when: Apex, direction: Falling, stop: Run(3))])";
    let scene = parse(text);
    let mut world = World::new(&scene);
    let mut apexes = 0;
    let mut counts = Vec::new();
    while world.stopped().is_none() && world.tick() < 2000 {
        world.step().unwrap();
        apexes += world.events().iter().filter_map(declared).count();
        counts.push(world.state().tallies.run.clone());
    }
    let stop = world.stopped().expect("the third apex stops the run");
    assert_eq!(apexes, 3);
    assert_eq!(stop.tick, world.tick());
    assert_eq!(world.state().tallies.run, [3]);
    // A stopped world steps no further.
    let (tick, hash) = (world.tick(), volley_sim::state_hash(&world));
    world.step().unwrap();
    assert_eq!((world.tick(), volley_sim::state_hash(&world)), (tick, hash));
    // The count is state: a world restored one tick after the first apex stops at the same
    // tick, and one restored with another count at another.
    let first = counts.iter().position(|c| c == &[1]).unwrap() as u64 + 1;
    let mut again = World::new(&scene);
    again.step_ticks(first).unwrap();
    let snapshot = again.snapshot();
    let mut restored = World::new(&scene);
    restored.restore(&snapshot).unwrap();
    while restored.stopped().is_none() && restored.tick() < 2000 {
        restored.step().unwrap();
    }
    assert_eq!(restored.stopped(), Some(stop));
    assert_eq!(volley_sim::state_hash(&restored), hash);
    let mut wrong = snapshot.clone();
    wrong.tallies.run = vec![2];
    let mut other = World::new(&scene);
    other.restore(&wrong).unwrap();
    assert_ne!(
        volley_sim::state_hash(&other),
        volley_sim::state_hash(&again)
    );
    while other.stopped().is_none() && other.tick() < 2000 {
        other.step().unwrap();
    }
    assert!(other.stopped().unwrap().tick < stop.tick);
}

#[test]
fn a_run_stopped_inside_a_tick_of_substeps_still_ends_that_tick() {
    // Four substeps of 0.075 s a tick: the apex at 2 s (20 m/s up under 10 m/s^2) falls in
    // the third of tick 7's (1.8 s to 2.1 s); the world stops at that tick's end, with the bits
    // of the same run without the event at that tick.
    let body = "bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((1, 0, 20)))]";
    let base = format!(
        "Scene(dt: 0.3, substeps: 4, integrator: Rk4, forces: [Gravity((0, 0, -10))], {body}"
    );
    let plain = parse(&format!("{base})"));
    let stopping = parse(&format!("{base}, events: [(when: Apex, stop: Run(1))])"));
    let mut world = World::new(&stopping);
    let mut free = World::new(&plain);
    while world.stopped().is_none() && world.tick() < 100 {
        world.step().unwrap();
        free.step().unwrap();
    }
    let stop = world.stopped().expect("the apex stops the run");
    assert!((stop.time - 2.0).abs() < 1e-9, "{stop}");
    assert_eq!((world.tick(), stop.tick), (7, 7));
    assert_eq!(free.tick(), world.tick());
    assert_eq!(
        volley_sim::state_hash(&world),
        volley_sim::state_hash(&free)
    );
}
