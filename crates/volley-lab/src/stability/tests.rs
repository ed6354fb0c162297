use super::*;
use volley_sim::internals::forces::{Forces, Spring};
use volley_sim::internals::integrate::{BodyState, step_body};

/// The scalar replica must be the integrators' own update: compare one step on a damped
/// zero-rest spring (all terms linear, so implicit Euler treats them all implicitly).
#[test]
fn the_scalar_update_matches_the_integrators() {
    let (w2, k, h) = (40.0, 3.0, 0.05);
    let forces = Forces {
        spring: Some(Spring {
            anchor: DVec3::ZERO,
            stiffness: w2,
            rest_length: 0.0,
            damping: k,
        }),
        ..Forces::default()
    };
    let s = Stiffness {
        w2_lin: w2,
        k_lin: k,
        ..Stiffness::default()
    };
    // Not the closed form nor Dormand-Prince: `growth_per_step` answers for both without it.
    for integrator in Integrator::ALL
        .into_iter()
        .filter(|i| !matches!(i, Integrator::Exact | Integrator::Dopri5))
    {
        let start = BodyState {
            p: DVec3::new(0.7, 0.0, 0.0),
            mv: DVec3::new(-1.3, 0.0, 0.0),
        };
        let real = step_body(integrator, &forces, start, 1.0, h);
        let (dx, dv) = linear_increment(integrator, &s, h, (0.7, -1.3));
        let (x, v) = (0.7 + dx, -1.3 + dv);
        // Same operations in a different association: a few ulps of values of order 1.
        assert!(
            (real.p.x - x).abs() < 1e-14,
            "{integrator}: {} vs {x}",
            real.p.x
        );
        assert!(
            (real.mv.x - v).abs() < 1e-14,
            "{integrator}: {} vs {v}",
            real.mv.x
        );
    }
}

#[test]
fn the_oscillator_limit_itself_is_unstable() {
    // w = 20 rad/s at h = 0.1 s: w h = 2, the limit of symplectic Euler and Verlet, where
    // the step sends x0 to -3 x0 and grows linearly after; just below it, stable.
    let spring = Stiffness {
        w2_lin: 400.0,
        ..Stiffness::default()
    };
    for integrator in [Integrator::SemiImplicitEuler, Integrator::VelocityVerlet] {
        assert!(
            !growth_per_step(integrator, &spring, 0.1).stable,
            "{integrator}"
        );
        assert!(
            growth_per_step(integrator, &spring, 0.0995).stable,
            "{integrator}"
        );
    }
    // Free flight is a defective eigenvalue at +1 and stays stable.
    let free = Stiffness::default();
    assert!(growth_per_step(Integrator::SemiImplicitEuler, &free, 0.1).stable);
}

#[test]
fn the_limits_of_the_pure_cases_are_the_documented_ones() {
    let spring = Stiffness {
        w2_lin: 1.0,
        ..Stiffness::default()
    };
    let drag = Stiffness {
        k_lin: 1.0,
        ..Stiffness::default()
    };
    for integrator in Integrator::ALL {
        let info = integrator.info();
        let osc = max_stable_step(integrator, &spring, 10.0);
        match info.oscillator_limit {
            None => assert_eq!(osc, None, "{integrator}"),
            Some(l) if l.is_finite() => {
                let m = osc.expect("stable below its limit");
                // Bisection to 2^-60 of the bracket; the growth tolerance moves the edge
                // by at most sqrt(1e-12) relative where rho touches 1 tangentially.
                assert!((m - l).abs() < 2e-6 * l, "{integrator}: {m} vs {l}");
            }
            Some(_) => assert_eq!(osc, Some(10.0), "{integrator}"),
        }
        // Forest-Ruth on drag is unstable only in a band, 1.1344 < k h < 1.2006 (its
        // backward substep's factor has a pole at k h = 2 / 1.70): search from inside it.
        let from = if integrator == Integrator::ForestRuth {
            assert!(growth_per_step(integrator, &drag, 10.0).stable);
            assert!(growth_per_step(integrator, &drag, 1.21).stable);
            1.16
        } else {
            10.0
        };
        let d = max_stable_step(integrator, &drag, from).expect("drag is stable for small k h");
        let expected = info.drag_limit.min(from);
        assert!(
            (d - expected).abs() < 2e-6 * expected,
            "{integrator}: {d} vs {expected}"
        );
    }
}
