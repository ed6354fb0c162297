//! Hard cases 17 to 19: a 900 m/s bullet against a 1 cm plate at 30 and 60 Hz, grazing shots
//! from 0.5 to 90 degrees, hits on a face's diagonal, an edge and a vertex; and the tunnelling
//! count of seeded shots.

use volley_sim::{Detection, Surface};

use super::{events, every, impacts, load, with};

use super::shots::{FACE, R, plate_shots, seed};

/// Tolerance on a time of impact (s). The root finder converges to a few ulps of the step's
/// time (1e-17 s at 30 Hz); the closed form's own rounding is a few ulps of 0.05 s. 1e-9 s is
/// the goal; the tests hold it with room to spare.
const TOI: f64 = 1e-9;

#[test]
fn a_900_m_s_bullet_hits_the_plate_at_30_and_60_hz_for_every_integrator() {
    let scene = load("hard/plate_bullet");
    // x = 900 t exactly for every integrator (no force along x): it touches at x = FACE - R.
    let t_star = (FACE - R) / 900.0;
    for dt in [1.0f64 / 30.0, 1.0 / 60.0] {
        for integrator in every(&scene) {
            let mut s = with(&scene, integrator);
            s.set_dt(dt).unwrap();
            let ticks = s.ticks_until(0.2);
            let (events, world) = events(&s, ticks);
            let hits = impacts(&events, 0);
            assert_eq!(hits.len(), 1, "{integrator} at {dt}: {hits:?}");
            let (t, surface, speed) = hits[0];
            eprintln!(
                "{integrator} at {:.0} Hz: time of impact off by {:.1e} s",
                1.0 / dt,
                t - t_star
            );
            assert!(
                (t - t_star).abs() <= TOI,
                "{integrator} at {dt}: {t} vs {t_star}"
            );
            assert!(
                matches!(surface, Surface::Mesh { surface: 0, .. }),
                "{surface:?}"
            );
            assert!((speed - 900.0).abs() < 1e-9, "{integrator}: {speed}");
            // It bounced back off the face (restitution 0.1) and is on the near side.
            let p = world.bodies().positions().get(0);
            assert!(
                p.x < FACE - R,
                "{integrator} at {dt}: tunnelled to x = {}",
                p.x
            );
            assert!(
                (world.velocity(0).x + 90.0).abs() < 1e-9,
                "{integrator}: {}",
                world.velocity(0)
            );
        }
    }
}

#[test]
fn discrete_detection_tunnels_through_the_plate() {
    // The comparison swept detection is there to win: ends of steps at 30 m spacing never
    // fall inside a 1 cm plate.
    let scene = load("hard/plate_bullet")
        .edit()
        .detection(Detection::Discrete)
        .build()
        .unwrap();
    let (events, world) = events(&scene, 6);
    assert!(impacts(&events, 0).is_empty());
    assert!(world.bodies().positions().get(0).x > 100.0);
}

#[test]
fn grazing_shots_from_half_a_degree_to_ninety_hit_the_face_on_time() {
    let scene = load("hard/grazing");
    for integrator in every(&scene) {
        let s = with(&scene, integrator);
        let (events, world) = events(&s, 3);
        let mut worst = 0.0f64;
        for (k, b) in s.bodies().iter().enumerate() {
            // x(t) = x0 + vx t for every integrator: it touches the face, which the glTF holds
            // in f32 (x = 50 - 0.004999999888), at x = face - R.
            let face = 50.0 + f64::from(-0.005f32);
            let t_star = (face - R - b.position.x) / b.velocity.x;
            let hits = impacts(&events, k as u32);
            assert_eq!(hits.len(), 1, "{integrator} body {k}: {hits:?}");
            let (t, surface, speed) = hits[0];
            worst = worst.max((t - t_star).abs());
            assert!(
                (t - t_star).abs() <= TOI,
                "{integrator} body {k}: {t} vs {t_star} ({} s off)",
                t - t_star
            );
            assert!(matches!(surface, Surface::Mesh { surface: 0, .. }));
            assert!(
                (speed - b.velocity.x).abs() < 1e-6 * b.velocity.x,
                "{speed}"
            );
            let p = world.bodies().positions().get(k);
            assert!(
                p.x < FACE - R,
                "{integrator} body {k} tunnelled: x = {}",
                p.x
            );
        }
        eprintln!("{integrator}: grazing times of impact off by at most {worst:.1e} s");
    }
}

#[test]
fn a_hit_on_the_shared_diagonal_an_edge_and_a_vertex_bounces_off_that_feature() {
    let scene = load("hard/edge_vertex");
    let r2 = R * R;
    // Distance across the flight from the feature: 0 on the face, r/2 from the edge, r/2 along
    // both axes from the vertex.
    let d2 = [0.0, 0.25 * r2, 0.5 * r2];
    for integrator in every(&scene) {
        let s = with(&scene, integrator);
        let (events, world) = events(&s, 6);
        for (k, &d2) in d2.iter().enumerate() {
            let x_touch = FACE - (r2 - d2).sqrt();
            let t_star = x_touch / 900.0;
            let hits = impacts(&events, k as u32);
            // One impact each, even on the diagonal two triangles share.
            assert_eq!(hits.len(), 1, "{integrator} body {k}: {hits:?}");
            assert!((hits[0].0 - t_star).abs() <= TOI, "{integrator} body {k}");
            // Elastic: the velocity is reflected about the contact normal (p - q) / r, whose x
            // component is -sqrt(1 - d^2 / r^2): the normal speed is 900 times that.
            let nx = (1.0 - d2 / r2).sqrt();
            assert!(
                (hits[0].2 - 900.0 * nx).abs() < 1e-6,
                "{integrator} body {k}: {}",
                hits[0].2
            );
            let v = world.velocity(k);
            let expected_vx = 900.0 * (1.0 - 2.0 * nx * nx);
            assert!(
                (v.x - expected_vx).abs() < 1e-6,
                "{integrator} body {k}: {v}"
            );
            assert!((v.length() - 900.0).abs() < 1e-6, "elastic: {v}");
        }
        // The edge hit is pushed out along +y only (the normal has no z part), the vertex hit
        // along +y and +z equally.
        let (v1, v2) = (world.velocity(1), world.velocity(2));
        assert!(v1.y > 0.0 && v1.z.abs() < 1e-9, "{v1}");
        assert!(v2.y > 0.0 && (v2.y - v2.z).abs() < 1e-6, "{v2}");
    }
}

/// Shots per integrator and rate: `VOLLEY_SHOTS`, else a few hundred. The 1e6 per
/// integrator and rate are fired by `scripts/bench-levels` (BENCHMARKS.md, "Level peers"), with
/// the same shots (`shots.rs`).
fn shots() -> usize {
    std::env::var("VOLLEY_SHOTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200)
}

#[test]
fn seeded_shots_at_900_m_s_never_tunnel_through_the_plate() {
    let base = load("hard/plate_bullet");
    let n = shots();
    for dt in [1.0f64 / 30.0, 1.0 / 60.0] {
        for integrator in every(&base) {
            let mut scene = with(&base, integrator);
            scene.set_dt(dt).unwrap();
            // Every shot at once: bodies do not touch each other, so a world of them is the
            // same as one world each.
            let bodies = plate_shots(seed(integrator, dt), n, base.bodies()[0]);
            let scene = scene.edit().bodies(bodies).build().unwrap();
            let ticks = scene.ticks_until(0.2);
            let (events, world) = events(&scene, ticks);
            let mut hit = vec![false; n];
            for e in &events {
                if matches!(e.kind, volley_sim::EventKind::Impact { .. }) {
                    hit[e.body.0 as usize] = true;
                }
            }
            let mut tunnels = 0;
            for (k, hit) in hit.iter().enumerate() {
                let p = world.bodies().positions().get(k);
                if !hit || p.x > FACE {
                    tunnels += 1;
                }
            }
            eprintln!(
                "{integrator} at {:.0} Hz: {tunnels} tunnels in {n} shots",
                1.0 / dt
            );
            assert_eq!(tunnels, 0, "{integrator} at {dt}");
        }
    }
}
