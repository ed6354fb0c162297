//! The linear system `x'' = a0 - kd x' - w2 (x - anchor)` (gravity, constant force, linear drag,
//! a zero-rest-length spring with any damping): `exact` at any t for any dt, in every regime,
//! across the critical-damping boundary and as the spring vanishes.

use glam::DVec3;
use proptest::prelude::*;
use volley_sim::internals::exact::{closed_form, linear_drag_flow};
use volley_sim::internals::forces::{Forces, Spring};
use volley_sim::internals::integrate::BodyState;
use volley_sim::internals::scene;
use volley_sim::{Integrator, World};

/// The textbook eigen-solution of `y'' = a0 - kd y' - w2 y` on one axis, by regime: about the
/// equilibrium `a0 / w2`, `e^(-g t) (A cos wd t + B sin wd t)` under-damped, two exponentials
/// over-damped, `(A + B t) e^(-g t)` critically damped. It divides by `w2` and by the root
/// difference, so it is only a reference away from those limits. Returns (y, v).
fn textbook(kd: f64, w2: f64, t: f64, y0: f64, v0: f64, a0: f64) -> (f64, f64) {
    let g = kd / 2.0;
    let yeq = a0 / w2;
    let a = y0 - yeq;
    let disc = g * g - w2;
    if disc < 0.0 {
        let wd = (-disc).sqrt();
        let b = (v0 + g * a) / wd;
        let (s, c) = (wd * t).sin_cos();
        let e = (-g * t).exp();
        let v = e * ((b * wd - g * a) * c - (a * wd + g * b) * s);
        (yeq + e * (a * c + b * s), v)
    } else if disc > 0.0 {
        let s = disc.sqrt();
        let (r1, r2) = (-g + s, -g - s);
        let c1 = (v0 - r2 * a) / (r1 - r2);
        let c2 = a - c1;
        let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
        (yeq + c1 * e1 + c2 * e2, r1 * c1 * e1 + r2 * c2 * e2)
    } else {
        let b = v0 + g * a;
        let e = (-g * t).exp();
        (yeq + (a + b * t) * e, (b - g * (a + b * t)) * e)
    }
}

/// A linear scene's forces: gravity, a constant force, drag `b`, a spring `k` with damping `c`.
fn forces(b: f64, k: f64, c: f64, anchor: DVec3) -> Forces {
    Forces {
        gravity: Some(DVec3::new(0.0, 0.0, -9.81)),
        constant: Some(DVec3::new(0.7, -0.4, 0.0)),
        linear_drag: Some(b),
        spring: Some(Spring {
            anchor,
            stiffness: k,
            rest_length: 0.0,
            damping: c,
        }),
        ..Forces::default()
    }
}

/// The textbook solution of `forces` for a body of mass `m`, axis by axis.
fn textbook_3d(f: &Forces, m: f64, s0: BodyState, t: f64) -> (DVec3, DVec3) {
    let spring = f.spring.expect("a spring is declared");
    let kd = (f.linear_drag.unwrap_or(0.0) + spring.damping) / m;
    let w2 = spring.stiffness / m;
    let a0 = f.gravity.unwrap_or(DVec3::ZERO) + f.constant.unwrap_or(DVec3::ZERO) / m;
    let (y0, v0) = (s0.p - spring.anchor, s0.mv / m);
    let axis = |i: usize| textbook(kd, w2, t, y0[i], v0[i], a0[i]);
    let (x, y, z) = (axis(0), axis(1), axis(2));
    (
        spring.anchor + DVec3::new(x.0, y.0, z.0),
        DVec3::new(x.1, y.1, z.1),
    )
}

/// The size of a motion, to measure errors against: displacement from the anchor, the
/// equilibrium offset and the reach of the initial velocity, `|y0| + |a0| / w2 + |v0| / w`.
fn scale(f: &Forces, m: f64, s0: BodyState) -> f64 {
    let spring = f.spring.expect("a spring is declared");
    let w2 = spring.stiffness / m;
    let a0 = f.gravity.unwrap_or(DVec3::ZERO) + f.constant.unwrap_or(DVec3::ZERO) / m;
    (s0.p - spring.anchor).length() + a0.length() / w2 + (s0.mv / m).length() / w2.sqrt()
}

fn state(p: (f64, f64, f64), v: (f64, f64, f64), m: f64) -> BodyState {
    BodyState {
        p: DVec3::from(p),
        mv: m * DVec3::from(v),
    }
}

/// Damping ratios away from critical (within 10 %), where the textbook form is a reference.
fn separated_zeta() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), 0.0..0.9f64, 1.1..20.0f64]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// `closed_form` is the textbook solution at any time, in both well-separated regimes,
    /// within 1e-9 of the motion's size: both are a few ulps from the truth there (the textbook
    /// form's worst cancellation, `-g + s` at zeta = 20, costs under 3 digits).
    #[test]
    fn closed_form_is_the_textbook_solution_in_every_separated_regime(
        m in 0.1..10.0f64,
        w in 0.1..100.0f64,
        zeta in separated_zeta(),
        drag_share in 0.0..1.0f64,
        periods in 0.0..30.0f64,
        p in (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
        v in (-20.0..20.0f64, -20.0..20.0f64, -20.0..20.0f64),
    ) {
        let total = 2.0 * zeta * m * w;
        let f = forces(drag_share * total, m * w * w, (1.0 - drag_share) * total, DVec3::new(0.5, 1.0, 3.0));
        let s0 = state(p, v, m);
        let t = periods / w;
        let got = closed_form(&f, s0, m, t).expect("a linear scene has a closed form");
        let (p_ref, v_ref) = textbook_3d(&f, m, s0, t);
        let size = scale(&f, m, s0);
        prop_assert!((got.p - p_ref).length() <= 1e-9 * size, "p {} vs {p_ref}", got.p);
        prop_assert!((got.mv / m - v_ref).length() <= 1e-9 * w * size, "v {} vs {v_ref}", got.mv / m);
    }

    /// Stepping `exact` n times lands on the closed form at t = n h, including at and next to
    /// critical damping: each step composes the exact flow, so only rounding accumulates (an
    /// ulp or so of the motion's size a step, 2e-13 for the 2000 steps here).
    #[test]
    fn exact_steps_land_on_the_closed_form_for_any_dt(
        w in 0.1..30.0f64,
        zeta in prop_oneof![Just(1.0), Just(1.0 + 1e-9), Just(1.0 - 1e-9), 0.0..3.0f64],
        dt in 1e-4..0.5f64,
        steps in 1u64..2000,
        v in (-20.0..20.0f64, -20.0..20.0f64, -20.0..20.0f64),
    ) {
        let (m, k) = (2.0, 2.0 * w * w);
        let c = 2.0 * zeta * m * w;
        let text = format!(
            "Scene(dt: {dt}, integrator: Exact,
               forces: [Gravity((0.0, 0.0, -9.81)), ConstantForce((0.7, -0.4, 0.0)),
                        LinearDrag({}), Spring(anchor: (0.5, 1.0, 3.0), stiffness: {k}, damping: {})],
               bodies: [(mass: {m}, position: (1.0, -2.0, 3.0), launch: Velocity(({}, {}, {})))],
               guard: (every: 0))",
            0.25 * c, 0.75 * c, v.0, v.1, v.2
        );
        let scene = scene::parse(&text, "inline.ron", "inline").unwrap();
        let mut world = World::new(&scene);
        let s0 = world.bodies().state(0);
        world.step_ticks(steps).unwrap();
        let expected = closed_form(scene.forces(), s0, m, world.time())
            .expect("a linear scene has a closed form");
        let got = world.bodies().state(0);
        let size = scale(scene.forces(), m, s0);
        prop_assert!((got.p - expected.p).length() <= 1e-9 * size,
            "t = {}: {} vs {}", world.time(), got.p, expected.p);
    }
}

/// Exactly critical: k/m = 100, (b + c)/m = 20, so `gamma^2 - w2` is 0 in floating point.
fn critical() -> (Forces, f64) {
    (forces(5.0, 100.0, 15.0, DVec3::new(0.5, 1.0, 3.0)), 1.0)
}

#[test]
fn exactly_critical_damping_is_the_critical_solution() {
    let (f, m) = critical();
    let s0 = state((1.0, -2.0, 3.0), (4.0, 0.0, -7.0), m);
    let size = scale(&f, m, s0);
    for t in [1e-9, 0.01, 0.37, 1.0, 5.0, 30.0] {
        let got = closed_form(&f, s0, m, t).unwrap();
        let (p, v) = textbook_3d(&f, m, s0, t);
        // Both forms are a few ulps of the motion's size from the truth here.
        assert!(
            (got.p - p).length() <= 1e-14 * size,
            "t = {t}: {} vs {p}",
            got.p
        );
        assert!((got.mv - v).length() <= 1e-13 * size, "t = {t}");
    }
}

#[test]
fn no_precision_is_lost_next_to_critical_damping() {
    // Along the drag coefficient through critical (kd = 20 (1 + d)) the flow is smooth: its
    // change is the slope at critical times the step, to first order. The slope comes from a
    // central difference at d = 1e-4 (error d^2 times the curvature, rounding 1e-16 / 1e-4).
    // A form that loses digits near the boundary (the textbook's 1/(r1 - r2) loses about
    // log10(1/sqrt(d)) of them) fails this by orders of magnitude at d = 1e-12.
    let (f0, m) = critical();
    let s0 = state((1.0, -2.0, 3.0), (4.0, 0.0, -7.0), m);
    let size = scale(&f0, m, s0);
    let t = 0.37;
    // kd = (b + c) / m with c = 15 and b = 5 + 20 d; `d` returned is the one the sum rounds to.
    let at = |d: f64| {
        let f = Forces {
            linear_drag: Some(5.0 + 20.0 * d),
            ..f0.clone()
        };
        let kd = (5.0 + 20.0 * d + 15.0) / m;
        ((kd - 20.0) / 20.0, closed_form(&f, s0, m, t).unwrap())
    };
    let (_, crit) = at(0.0);
    let ((hp, up), (hm, down)) = (at(1e-4), at(-1e-4));
    let slope_p = (up.p - down.p) / (hp - hm);
    let slope_v = (up.mv - down.mv) / (hp - hm);
    for d in [1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16] {
        for d in [d, -d] {
            let (d, s) = at(d);
            let bound = 8.0 * f64::EPSILON * size + 1e-6 * d.abs() * size;
            let ep = (s.p - crit.p - d * slope_p).length();
            let ev = (s.mv - crit.mv - d * slope_v).length();
            assert!(ep <= bound, "d = {d}: position off the tangent by {ep:e}");
            assert!(
                ev <= 10.0 * bound,
                "d = {d}: velocity off the tangent by {ev:e}"
            );
        }
    }
}

#[test]
fn a_vanishing_spring_tends_to_the_drag_and_free_flight_flows() {
    let (p0, v0) = (DVec3::new(1.0, -2.0, 3.0), DVec3::new(4.0, 0.0, -7.0));
    let (m, t) = (1.0, 3.0);
    for b in [0.0, 0.5] {
        let drag_only = Forces {
            spring: None,
            ..forces(b, 0.0, 0.0, DVec3::ZERO)
        };
        let a0 = DVec3::new(0.7, -0.4, -9.81);
        let (p_drag, _) = linear_drag_flow(p0, v0, a0, b / m, t);
        let s0 = BodyState { p: p0, mv: m * v0 };
        assert_eq!(closed_form(&drag_only, s0, m, t).unwrap().p, p_drag);
        // The spring's pull is at most w2 |y| with |y| <= |y0| + |v0| t + |a0| t^2 / 2 over the
        // flight, and moves the body by at most that times t^2 / 2 (to first order in w2).
        let reach = p0.length() + v0.length() * t + a0.length() * t * t / 2.0;
        let mut per_w2 = Vec::new();
        for w2 in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-20, 1e-300] {
            let f = forces(b, m * w2, 0.0, DVec3::ZERO);
            let got = closed_form(&f, s0, m, t).unwrap();
            let gap = (got.p - p_drag).length();
            assert!(
                gap <= w2 * reach * t * t + 4.0 * f64::EPSILON * reach,
                "b = {b}, w2 = {w2}: {gap:e}"
            );
            per_w2.push((got.p - p_drag) / w2);
        }
        // Smoothly: (p(w2) - p(0)) / w2 settles to the derivative (the second-order term is
        // w2 times smaller; rounding is 1e-16 / w2 of the motion).
        let (d6, d8) = (per_w2[1], per_w2[2]);
        assert!((d6 - d8).length() <= 1e-4 * d8.length(), "{d6} vs {d8}");
    }
}

/// Classical RK4 on `y'' = a0 - kd y' - w2 y`, written here independently of the crate.
fn rk4(kd: f64, w2: f64, a0: DVec3, (mut y, mut v): (DVec3, DVec3), t: f64, n: u32) -> DVec3 {
    let h = t / f64::from(n);
    let acc = |y: DVec3, v: DVec3| a0 - kd * v - w2 * y;
    for _ in 0..n {
        let (k1y, k1v) = (v, acc(y, v));
        let (k2y, k2v) = (v + 0.5 * h * k1v, acc(y + 0.5 * h * k1y, v + 0.5 * h * k1v));
        let (k3y, k3v) = (v + 0.5 * h * k2v, acc(y + 0.5 * h * k2y, v + 0.5 * h * k2v));
        let (k4y, k4v) = (v + h * k3v, acc(y + h * k3y, v + h * k3v));
        y += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    y
}

#[test]
fn a_fine_rk4_integration_agrees_in_every_regime() {
    // k/m = 100 (w = 10) over t = 2 s with h = 2e-5 (w h = 2e-4): RK4's global error is about
    // (w h)^4 w t / 120 ~ 2e-16 of the motion, below the rounding of its 1e5 steps (~1e-12).
    let m = 1.0;
    let s0 = state((1.0, -2.0, 3.0), (4.0, 0.0, -7.0), m);
    for kd in [0.0, 2.0, 20.0, 20.0 * (1.0 + 1e-10), 60.0] {
        let f = forces(kd / 2.0, 100.0, kd / 2.0, DVec3::new(0.5, 1.0, 3.0));
        let got = closed_form(&f, s0, m, 2.0).unwrap();
        let anchor = DVec3::new(0.5, 1.0, 3.0);
        let a0 = DVec3::new(0.7, -0.4, -9.81);
        let y = rk4(kd, 100.0, a0, (s0.p - anchor, s0.mv / m), 2.0, 100_000);
        let size = scale(&f, m, s0);
        assert!(
            (got.p - (anchor + y)).length() <= 1e-10 * size,
            "kd = {kd}: {} vs {}",
            got.p,
            anchor + y
        );
    }
}

#[test]
fn exact_is_accepted_on_every_linear_scene_and_refused_with_a_rest_length() {
    let linear = forces(0.3, 40.0, 2.0, DVec3::ZERO);
    assert_eq!(scene::check_integrator(Integrator::Exact, &linear), Ok(()));
    let bare = Forces {
        spring: linear.spring,
        ..Forces::default()
    };
    assert_eq!(scene::check_integrator(Integrator::Exact, &bare), Ok(()));
    let rest = Forces {
        spring: linear.spring.map(|s| Spring {
            rest_length: 1.0,
            ..s
        }),
        ..linear
    };
    let err = scene::check_integrator(Integrator::Exact, &rest).unwrap_err();
    assert_eq!(
        err.to_string(),
        "`exact` needs a closed form, and force term Spring has none with a rest length (exact \
         covers any mix of Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, \
         or a PointMass alone); choose another integrator"
    );
    let s0 = state((1.0, 0.0, 0.0), (0.0, 0.0, 0.0), 1.0);
    assert_eq!(closed_form(&rest, s0, 1.0, 1.0), None);
}
