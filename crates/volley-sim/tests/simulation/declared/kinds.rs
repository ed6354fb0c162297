//! The other conditions against closed forms (downrange, speed, closest approach), Mach 1 on the
//! rifle against its own function, and events that watch without changing the run.

use super::*;
use volley_sim::{EventCondition, EventSpec, Integrator, state_hash};

/// The schemes exact under constant force.
const EXACT_UNDER_GRAVITY: [Integrator; 7] = [
    Integrator::VelocityVerlet,
    Integrator::Midpoint,
    Integrator::Rk4,
    Integrator::Exact,
    Integrator::ForestRuth,
    Integrator::Dopri5,
    Integrator::ImplicitMidpoint,
];

#[test]
fn a_downrange_distance_along_the_azimuth_is_reached_at_its_distance_over_the_horizontal_speed() {
    // Launcher at (5, -3, 1.5) aiming 30 degrees left of +x; the body flies along the azimuth
    // at 40 m/s horizontally, 15 m/s up: 100 m downrange at 2.5 s, whatever gravity does.
    let az = 30f64.to_radians();
    let (c, s) = (az.cos(), az.sin());
    for integrator in EXACT_UNDER_GRAVITY {
        let scene = parse(&format!(
            "Scene(dt: 0.016666667, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
                   launcher: (position: (5, -3, 1.5), speed: 10, elevation_deg: 0, azimuth_deg: 30),
                   bodies: [(mass: 1, position: (5, -3, 1.5),
                             launch: Velocity(({:?}, {:?}, 15)))],
                   events: [(when: Downrange(100.0))])",
            40.0 * c,
            40.0 * s
        ));
        let seen = run(&scene, 200);
        assert_eq!(seen.len(), 1, "{integrator}: {seen:?}");
        assert!((seen[0].time - 2.5).abs() < 1e-9, "{integrator}: {seen:?}");
        assert_eq!(seen[0].direction, EventDirection::Rising);
        let p = seen[0].state.p;
        let along = (p.x - 5.0) * c + (p.y + 3.0) * s;
        assert!((along - 100.0).abs() < 1e-9, "{integrator}: {p}");
        let z = 1.5 + 15.0 * 2.5 - 0.5 * 9.81 * 2.5 * 2.5;
        assert!((p.z - z).abs() < 1e-9, "{integrator}: {p}");
    }
}

#[test]
fn a_speed_is_passed_down_and_up_where_the_vertical_speed_makes_it() {
    // |V|^2 = 10^2 + (20 - g t)^2 = 15^2: 20 - g t = +-sqrt(125), slowing on the way up,
    // speeding up on the way down.
    let g = 9.81f64;
    let roots = [(20.0 - 125f64.sqrt()) / g, (20.0 + 125f64.sqrt()) / g];
    for integrator in EXACT_UNDER_GRAVITY {
        let scene = parse(&format!(
            "Scene(dt: 0.016666667, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
                   bodies: [(mass: 2, position: (0, 0, 0), launch: Velocity((10, 0, 20)))],
                   events: [(when: Speed(15.0))])"
        ));
        let seen = run(&scene, 300);
        assert_eq!(seen.len(), 2, "{integrator}: {seen:?}");
        for (s, t) in seen.iter().zip(roots) {
            assert!((s.time - t).abs() < 1e-9, "{integrator}: {} vs {t}", s.time);
            assert!(((s.state.mv / 2.0).length() - 15.0).abs() < 1e-9);
        }
        assert_eq!(seen[0].direction, EventDirection::Falling);
        assert_eq!(seen[1].direction, EventDirection::Rising);
    }
}

#[test]
fn the_closest_approach_to_a_moving_point_is_where_their_relative_velocity_is_square_to_them() {
    // No force: the body from the origin at (10, 0, 2) m/s, the point from (50, 5, 0) at
    // (-10, 0, 0) m/s. Relative position r(t) = (-50 + 20 t, -5, 2 t), relative velocity
    // (20, 0, 2): r . w = 0 at t = 1000 / 404.
    let t = 1000.0 / 404.0;
    for integrator in Integrator::ALL {
        let scene = parse(&format!(
            "Scene(dt: 0.01, integrator: {integrator:?},
                   bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((10, 0, 2)))],
                   events: [(when: Closest(point: (50, 5, 0), velocity: (-10, 0, 0)),
                             direction: Rising)])"
        ));
        let seen = run(&scene, 400);
        assert_eq!(seen.len(), 1, "{integrator}: {seen:?}");
        assert!((seen[0].time - t).abs() < 1e-9, "{integrator}: {seen:?}");
        let p = seen[0].state.p;
        assert!((p.x - 10.0 * t).abs() < 1e-9 && (p.z - 2.0 * t).abs() < 1e-9);
    }
}

#[test]
fn the_closest_approach_under_gravity_matches_the_cubic_of_the_closed_form() {
    // p(t) = (30 t, 0, 20 t - g t^2 / 2) past the point (40, 0, 15): g(t) = (p - c) . V is a
    // cubic, its rising root found here by bisection of the closed form to rounding.
    let gz = 9.81f64;
    let f = |t: f64| {
        let (px, pz) = (30.0 * t, 20.0 * t - 0.5 * gz * t * t);
        let (vx, vz) = (30.0, 20.0 - gz * t);
        (px - 40.0) * vx + (pz - 15.0) * vz
    };
    let (mut lo, mut hi) = (0.5f64, 2.0f64);
    assert!(f(lo) < 0.0 && f(hi) > 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    for integrator in EXACT_UNDER_GRAVITY {
        let scene = parse(&format!(
            "Scene(dt: 0.016666667, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
                   bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((30, 0, 20)))],
                   events: [(when: Closest(point: (40, 0, 15)), direction: Rising)])"
        ));
        let seen = run(&scene, 150);
        assert_eq!(seen.len(), 1, "{integrator}: {seen:?}");
        assert!(
            (seen[0].time - lo).abs() < 1e-9,
            "{integrator}: {} vs {lo}",
            seen[0].time
        );
    }
}

#[test]
fn the_rifle_goes_subsonic_once_where_its_mach_function_is_zero() {
    // The bundled rifle: Mach drag in the standard atmosphere with a crosswind. No closed form;
    // the event must be the one tick whose ends straddle Mach 1, and its state on Mach 1.
    let rifle = volley_sim::bundled_scene("rifle")
        .unwrap()
        .edit()
        .event(EventSpec::new(EventCondition::Mach(1.0)).falling())
        .build()
        .unwrap();
    let mut world = World::new(&rifle);
    let set = world.declared_events().clone();
    let inv_m = 1.0 / 0.0109;
    let mach = |w: &World| {
        let b = w.bodies();
        let s = BodyState {
            p: b.positions().get(0),
            mv: b.momenta().get(0),
        };
        set.value(0, w.time() - rifle.start_time(), &s, inv_m)
    };
    let mut seen = Vec::new();
    let mut straddle = None;
    for _ in 0..144 {
        let before = mach(&world);
        world.step().unwrap();
        if world.bodies().is_empty() {
            break;
        }
        if before > 0.0 && mach(&world) <= 0.0 {
            straddle = Some(world.tick());
        }
        seen.extend(world.events().iter().filter_map(declared));
    }
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert_eq!(Some(seen[0].tick), straddle);
    assert_eq!(seen[0].direction, EventDirection::Falling);
    let at = set.value(0, seen[0].time - rifle.start_time(), &seen[0].state, inv_m);
    assert!(at.abs() < 1e-12, "Mach - 1 = {at}");
}

#[test]
fn declared_events_watch_without_changing_the_run() {
    // The same scene with and without events, every integrator, drag and a ground: the same
    // bits at every tick (no stop is declared, so nothing is counted).
    for integrator in Integrator::ALL {
        let base = format!(
            "Scene(dt: 0.02, integrator: {integrator:?},
                   forces: [Gravity((0, 0, -9.81)), LinearDrag(0.05)],
                   ground: (restitution: 0.5),
                   bodies: [(mass: 1, radius: 0.1, position: (0, 0, 1), launch: Velocity((12, 3, 9))),
                            (mass: 2, radius: 0.1, position: (1, 0, 4), launch: Velocity((-4, 0, 1)))]"
        );
        let plain = parse(&format!("{base})"));
        let watched = parse(&format!(
            "{base}, events: [(when: Apex), (when: Altitude(2.0)), (when: Speed(10.0)),
                              (when: Closest(point: (5, 1, 1))), (when: Downrange(7.0))])"
        ));
        let (mut a, mut b) = (World::new(&plain), World::new(&watched));
        let mut reported = 0;
        for _ in 0..150 {
            a.step().unwrap();
            b.step().unwrap();
            assert_eq!(
                state_hash(&a),
                state_hash(&b),
                "{integrator} at tick {}",
                a.tick()
            );
            assert_eq!(a.force_evals(), b.force_evals(), "{integrator}");
            reported += b.events().iter().filter_map(declared).count();
        }
        assert!(reported >= 6, "{integrator}: {reported} events");
    }
}

#[test]
fn bad_declarations_are_one_line_naming_the_field() {
    let scene = |forces: &str, events: &str| {
        volley_sim::parse_scene(
            &format!(
                "Scene(dt: 0.01, integrator: Rk4, forces: [{forces}], targets: [(center: (10, 0, 1), radius: 0.5)],
                       bodies: [(mass: 1, position: (0, 0, 1))], events: [{events}])"
            ),
            "s.ron",
            "s",
        )
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    let cases = [
        (
            "",
            "(when: Plane(point: (0, 0, 0), normal: (0, 0, 0)))",
            "events[0].when.normal",
        ),
        (
            "",
            "(when: Apex), (when: ClosestToTarget(3))",
            "events[1].when",
        ),
        (
            "Gravity((0, 0, -9.81))",
            "(when: Mach(1.0))",
            "events[0].when",
        ),
        ("", "(when: Mach(0.0))", "events[0].when"),
        ("", "(when: Speed(-1.0))", "events[0].when"),
        ("", "(when: Apex, stop: Body(0))", "events[0].stop"),
        ("", "(when: Altitude(NaN))", "events[0].when"),
        (
            "",
            "(when: Closest(point: (0, 0, inf)))",
            "events[0].when.point",
        ),
        ("", "(when: Apex, direction: Up)", "event direction"),
    ];
    for (forces, events, field) in cases {
        let e = scene(forces, events);
        assert!(e.starts_with("s.ron"), "{events}: {e}");
        assert!(e.contains(field), "{events}: {e}");
        assert_eq!(e.lines().count(), 1, "{events}: {e}");
    }
    assert!(scene("Gravity((0, 0, -9.81))", "(when: Mach(1.0))").contains("MachDrag"));
    assert!(scene("", "(when: ClosestToTarget(3))").contains("got 3: it has 1"));
}
