//! Hard cases 20 and 23: a ball bouncing down a heightfield hill; a ball resting on a slope.

use glam::DVec3;
use volley_sim::Integrator::*;
use volley_sim::internals::contact::{Feature, closest_point};
use volley_sim::{EventKind, Surface};

use super::{allowed, events, impacts, load, with};

/// The world corners of cell `(i, j)`'s triangle `half` of the hill (grid spacing 0.5 m, moved
/// by (-16, -16, 0)), as the walk builds them.
fn hill_triangle(scene: &volley_sim::Scene, i: u32, j: u32, half: u8) -> [DVec3; 3] {
    let h = &scene.heightfields()[0];
    let at = |i: u32, j: u32| {
        h.transform.position
            + DVec3::new(
                f64::from(i) * h.cell_size,
                f64::from(j) * h.cell_size,
                h.grid.height(i, j),
            )
    };
    let (p00, p10, p11, p01) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    if half == 0 {
        [p00, p10, p11]
    } else {
        [p00, p11, p01]
    }
}

#[test]
fn a_ball_dropped_on_the_hill_first_lands_on_the_closed_form_time_and_cell() {
    let scene = load("hard/hill");
    let b = scene.bodies()[0];
    // The ball falls straight down at (3.1, 1.7): grid (19.1, 17.7) / 0.5 = cell (38, 35), at
    // (0.2, 0.4) inside it, above its diagonal: triangle 1.
    let (i, j) = (38, 35);
    let t = hill_triangle(&scene, i, j, 1);
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
    let n = if n.z < 0.0 { -n } else { n };
    // The sphere touches the face's plane when n . (p - a) = r, p = (x, y, z): solve for z.
    let z_touch =
        (b.radius - n.x * (b.position.x - t[0].x) - n.y * (b.position.y - t[0].y)) / n.z + t[0].z;
    let contact = DVec3::new(b.position.x, b.position.y, z_touch) - b.radius * n;
    assert_eq!(closest_point(contact, t[0], t[1], t[2]).1, Feature::Face);
    let t_star = (2.0 * (b.position.z - z_touch) / 9.81).sqrt();
    // Verlet, midpoint, RK4, exact, Forest-Ruth, Dormand-Prince and implicit midpoint are exact
    // under gravity: the root is the closed form's time to the root finder's ulps.
    for integrator in [
        VelocityVerlet,
        Midpoint,
        Rk4,
        Exact,
        ForestRuth,
        Dopri5,
        ImplicitMidpoint,
    ] {
        let (events, _) = events(&with(&scene, integrator), 90);
        let (time, surface, _) = impacts(&events, 0)[0];
        eprintln!(
            "{integrator}: first impact on the hill off by {:.1e} s",
            time - t_star
        );
        let cell = j * 64 + i;
        assert_eq!(
            surface,
            Surface::Heightfield {
                surface: 0,
                cell,
                triangle: 1
            },
            "{integrator}"
        );
        assert!(
            (time - t_star).abs() < 1e-9,
            "{integrator}: {time} vs {t_star}"
        );
    }
}

#[test]
fn the_bounces_down_the_hill_agree_with_a_run_at_eight_times_the_rate() {
    // The converged reference: under gravity alone Verlet's flights are exact and every impact
    // is a root of the same path, so the run at 480 Hz meets the same cells at the same times;
    // only the root finder's rounding (a few ulps of the step) and its propagation through the
    // bounces differ. 1e-9 s holds for the whole run.
    let scene = load("hard/hill");
    let (coarse, _) = events(&scene, 240);
    let mut fine = scene.clone();
    fine.set_dt(scene.dt() / 8.0).unwrap();
    let (fine, _) = events(&fine, 240 * 8);
    let (a, b) = (impacts(&coarse, 0), impacts(&fine, 0));
    assert!(a.len() >= 3, "{a:?}");
    assert_eq!(a.len(), b.len(), "{a:?}\n{b:?}");
    let on_hill = a
        .iter()
        .filter(|(_, s, _)| matches!(s, Surface::Heightfield { .. }))
        .count();
    assert!(on_hill >= 2, "bounces on the hill: {a:?}");
    for ((ta, sa, va), (tb, sb, vb)) in a.iter().zip(&b) {
        assert_eq!(sa, sb);
        assert!((ta - tb).abs() < 1e-9, "{ta} vs {tb}");
        assert!((va - vb).abs() < 1e-6, "{va} vs {vb}");
    }
}

#[test]
fn a_ball_on_a_slope_slides_down_it_without_sinking_or_jittering() {
    // The model: frictionless resting contact. Each step the momentum into the surface is
    // removed, the step is integrated and the ball put back on the tangent plane, so under
    // gravity it slides at g sin a along the slope: s(t) = g sin a t^2 / 2, exactly for the
    // integrators exact under constant force. The ramp rises 3 in 4 (sin a = 0.6, cos a = 0.8,
    // its corners exact in the file's f32), the ball starts 5 m up it, at rest.
    let scene = load("hard/slope");
    let (sin, cos) = (0.6, 0.8);
    let n = DVec3::new(-sin, 0.0, cos);
    let down = DVec3::new(-cos, 0.0, -sin);
    let r = scene.bodies()[0].radius;
    for integrator in allowed(&scene) {
        let s = with(&scene, integrator);
        let mut sim = volley_sim::SimLoop::new(volley_sim::World::new(&s));
        let p0 = s.bodies()[0].position;
        // 70 ticks: 4.8 m of the 5 m to the foot of the ramp.
        for tick in 1..=70u64 {
            let mut clock = volley_sim::internals::clock::VirtualClock::Steady(s.timestep());
            sim.run_until(tick, &mut clock, &mut ()).unwrap();
            let w = &sim.world;
            let (p, v) = (w.bodies().positions().get(0), w.velocity(0));
            // Neither sinks nor lifts off: on the plane to rounding, no speed across it.
            assert!(
                (n.dot(p) - r).abs() < 1e-12,
                "{integrator} tick {tick}: {}",
                n.dot(p) - r
            );
            assert!(n.dot(v).abs() < 1e-12, "{integrator} tick {tick}: {v}");
            // No bounce: not one impact event.
            assert!(
                !w.events()
                    .iter()
                    .any(|e| matches!(e.kind, EventKind::Impact { .. })),
                "{integrator} tick {tick}: {:?}",
                w.events()
            );
            let t = tick as f64 * s.dt();
            let along = down.dot(p - p0);
            let exact = 0.5 * 9.81 * sin * t * t;
            if matches!(
                integrator,
                VelocityVerlet | Midpoint | Rk4 | Exact | ForestRuth | Dopri5 | ImplicitMidpoint
            ) {
                assert!(
                    (along - exact).abs() < 1e-9,
                    "{integrator} tick {tick}: {along} vs {exact}"
                );
                assert!((down.dot(v) - 9.81 * sin * t).abs() < 1e-9, "{integrator}");
            } else {
                // The Eulers slide with their own first-order error: g sin a t h / 2 in s.
                let err = 9.81 * sin * t * s.dt() / 2.0;
                assert!(
                    (along - exact).abs() <= 1.01 * err + 1e-12,
                    "{integrator} tick {tick}"
                );
            }
        }
    }
}
