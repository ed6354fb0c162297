//! Hard cases 21 and 22: a grenade in a concave corner; a hit on a tick boundary. And two
//! faces met at the same instant.

use glam::DVec3;
use volley_sim::{BodySpec, EventKind, MeshGeometry, Scene, Surface, Transform};

use super::{allowed, events, impacts, load, with};

#[test]
fn a_grenade_rattles_into_the_corner_without_sinking_into_either_face() {
    let scene = load("hard/grenade_corner");
    // The floor's plane: through (2, y, 0) and (-2, y, 0.6), normal up and towards the wall.
    let n_floor = DVec3::new(0.6, 0.0, 4.0).normalize();
    let r = scene.bodies()[0].radius;
    for integrator in allowed(&scene) {
        let s = with(&scene, integrator);
        let mut sim = volley_sim::SimLoop::new(volley_sim::World::new(&s));
        let mut all = Vec::new();
        for tick in 1..=300u64 {
            let mut clock = volley_sim::internals::clock::VirtualClock::Steady(s.timestep());
            sim.run_until(tick, &mut clock, &mut ()).unwrap();
            let p = sim.world.bodies().positions().get(0);
            // Inside both faces (to rounding) at every tick: x <= 2 - r, above the floor by r.
            assert!(
                p.x <= 2.0 - r + 1e-9,
                "{integrator} tick {tick}: x = {}",
                p.x
            );
            assert!(
                n_floor.dot(p - DVec3::new(2.0, 0.0, 0.0)) >= r - 1e-9,
                "{integrator} tick {tick}: {p}"
            );
            all.extend(impacts(sim.world.events(), 0));
        }
        let wall: Vec<f64> = all
            .iter()
            .filter(|(_, s, _)| {
                matches!(
                    s,
                    Surface::Mesh {
                        triangle: 2 | 3,
                        ..
                    }
                )
            })
            .map(|(_, _, v)| *v)
            .collect();
        assert!(wall.len() >= 2, "{integrator}: {all:?}");
        // It rattles to rest: each blow on the wall is softer than the first.
        assert!(
            wall[1..].iter().all(|&v| v < wall[0]),
            "{integrator}: {wall:?}"
        );
    }
}

/// A corner of two faces, the floor z = 0 and the wall x = 2, as a mesh built in code.
fn corner() -> MeshGeometry {
    let v = vec![
        DVec3::new(-2.0, -2.0, 0.0),
        DVec3::new(2.0, -2.0, 0.0),
        DVec3::new(2.0, 2.0, 0.0),
        DVec3::new(-2.0, 2.0, 0.0),
        DVec3::new(2.0, -2.0, 2.0),
        DVec3::new(2.0, 2.0, 2.0),
    ];
    MeshGeometry::new(v, vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
}

#[test]
fn a_ball_meeting_both_faces_of_a_corner_at_once_comes_straight_back() {
    // No gravity, elastic: the ball reaches the floor and the wall at the same instant (its
    // centre 0.3 m from each, moving at 1 m/s towards both); the two impacts are resolved at
    // that instant, one after the other, and it leaves along (-1, 0, 1).
    let r = 0.1;
    let scene = Scene::builder("corner", 1.0 / 30.0)
        .mesh("corner", corner(), Transform::IDENTITY, 1.0)
        .body(BodySpec {
            mass: 1.0,
            radius: r,
            position: DVec3::new(2.0 - r - 0.3, 0.0, r + 0.3),
            velocity: DVec3::new(1.0, 0.0, -1.0),
            spin: DVec3::ZERO,
        })
        .build()
        .unwrap();
    for integrator in allowed(&scene) {
        let (events, world) = events(&with(&scene, integrator), 30);
        let hits = impacts(&events, 0);
        assert_eq!(hits.len(), 2, "{integrator}: {hits:?}");
        for (t, _, v) in &hits {
            assert!((t - 0.3).abs() < 1e-9, "{integrator}: {t}");
            assert!((v - 1.0).abs() < 1e-9, "{integrator}: {v}");
        }
        let v = world.velocity(0);
        assert!(
            (v - DVec3::new(-1.0, 0.0, 1.0)).length() < 1e-9,
            "{integrator}: {v}"
        );
    }
}

#[test]
fn a_hit_on_a_tick_boundary_is_found_once_in_the_tick_it_ends() {
    let scene = load("hard/tick_boundary");
    for integrator in allowed(&scene) {
        let (events, world) = events(&with(&scene, integrator), 20);
        let hits: Vec<_> = events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Impact { .. }))
            .collect();
        assert_eq!(hits.len(), 1, "{integrator}: {hits:?}");
        // x = 0.5 + 64 t reaches 9.5 at t = 9/64 s, the end of tick 9: found once, at that
        // instant to a few ulps of 1/64 s. The fixed-step integrators land on 9.5 exactly and
        // find it in tick 9 (a root at the end of a step is taken from its positive side);
        // Dormand-Prince's step ends an ulp short, and meets it at the start of tick 10.
        let tick = if integrator == volley_sim::Integrator::Dopri5 {
            10
        } else {
            9
        };
        assert_eq!(hits[0].tick, tick, "{integrator}");
        assert!(
            (hits[0].time - 9.0 / 64.0).abs() < 1e-15,
            "{integrator}: {}",
            hits[0].time
        );
        // Elastic, head on: back at 64 m/s, 20 ticks in at x = 9.5 - 64 (20 - 9) / 64 = -1.5.
        assert_eq!(
            world.velocity(0),
            DVec3::new(-64.0, 0.0, 0.0),
            "{integrator}"
        );
        let p = world.bodies().positions().get(0);
        assert!((p.x + 1.5).abs() < 1e-12, "{integrator}: {p}");
    }
}

#[test]
fn a_ball_hitting_the_wall_then_the_floor_within_one_tick_meets_both_on_time() {
    // No gravity, elastic, at 4 Hz: from (1.5, 0, 0.5) at (10, 0, -3) the ball (r = 0.1) meets
    // the wall at t = (1.9 - 1.5) / 10 = 0.04 s and, coming back, the floor at
    // t = (0.5 - 0.1) / 3 = 0.1333 s: both inside the first 0.25 s tick.
    let scene = Scene::builder("corner", 0.25)
        .mesh("corner", corner(), Transform::IDENTITY, 1.0)
        .body(BodySpec {
            mass: 1.0,
            radius: 0.1,
            position: DVec3::new(1.5, 0.0, 0.5),
            velocity: DVec3::new(10.0, 0.0, -3.0),
            spin: DVec3::ZERO,
        })
        .build()
        .unwrap();
    for integrator in allowed(&scene) {
        let (events, world) = events(&with(&scene, integrator), 1);
        let hits = impacts(&events, 0);
        assert_eq!(hits.len(), 2, "{integrator}: {hits:?}");
        assert!((hits[0].0 - 0.04).abs() < 1e-12, "{integrator}: {hits:?}");
        assert!(
            (hits[1].0 - 0.4 / 3.0).abs() < 1e-12,
            "{integrator}: {hits:?}"
        );
        assert!(matches!(
            hits[0].1,
            Surface::Mesh {
                triangle: 2 | 3,
                ..
            }
        ));
        assert!(matches!(
            hits[1].1,
            Surface::Mesh {
                triangle: 0 | 1,
                ..
            }
        ));
        // After both: (-10, 0, 3), at x = 1.9 - 10 (0.25 - 0.04), z = 0.1 + 3 (0.25 - 0.4 / 3).
        let (p, v) = (world.bodies().positions().get(0), world.velocity(0));
        assert!(
            (v - DVec3::new(-10.0, 0.0, 3.0)).length() < 1e-12,
            "{integrator}: {v}"
        );
        let expected = DVec3::new(1.9 - 10.0 * 0.21, 0.0, 0.1 + 3.0 * (0.25 - 0.4 / 3.0));
        assert!((p - expected).length() < 1e-12, "{integrator}: {p}");
    }
}
