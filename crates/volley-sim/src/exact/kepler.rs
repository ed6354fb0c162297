//! Kepler's problem: a body around a fixed point mass, `x'' = -mu x / |x|^3`, solved exactly in
//! universal variables, one formulation for elliptic, parabolic and hyperbolic orbits.
//!
//! ## Universal variables
//!
//! With `r0 = |x0|`, `sigma0 = x0 . v0 / sqrt(mu)`, `alpha = 2 / r0 - |v0|^2 / mu` (the inverse
//! semi-major axis: `> 0` elliptic, `0` parabolic, `< 0` hyperbolic) and the universal anomaly
//! `chi` (sqrt m), let `z = alpha chi^2` and
//!
//! ```text
//! U0 = 1 - z c2(z),  U1 = chi (1 - z c3(z)),  U2 = chi^2 c2(z),  U3 = chi^3 c3(z)
//! ```
//!
//! with Stumpff's `c2(z) = (1 - cos sqrt z) / z`, `c3(z) = (sqrt z - sin sqrt z) / z^(3/2)`
//! (entire in `z`; cosh and sinh for `z < 0`; series near 0). Time and anomaly are related by
//! the universal Kepler equation
//!
//! ```text
//! sqrt(mu) t = F(chi) = r0 U1 + sigma0 U2 + U3,    dF/dchi = r(chi) = r0 U0 + sigma0 U1 + U2 > 0,
//! ```
//!
//! and the state follows from Lagrange's coefficients:
//! `x = f x0 + g v0`, `v = f' x0 + g' v0` with `f = 1 - U2 / r0`, `g = (r0 U1 + sigma0 U2) /
//! sqrt(mu)`, `f' = -sqrt(mu) U1 / (r r0)`, `g' = 1 - U2 / r`. (`g` is written from the
//! anomaly, not as `t - U3 / sqrt(mu)`, so that `f g' - f' g = 1` holds at the solved `chi`
//! whatever is left of the equation's residual: the result is the exact state at a time within
//! rounding of `t`, on the orbit, so the energy and angular momentum are kept to rounding.)
//! The displacement `x - x0 = -(U2 / r0) x0 + g v0` is what is added to the position, so short
//! steps lose nothing against the size of the orbit.
//!
//! ## Solving for chi
//!
//! `F` is increasing (its slope is the distance `r`), so the root is bracketed: by
//! `[0, 2 pi / sqrt(alpha)]` (one period) on an ellipse, after whole periods are taken off `t`
//! (`t - n T`, rounding only shifts the time, never leaves the orbit); on an open orbit by
//! doubling an upper bound until `F` passes `sqrt(mu) t`. Inside the bracket Laguerre's method
//! (Conway's choice for Kepler's equation, `n = 5`: it converges from anywhere on these
//! equations, cubically near the root) starts from `sqrt(mu) alpha t` on an ellipse (exact for a
//! circle) or `sqrt(mu) t / r0` otherwise; a step that leaves the bracket, or does not at least
//! halve the step before it, is replaced by bisection. So every iteration either converges fast
//! or halves the bracket, and at most [`MAX_ITERATIONS`] are made: the solve always ends, for any
//! eccentricity (tested to `e = 0.999` and on hyperbolas to `e = 100`).
//!
//! ## What is refused
//!
//! - A **radial** orbit (angular momentum zero within rounding, `|x0 x v0| <= 4 eps |x0| |v0|`,
//!   e.g. a body dropped from rest) falls into the centre at a finite time `t_c`. Up to `t_c`
//!   it is solved exactly like any other orbit (the formulas need no angular momentum); at and
//!   after `t_c` there is no solution of Newton's equations (the speed is infinite there, and
//!   whether the body swings around or hits is not decided by a state known to rounding), so
//!   [`KeplerError::Collision`] is returned with `t_c`. The `exact` integrator turns that into
//!   a non-finite state, which stops the run as a divergence at that tick.
//! - A body **at the centre**, a non-positive or non-finite `mu`, a non-finite state or time:
//!   [`KeplerError::AtCentre`] and [`KeplerError::InvalidInput`].

use std::f64::consts::TAU;

use glam::DVec3;

use super::series::{stumpff_c2, stumpff_c3};
use crate::forces::PointMass;

/// Most iterations of the solve for the universal anomaly. Each one either converges at least
/// as fast as bisection or bisects, and bisection alone takes the one-period bracket to an ulp
/// in about 60; an open orbit's bracket is found by doubling first.
pub const MAX_ITERATIONS: u32 = 100;

/// Why a Kepler orbit has no answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KeplerError {
    /// The body is at the attracting centre, where the force is undefined.
    AtCentre,
    /// A radial orbit (no angular momentum) reaches the centre at `time` (s after the start),
    /// at or before the time asked for; Newton's equations have no solution past it.
    Collision {
        /// When the body reaches the centre (s after the start state).
        time: f64,
    },
    /// `mu` is not a positive finite number, or the state or the time is not finite.
    InvalidInput,
}

impl std::fmt::Display for KeplerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KeplerError::AtCentre => f.write_str("the body is at the point mass's centre"),
            KeplerError::Collision { time } => write!(
                f,
                "a radial orbit (no angular momentum) reaches the centre {time} s after its \
                 start; there is no solution past that"
            ),
            KeplerError::InvalidInput => {
                f.write_str("mu must be positive and finite, and the state and time finite")
            }
        }
    }
}

impl std::error::Error for KeplerError {}

/// The universal anomaly at one time, and what it took to find it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anomaly {
    /// The universal anomaly chi (sqrt m) for the time asked, after whole periods were removed.
    pub chi: f64,
    /// Iterations of the safeguarded Laguerre solve (at most [`MAX_ITERATIONS`]).
    pub iterations: u32,
    /// Whether the last step was below rounding (otherwise the bracket ran out, or the
    /// iteration cap was met with the root known to the bracket's width).
    pub converged: bool,
}

/// A body's Kepler orbit about a fixed point mass, set up once from a state; evaluated at any
/// time with [`KeplerOrbit::state_at`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeplerOrbit {
    p0: DVec3,
    x0: DVec3,
    v0: DVec3,
    mu: f64,
    sqrt_mu: f64,
    r0: f64,
    sigma0: f64,
    alpha: f64,
    radial: bool,
}

impl KeplerOrbit {
    /// The orbit through position `p0` (m) with velocity `v0` (m/s) about `pm`.
    pub fn new(p0: DVec3, v0: DVec3, pm: &PointMass) -> Result<KeplerOrbit, KeplerError> {
        let mu = pm.mu;
        if !(mu.is_finite() && mu > 0.0 && p0.is_finite() && v0.is_finite()) {
            return Err(KeplerError::InvalidInput);
        }
        let x0 = p0 - pm.center;
        let r0 = x0.length();
        if r0 == 0.0 {
            return Err(KeplerError::AtCentre);
        }
        if !x0.is_finite() {
            return Err(KeplerError::InvalidInput);
        }
        let sqrt_mu = mu.sqrt();
        let h2 = x0.cross(v0).length_squared();
        let bound = 4.0 * f64::EPSILON * r0 * v0.length();
        Ok(KeplerOrbit {
            p0,
            x0,
            v0,
            mu,
            sqrt_mu,
            r0,
            sigma0: x0.dot(v0) / sqrt_mu,
            alpha: 2.0 / r0 - v0.length_squared() / mu,
            radial: h2 <= bound * bound,
        })
    }

    /// The inverse semi-major axis `alpha = 2 / r0 - v0^2 / mu` (1/m): `> 0` on an ellipse.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The eccentricity `|((v^2 - mu / r) x - (x . v) v) / mu|`.
    pub fn eccentricity(&self) -> f64 {
        let e = (self.v0.length_squared() - self.mu / self.r0) * self.x0
            - self.x0.dot(self.v0) * self.v0;
        e.length() / self.mu
    }

    /// The period `2 pi / (sqrt(mu) alpha^(3/2))` (s) of an ellipse; `None` on an open orbit.
    pub fn period(&self) -> Option<f64> {
        (self.alpha > 0.0).then(|| TAU / (self.sqrt_mu * self.alpha * self.alpha.sqrt()))
    }

    /// Whether the angular momentum is zero within rounding (see the module docs).
    pub fn is_radial(&self) -> bool {
        self.radial
    }

    /// When a radial orbit reaches the centre (s after the start), if it does going forward.
    pub fn collision_time(&self) -> Option<f64> {
        let chi = self.collision_anomaly()?;
        Some(self.at_anomaly(chi).f / self.sqrt_mu)
    }

    /// The anomaly at which a radial orbit reaches the centre going forward.
    ///
    /// With no angular momentum the eccentricity is 1, so on an ellipse `1 - alpha r0 = cos E0`
    /// and `sigma0 sqrt(alpha) = sin E0` (E the eccentric anomaly, `chi sqrt(alpha) = E - E0`),
    /// and the centre is `E = 0` (mod 2 pi); on a hyperbola the same with cosh and sinh; on a
    /// parabola `r' = sigma0 + chi` vanishes at `chi = -sigma0`. Each form tends to `-sigma0`
    /// as `alpha -> 0`.
    fn collision_anomaly(&self) -> Option<f64> {
        if !self.radial {
            return None;
        }
        let (a, s0, c) = (self.alpha, self.sigma0, 1.0 - self.alpha * self.r0);
        if a > 0.0 {
            let q = a.sqrt();
            let e0 = libm::atan2(s0 * q, c);
            // Falling in (E0 < 0): E reaches 0; rising (E0 >= 0): it comes back at 2 pi.
            let de = if s0 < 0.0 { -e0 } else { TAU - e0 };
            Some(de / q)
        } else if s0 >= 0.0 {
            None
        } else if a < 0.0 {
            let q = (-a).sqrt();
            Some(libm::asinh(-s0 * q) / q)
        } else {
            Some(-s0)
        }
    }

    /// The universal Kepler equation and Lagrange's coefficients' ingredients at `chi`.
    fn at_anomaly(&self, chi: f64) -> AtAnomaly {
        let z = self.alpha * chi * chi;
        let (c2, c3) = (stumpff_c2(z), stumpff_c3(z));
        let u2 = chi * chi * c2;
        let u3 = chi * chi * chi * c3;
        let u1 = chi * (1.0 - z * c3);
        let u0 = 1.0 - z * c2;
        let terms = [self.r0 * u1, self.sigma0 * u2, u3];
        AtAnomaly {
            f: terms[0] + terms[1] + terms[2],
            size: terms.iter().map(|t| t.abs()).sum(),
            r: self.r0 * u0 + self.sigma0 * u1 + u2,
            f2: self.sigma0 * u0 + (1.0 - self.alpha * self.r0) * u1,
            u1,
            u2,
        }
    }

    /// The universal anomaly at `t >= 0` s after the start, whole periods of an ellipse removed.
    pub fn anomaly(&self, t: f64) -> Result<Anomaly, KeplerError> {
        if !(t.is_finite() && t >= 0.0) {
            return Err(KeplerError::InvalidInput);
        }
        if let Some(tc) = self.collision_time()
            && t >= tc
        {
            return Err(KeplerError::Collision { time: tc });
        }
        let (t, hi) = match self.period() {
            Some(period) => {
                let turns = libm::floor(t / period);
                let left = (t - turns * period).clamp(0.0, period);
                (left, Some(TAU / self.alpha.sqrt()))
            }
            None => (t, None),
        };
        Ok(self.solve(self.sqrt_mu * t, hi))
    }

    /// Safeguarded Laguerre on `F(chi) = target`, `target >= 0`, bracketed by `[0, period_chi]`
    /// on an ellipse.
    fn solve(&self, target: f64, period_chi: Option<f64>) -> Anomaly {
        let done = |chi: f64, iterations: u32, converged: bool| Anomaly {
            chi,
            iterations,
            converged,
        };
        if target == 0.0 {
            return done(0.0, 0, true);
        }
        let (mut lo, mut hi, guess) = match period_chi {
            Some(hi) => (0.0, hi, target * self.alpha),
            None => {
                let guess = target / self.r0;
                let (mut lo, mut hi) = (0.0, guess);
                // F grows at least like chi^3 / 6 on an open orbit, so a few doublings pass the
                // target; a non-finite F (cosh overflowing far past it) counts as past it.
                for _ in 0..2100 {
                    let past = !matches!(
                        self.at_anomaly(hi).f.partial_cmp(&target),
                        Some(std::cmp::Ordering::Less)
                    );
                    if past {
                        break;
                    }
                    lo = hi;
                    hi *= 2.0;
                }
                (lo, hi, guess)
            }
        };
        let mut chi = guess.clamp(lo, hi);
        let (mut step, mut step_before) = (f64::INFINITY, f64::INFINITY);
        for i in 1..=MAX_ITERATIONS {
            let at = self.at_anomaly(chi);
            let g = at.f - target;
            if g < 0.0 {
                lo = chi
            } else {
                hi = chi
            }
            // Laguerre's step for a polynomial of degree N (Conway: N = 5).
            const N: f64 = 5.0;
            let root = ((N - 1.0) * (N - 1.0) * at.r * at.r - N * (N - 1.0) * g * at.f2)
                .abs()
                .sqrt();
            let delta = -N * g / (at.r + root);
            // Converged: the step is below rounding of chi, or the residual is rounding of F's
            // terms (the next step would only chase that noise).
            let tiny = delta.abs() <= 2.0 * f64::EPSILON * chi.abs();
            if g == 0.0 || tiny || g.abs() <= 4.0 * f64::EPSILON * (at.size + target) {
                let last = chi + delta;
                let inside = last >= lo && last <= hi && last.is_finite();
                return done(if inside { last } else { chi }, i, true);
            }
            let mut next = chi + delta;
            if !(next > lo && next < hi) || delta.abs() > 0.5 * step_before {
                next = 0.5 * (lo + hi);
            }
            step_before = step;
            step = (next - chi).abs();
            if !(next > lo && next < hi) {
                // The bracket is down to adjacent numbers.
                return done(chi, i, false);
            }
            chi = next;
        }
        done(chi, MAX_ITERATIONS, false)
    }

    /// Position (m) and velocity (m/s) `t` s after the start (any sign: a negative time runs
    /// the orbit backwards).
    pub fn state_at(&self, t: f64) -> Result<(DVec3, DVec3), KeplerError> {
        if t == 0.0 {
            return Ok((self.p0, self.v0));
        }
        if t < 0.0 {
            let back = KeplerOrbit {
                v0: -self.v0,
                sigma0: -self.sigma0,
                ..*self
            };
            let (p, v) = back.state_at(-t)?;
            return Ok((p, -v));
        }
        let at = self.at_anomaly(self.anomaly(t)?.chi);
        let (r, u1, u2) = (at.r, at.u1, at.u2);
        let g = (self.r0 * u1 + self.sigma0 * u2) / self.sqrt_mu;
        let p = self.p0 + (-u2 / self.r0) * self.x0 + g * self.v0;
        let v = self.v0 + (-self.sqrt_mu * u1 / (r * self.r0)) * self.x0 + (-u2 / r) * self.v0;
        Ok((p, v))
    }
}

/// The universal Kepler equation at one anomaly.
struct AtAnomaly {
    /// `F(chi) = sqrt(mu) t`.
    f: f64,
    /// The sum of the sizes of `F`'s terms: its rounding is a few ulps of this.
    size: f64,
    /// `F'(chi) = r`, the distance (m).
    r: f64,
    /// `F''(chi) = r'`.
    f2: f64,
    /// `U1(chi)`.
    u1: f64,
    /// `U2(chi)`.
    u2: f64,
}

/// Exact flow of a body under a lone point mass over `t`: returns (p, v). See [`KeplerOrbit`].
pub fn kepler_flow(
    p0: DVec3,
    v0: DVec3,
    pm: &PointMass,
    t: f64,
) -> Result<(DVec3, DVec3), KeplerError> {
    KeplerOrbit::new(p0, v0, pm)?.state_at(t)
}
