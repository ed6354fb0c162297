//! The exact flow of every linear scene: `x'' = a0 - kd x' - w2 (x - anchor)`.
//!
//! Gravity, a constant force, linear drag and a zero-rest-length spring with any damping add up
//! to this one equation with constant coefficients (per axis, the same scalars on all three).
//!
//! ## Derivation
//!
//! With `gamma = kd / 2`, the homogeneous equation `y'' + 2 gamma y' + w2 y = 0` has the impulse
//! response (the solution with `y(0) = 0`, `y'(0) = 1`)
//!
//! ```text
//! K(t) = e^(-gamma t) sinh(s t) / s,        s^2 = gamma^2 - w2   (the discriminant / 4),
//! ```
//!
//! an entire function of `s^2`: `sinh(s t)/s` becomes `t` at critical damping and
//! `sin(wd t)/wd` with `wd^2 = -s^2` below it. Every other solution is built from it:
//! `K' = e^(-gamma t)(cosh(s t) - gamma sinh(s t)/s)` moves a velocity, `K'' = -2 gamma K' - w2 K`,
//! and the response to a constant acceleration is `J(t) = integral_0^t K`, which solves
//! `J'' + 2 gamma J' + w2 J = 1` from rest. Starting from `(p0, v0)` the flow is
//!
//! ```text
//! p(t) = p0 + K(t) v0 + J(t) a_s,      v(t) = K'(t) v0 + K(t) a_s,      a_s = a0 - w2 (p0 - anchor),
//! ```
//!
//! (`a_s` is the acceleration at `p0` at rest). It is the drag flow's shape: at `w2 = 0`,
//! `K = t phi1(kd t)`, `K' = e^(-kd t)` and `J = t^2 phi2(kd t)`, so as the stiffness goes to 0
//! the flow goes to the drag (and, with `kd = 0`, the free-flight) solution, continuously, and
//! nothing is divided by `w2` or by the root difference `2 s`.
//!
//! The three kernels are evaluated so that they never cancel, with `x = gamma t`:
//!
//! - **Under-damped** (`s^2 < 0`, `wd = sqrt(w2 - gamma^2)`, `b = wd t`): `K = t e^-x sin(b)/b`,
//!   `K' = e^-x (cos b - x sin(b)/b)`, and, writing `cos b = 1 - b^2 c2(b^2)`,
//!   `sin(b)/b = 1 - b^2 c3(b^2)` (Stumpff's functions, both `>= 0`),
//!   `1 - e^-x (cos b + x sin(b)/b) = x^2 chi(x) + e^-x b^2 (c2 + x c3)`: a sum of two
//!   non-negative terms, so `J = t^2 (gamma^2 chi(x) + wd^2 e^-x (c2 + x c3)) / (gamma^2 + wd^2)`
//!   is a weighted mean of non-negative numbers (`chi(x) = (1 - e^-x (1 + x)) / x^2`).
//! - **Critical and over-damped** (`s^2 >= 0`): with the decay rates of the two modes,
//!   `lp = gamma + s` and `lm = gamma - s = w2 / lp` (the second form does not cancel when the
//!   spring is weak), `l = lm t`, `d = 2 s t`, `E = e^-l`:
//!   `K = t E phi1(d)`, `K' = E (e^-d - l phi1(d))`, and
//!   `J = t (l chi(l) + d E phi2(d)) / lp`, again non-negative terms only. The exponentials are
//!   of `l` and `d`, never `e^-x cosh(s t)` with both factors extreme, so a stiff, strongly
//!   over-damped spring (`gamma t = 1e4`) neither overflows nor underflows to 0.
//!
//! At `s^2 = 0` both forms give `K = t e^-x`, `K' = e^-x (1 - x)`, `J = t^2 chi(x)`: the
//! critically damped kernels. Both sides are smooth functions of `s^2` (the over-damped form is
//! even in `s`), so the rounding of the discriminant `gamma^2 - w2` near critical damping moves
//! the result by a rounding-sized amount only, and there is no precision lost at the boundary.
//!
//! The flow is exact for any `t`, so one call covers a whole trajectory; the `exact` integrator
//! calls it once per step.

use glam::DVec3;

use super::series::{chi, phi2, stumpff_c2, stumpff_c3};
use crate::forces::LinearPart;

/// The three scalar kernels of the linear flow over `t` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearKernel {
    /// `K(t)` (s): the displacement a unit initial velocity causes, and the velocity a unit
    /// constant acceleration causes.
    pub k: f64,
    /// `K'(t)` (1): the velocity a unit initial velocity keeps.
    pub k_dot: f64,
    /// `J(t)` (s^2): the displacement a unit constant acceleration causes from rest.
    pub j: f64,
}

impl LinearKernel {
    /// The kernels of `x'' = -kd x' - w2 x` (damping rate `kd` in 1/s, `w2` in 1/s^2) over `t` (s).
    ///
    /// Meant for `kd >= 0`, `w2 > 0`, any finite `t` (the formulas are analytic in `t`, so
    /// negative times run the flow backwards). At `w2 = 0` it is the drag flow, computed through
    /// the same kernels (the `exact` integrator keeps the older [`super::linear_drag_flow`] there).
    pub fn new(kd: f64, w2: f64, t: f64) -> LinearKernel {
        let gamma = 0.5 * kd;
        let disc = gamma * gamma - w2;
        if disc < 0.0 {
            under_damped(gamma, -disc, t)
        } else {
            over_damped(gamma, disc, w2, t)
        }
    }
}

fn under_damped(gamma: f64, wd2: f64, t: f64) -> LinearKernel {
    let (x, b) = (gamma * t, wd2.sqrt() * t);
    let z = b * b;
    let e = libm::exp(-x);
    let sinc = if b == 0.0 { 1.0 } else { libm::sin(b) / b };
    let g2 = gamma * gamma;
    let forced = (g2 * chi(x) + wd2 * e * (stumpff_c2(z) + x * stumpff_c3(z))) / (g2 + wd2);
    LinearKernel {
        k: t * e * sinc,
        k_dot: e * (libm::cos(b) - x * sinc),
        j: t * t * forced,
    }
}

fn over_damped(gamma: f64, s2: f64, w2: f64, t: f64) -> LinearKernel {
    let s = s2.sqrt();
    let lp = gamma + s;
    let lm = w2 / lp;
    let (l, d) = (lm * t, 2.0 * s * t);
    let e = libm::exp(-l);
    let p1 = super::phi1(d);
    LinearKernel {
        k: t * e * p1,
        k_dot: e * (libm::exp(-d) - l * p1),
        j: t * (l * chi(l) + d * e * phi2(d)) / lp,
    }
}

/// Exact flow of `x'' = a0 - kd x' - w2 (x - anchor)` (the [`LinearPart`] of any linear scene)
/// over `t`: returns (p, v).
///
/// At `w2 = 0` this is [`super::linear_drag_flow`] itself, bit for bit (the flow of every scene
/// `exact` covered before springs); otherwise the damped-oscillator kernels of
/// [`LinearKernel`], under-, critically or over-damped, with `p = p0 + K v0 + J a_s` and
/// `v = K' v0 + K a_s`, `a_s = a0 - w2 (p0 - anchor)`.
#[inline]
pub fn linear_flow(p0: DVec3, v0: DVec3, lin: &LinearPart, t: f64) -> (DVec3, DVec3) {
    if lin.w2 == 0.0 {
        return super::linear_drag_flow(p0, v0, lin.a0, lin.kd, t);
    }
    let kernel = LinearKernel::new(lin.kd, lin.w2, t);
    let a_s = lin.a0 - lin.w2 * (p0 - lin.anchor);
    let p = p0 + kernel.k * v0 + kernel.j * a_s;
    let v = kernel.k_dot * v0 + kernel.k * a_s;
    (p, v)
}

/// The same flow on the seed's state `<mV, p>` of a body of mass `m`, as the `exact` integrator
/// applies it with a spring (`w2 > 0`): `mV' = K' mV + K (m a_s)`, `p' = p + K (mV / m) + J a_s`.
/// The momentum is not turned into a velocity and back, so rounding `1/m` does not scale it a
/// little every step (on an undamped spring, an energy drift of about an ulp a step). Without a
/// spring the integrator keeps [`super::linear_drag_flow`] on `V = mV (1/m)`, as before springs
/// were covered. Returns (p, mV).
pub fn linear_flow_momentum(
    p0: DVec3,
    mv0: DVec3,
    m: f64,
    lin: &LinearPart,
    t: f64,
) -> (DVec3, DVec3) {
    let kernel = LinearKernel::new(lin.kd, lin.w2, t);
    let a_s = lin.a0 - lin.w2 * (p0 - lin.anchor);
    let p = p0 + kernel.k * (mv0 / m) + kernel.j * a_s;
    let mv = kernel.k_dot * mv0 + kernel.k * (m * a_s);
    (p, mv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kernels_are_continuous_through_critical_damping() {
        // w2 = 100 (w = 10), critical at kd = 20: the kernels at kd = 20 (1 -+ 1e-12) differ
        // from the critical ones by O(1e-12) times their slope in kd (t K / 2 and the like, < 1
        // here), plus rounding.
        let t = 0.37;
        let crit = LinearKernel::new(20.0, 100.0, t);
        let x = 10.0 * t;
        let e = (-x).exp();
        assert!((crit.k - t * e).abs() <= 4.0 * f64::EPSILON * t * e);
        assert!((crit.k_dot - e * (1.0 - x)).abs() <= 1e-15);
        let j = (1.0 - e * (1.0 + x)) / 100.0;
        assert!((crit.j - j).abs() <= 1e-15 * j.abs());
        for kd in [20.0 * (1.0 - 1e-12), 20.0 * (1.0 + 1e-12)] {
            let near = LinearKernel::new(kd, 100.0, t);
            for (a, b) in [(near.k, crit.k), (near.k_dot, crit.k_dot), (near.j, crit.j)] {
                assert!((a - b).abs() <= 1e-13, "kd = {kd}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn a_stiff_strongly_over_damped_spring_does_not_underflow() {
        // kd = 2e4, w2 = 1: the slow mode decays at lm = w2 / (gamma + s) ~ 1e-4 1/s, so after
        // t = 1000 s about e^-0.1 of the displacement is left, while e^(-gamma t) = e^-1e7 is 0.
        let (kd, w2, t) = (2e4f64, 1.0f64, 1000.0);
        let gamma = kd / 2.0;
        let s = (gamma * gamma - w2).sqrt();
        let lm = w2 / (gamma + s);
        let k = LinearKernel::new(kd, w2, t);
        // hom = 1 - w2 J = E (1 + l phi1(d)) with phi1(d) ~ 1/d = 5e-8: the slow mode's decay.
        let hom = 1.0 - w2 * k.j;
        let slow = (-lm * t).exp();
        assert!((hom - slow).abs() <= 1e-7 * slow, "{hom} vs {slow}");
        assert!(k.k > 0.0 && k.k.is_finite());
    }
}
