//! Hard cases 1, 2 and 10: a stiff spring, strong drag, a critically damped spring.
//!
//! On the test equation each method multiplies the state by its stability function R; in the
//! coordinates (x, v/w) of an undamped oscillator that is a complex multiplication by R(i w h),
//! so the energy of explicit Euler, midpoint, RK4 and implicit Euler changes by exactly
//! |R(i w h)|^2 per step, and the guard (10x the start energy) trips at the first tick past it.

use volley_lab::stability;
use volley_sim::Integrator::{self, *};
use volley_sim::internals::world::DivergenceCause;

use super::{allowed, diverged, load, run, ticks_to_pass, with};

/// |R(i y)|^2 of the methods whose step is a complex multiplication on the oscillator.
fn oscillator_energy_ratio(integrator: Integrator, y: f64) -> Option<f64> {
    let y2 = y * y;
    match integrator {
        ExplicitEuler => Some(1.0 + y2),
        Midpoint => Some((1.0 - y2 / 2.0).powi(2) + y2),
        Rk4 => Some((1.0 - y2 / 2.0 + y2 * y2 / 24.0).powi(2) + (y - y2 * y / 6.0).powi(2)),
        ImplicitEuler => Some(1.0 / (1.0 + y2)),
        // The Cayley transform of a rotation is a rotation.
        ImplicitMidpoint => Some(1.0),
        _ => None,
    }
}

#[test]
fn stiff_spring_energy_changes_by_the_stability_function_and_the_guard_catches_growth() {
    let scene = load("hard/stiff_spring");
    let y = 100.0 * scene.dt(); // w = sqrt(k/m) = 100 rad/s
    for integrator in [
        ExplicitEuler,
        Midpoint,
        Rk4,
        ImplicitEuler,
        ImplicitMidpoint,
    ] {
        let ratio = oscillator_energy_ratio(integrator, y).unwrap();
        let (trace, result, _) = run(&with(&scene, integrator), 600);
        for pair in trace.energy.windows(2).take(2) {
            // Exact in real arithmetic; a few ulps of rounding per step.
            let r = pair[1] / pair[0];
            assert!(
                (r - ratio).abs() < 1e-12 * ratio,
                "{integrator}: {r} vs {ratio}"
            );
        }
        if ratio > 1.0 {
            let d = diverged(&result, integrator.name());
            assert_eq!(d.tick, ticks_to_pass(ratio, 10.0), "{integrator}");
            assert_eq!(d.body.0, 0);
            assert!(
                matches!(d.cause, DivergenceCause::EnergyGrowth { .. }),
                "{d}"
            );
        } else {
            assert!(
                result.is_ok(),
                "{integrator} decays and must not be stopped: {result:?}"
            );
        }
    }
}

#[test]
fn stiff_spring_symplectic_methods_stay_bounded() {
    let scene = load("hard/stiff_spring");
    let y = 100.0 * scene.dt();
    // Semi-implicit Euler conserves Q = v^2 + w^2 x^2 - h w^2 x v, so from rest E/E0 stays in
    // [1/(1 + y/2), 1/(1 - y/2)]; Verlet conserves v^2 + w^2 x^2 (1 - y^2/4), so from rest at the
    // amplitude E/E0 stays in [1 - y^2/4, 1]. Rounding over 600 steps: 1e-9 relative is generous.
    let bounds = [
        (
            SemiImplicitEuler,
            1.0 / (1.0 + y / 2.0),
            1.0 / (1.0 - y / 2.0),
        ),
        (VelocityVerlet, 1.0 - y * y / 4.0, 1.0),
    ];
    for (integrator, lo, hi) in bounds {
        let (trace, result, _) = run(&with(&scene, integrator), 600);
        assert!(result.is_ok(), "{integrator}: {result:?}");
        let e0 = trace.energy[0];
        for (tick, e) in trace.energy.iter().enumerate() {
            let r = e / e0;
            assert!(
                r >= lo - 1e-9 && r <= hi + 1e-9,
                "{integrator} tick {tick}: E/E0 = {r}"
            );
        }
    }
}

#[test]
fn stiff_spring_exact_is_the_oscillation_itself() {
    // A zero-rest-length spring is linear: `exact` runs it, at w h = 1.667 as at any step.
    let scene = load("hard/stiff_spring");
    assert!(allowed(&scene).contains(&Exact));
    let (trace, result, _) = run(&with(&scene, Exact), 600);
    assert!(result.is_ok(), "{result:?}");
    let (w, h) = (100.0, scene.dt());
    for (n, p) in trace.p.iter().enumerate() {
        // From rest at 1 m: x = cos(w t). Each step composes the exact flow, so only rounding
        // accumulates, about an ulp a step: 600 steps stay below 1e-12 m.
        let x = (w * n as f64 * h).cos();
        assert!((p.x - x).abs() < 1e-12, "tick {n}: {} vs {x}", p.x);
    }
    let e0 = trace.energy[0];
    assert!(trace.energy.iter().all(|e| (e - e0).abs() < 1e-12 * e0));
}

#[test]
fn stiff_spring_overflow_is_caught_as_non_finite_without_the_energy_guard() {
    let scene = with(&load("hard/stiff_spring"), ExplicitEuler);
    let scene = scene
        .edit()
        .guard(volley_sim::Guard {
            every: 0,
            ..scene.guard()
        })
        .build()
        .unwrap();
    let y = 100.0 * scene.dt();
    let (_, result, world) = run(&scene, 5000);
    let d = diverged(&result, "explicit-euler, no energy guard");
    assert_eq!((d.body.0, d.cause), (0, DivergenceCause::NonFinite));
    // The amplitude grows by rho = sqrt(1 + y^2) per step from 1 m; the force k x (k = 1e4)
    // overflows once rho^n passes f64::MAX / 1e4, and not before rho^n passes f64::MAX / 1e5.
    let ln_rho = 0.5 * (1.0 + y * y).ln();
    let earliest = ((f64::MAX / 1e5).ln() / ln_rho).floor() as u64;
    let latest = (f64::MAX.ln() / ln_rho).ceil() as u64 + 1;
    assert!(
        (earliest..=latest).contains(&d.tick),
        "tick {} not in {earliest}..={latest}",
        d.tick
    );
    assert_eq!(
        world.tick(),
        d.tick,
        "the world keeps the state it stopped at"
    );
}

#[test]
fn stiff_spring_at_1e5_every_explicit_method_is_flagged_before_running() {
    let scene = load("hard/stiff_spring_1e5");
    let y = 1e5f64.sqrt() * scene.dt();
    let report = stability::check(&scene);
    for v in &report.verdicts {
        // Dormand-Prince is explicit, but its controller shrinks the internal step instead.
        let explicit = !matches!(
            v.integrator,
            ImplicitEuler | Exact | ImplicitMidpoint | Dopri5
        );
        assert_eq!(v.stable, !explicit, "{}", v.integrator);
        // Substeps n with y / n inside the oscillator limit: the first whole n past y / limit.
        let expected = match v.integrator.info().oscillator_limit {
            None => None,
            Some(l) if l.is_finite() => Some((y / l).floor() as u32 + 1),
            Some(_) => Some(1),
        };
        assert_eq!(v.substeps, expected, "{}", v.integrator);
    }
    let text = report.warnings().join("\n");
    for needle in [
        "every explicit integrator diverges",
        "--substeps 3",
        "implicit-euler",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in:\n{text}");
    }
}

#[test]
fn stiff_spring_at_1e5_explicit_methods_diverge_and_the_fixes_hold() {
    let scene = load("hard/stiff_spring_1e5");
    let y = 1e5f64.sqrt() * scene.dt();
    for integrator in [
        ExplicitEuler,
        SemiImplicitEuler,
        VelocityVerlet,
        Midpoint,
        Rk4,
    ] {
        let (_, result, _) = run(&with(&scene, integrator), 600);
        let d = diverged(&result, integrator.name());
        match oscillator_energy_ratio(integrator, y) {
            Some(ratio) => assert_eq!(d.tick, ticks_to_pass(ratio, 10.0), "{integrator}"),
            // Amplitude x25.7 per step (spectral radius at y = 5.27): past 10x energy at once.
            None => assert!(d.tick <= 2, "{integrator}: tick {}", d.tick),
        }
    }
    let report = stability::check(&scene);
    for integrator in [SemiImplicitEuler, VelocityVerlet, Rk4] {
        let n = report.verdict(integrator).unwrap().substeps.unwrap();
        let mut fixed = with(&scene, integrator);
        fixed.set_substeps(n).unwrap();
        let (_, result, _) = run(&fixed, 600);
        assert!(result.is_ok(), "{integrator} at {n} substeps: {result:?}");
    }
    let (trace, result, _) = run(&with(&scene, ImplicitEuler), 600);
    assert!(result.is_ok());
    let r = trace.energy[1] / trace.energy[0];
    assert!(
        (r - 1.0 / (1.0 + y * y)).abs() < 1e-12,
        "implicit Euler damps by 1/(1+y^2): {r}"
    );
}

#[test]
fn strong_drag_multiplies_velocity_by_the_stability_function() {
    let scene = load("hard/strong_drag");
    let z = 200.0 * scene.dt(); // k h
    for integrator in allowed(&scene) {
        // A midpoint-rule substep of length c h multiplies v by (1 - c z/2) / (1 + c z/2).
        let cayley = |c: f64| (1.0 - c * z / 2.0) / (1.0 + c * z / 2.0);
        let c1 = 1.0 / (2.0 - 2f64.cbrt());
        let r = match integrator {
            ExplicitEuler | SemiImplicitEuler => 1.0 - z,
            VelocityVerlet | Midpoint => 1.0 - z + z * z / 2.0,
            Rk4 => 1.0 - z + z * z / 2.0 - z.powi(3) / 6.0 + z.powi(4) / 24.0,
            ImplicitEuler => 1.0 / (1.0 + z),
            Exact | Dopri5 => (-z).exp(),
            ForestRuth => cayley(c1) * cayley(1.0 - 2.0 * c1) * cayley(c1),
            ImplicitMidpoint => cayley(1.0),
        };
        let s = with(&scene, integrator);
        let mut one = volley_sim::World::new(&s);
        let v0 = one.velocity(0).x;
        let _ = one.step(); // the state it stopped at is kept if the guard trips
        let first = one.velocity(0).x / v0;
        // Dormand-Prince: each internal step's estimated error is at most tol (1 + |mV|), so
        // the tick's is at most attempts x that (evaluations: 1 + 6 per attempt).
        let allowed_error = if integrator == Dopri5 {
            let attempts = (one.force_evals() - 1) / 6;
            let mv0 = v0 * s.bodies()[0].mass;
            attempts as f64 * s.tolerance() * (1.0 + mv0) / mv0
        } else {
            1e-12 * r.abs().max(1.0)
        };
        let (trace, result, _) = run(&s, 120);
        assert!(
            (first - r).abs() < allowed_error,
            "{integrator}: {first} vs {r}"
        );
        if r.abs() > 1.0 {
            // Energy grows by r^2 per step; the guard's bound is 10x the start (kinetic only).
            let d = diverged(&result, integrator.name());
            assert_eq!(d.tick, ticks_to_pass(r * r, 10.0), "{integrator}");
        } else {
            assert!(result.is_ok(), "{integrator}: {result:?}");
            // Dormand-Prince's tolerance has an absolute part: below it the sign is noise.
            let floor = if integrator == Dopri5 {
                1e3 * s.tolerance()
            } else {
                0.0
            };
            for pair in trace.v.windows(2).filter(|p| p[1].x.abs() > floor) {
                // A negative factor (implicit midpoint, Forest-Ruth here) flips the sign each
                // step; the speed still falls.
                assert!(
                    pair[1].x.abs() < pair[0].x.abs()
                        && (pair[1].x.signum() == pair[0].x.signum()) == (r > 0.0),
                    "{integrator} does not decay by its factor"
                );
            }
        }
    }
    // Explicit Euler flips the sign every step: 1 - k h = -2.33.
    let unguarded = with(&scene, ExplicitEuler);
    let unguarded = unguarded
        .edit()
        .guard(volley_sim::Guard {
            every: 0,
            ..unguarded.guard()
        })
        .build()
        .unwrap();
    let (trace, _, _) = run(&unguarded, 3);
    assert!(trace.v[1].x < 0.0 && trace.v[2].x > 0.0 && trace.v[3].x < 0.0);
    assert!(trace.v[3].x.abs() > trace.v[2].x.abs());
}

/// Hard case 10's critical solution about the equilibrium, per axis: with `g = w = 10` and
/// `A = y0 - y_eq`, `y = y_eq + (A + (v0 + g A) t) e^(-g t)`.
fn critical_textbook(scene: &volley_sim::Scene, t: f64) -> glam::DVec3 {
    let s = scene.forces().spring.expect("a spring is declared");
    let b = scene.bodies()[0];
    let g = 10.0;
    let eq = s.anchor + scene.forces().gravity.unwrap() / 100.0;
    let a = b.position - eq;
    eq + (a + (b.velocity + g * a) * t) * (-g * t).exp()
}

#[test]
fn critical_spring_exact_is_the_critical_closed_form_at_every_tick() {
    let scene = load("hard/critical_spring");
    let (k, c, m) = (100.0, 20.0, scene.bodies()[0].mass);
    // Exactly critical in floating point: gamma^2 = (c / 2m)^2 = k / m.
    assert_eq!((c / (2.0 * m)) * (c / (2.0 * m)), k / m);
    assert_eq!(scene.integrator(), Exact);
    let (trace, result, world) = run(&scene, 600);
    assert!(result.is_ok(), "{result:?}");
    let s0 = volley_sim::internals::integrate::BodyState {
        p: scene.bodies()[0].position,
        mv: m * scene.bodies()[0].velocity,
    };
    for (n, p) in trace.p.iter().enumerate() {
        let t = n as f64 * scene.dt();
        let closed = volley_sim::internals::exact::closed_form(scene.forces(), s0, m, t).unwrap();
        // Each step composes the exact flow, so only rounding accumulates (an ulp of the 5 m
        // coordinates a step, damped by the flow itself): 1e-12 m over 600 steps. The closed
        // form and the textbook critical solution are both a few ulps from the truth.
        assert!(
            (*p - closed.p).length() < 1e-12,
            "tick {n}: {p} vs {}",
            closed.p
        );
        let textbook = critical_textbook(&scene, t);
        assert!((closed.p - textbook).length() < 1e-14 * 5.0, "tick {n}");
    }
    assert_eq!(world.force_evals(), 0);
}

#[test]
fn critical_spring_every_integrator_runs_with_its_order_and_settles() {
    let scene = load("hard/critical_spring");
    assert_eq!(allowed(&scene), Integrator::ALL.to_vec());
    let report = stability::check(&scene);
    assert!(report.verdicts.iter().all(|v| v.stable), "{report:?}");
    let eq = scene.forces().spring.unwrap().anchor + scene.forces().gravity.unwrap() / 100.0;
    // Largest position error against the closed form over the first second, at dt and dt / 2.
    let max_error = |integrator: Integrator, halve: bool| {
        let mut s = with(&scene, integrator);
        if halve {
            s.set_dt(scene.dt() / 2.0).unwrap();
        }
        let ticks = (1.0 / s.dt()).round() as u64;
        let (trace, result, _) = run(&s, ticks);
        assert!(result.is_ok(), "{integrator}: {result:?}");
        trace
            .p
            .iter()
            .enumerate()
            .map(|(n, p)| (*p - critical_textbook(&s, n as f64 * s.dt())).length())
            .fold(0.0, f64::max)
    };
    for integrator in Integrator::ALL {
        let (_, result, world) = run(&with(&scene, integrator), 600);
        assert!(result.is_ok(), "{integrator}: {result:?}");
        // Ten seconds is 100 decay times: every stable method has reached the equilibrium,
        // which is a fixed point of each of them, to rounding.
        let p = world.bodies().positions().get(0);
        assert!((p - eq).length() < 1e-12, "{integrator}: {p} vs {eq}");
        if integrator == Exact {
            continue;
        }
        if integrator == Dopri5 {
            // Adaptive: the error follows the tolerance, not dt. Each accepted internal step's
            // position error is at most tol (1 + |p|) by its estimate, and the damped flow does
            // not amplify earlier errors, so the sum over the attempts bounds the error.
            let s = with(&scene, Dopri5);
            let ticks = (1.0 / s.dt()).round() as u64;
            let (trace, _, world) = run(&s, ticks);
            let attempts = (world.force_evals() - ticks) / 6;
            let scale = 1.0
                + trace
                    .p
                    .iter()
                    .map(|p| p.abs().max_element())
                    .fold(0.0, f64::max);
            let bound = attempts as f64 * s.tolerance() * scale;
            let e = max_error(Dopri5, false);
            assert!(
                e < bound,
                "dopri5: error {e} m over {attempts} attempts, bound {bound}"
            );
            continue;
        }
        let order = integrator.info().order as i32;
        let ratio = max_error(integrator, false) / max_error(integrator, true);
        // The next term of the error expansion is O(w h) = 0.17 of the first at dt, so halving
        // dt divides the error by 2^order within 25%.
        let expected = 2f64.powi(order);
        assert!(
            (0.8 * expected..1.25 * expected).contains(&ratio),
            "{integrator}: halving dt divides the error by {ratio}, not 2^{order}"
        );
    }
}
