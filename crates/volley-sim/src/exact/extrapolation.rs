//! A numerical reference for the scenes without a closed form: the Gragg-Bulirsch-Stoer
//! extrapolation method, adaptive, with its own error estimate.
//!
//! One macro step `H` runs Gragg's modified midpoint rule with `n = 2, 4, 6, ..., 16` substeps;
//! its error has an expansion in even powers of `H / n`, so Richardson extrapolation of the
//! column of results to `n -> infinity` (Aitken-Neville in `(H/n)^2`) gains two orders per
//! column: the eighth row is of order 16 on a smooth problem. The difference between the last
//! two entries of the diagonal is the error estimate. A step is accepted when that estimate is
//! below `tolerance * (1 + |y|)` (per component of position and velocity, max norm); otherwise
//! the macro step is halved. Accepted steps grow the next by up to 2x.
//!
//! Deterministic: the step choice depends on the state only; every loop is bounded (a step
//! below `1e-12` of the span, or more than [`MAX_STEPS`] steps, is an error, never a hang).

use glam::DVec3;

use crate::body::{BodyState, Mass};
use crate::forces::{ForceModel, Forces};

/// Most macro steps one [`extrapolate`] call takes.
pub const MAX_STEPS: usize = 1_000_000;
/// Substep counts of the extrapolation column.
const SEQUENCE: [u32; 8] = [2, 4, 6, 8, 10, 12, 14, 16];

/// Why the reference could not get there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ExtrapolationError {
    /// The step fell below 1e-12 of the span at this time (s): the problem is too stiff or
    /// singular for the tolerance.
    StepTooSmall(f64),
    /// More than `MAX_STEPS` (a million) macro steps.
    TooManySteps,
    /// The state stopped being finite at this time (s).
    NonFinite(f64),
}

impl std::fmt::Display for ExtrapolationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExtrapolationError::StepTooSmall(t) => {
                write!(
                    f,
                    "the reference's step fell below 1e-12 of the span at t = {t} s"
                )
            }
            ExtrapolationError::TooManySteps => {
                write!(f, "the reference took more than {MAX_STEPS} steps")
            }
            ExtrapolationError::NonFinite(t) => {
                write!(f, "the reference is not finite at t = {t} s")
            }
        }
    }
}

impl std::error::Error for ExtrapolationError {}

/// The state `(p, v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Y {
    p: DVec3,
    v: DVec3,
}

impl Y {
    fn add(self, h: f64, d: Y) -> Y {
        Y {
            p: self.p + h * d.p,
            v: self.v + h * d.v,
        }
    }

    fn scale_max(self) -> f64 {
        self.p.abs().max_element().max(self.v.abs().max_element())
    }
}

/// The derivative at time `t` on the world's clock: every term at its own time and with the
/// body's launch (a spin's lift, a motor, a game's own term), as the integrators read them.
fn deriv(forces: &Forces, w: Mass, t: f64, y: Y) -> Y {
    Y {
        p: y.v,
        v: forces.force_at(t, y.p, y.v, w) / w.m,
    }
}

/// Gragg's modified midpoint rule over `big_h` with `n` substeps, from time `t0`.
fn midpoint(forces: &Forces, w: Mass, t0: f64, y0: Y, big_h: f64, n: u32) -> Y {
    let h = big_h / f64::from(n);
    let mut prev = y0;
    let mut cur = y0.add(h, deriv(forces, w, t0, y0));
    for k in 1..n {
        let next = prev.add(2.0 * h, deriv(forces, w, t0 + f64::from(k) * h, cur));
        (prev, cur) = (cur, next);
    }
    let end = cur.add(h, deriv(forces, w, t0 + big_h, cur));
    Y {
        p: 0.5 * (prev.p + end.p),
        v: 0.5 * (prev.v + end.v),
    }
}

/// One extrapolated macro step: the best estimate and its error estimate (max norm).
fn macro_step(forces: &Forces, w: Mass, t0: f64, y0: Y, big_h: f64) -> (Y, f64) {
    let mut table: Vec<Y> = Vec::with_capacity(SEQUENCE.len());
    let mut err = f64::INFINITY;
    for (j, &nj) in SEQUENCE.iter().enumerate() {
        let mut t = midpoint(forces, w, t0, y0, big_h, nj);
        // Aitken-Neville: row j from row j - 1, in place.
        let mut row = vec![t];
        for k in 1..=j {
            let ratio = f64::from(nj) / f64::from(SEQUENCE[j - k]);
            let denom = ratio * ratio - 1.0;
            let prev = table[k - 1];
            let d = Y {
                p: (t.p - prev.p) / denom,
                v: (t.v - prev.v) / denom,
            };
            t = t.add(1.0, d);
            row.push(t);
        }
        if j > 0 {
            let (a, b) = (row[j], row[j - 1]);
            err = (a.p - b.p)
                .abs()
                .max_element()
                .max((a.v - b.v).abs().max_element());
        }
        table = row;
    }
    (table[SEQUENCE.len() - 1], err)
}

/// The state of a body of mass `m` under `forces` (no contacts) `t` seconds after `s0`, by
/// adaptive extrapolation to `tolerance` (relative, per component: `tolerance * (1 + |y|)`),
/// and the sum of the accepted steps' error estimates (m or m/s, max norm): the reference's own
/// estimate of its error.
pub fn extrapolate(
    forces: &Forces,
    s0: BodyState,
    m: f64,
    t: f64,
    tolerance: f64,
) -> Result<(BodyState, f64), ExtrapolationError> {
    extrapolate_from(forces, s0, Mass::new(m), 0.0, t, tolerance)
}

/// [`extrapolate`] for a body launched as `w.launch` says, from time `start` on the world's
/// clock: the terms that read the clock or the launch (a game's own, a spin, a motor) are
/// evaluated at each substep's own time. With a motor the state's momentum stays `w.m V` (the
/// step's convention, [`crate::forces::Thrust`]): compare velocities, not momenta.
pub fn extrapolate_from(
    forces: &Forces,
    s0: BodyState,
    w: Mass,
    start: f64,
    t: f64,
    tolerance: f64,
) -> Result<(BodyState, f64), ExtrapolationError> {
    let m = w.m;
    let mut y = Y {
        p: s0.p,
        v: s0.mv / m,
    };
    if t <= 0.0 {
        return Ok((s0, 0.0));
    }
    let (mut done, mut h, mut total) = (0.0f64, t.min(1.0), 0.0);
    for _ in 0..MAX_STEPS {
        if done >= t {
            return Ok((
                BodyState {
                    p: y.p,
                    mv: m * y.v,
                },
                total,
            ));
        }
        let step = h.min(t - done);
        let (next, err) = macro_step(forces, w, start + done, y, step);
        let bound = tolerance * (1.0 + y.scale_max().max(next.scale_max()));
        if !(next.p.is_finite() && next.v.is_finite()) {
            if step <= 1e-12 * t {
                return Err(ExtrapolationError::NonFinite(done));
            }
            h = 0.5 * step;
            continue;
        }
        if err <= bound {
            y = next;
            done += step;
            total += err;
            if err < 0.1 * bound {
                h = 2.0 * step;
            }
        } else {
            if step <= 1e-12 * t {
                return Err(ExtrapolationError::StepTooSmall(done));
            }
            h = 0.5 * step;
        }
    }
    Err(ExtrapolationError::TooManySteps)
}
