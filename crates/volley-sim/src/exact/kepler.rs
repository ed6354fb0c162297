//! Kepler's problem: a body around a fixed point mass, `x'' = -mu x / |x|^3`, solved exactly in
//! universal variables, one formulation for elliptic, parabolic and hyperbolic orbits.
//!
//! One file past the crate's ~600 lines on purpose: it is one algorithm (the universal-variable
//! solve, its two ways to the state and its refusals) whose derivation below is a fifth of it,
//! and whose pieces share the private orbit state; split, each part would be read only beside
//! the others.
//!
//! ## Universal variables
//!
//! From a base point at distance `rb` with `sigma_b = x . v / sqrt(mu)` there, with
//! `alpha = 2 / r - |v|^2 / mu` (the inverse semi-major axis: `> 0` elliptic, `0` parabolic,
//! `< 0` hyperbolic) and the universal anomaly `chi` (sqrt m), let `z = alpha chi^2` and
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
//! sqrt(mu) t = F(chi) = rb U1 + sigma_b U2 + U3,    dF/dchi = r(chi) = rb U0 + sigma_b U1 + U2 > 0.
//! ```
//!
//! ## Two ways to the state
//!
//! - **From the start**, the default: the base is the start state and Lagrange's coefficients
//!   give `x = f x0 + g v0`, `v = f' x0 + g' v0` with `f = 1 - U2 / r0`,
//!   `g = (r0 U1 + sigma0 U2) / sqrt(mu)`, `f' = -sqrt(mu) U1 / (r r0)`, `g' = 1 - U2 / r`,
//!   `r = |x|`. (`g` is written from the anomaly, not as `t - U3 / sqrt(mu)`, so that
//!   `f g' - f' g = 1` holds at the solved `chi`: the result is the exact state at a time within
//!   rounding of `t`.) A short step adds the displacement `(f - 1) x0 + g v0` to the position,
//!   so it loses nothing against the size of the orbit. With `e <= 1/2` the distance never
//!   falls below a third of the start's, so these sums never cancel by more than two bits.
//! - **From periapsis**, for a step whose sums above would cancel by more than two bits on an
//!   orbit with `e > 1/2`: the step that dives from `r0` to periapsis `q << r0` would form a
//!   small `x` and a large `v` as differences of terms the size of `x0` and `v0`, losing
//!   `log2(r0 / q)` bits (100 ulps at e = 0.99). Instead the orbit's frame is taken from the
//!   start state, every part of it well conditioned for `e > 1/2`: `h = |x0 x v0|`,
//!   `p = h^2 / mu`, `e = sqrt(1 - alpha p)` (not `|e_vec|`, whose `1 - e` would cancel),
//!   `q = p / (1 + e)`, the periapsis direction `P = e_vec / |e_vec|` and `Q = h_hat x P`, and
//!   the start's anomaly from periapsis, `chi0 = E0 / sqrt(alpha)` with
//!   `E0 = atan2(sigma0 sqrt(alpha), 1 - alpha r0)` (asinh on a hyperbola, `chi0 = sigma0` on a
//!   parabola), at time `t0 = F(chi0) / sqrt(mu)`. With periapsis as the base (`rb = q`,
//!   `sigma_b = 0`) the state at `t0 + t` is `x = (q - U2) P + (h U1 / sqrt(mu)) Q`,
//!   `v = (-sqrt(mu) U1 P + h U0 Q) / r`, `r = q U0 + U2`: sums whose terms do not cancel near
//!   periapsis. (Every step formed so would round the frame's unit vectors the same way orbit
//!   after orbit, which is why it is kept to the steps that need it.)
//!
//! Either way the new momentum is then corrected, by a few ulps, so that the energy evaluated in
//! double-double is the start's (see `keep_energy`): the exact flow conserves it, and without
//! the correction the same rounding repeated at every periapsis passage walks it.
//!
//! ## Solving for chi
//!
//! `F` is increasing (its slope is the distance `r`), so the root is bracketed: by
//! `[0, 2 pi / sqrt(alpha)]` (one period) on an ellipse, after whole periods are taken off `t`
//! (`t - n T`, rounding only shifts the time, never leaves the orbit); on an open orbit by
//! `min(sqrt(mu) t / rb, cbrt(6 sqrt(mu) t))` (a bound when not falling in), doubled until `F`
//! passes `sqrt(mu) t`. Inside the bracket Laguerre's method (Conway's choice for Kepler's
//! equation, `n = 5`: it converges from anywhere on these equations, cubically near the root)
//! starts from `sqrt(mu) alpha t` on an ellipse (exact for a circle), Vallado's logarithmic
//! guess on a hyperbola, or the bracket's end; a step that leaves the bracket, or does not at
//! least halve the step before it, is replaced by bisection. So every iteration either converges
//! fast or halves the bracket, and at most [`MAX_ITERATIONS`] are made: the solve always ends,
//! for any eccentricity (tested to `e = 0.9999` and on hyperbolas to `e = 100`).
//!
//! ## What is refused
//!
//! - A **radial** orbit, one that passes the centre closer than [`RADIAL_PERIAPSIS`] (4 ulps)
//!   of its start distance (zero angular momentum up to rounding: a body dropped from rest, or
//!   moving straight in), falls into the centre at a finite time `t_c`. Up to `t_c` it is
//!   solved exactly like any other orbit (from the start; the formulas need no angular
//!   momentum); at and after `t_c` Newton's equations have no solution (the speed is infinite
//!   there, and whether the body swings around or hits is not decided by a state known to
//!   rounding), so [`KeplerError::Collision`] is returned with `t_c`. The `exact` integrator
//!   turns that into a non-finite state, which stops the run as a divergence at that tick.
//!   (Continuing through the centre, as the regularised universal formulas would, makes the
//!   body bounce back out: the limit of ever thinner ellipses, but not Newton's answer, so it
//!   is not offered.)
//! - A body **at the centre**, a non-positive or non-finite `mu`, a non-finite state or time:
//!   [`KeplerError::AtCentre`] and [`KeplerError::InvalidInput`].

use std::f64::consts::TAU;

use glam::DVec3;

use super::compensated;
use super::series::{stumpff_c2, stumpff_c3};
use crate::forces::PointMass;

/// Most iterations of the solve for the universal anomaly. Each one either converges at least
/// as fast as bisection or bisects, and bisection alone takes the one-period bracket to an ulp
/// in about 60; an open orbit's bracket is found by doubling first.
pub const MAX_ITERATIONS: u32 = 100;

/// Eccentricity above which the state is formed from periapsis (see the module docs).
const FROM_PERIAPSIS_ABOVE: f64 = 0.5;

/// A periapsis closer to the centre than this many times the start distance counts as a
/// collision (4 ulps): the body would pass the centre closer than the rounding of its own
/// distance, which no state known to rounding can tell from hitting it. A state moving straight
/// in (zero angular momentum, or the few ulps of it that rounding leaves in a stepped fall that
/// is not along an axis) is always below it.
pub const RADIAL_PERIAPSIS: f64 = 4.0 * f64::EPSILON;

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
    center: DVec3,
    mu: f64,
    sqrt_mu: f64,
    alpha: f64,
    /// The start as the base of the universal variables.
    start: Base,
    radial: bool,
    /// The frame from periapsis, when the orbit is eccentric (`e > 1/2`) and not radial.
    frame: Option<Perifocal>,
}

/// A base point of the universal variables: its distance (m) and `x . v / sqrt(mu)` (sqrt m).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Base {
    r: f64,
    sigma: f64,
}

/// An eccentric orbit's frame at periapsis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Perifocal {
    /// Periapsis distance (m).
    q: f64,
    /// Angular momentum per mass (m^2/s).
    h: f64,
    /// Towards periapsis.
    p_hat: DVec3,
    /// In the orbit's plane, a quarter turn ahead of `p_hat`.
    q_hat: DVec3,
    /// Time (s) from periapsis to the start (negative before it).
    t0: f64,
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
        let alpha = 2.0 / r0 - v0.length_squared() / mu;
        let h_vec = x0.cross(v0);
        // Semi-latus rectum p = h^2 / mu and e = sqrt(1 - alpha p); periapsis q = p / (1 + e).
        let p = h_vec.length_squared() / mu;
        let e = (1.0 - alpha * p).max(0.0).sqrt();
        let q = p / (1.0 + e);
        let radial = q <= RADIAL_PERIAPSIS * r0;
        let mut orbit = KeplerOrbit {
            p0,
            x0,
            v0,
            center: pm.center,
            mu,
            sqrt_mu,
            alpha,
            start: Base {
                r: r0,
                sigma: x0.dot(v0) / sqrt_mu,
            },
            radial,
            frame: None,
        };
        if !radial && e > FROM_PERIAPSIS_ABOVE {
            orbit.frame = orbit.perifocal(h_vec, e, q);
        }
        Ok(orbit)
    }

    /// The frame at periapsis (see the module docs), if it comes out finite.
    fn perifocal(&self, h_vec: DVec3, e: f64, q: f64) -> Option<Perifocal> {
        let (x0, v0, mu) = (self.x0, self.v0, self.mu);
        let e_vec = (v0.length_squared() - mu / self.start.r) * x0 - x0.dot(v0) * v0;
        let p_hat = e_vec.normalize();
        let q_hat = (h_vec.normalize().cross(p_hat)).normalize();
        let (a, s0, c) = (
            self.alpha,
            self.start.sigma,
            1.0 - self.alpha * self.start.r,
        );
        let chi0 = if a > 0.0 {
            libm::atan2(s0 * a.sqrt(), c) / a.sqrt()
        } else if a < 0.0 {
            libm::asinh(s0 * (-a).sqrt() / e) / (-a).sqrt()
        } else {
            s0
        };
        let base = Base { r: q, sigma: 0.0 };
        let frame = Perifocal {
            q,
            h: h_vec.length(),
            p_hat,
            q_hat,
            t0: self.at_anomaly(base, chi0).f / self.sqrt_mu,
        };
        let finite = p_hat.is_finite() && q_hat.is_finite() && frame.t0.is_finite();
        finite.then_some(frame)
    }

    /// The inverse semi-major axis `alpha = 2 / r0 - v0^2 / mu` (1/m): `> 0` on an ellipse.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The eccentricity `|((v^2 - mu / r) x - (x . v) v) / mu|`.
    pub fn eccentricity(&self) -> f64 {
        let e = (self.v0.length_squared() - self.mu / self.start.r) * self.x0
            - self.x0.dot(self.v0) * self.v0;
        e.length() / self.mu
    }

    /// The period `2 pi / (sqrt(mu) alpha^(3/2))` (s) of an ellipse; `None` on an open orbit.
    pub fn period(&self) -> Option<f64> {
        (self.alpha > 0.0).then(|| TAU / (self.sqrt_mu * self.alpha * self.alpha.sqrt()))
    }

    /// Whether the orbit is radial: its periapsis is within [`RADIAL_PERIAPSIS`] times the
    /// start distance of the centre (zero angular momentum up to rounding).
    pub fn is_radial(&self) -> bool {
        self.radial
    }

    /// Whether the orbit has a periapsis frame (`e > 1/2`, not radial), from which the steps
    /// that dive towards periapsis are formed (see the module docs).
    pub fn has_periapsis_frame(&self) -> bool {
        self.frame.is_some()
    }

    /// When a radial orbit reaches the centre (s after the start), if it does going forward.
    pub fn collision_time(&self) -> Option<f64> {
        let chi = self.collision_anomaly()?;
        Some(self.at_anomaly(self.start, chi).f / self.sqrt_mu)
    }

    /// The anomaly at which a radial orbit reaches the centre going forward.
    ///
    /// On an ellipse `1 - alpha r0 = e cos E0` and `sigma0 sqrt(alpha) = e sin E0` (E the
    /// eccentric anomaly, `chi sqrt(alpha) = E - E0`), and the centre of a radial orbit is its
    /// periapsis `E = 0` (mod 2 pi); on a hyperbola the same with cosh and sinh (`e = 1` within
    /// rounding here); on a parabola `r' = sigma0 + chi` vanishes at `chi = -sigma0`. Each form
    /// tends to `-sigma0` as `alpha -> 0`.
    fn collision_anomaly(&self) -> Option<f64> {
        if !self.radial {
            return None;
        }
        let (a, s0, c) = (
            self.alpha,
            self.start.sigma,
            1.0 - self.alpha * self.start.r,
        );
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

    /// The universal Kepler equation from `base` at `chi`, and the U functions.
    fn at_anomaly(&self, base: Base, chi: f64) -> AtAnomaly {
        let z = self.alpha * chi * chi;
        let (c2, c3) = (stumpff_c2(z), stumpff_c3(z));
        let u2 = chi * chi * c2;
        let u3 = chi * chi * chi * c3;
        let u1 = chi * (1.0 - z * c3);
        let u0 = 1.0 - z * c2;
        let terms = [base.r * u1, base.sigma * u2, u3];
        AtAnomaly {
            f: terms[0] + terms[1] + terms[2],
            size: terms.iter().map(|t| t.abs()).sum(),
            r: base.r * u0 + base.sigma * u1 + u2,
            f2: base.sigma * u0 + (1.0 - self.alpha * base.r) * u1,
            u0,
            u1,
            u2,
        }
    }

    /// The universal anomaly from the start at `t >= 0` s after it (whole periods of an ellipse
    /// removed), as every step solves first.
    pub fn anomaly(&self, t: f64) -> Result<Anomaly, KeplerError> {
        if !(t.is_finite() && t >= 0.0) {
            return Err(KeplerError::InvalidInput);
        }
        if let Some(tc) = self.collision_time()
            && t >= tc
        {
            return Err(KeplerError::Collision { time: tc });
        }
        Ok(self.solve_signed(self.start, t))
    }

    /// The universal anomaly from periapsis at `t >= 0` s after the start, as solved when a
    /// step is formed from periapsis; `None` without a periapsis frame.
    pub fn periapsis_anomaly(&self, t: f64) -> Option<Anomaly> {
        let frame = self.frame?;
        (t.is_finite() && t >= 0.0).then(|| self.solve_signed(frame.base(), frame.t0 + t))
    }

    /// The anomaly from `base` at time `t` (any sign) after it.
    fn solve_signed(&self, base: Base, t: f64) -> Anomaly {
        if let Some(period) = self.period() {
            // One turn: rounding in t - n T only shifts the time along the orbit.
            let turns = libm::floor(t / period);
            let left = (t - turns * period).clamp(0.0, period);
            return self.solve(base, self.sqrt_mu * left, Some(TAU / self.alpha.sqrt()));
        }
        // An open orbit is traced backwards by the odd anomaly: only the periapsis base meets
        // negative times (the start's are reversed by `step`).
        let a = self.solve(base, self.sqrt_mu * t.abs(), None);
        Anomaly {
            chi: a.chi.copysign(t),
            ..a
        }
    }

    /// Safeguarded Laguerre on `F(chi) = target`, `target >= 0`, bracketed by `[0, period_chi]`
    /// on an ellipse.
    fn solve(&self, base: Base, target: f64, period_chi: Option<f64>) -> Anomaly {
        let done = |chi: f64, iterations: u32, converged: bool| Anomaly {
            chi,
            iterations,
            converged,
        };
        if target == 0.0 {
            return done(0.0, 0, true);
        }
        // F below the target (a non-finite F, cosh overflowing far past the root, is above).
        let below = |chi: f64| {
            matches!(
                self.at_anomaly(base, chi).f.partial_cmp(&target),
                Some(std::cmp::Ordering::Less)
            )
        };
        let (mut lo, mut hi, guess) = match period_chi {
            // exact for a circle: chi sqrt(alpha) is then the mean anomaly.
            Some(hi) => (0.0, hi, target * self.alpha),
            None => {
                // On an open orbit r0 U1 >= r0 chi and U3 >= chi^3 / 6, so when not falling in
                // (sigma_b >= 0) F passes the target by the smaller of these; otherwise doubling
                // from there does, F growing at least like chi^3 / 6.
                let mut hi = (target / base.r).min(libm::cbrt(6.0 * target));
                let mut lo = 0.0;
                for _ in 0..2100 {
                    if !below(hi) {
                        break;
                    }
                    lo = hi;
                    hi *= 2.0;
                }
                (lo, hi, self.hyperbolic_guess(base, target).unwrap_or(hi))
            }
        };
        let mut chi = guess.clamp(lo, hi);
        let (mut step, mut step_before) = (f64::INFINITY, f64::INFINITY);
        for i in 1..=MAX_ITERATIONS {
            let at = self.at_anomaly(base, chi);
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
            let finite = g.is_finite() && at.size.is_finite();
            let tiny = delta.abs() <= 2.0 * f64::EPSILON * chi.abs();
            if finite && (g == 0.0 || tiny || g.abs() <= 4.0 * f64::EPSILON * (at.size + target)) {
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

    /// Vallado's starting anomaly on a hyperbola, good for long times (where `F` grows like
    /// `e^(chi sqrt(-alpha))`): `sqrt(-a) ln(-2 mu alpha t / (x0 . v0 + sqrt(-mu a) (1 - alpha
    /// r0)))`, `a = 1 / alpha`; `None` where it is not a positive number.
    fn hyperbolic_guess(&self, base: Base, target: f64) -> Option<f64> {
        if self.alpha >= 0.0 {
            return None;
        }
        let a = 1.0 / self.alpha;
        let den = base.sigma * self.sqrt_mu + (-self.mu * a).sqrt() * (1.0 - self.alpha * base.r);
        let guess = (-a).sqrt() * libm::log(-2.0 * self.sqrt_mu * self.alpha * target / den);
        (guess.is_finite() && guess > 0.0).then_some(guess)
    }

    /// Position (m) and velocity (m/s) `t` s after the start (any sign: a negative time runs
    /// the orbit backwards).
    pub fn state_at(&self, t: f64) -> Result<(DVec3, DVec3), KeplerError> {
        let (p, v) = match self.step(t)? {
            Step::Lagrange(l) => (
                l.moved(self.p0, self.x0, self.v0),
                l.velocity(self.x0, self.v0),
            ),
            Step::Formed(p, v) => (p, v),
        };
        Ok((p, self.keep_energy(self.p0, self.v0, 1.0, p, v)))
    }

    /// `mv1` (a momentum, or a velocity with `m = 1`) corrected so that the energy of
    /// `(p1, mv1)`, evaluated in double-double, is the energy of the start `(p0, mv0)`.
    ///
    /// Forming the new state rounds its energy by a few ulps of the kinetic energy, and on an
    /// eccentric orbit stepped at a fixed step every periapsis passage repeats nearly the same
    /// rounding, so the energy walks (measured without this, 1000 orbits at 100 steps an orbit:
    /// 3e-12 at e = 0.9, 2e-11 at e = 0.99; with it 1e-13 and 5e-13, what a flow computed in 40
    /// digits and rounded to f64 each step does). The exact flow conserves the energy, so
    /// putting it back removes rounding only: the factor differs from 1 by a few ulps and is
    /// added as a correction, and one rounding of the new momentum is what is left. A
    /// correction above 1e-8 would mean the energy cannot be evaluated that well here (an
    /// overflow, a state next to the centre); the state is then left as formed.
    fn keep_energy(&self, p0: DVec3, mv0: DVec3, m: f64, p1: DVec3, mv1: DVec3) -> DVec3 {
        let energy = |p, mv| compensated::kepler_energy(p, mv, m, self.center, self.mu);
        let gap = energy(p0, mv0).add(energy(p1, mv1).neg()).hi;
        // Added as mv1 + d mv1: a factor 1 + d with d ~ 1e-16 would round to 1 or 1 + 2^-52.
        let d = gap * (m * m) / mv1.length_squared();
        if d.is_finite() && d.abs() < 1e-8 {
            mv1 + d * mv1
        } else {
            mv1
        }
    }

    /// The step over `t`: Lagrange's coefficients from the start, or, when their sums would
    /// cancel by more than two bits and the orbit has a periapsis frame, the state formed from
    /// periapsis.
    fn step(&self, t: f64) -> Result<Step, KeplerError> {
        if t == 0.0 {
            return Ok(Step::Lagrange(Lagrange::IDENTITY));
        }
        if !t.is_finite() {
            return Err(KeplerError::InvalidInput);
        }
        if t < 0.0 {
            // Reversing time is reversing the velocity: f and g' keep their values, g and f'
            // change sign, and a formed velocity is reversed.
            let pm = PointMass {
                center: self.center,
                mu: self.mu,
            };
            return Ok(match KeplerOrbit::new(self.p0, -self.v0, &pm)?.step(-t)? {
                Step::Lagrange(l) => Step::Lagrange(Lagrange {
                    g: -l.g,
                    f_dot: -l.f_dot,
                    ..l
                }),
                Step::Formed(p, v) => Step::Formed(p, -v),
            });
        }
        let l = self.coefficients(t)?;
        match self.frame {
            Some(frame) if l.cancels(self.x0, self.v0) => Ok(self.formed(&frame, t)),
            _ => Ok(Step::Lagrange(l)),
        }
    }

    /// Lagrange's coefficients from the start over `t > 0`.
    fn coefficients(&self, t: f64) -> Result<Lagrange, KeplerError> {
        let at = self.at_anomaly(self.start, self.anomaly(t)?.chi);
        let r0 = self.start.r;
        let f_minus_1 = -at.u2 / r0;
        let g = (r0 * at.u1 + self.start.sigma * at.u2) / self.sqrt_mu;
        // r as |f x0 + g v0|: equal to r(chi), which cancels where r << r0.
        let r = Lagrange::position(f_minus_1, g, self.x0, self.v0).length();
        Ok(Lagrange {
            f_minus_1,
            g,
            f_dot: -self.sqrt_mu * at.u1 / (r * r0),
            g_dot_minus_1: -at.u2 / r,
        })
    }

    /// The state `t` s after the start, formed from periapsis.
    fn formed(&self, frame: &Perifocal, t: f64) -> Step {
        let base = frame.base();
        let chi = self.solve_signed(base, frame.t0 + t).chi;
        let at = self.at_anomaly(base, chi);
        let x = (frame.q - at.u2) * frame.p_hat + (frame.h * at.u1 / self.sqrt_mu) * frame.q_hat;
        let v = ((-self.sqrt_mu * at.u1) * frame.p_hat + (frame.h * at.u0) * frame.q_hat) / at.r;
        Step::Formed(self.center + x, v)
    }
}

impl Perifocal {
    /// Periapsis as the base of the universal variables.
    fn base(&self) -> Base {
        Base {
            r: self.q,
            sigma: 0.0,
        }
    }
}

/// One step of an orbit: coefficients to apply to the start state, or the new state itself.
enum Step {
    Lagrange(Lagrange),
    Formed(DVec3, DVec3),
}

/// Lagrange's coefficients of a Kepler orbit over one time, as differences from the identity so
/// that a short step adds small numbers to the state rather than rounding it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Lagrange {
    /// `f - 1` (1): `f = 1 - U2 / r0`.
    f_minus_1: f64,
    /// `g` (s): `(r0 U1 + sigma0 U2) / sqrt(mu)`.
    g: f64,
    /// `f'` (1/s): `-sqrt(mu) U1 / (r r0)`.
    f_dot: f64,
    /// `g' - 1` (1): `g' = 1 - U2 / r`.
    g_dot_minus_1: f64,
}

impl Lagrange {
    const IDENTITY: Lagrange = Lagrange {
        f_minus_1: 0.0,
        g: 0.0,
        f_dot: 0.0,
        g_dot_minus_1: 0.0,
    };

    /// Whether forming the state from `x0` and `v0` with these coefficients would lose more
    /// than two bits: the sizes of the terms of `x` or of `v` over four times the result.
    fn cancels(self, x0: DVec3, v0: DVec3) -> bool {
        let (r0, s0) = (x0.length(), v0.length());
        let f = if self.short() {
            self.f_minus_1
        } else {
            1.0 + self.f_minus_1
        };
        let gd = if self.g_dot_minus_1.abs() <= 0.5 {
            self.g_dot_minus_1
        } else {
            1.0 + self.g_dot_minus_1
        };
        let x = Lagrange::position(self.f_minus_1, self.g, x0, v0).length();
        let v = self.velocity(x0, v0).length();
        f.abs() * r0 + self.g.abs() * s0 > 4.0 * x
            || self.f_dot.abs() * r0 + gd.abs() * s0 > 4.0 * v
    }

    /// Whether the step moved the body little (`|f - 1| <= 1/2`): then the displacement
    /// `(f - 1) x0 + g v0` is added to the state, otherwise the state is formed anew from
    /// `f x0 + g v0`, so that neither a short step rounds against the whole state nor a long one
    /// cancels the whole of `x0`.
    fn short(self) -> bool {
        self.f_minus_1.abs() <= 0.5
    }

    /// `x = f x0 + g v0`, relative to the centre.
    fn position(f_minus_1: f64, g: f64, x0: DVec3, v0: DVec3) -> DVec3 {
        if f_minus_1.abs() <= 0.5 {
            x0 + (f_minus_1 * x0 + g * v0)
        } else {
            (1.0 + f_minus_1) * x0 + g * v0
        }
    }

    /// The absolute position after the step from `p0` (relative position `x0`, velocity `v0`).
    fn moved(self, p0: DVec3, x0: DVec3, v0: DVec3) -> DVec3 {
        if self.short() {
            p0 + (self.f_minus_1 * x0 + self.g * v0)
        } else {
            (p0 - x0) + ((1.0 + self.f_minus_1) * x0 + self.g * v0)
        }
    }

    /// `f' x0 + g' u0` for the velocity (or momentum, with `f_dot` scaled by the mass) `u0`.
    fn velocity(self, x0: DVec3, u0: DVec3) -> DVec3 {
        if self.g_dot_minus_1.abs() <= 0.5 {
            u0 + (self.f_dot * x0 + self.g_dot_minus_1 * u0)
        } else {
            self.f_dot * x0 + (1.0 + self.g_dot_minus_1) * u0
        }
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
    /// `U0(chi)`.
    u0: f64,
    /// `U1(chi)`.
    u1: f64,
    /// `U2(chi)`.
    u2: f64,
}

/// The same flow on the seed's state `<mV, p>` of a body of mass `m`, as the `exact` integrator
/// applies it. From the start, `mV' = (m f') x0 + g' mV`: the momentum is not divided by `m` and
/// multiplied back (only the coefficients use `V = mV / m`), so rounding `1/m` does not scale it
/// a little every step, which would drift the energy by an ulp or so a step; from periapsis the
/// new velocity is formed and multiplied by `m` once. Returns (p, mV).
pub fn kepler_flow_momentum(
    p0: DVec3,
    mv0: DVec3,
    m: f64,
    pm: &PointMass,
    t: f64,
) -> Result<(DVec3, DVec3), KeplerError> {
    let v0 = mv0 / m;
    let orbit = KeplerOrbit::new(p0, v0, pm)?;
    let (p, mv) = match orbit.step(t)? {
        Step::Lagrange(l) => {
            let scaled = Lagrange {
                f_dot: m * l.f_dot,
                ..l
            };
            (l.moved(p0, orbit.x0, v0), scaled.velocity(orbit.x0, mv0))
        }
        Step::Formed(p, v) => (p, m * v),
    };
    Ok((p, orbit.keep_energy(p0, mv0, m, p, mv)))
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
