//! The extrapolation reference (`exact::extrapolate`) where an answer is known: the linear-drag
//! closed form, and a vertical throw under quadratic drag, whose apex height and time have
//! closed forms of their own.

use glam::DVec3;
use volley_sim::internals::body::BodyState;
use volley_sim::internals::exact::{extrapolate, linear_drag_flow};
use volley_sim::internals::forces::Forces;

const G: f64 = 9.81;

#[test]
fn on_linear_drag_it_lands_on_the_closed_form_within_its_own_error_estimate() {
    let (m, b) = (2.5, 0.25);
    let forces = Forces {
        gravity: Some(DVec3::new(0.0, 0.0, -G)),
        linear_drag: Some(b),
        ..Forces::default()
    };
    let s0 = BodyState {
        p: DVec3::new(10.0, 0.0, 2.0),
        mv: m * DVec3::new(7.681, 0.0, 29.0),
    };
    for t in [0.37, 2.0, 5.2077, 30.0] {
        let (s, estimate) = extrapolate(&forces, s0, m, t, 1e-13).unwrap();
        let (p, v) = linear_drag_flow(s0.p, s0.mv / m, DVec3::new(0.0, 0.0, -G), b / m, t);
        let (dp, dv) = ((s.p - p).length(), (s.mv / m - v).length());
        // A tolerance of 1e-13 relative on a motion of some 100 m and 30 m/s: within 1e-9 of
        // both, and the estimate (a sum over steps) is not below what is left, give or take
        // rounding of the closed form's own (a few ulps of 100 m).
        assert!(dp < 1e-9 && dv < 1e-9, "t = {t}: {dp} m, {dv} m/s");
        assert!(
            dp <= estimate + 1e-12 * (1.0 + p.length()),
            "t = {t}: {dp} > {estimate}"
        );
    }
}

/// Vertical speed of the throw `t` after launch, by the reference.
fn vz(forces: &Forces, s0: BodyState, m: f64, t: f64) -> f64 {
    extrapolate(forces, s0, m, t, 1e-14).unwrap().0.mv.z / m
}

#[test]
fn a_vertical_throw_under_quadratic_drag_tops_out_where_the_closed_forms_say() {
    // m dv/dt = -m g - c |v| v. With vT = sqrt(m g / c): the apex is at t* = (vT / g)
    // atan(v0 / vT), at height vT^2 / (2 g) ln(1 + v0^2 / vT^2).
    let (m, c, v0) = (0.45, 0.002, 40.0);
    let forces = Forces {
        gravity: Some(DVec3::new(0.0, 0.0, -G)),
        quadratic_drag: Some(c),
        ..Forces::default()
    };
    let s0 = BodyState {
        p: DVec3::ZERO,
        mv: DVec3::new(0.0, 0.0, m * v0),
    };
    let vt = (m * G / c).sqrt();
    let t_apex = vt / G * (v0 / vt).atan();
    let h_apex = vt * vt / (2.0 * G) * (1.0 + v0 * v0 / (vt * vt)).ln();
    // The apex time: the root of vz, by bisection on the reference (vz falls monotonically).
    let (mut lo, mut hi) = (0.5 * t_apex, 1.5 * t_apex);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if vz(&forces, s0, m, mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t_found = 0.5 * (lo + hi);
    let (top, _) = extrapolate(&forces, s0, m, t_found, 1e-14).unwrap();
    // 1e-9 relative: the tolerance asked is 1e-14, the bisection resolves t to ulps, and the
    // height is flat at the apex, so its error is second order in the time's.
    assert!(
        (t_found - t_apex).abs() < 1e-9 * t_apex,
        "{t_found} vs {t_apex}"
    );
    assert!(
        (top.p.z - h_apex).abs() < 1e-9 * h_apex,
        "{} vs {h_apex}",
        top.p.z
    );
}

#[test]
fn bad_runs_are_errors_not_hangs() {
    // A point mass at the origin and a body dropped onto it from rest: the fall reaches the
    // singularity, where no step is small enough.
    let forces = Forces {
        point_mass: Some(volley_sim::internals::forces::PointMass {
            center: DVec3::ZERO,
            mu: 1.0,
        }),
        ..Forces::default()
    };
    let s0 = BodyState {
        p: DVec3::new(1.0, 0.0, 0.0),
        mv: DVec3::ZERO,
    };
    // It falls in at t = pi / (2 sqrt(2)) = 1.11 s; ask for 2 s.
    assert!(extrapolate(&forces, s0, 1.0, 2.0, 1e-12).is_err());
}
