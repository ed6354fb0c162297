//! Hard case 13: a vertical throw under quadratic drag, for every integrator.
//!
//! `m dv/dt = -m g - c |v| v`. With `vT = sqrt(m g / c)` and `a = atan(v0 / vT)`, on the way up
//! `v(t) = vT tan(a - g t / vT)` and `z(t) = (vT^2 / g) ln(cos(a - g t / vT) / cos a)`, reaching
//! the apex at `t* = (vT / g) a`, `h = vT^2 / (2 g) ln(1 + v0^2 / vT^2)`. `|v| v` is smooth while
//! `v > 0`, so each method shows its order there; at the apex `|v| v` has a kink, which is why
//! the window and the study measure the whole flight against the numerical reference, whose
//! apex time and height are checked against `t*` and `h` in `exact/extrapolation.rs`.

use volley_sim::Integrator::*;
use volley_sim::{Integrator, Scene};

use super::{allowed, load, run, with};

const G: f64 = 9.81;

/// (vT, a, t*, h) of the scene's throw.
fn throw(scene: &Scene) -> (f64, f64, f64, f64) {
    let (m, c) = (
        scene.bodies()[0].mass,
        scene.forces().quadratic_drag.unwrap(),
    );
    let v0 = scene.bodies()[0].velocity.z;
    let vt = (m * G / c).sqrt();
    let a = (v0 / vt).atan();
    let h = vt * vt / (2.0 * G) * (1.0 + v0 * v0 / (vt * vt)).ln();
    (vt, a, vt / G * a, h)
}

fn height(scene: &Scene, t: f64) -> f64 {
    let (vt, a, _, _) = throw(scene);
    vt * vt / G * ((a - G * t / vt).cos() / a.cos()).ln()
}

/// Largest height error over the ticks strictly before the apex.
fn error_before_apex(scene: &Scene, integrator: Integrator) -> (f64, u64) {
    let s = with(scene, integrator);
    let (_, _, t_star, _) = throw(&s);
    let ticks = (t_star / s.dt()).floor() as u64;
    let (trace, result, world) = run(&s, ticks);
    assert!(result.is_ok(), "{integrator}: {result:?}");
    let e = trace
        .p
        .iter()
        .enumerate()
        .map(|(n, p)| (p.z - height(&s, n as f64 * s.dt())).abs())
        .fold(0.0, f64::max);
    (e, world.force_evals())
}

#[test]
fn the_closed_form_apex_is_what_the_scene_says() {
    let scene = load("hard/quadratic_throw");
    let (vt, a, t_star, h) = throw(&scene);
    // The closed form's own apex: z(t*) = (vT^2/g) ln(1 / cos a) = vT^2/(2g) ln(1 + tan^2 a).
    assert!((height(&scene, t_star) - h).abs() < 1e-12 * h);
    assert!(
        (vt - 31.32).abs() < 0.01 && (t_star - 2.44).abs() < 0.01,
        "{vt} {a} {t_star}"
    );
}

#[test]
fn every_integrator_shows_its_order_on_the_way_up() {
    let scene = load("hard/quadratic_throw");
    let mut halved = scene.clone();
    halved.set_dt(scene.dt() / 2.0).unwrap();
    for integrator in allowed(&scene) {
        assert_ne!(integrator, Exact, "quadratic drag has no closed form");
        if integrator == Dopri5 {
            // Adaptive: the error follows the tolerance. Each accepted internal step's error
            // is at most tol (1 + |y|) by its estimate (|y| <= 30 here), and the drag does not
            // amplify earlier errors on the way up, so the sum over the attempts bounds it.
            let (e, evals) = error_before_apex(&scene, Dopri5);
            let ticks = (throw(&scene).2 / scene.dt()).floor() as u64;
            let attempts = (evals - ticks) / 6;
            let bound = attempts as f64 * scene.tolerance() * 31.0;
            assert!(
                e < bound,
                "dopri5: {e} m over {attempts} attempts, bound {bound}"
            );
            continue;
        }
        let order = integrator.info().order as i32;
        let ratio =
            error_before_apex(&scene, integrator).0 / error_before_apex(&halved, integrator).0;
        // The next term of the error expansion is O(h) relative to the first: k h = c v h / m
        // <= 0.015 and g h / v0 = 0.016 at dt = 0.05. Within 25% of 2^order.
        let expected = 2f64.powi(order);
        println!("{integrator}: halving dt divides the error by {ratio:.3} (2^{order})");
        assert!(
            (0.8 * expected..1.25 * expected).contains(&ratio),
            "{integrator}: halving dt divides the error by {ratio}, not 2^{order}"
        );
    }
}
