//! The linear test problem each integrator is checked on: the scalar copy of every scheme's
//! update on the linearised forces, its growth per step, and the largest stable step.

use glam::DVec3;

use super::*;

/// Periapsis distance (m) of the Kepler orbit through relative position `r` with velocity `v`.
pub(super) fn periapsis(mu: f64, r: DVec3, v: DVec3) -> f64 {
    let (rn, l2) = (r.length(), r.cross(v).length_squared());
    let energy = 0.5 * v.length_squared() - mu / rn;
    let e = (1.0 + 2.0 * energy * l2 / (mu * mu)).max(0.0).sqrt();
    // r_p = l^2 / (mu (1 + e)) holds for every conic; never above the current distance.
    (l2 / (mu * (1.0 + e))).min(rn)
}

/// The increment `(dx, dv)` of one step of `integrator` on the scalar test system
/// `x'' = -W x - K x'` (mass 1) from `(x, v)`: the same update as the integrator's scheme, with
/// implicit Euler treating only the `_lin` part implicitly. Increments rather than new states,
/// so that the growth `|1 + mu|` of a nearly neutral step is not lost in rounding against 1.
pub(super) fn linear_increment(
    integrator: Integrator,
    s: &Stiffness,
    h: f64,
    (x, v): (f64, f64),
) -> (f64, f64) {
    let (w2, k) = (s.w2_lin + s.w2_nl, s.k());
    let a = |x: f64, v: f64| -w2 * x - k * v;
    match integrator {
        Integrator::ExplicitEuler => (h * v, h * a(x, v)),
        Integrator::SemiImplicitEuler => {
            let dv = h * a(x, v);
            (h * (v + dv), dv)
        }
        Integrator::VelocityVerlet => {
            let a0 = a(x, v);
            let dv_half = 0.5 * h * a0;
            let dx = h * (v + dv_half);
            // With damping Volley evaluates the end force at the Euler-predicted velocity.
            let v_pred = if k == 0.0 { v + dv_half } else { v + h * a0 };
            (dx, dv_half + 0.5 * h * a(x + dx, v_pred))
        }
        Integrator::Midpoint => {
            let (mx, mv) = (x + 0.5 * h * v, v + 0.5 * h * a(x, v));
            (h * mv, h * a(mx, mv))
        }
        Integrator::Rk4 => {
            let stage = |x: f64, v: f64| (v, a(x, v));
            let k1 = stage(x, v);
            let k2 = stage(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = stage(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = stage(x + h * k3.0, v + h * k3.1);
            (
                h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
                h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
            )
        }
        Integrator::ForestRuth => {
            // Three generalised Verlet steps; the damping is implicit in the first half kick.
            let (c1, c2) = (FOREST_RUTH_C1, FOREST_RUTH_C2);
            let (mut dx, mut dv) = (0.0, 0.0);
            for c in [c1, c2, c1] {
                let (hc, (x, v)) = (c * h, (x + dx, v + dv));
                let dv_half = (0.5 * hc * (-w2 * x) - 0.5 * hc * k * v) / (1.0 + 0.5 * hc * k);
                let step_dx = hc * (v + dv_half);
                let v_half = v + dv_half;
                let step_dv = dv_half + 0.5 * hc * (-w2 * (x + step_dx) - k * v_half);
                (dx, dv) = (dx + step_dx, dv + step_dv);
            }
            (dx, dv)
        }
        Integrator::ImplicitMidpoint => {
            // The `_lin` part by the midpoint rule, the rest at the Euler-predicted midpoint.
            let (mx, mv) = (x + 0.5 * h * v, v + 0.5 * h * a(x, v));
            let a_nl = -s.w2_nl * mx - s.k_nl * mv;
            let damp = 0.5 * h * s.k_lin + 0.25 * h * h * s.w2_lin;
            let dv = (h * (a_nl - s.w2_lin * x) - 2.0 * damp * v) / (1.0 + damp);
            (h * (v + 0.5 * dv), dv)
        }
        // Dormand-Prince never gets here: `growth_per_step` answers for it first.
        Integrator::Dopri5 | Integrator::ImplicitEuler | Integrator::Exact => {
            // v' = (v + h (a_nl - W_lin x)) / (1 + h K_lin + h^2 W_lin), written as v' - v.
            let a_nl = -s.w2_nl * x - s.k_nl * v;
            let den = 1.0 + h * s.k_lin + h * h * s.w2_lin;
            let dv = h * (a_nl - s.w2_lin * x - s.k_lin * v - h * s.w2_lin * v) / den;
            (h * (v + dv), dv)
        }
    }
}

/// Growth of the exact flow over `h`: `e^(h Re(lambda_max))` of the test system.
pub(super) fn exact_growth(s: &Stiffness, h: f64) -> f64 {
    let (w2, k) = (s.w2_lin + s.w2_nl, s.k());
    let disc = k * k - 4.0 * w2;
    let re = if disc > 0.0 {
        -2.0 * w2 / (k + disc.sqrt())
    } else {
        -0.5 * k
    };
    libm::exp(h * re)
}

/// How one step amplifies the test system.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Growth {
    /// Spectral radius of the amplification matrix (1 = neutral).
    pub rho: f64,
    /// Whether `rho <= 1`, decided on the increments so rounding against 1 cannot flip it.
    pub stable: bool,
}

/// Spectral radius of `integrator`'s amplification matrix on `s` at step `h`, and whether it
/// is at most 1.
pub fn growth_per_step(integrator: Integrator, s: &Stiffness, h: f64) -> Growth {
    // The closed form grows as the flow does; Dormand-Prince's controller shrinks its internal
    // steps until the error estimate (and with it the growth) is bounded, at whatever cost.
    if matches!(integrator, Integrator::Exact | Integrator::Dopri5) {
        return Growth {
            rho: exact_growth(s, h),
            stable: true,
        };
    }
    // Forest-Ruth's backward substep (length c2 h, c2 = -1.70) solves its half kick with the
    // quadratic drag implicitly: `(h c2 / 2) k s^2/|v| + s = |rhs|` has no real root once
    // `2 |c2| h k_nl > 1` (k h > 0.29), and the step turns NaN however the linearisation grows.
    if integrator == Integrator::ForestRuth && 2.0 * FOREST_RUTH_C2.abs() * h * s.k_nl > 1.0 {
        return Growth {
            rho: f64::INFINITY,
            stable: false,
        };
    }
    // M = I + D; the eigenvalues of M are 1 + mu for the eigenvalues mu of D.
    let (a, c) = linear_increment(integrator, s, h, (1.0, 0.0));
    let (b, d) = linear_increment(integrator, s, h, (0.0, 1.0));
    let (tr, det) = (a + d, a * d - b * c);
    let disc = tr * tr - 4.0 * det;
    // Rounding allowance: a few ulps of the increments' own size. Forest-Ruth's increments
    // are sums over three substeps whose own increments are of order 1 (the middle one runs
    // backwards 1.7 h), so `det(M) - 1 = tr + det` carries a few ulps of 1, not of the sum.
    let mut tol = 8.0 * f64::EPSILON * (tr.abs() + det.abs());
    if integrator == Integrator::ForestRuth {
        tol = tol.max(64.0 * f64::EPSILON);
    }
    // The edge at 1 + mu = -1 is excluded: there the two eigenvalues meet at -1 (symplectic
    // Euler and Verlet at w h = 2 exactly) and the matrix is defective, so the state grows
    // linearly (tripling the spring's stretch in the first step). The edge at +1 stays: free
    // flight (k = 0) is a defective +1, and moving at constant velocity is not a divergence.
    if disc < 0.0 {
        // mu = alpha +- i beta: |1 + mu|^2 = 1 + 2 alpha + alpha^2 + beta^2 = 1 + tr + det.
        let excess = tr + det;
        Growth {
            rho: (1.0 + excess).sqrt(),
            stable: excess <= tol && tr > -4.0 + tol,
        }
    } else {
        let root = disc.sqrt();
        let big = if tr >= 0.0 {
            0.5 * (tr + root)
        } else {
            0.5 * (tr - root)
        };
        let small = if big != 0.0 { det / big } else { 0.0 };
        let (hi, lo) = (big.max(small), big.min(small));
        Growth {
            rho: (1.0 + hi).abs().max((1.0 + lo).abs()),
            stable: hi <= tol && lo > -2.0 + tol,
        }
    }
}
