//! Kepler's problem: `exact` on a lone point mass against Kepler's equation solved here
//! independently (elliptic, hyperbolic, Barker's for the parabola), the solver's convergence,
//! the invariants over 1000 orbits, and radial orbits up to their collision.

use glam::DVec3;
use volley_sim::internals::exact::{
    KeplerError, KeplerOrbit, MAX_ITERATIONS, closed_form, kepler_flow,
};
use volley_sim::internals::forces::{Forces, PointMass};
use volley_sim::internals::integrate::BodyState;
use volley_sim::internals::scene;
use volley_sim::internals::world::DivergenceCause;
use volley_sim::{Integrator, World};

/// Bisection to the last bit on an increasing `f` with `f(lo) <= 0 <= f(hi)`.
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            return mid;
        }
        if f(mid) < 0.0 { lo = mid } else { hi = mid }
    }
}

/// The orbit's frame from the state: eccentricity vector direction `P`, `Q = h x P / |h|`,
/// semi-major axis `a` (negative on a hyperbola), eccentricity `e`.
struct Elements {
    p: DVec3,
    q: DVec3,
    a: f64,
    e: f64,
}

fn elements(x: DVec3, v: DVec3, mu: f64) -> Elements {
    let r = x.length();
    let h = x.cross(v);
    let ev = ((v.length_squared() - mu / r) * x - x.dot(v) * v) / mu;
    let e = ev.length();
    let p = ev / e;
    Elements {
        p,
        q: h.normalize().cross(p),
        a: 1.0 / (2.0 / r - v.length_squared() / mu),
        e,
    }
}

/// Position after `t` on an ellipse, from Kepler's equation `M = E - e sin E`.
fn kepler_ellipse(x0: DVec3, v0: DVec3, mu: f64, t: f64) -> DVec3 {
    let el = elements(x0, v0, mu);
    let (a, e) = (el.a, el.e);
    let r0 = x0.length();
    let (c0, s0) = ((1.0 - r0 / a) / e, x0.dot(v0) / (e * (mu * a).sqrt()));
    let e0 = s0.atan2(c0);
    let n = (mu / (a * a * a)).sqrt();
    let tau = std::f64::consts::TAU;
    // Mean anomaly reduced to one turn from the start's, so the bisection works on [0, 2 pi).
    let m = (e0 - e * e0.sin() + n * t).rem_euclid(tau);
    let big_e = bisect(|big_e| big_e - e * big_e.sin() - m, m - 1.0, m + 1.0);
    a * (big_e.cos() - e) * el.p + a * (1.0 - e * e).sqrt() * big_e.sin() * el.q
}

/// Position after `t` on a hyperbola, from `M = e sinh F - F`.
fn kepler_hyperbola(x0: DVec3, v0: DVec3, mu: f64, t: f64) -> DVec3 {
    let el = elements(x0, v0, mu);
    let (a, e) = (-el.a, el.e);
    let sinh_f0 = x0.dot(v0) / (e * (mu * a).sqrt());
    let f0 = sinh_f0.asinh();
    let n = (mu / (a * a * a)).sqrt();
    let m = e * f0.sinh() - f0 + n * t;
    // (e - 1) sinh F <= e sinh F - F for F >= 0: |F| <= asinh(|M| / (e - 1)).
    let lim = (m.abs() / (e - 1.0)).asinh() + 1.0;
    let f = bisect(|f| e * f.sinh() - f - m, -lim, lim);
    a * (e - f.cosh()) * el.p + a * (e * e - 1.0).sqrt() * f.sinh() * el.q
}

const PM: PointMass = PointMass {
    center: DVec3::new(3.0, -1.0, 2.0),
    mu: 2.5,
};

/// An orbit of semi-major axis `a` and eccentricity `e` about [`PM`], tilted out of every
/// coordinate plane, starting at apoapsis (`apo`) or periapsis. Returns (p0, v0).
fn start(a: f64, e: f64, apo: bool) -> (DVec3, DVec3) {
    // Unit and orthogonal: 0.6 * -0.48 + 0.8 * 0.36 = 0.
    let (u, w) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.48, 0.6, 0.36));
    let r = if apo { a * (1.0 + e) } else { a * (1.0 - e) };
    let v = (PM.mu * (2.0 / r - 1.0 / a)).sqrt();
    (PM.center + r * u, v * w.normalize())
}

#[test]
fn ellipses_follow_keplers_equation() {
    for e in [0.0, 0.3, 0.7, 0.9, 0.99, 0.999] {
        // From apoapsis the state's rounding moves the period by only ~(3 - e)/(1 + e) ulps
        // (from periapsis by (3 + e)/(1 - e), 4000 ulps at e = 0.999), so ten orbits keep the
        // two computations within 1e-12 of the orbit's size, for the test's bisection and the
        // crate's Laguerre alike.
        let (p0, v0) = start(1.7, e, true);
        let period = std::f64::consts::TAU * (1.7f64.powi(3) / PM.mu).sqrt();
        for frac in [1e-7, 0.013, 0.25, 0.5, 0.501, 0.75, 0.999, 1.0, 3.3, 10.0] {
            let t = frac * period;
            let (p, _) = kepler_flow(p0, v0, &PM, t).unwrap();
            let expected = if e == 0.0 {
                // Uniform rotation in the plane of (x0, v0).
                let (x0, th) = (p0 - PM.center, std::f64::consts::TAU * frac);
                x0 * th.cos() + v0.normalize() * x0.length() * th.sin()
            } else {
                kepler_ellipse(p0 - PM.center, v0, PM.mu, t)
            };
            let err = (p - PM.center - expected).length();
            assert!(err <= 1e-12 * 1.7, "e = {e}, t = {frac} T: off by {err:e}");
        }
    }
}

#[test]
fn hyperbolas_and_the_parabola_follow_their_equations() {
    let mu = PM.mu;
    for e in [1.01, 1.5, 3.0, 100.0] {
        // From periapsis q = 0.8 at v^2 = mu (1 + e) / q, to 50 crossing times q / v later,
        // and back (negative times run the orbit backwards).
        let q = 0.8;
        let x0 = DVec3::new(0.0, 0.0, q);
        let v0 = DVec3::new((mu * (1.0 + e) / q).sqrt(), 0.0, 0.0);
        let cross = q / v0.length();
        for k in [-50.0, -1.0, 1e-6, 0.5, 1.0, 7.0, 50.0] {
            let t = k * cross;
            let (p, _) = kepler_flow(PM.center + x0, v0, &PM, t).unwrap();
            let expected = kepler_hyperbola(x0, v0, mu, t);
            let size = expected.length();
            // Both solve well-conditioned equations to rounding; the elements from the state
            // carry a few ulps of (e - 1) into F, hence 1e-11 at e = 1.01.
            let err = (p - PM.center - expected).length();
            assert!(err <= 1e-11 * size, "e = {e}, t = {k}: off by {err:e}");
        }
    }
    // The parabola: r0 = 2, v0 = 1 = sqrt(2 mu / r0) at mu = 1, so alpha is 0 exactly. Barker:
    // with D = tan(nu / 2), t = sqrt(2 q^3 / mu) (D + D^3 / 3), position q (1 - D^2, 2 D).
    let pm = PointMass {
        center: DVec3::ZERO,
        mu: 1.0,
    };
    let (q, x0, v0) = (2.0, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0));
    let orbit = KeplerOrbit::new(x0, v0, &pm).unwrap();
    assert_eq!(orbit.alpha(), 0.0);
    for t in [-300.0, -4.0, 0.1, 1.0, 10.0, 1e4] {
        let k = (2.0f64 * q * q * q).sqrt();
        let d = bisect(|d| k * (d + d * d * d / 3.0) - t, -1e3, 1e3);
        let expected = q * DVec3::new(1.0 - d * d, 2.0 * d, 0.0);
        let (p, _) = orbit.state_at(t).unwrap();
        let err = (p - expected).length();
        assert!(err <= 1e-12 * expected.length(), "t = {t}: off by {err:e}");
    }
}

#[test]
fn the_anomaly_solve_converges_in_a_few_iterations_for_any_eccentricity() {
    // Safeguarded Laguerre: measured well under 10 iterations; 12 leaves room, and the cap
    // (MAX_ITERATIONS) is never reached.
    let mut worst = 0;
    let cases: Vec<(f64, f64)> = [0.0, 0.5, 0.9, 0.99, 0.999, 0.9999]
        .iter()
        .map(|e| (1.0, *e))
        .chain([1.0001, 1.5, 10.0, 100.0].iter().map(|e| (-1.0, *e)))
        .collect();
    for (a, e) in cases {
        for apo in [false, true] {
            if a < 0.0 && apo {
                continue;
            }
            let (p0, v0) = if a > 0.0 {
                start(a, e, apo)
            } else {
                let q = -a * (e - 1.0);
                let v = (PM.mu * (1.0 + e) / q).sqrt();
                (PM.center + DVec3::new(q, 0.0, 0.0), DVec3::new(0.0, v, 0.0))
            };
            let orbit = KeplerOrbit::new(p0, v0, &PM).unwrap();
            let scale_t = (a.abs().powi(3) / PM.mu).sqrt();
            for i in 0..400 {
                let t = scale_t * 1e-3 * 1.06f64.powi(i);
                // Both solves a step may make: from the start, and from periapsis.
                let from_start = orbit.anomaly(t).unwrap();
                let from_periapsis = orbit.periapsis_anomaly(t);
                assert_eq!(from_periapsis.is_some(), e > 0.5);
                for anomaly in std::iter::once(from_start).chain(from_periapsis) {
                    assert!(anomaly.converged, "e = {e}, t = {t}: {anomaly:?}");
                    assert!(anomaly.iterations <= 12, "e = {e}, t = {t}: {anomaly:?}");
                    worst = worst.max(anomaly.iterations);
                }
            }
        }
    }
    assert!(worst < MAX_ITERATIONS);
}

/// The largest relative change of the energy and of the angular momentum (per unit mass) of a
/// body of mass 1.5 on an orbit of `a = 1`, eccentricity `e` about `pm`, started at periapsis and
/// stepped 1e5 times with `exact` at 100 steps an orbit; and their change in one jump to the
/// same time.
fn invariant_drift(pm: PointMass, e: f64) -> ((f64, f64), (f64, f64)) {
    let period = std::f64::consts::TAU / pm.mu.sqrt();
    let (p0, v0) = start(1.0, e, false);
    let (p0, c) = (p0 - PM.center + pm.center, pm.center);
    let text = format!(
        "Scene(dt: {}, integrator: Exact,
           forces: [PointMass(center: ({}, {}, {}), mu: {})],
           bodies: [(mass: 1.5, position: ({}, {}, {}), launch: Velocity(({}, {}, {})))])",
        period / 100.0,
        c.x,
        c.y,
        c.z,
        pm.mu,
        p0.x,
        p0.y,
        p0.z,
        v0.x,
        v0.y,
        v0.z,
    );
    let scene = scene::parse(&text, "inline.ron", "inline").unwrap();
    let invariants = |p: DVec3, v: DVec3| {
        let x = p - c;
        (0.5 * v.length_squared() - pm.mu / x.length(), x.cross(v))
    };
    let mut world = World::new(&scene);
    let s0 = world.bodies().state(0);
    let (e0, h0) = invariants(s0.p, world.velocity(0));
    let change = |(en, h): (f64, DVec3)| (((en - e0) / e0).abs(), (h - h0).length() / h0.length());
    let (mut de, mut dh) = (0.0f64, 0.0f64);
    for _ in 0..100_000 {
        world.step().unwrap();
        let (a, b) = change(invariants(
            world.bodies().positions().get(0),
            world.velocity(0),
        ));
        (de, dh) = (de.max(a), dh.max(b));
    }
    assert!(world.time() > 999.0 * period);
    let jump = closed_form(scene.forces(), s0, 1.5, world.time()).unwrap();
    ((de, dh), change(invariants(jump.p, jump.mv / 1.5)))
}

#[test]
fn energy_and_angular_momentum_hold_over_1000_orbits() {
    // mu = 2.5, a = 1: T = 3.974 s, dt = T/100 rounded to whole nanoseconds, 1e5 steps from
    // periapsis. Each step is the exact flow up to rounding, and the energy is put back to the
    // start's (evaluated in double-double) before the new momentum is rounded, so what is left
    // is one rounding of the state a step: a random walk far below 1e-12 (the correctly rounded
    // flow, computed in 40 digits, walks 1e-13 at e = 0.9 over the same run).
    let origin = PointMass {
        center: DVec3::ZERO,
        ..PM
    };
    for e in [0.0, 0.5, 0.9, 0.99] {
        let ((de, dh), (je, jh)) = invariant_drift(origin, e);
        assert!(
            de <= 1e-12 && dh <= 1e-12,
            "e = {e}: dE/E {de:e}, dh/h {dh:e}"
        );
        assert!(
            je <= 1e-12 && jh <= 1e-12,
            "e = {e}: one jump dE/E {je:e}, dh/h {jh:e}"
        );
    }
}

#[test]
fn away_from_the_origin_periapsis_is_stored_to_ulps_of_the_centre() {
    // With the centre at (3, -1, 2) a position at periapsis is rounded to ulps of |p| = 3.7 m,
    // not of r_p: at e = 0.99 (r_p = 0.01 m) each passage moves the orbit by up to
    // ulp(3.7) sqrt(3) / 2 / r_p = 3.8e-14 of its size, and 1000 passages walk the invariants
    // by about sqrt(1000) times that, 1.2e-12; three times that is allowed. At e <= 0.9 the
    // floor is ten times lower and 1e-12 holds.
    for e in [0.5, 0.9, 0.99] {
        let ((de, dh), (je, jh)) = invariant_drift(PM, e);
        let rp = 1.0 - e;
        let floor = 3.0 * 1000f64.sqrt() * (4.0 * f64::EPSILON) * 3f64.sqrt() / 2.0 / rp;
        let bound = floor.max(1e-12);
        assert!(
            de <= bound && dh <= bound,
            "e = {e}: dE/E {de:e}, dh/h {dh:e} (bound {bound:e})"
        );
        assert!(
            je <= 1e-12 && jh <= 1e-12,
            "e = {e}: one jump dE/E {je:e}, dh/h {jh:e}"
        );
    }
}

#[test]
fn a_body_dropped_from_rest_falls_in_and_is_refused_at_the_centre() {
    // Radial free fall from r0 at rest: a degenerate ellipse with a = r0 / 2, r = a (1 - cos E)
    // (E from pi), t = sqrt(a^3 / mu) (E - sin E - pi); it reaches the centre at
    // t_c = pi sqrt(a^3 / mu).
    let pm = PointMass {
        center: DVec3::new(1.0, 2.0, 3.0),
        mu: 4.0,
    };
    let dir = DVec3::new(2.0, -1.0, 2.0) / 3.0;
    let r0 = 9.0;
    let orbit = KeplerOrbit::new(pm.center + r0 * dir, DVec3::ZERO, &pm).unwrap();
    assert!(orbit.is_radial());
    let a = r0 / 2.0;
    let n = (pm.mu / (a * a * a)).sqrt();
    let tc = std::f64::consts::PI / n;
    let got = orbit.collision_time().unwrap();
    assert!((got - tc).abs() <= 1e-14 * tc, "{got} vs {tc}");
    for frac in [0.1, 0.5, 0.9, 0.999] {
        let t = frac * tc;
        let big_e = bisect(
            |big_e| big_e - big_e.sin() - std::f64::consts::PI - n * t,
            std::f64::consts::PI,
            std::f64::consts::TAU,
        );
        let r = a * (1.0 - big_e.cos());
        let (p, v) = orbit.state_at(t).unwrap();
        // Along the line, inwards, at the distance of the radial Kepler equation: its
        // conditioning grows like 1 / r near the centre, hence the looser bound at 0.999.
        let x = p - pm.center;
        assert!(
            (x.length() - r).abs() <= 1e-12 * r0 / (r / r0),
            "t = {frac} tc"
        );
        assert!(x.normalize().dot(dir) > 1.0 - 1e-12 && v.dot(dir) < 0.0);
    }
    for t in [tc, 1.5 * tc, 100.0 * tc] {
        assert_eq!(orbit.state_at(t), Err(KeplerError::Collision { time: got }));
    }
    // Moving straight out faster than escape: never comes back, no collision.
    let out = KeplerOrbit::new(pm.center + r0 * dir, 2.0 * dir, &pm).unwrap();
    assert!(out.is_radial() && out.collision_time().is_none());
    let (p, _) = out.state_at(1e6).unwrap();
    assert!((p - pm.center).normalize().dot(dir) > 1.0 - 1e-12);
}

#[test]
fn exact_stops_a_radial_fall_at_the_tick_that_reaches_the_centre() {
    // From rest at 9 m about mu = 4: t_c = pi sqrt(4.5^3 / 4) = 14.99 s, inside tick 900 at
    // 60 Hz (tick 899 ends at 14.98 s); the world stops there as a non-finite divergence.
    let text = "Scene(dt: 0.016666667, integrator: Exact,
        forces: [PointMass(center: (0.0, 0.0, 0.0), mu: 4.0)],
        bodies: [(mass: 1.0, position: (9.0, 0.0, 0.0))], guard: (every: 0))";
    let scene = scene::parse(text, "inline.ron", "inline").unwrap();
    let tc = std::f64::consts::PI * (4.5f64.powi(3) / 4.0).sqrt();
    let mut world = World::new(&scene);
    let d = world.step_ticks(2000).unwrap_err();
    assert_eq!(d.tick, (tc / scene.dt()).ceil() as u64);
    assert_eq!((d.body.0, d.cause), (0, DivergenceCause::NonFinite));
    // A state that cannot be evaluated never panics: at the centre, or with a NaN time.
    let at_centre = PointMass {
        center: DVec3::ONE,
        mu: 1.0,
    };
    assert_eq!(
        kepler_flow(DVec3::ONE, DVec3::X, &at_centre, 1.0),
        Err(KeplerError::AtCentre)
    );
    assert_eq!(
        kepler_flow(DVec3::ZERO, DVec3::X, &at_centre, f64::NAN),
        Err(KeplerError::InvalidInput)
    );
}

#[test]
fn exact_runs_a_lone_point_mass_and_refuses_one_with_company() {
    let lone = Forces {
        point_mass: Some(PM),
        ..Forces::default()
    };
    assert_eq!(scene::check_integrator(Integrator::Exact, &lone), Ok(()));
    let perturbed = Forces {
        gravity: Some(DVec3::NEG_Z),
        ..lone.clone()
    };
    let err = scene::check_integrator(Integrator::Exact, &perturbed).unwrap_err();
    assert!(
        err.to_string()
            .contains("force term PointMass has one only alone"),
        "{err}"
    );
    let s0 = BodyState {
        p: DVec3::new(5.0, 0.0, 0.0),
        mv: DVec3::new(0.0, 1.0, 0.0),
    };
    assert_eq!(closed_form(&perturbed, s0, 1.0, 1.0), None);
    assert!(closed_form(&lone, s0, 1.0, 1.0).is_some());
}
