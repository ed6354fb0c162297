//! Dormand-Prince 5(4): the adaptive scheme, its tableau, and the error norm that accepts or
//! rejects a sub-step.

use glam::DVec3;

use super::*;

/// The Dormand-Prince 5(4) tableau: stage times `c` (stages 6 and 7 at the step's end),
/// stage coefficients `a`, the 5th-order weights (the last
/// row of `a`, so the 7th stage is the next step's first) and the error weights `b5 - b4`.
mod dp {
    pub const C2: f64 = 1.0 / 5.0;
    pub const C3: f64 = 3.0 / 10.0;
    pub const C4: f64 = 4.0 / 5.0;
    pub const C5: f64 = 8.0 / 9.0;
    pub const A21: f64 = 1.0 / 5.0;
    pub const A31: f64 = 3.0 / 40.0;
    pub const A32: f64 = 9.0 / 40.0;
    pub const A41: f64 = 44.0 / 45.0;
    pub const A42: f64 = -56.0 / 15.0;
    pub const A43: f64 = 32.0 / 9.0;
    pub const A51: f64 = 19372.0 / 6561.0;
    pub const A52: f64 = -25360.0 / 2187.0;
    pub const A53: f64 = 64448.0 / 6561.0;
    pub const A54: f64 = -212.0 / 729.0;
    pub const A61: f64 = 9017.0 / 3168.0;
    pub const A62: f64 = -355.0 / 33.0;
    pub const A63: f64 = 46732.0 / 5247.0;
    pub const A64: f64 = 49.0 / 176.0;
    pub const A65: f64 = -5103.0 / 18656.0;
    pub const B1: f64 = 35.0 / 384.0;
    pub const B3: f64 = 500.0 / 1113.0;
    pub const B4: f64 = 125.0 / 192.0;
    pub const B5: f64 = -2187.0 / 6784.0;
    pub const B6: f64 = 11.0 / 84.0;
    pub const E1: f64 = 71.0 / 57600.0;
    pub const E3: f64 = -71.0 / 16695.0;
    pub const E4: f64 = 71.0 / 1920.0;
    pub const E5: f64 = -17253.0 / 339200.0;
    pub const E6: f64 = 22.0 / 525.0;
    pub const E7: f64 = -1.0 / 40.0;
}

/// A state derivative on y = (p, mV): (V, F).
#[derive(Clone, Copy)]
pub(super) struct Slope {
    pub(super) p: DVec3,
    pub(super) m: DVec3,
}

impl<F: ForceModel> Dopri5<'_, F> {
    #[inline(always)]
    pub(super) fn slope(&self, t: f64, p: DVec3, mv: DVec3, w: Mass) -> Slope {
        let v = mv * w.inv;
        Slope {
            p: v,
            m: self.0.force_at(t, p, v, w),
        }
    }
}

/// Largest of `|e_i| / (1 + max(|y0_i|, |y1_i|))` over the components of `e`.
#[inline(always)]
pub(super) fn scaled_error(e: DVec3, y0: DVec3, y1: DVec3) -> f64 {
    let scale = DVec3::ONE + y0.abs().max(y1.abs());
    (e.abs() / scale).max_element()
}

impl<F: ForceModel> Scheme for Dopri5<'_, F> {
    const EVALS: u64 = 7;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    const ADAPTIVE: bool = true;
    const DENSE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t0: f64, h: f64, c: DVec3) -> (BodyState, DVec3) {
        let (s, c, _) = self.step_counted(s, w, t0, h, c);
        (s, c)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
    #[inline(never)]
    fn step_counted(
        &self,
        s: BodyState,
        w: Mass,
        t0: f64,
        h: f64,
        _: DVec3,
    ) -> (BodyState, DVec3, u64) {
        self.adaptive(s, w, t0, h, &mut ())
    }
    #[inline(never)]
    fn step_dense(
        &self,
        s: BodyState,
        w: Mass,
        t0: f64,
        h: f64,
        _: DVec3,
        dense: &mut Dense,
    ) -> (BodyState, DVec3, u64) {
        dense.clear();
        self.adaptive(s, w, t0, h, dense)
    }
}

/// What the adaptive step tells about each internal step it accepts: nothing (`()`, the
/// plain step), or its continuous extension ([`Dense`]).
pub(super) trait Accepted {
    /// The internal step from `t` (s into the step) over `d` from `y0` to `y1`, its stages
    /// `k` (k7 the slope at `y1`).
    fn accepted(&mut self, t: f64, d: f64, y0: &BodyState, y1: &BodyState, k: [&Slope; 7]);
}

impl Accepted for () {
    #[inline(always)]
    fn accepted(&mut self, _: f64, _: f64, _: &BodyState, _: &BodyState, _: [&Slope; 7]) {}
}

/// Hairer's dense output coefficients of Dormand-Prince 5(4) (dopri5.f, `CONTD5`): the
/// continuous extension of order 4 from the seven stages, no further evaluation.
mod dense {
    pub const D1: f64 = -12715105075.0 / 11282082432.0;
    pub const D3: f64 = 87487479700.0 / 32700410799.0;
    pub const D4: f64 = -10690763975.0 / 1880347072.0;
    pub const D5: f64 = 701980252875.0 / 199316789632.0;
    pub const D6: f64 = -1453857185.0 / 822651844.0;
    pub const D7: f64 = 69997945.0 / 29380423.0;
}

/// One accepted internal step's continuous extension: `y(theta) = r1 + theta (r2 + (1 -
/// theta) (r3 + theta (r4 + (1 - theta) r5)))`, `theta` from 0 to 1 over the internal step.
#[derive(Clone, Copy, Debug)]
struct Piece {
    t: f64,
    d: f64,
    p: [DVec3; 5],
    m: [DVec3; 5],
}

/// The continuous extension of one Dormand-Prince step (all its accepted internal steps):
/// the state at any time inside the step at no force evaluation, the path the event search
/// walks for this integrator (docs/physics.md, "Declared events").
#[derive(Clone, Debug, Default)]
pub(crate) struct Dense {
    pieces: Vec<Piece>,
}

impl Dense {
    /// Forgets the last step's extension.
    #[inline]
    pub(crate) fn clear(&mut self) {
        self.pieces.clear();
    }

    /// The state `tau` s into the step (clamped to it).
    pub(crate) fn at(&self, tau: f64) -> BodyState {
        let i = self
            .pieces
            .partition_point(|p| p.t + p.d < tau)
            .min(self.pieces.len() - 1);
        let c = &self.pieces[i];
        let theta = ((tau - c.t) / c.d).clamp(0.0, 1.0);
        let one = 1.0 - theta;
        let y = |r: &[DVec3; 5]| r[0] + theta * (r[1] + one * (r[2] + theta * (r[3] + one * r[4])));
        BodyState {
            p: y(&c.p),
            mv: y(&c.m),
        }
    }
}

impl Accepted for Dense {
    fn accepted(&mut self, t: f64, d: f64, y0: &BodyState, y1: &BodyState, k: [&Slope; 7]) {
        use dense::*;
        let coefficients = |y0: DVec3, y1: DVec3, slope: fn(&Slope) -> DVec3| {
            let diff = y1 - y0;
            let bspl = d * slope(k[0]) - diff;
            [
                y0,
                diff,
                bspl,
                diff - d * slope(k[6]) - bspl,
                d * (D1 * slope(k[0])
                    + D3 * slope(k[2])
                    + D4 * slope(k[3])
                    + D5 * slope(k[4])
                    + D6 * slope(k[5])
                    + D7 * slope(k[6])),
            ]
        };
        self.pieces.push(Piece {
            t,
            d,
            p: coefficients(y0.p, y1.p, |k| k.p),
            m: coefficients(y0.mv, y1.mv, |k| k.m),
        });
    }
}

impl<F: ForceModel> Dopri5<'_, F> {
    /// The adaptive step, telling `record` of every internal step it accepts.
    #[inline(always)]
    fn adaptive(
        &self,
        s: BodyState,
        w: Mass,
        t0: f64,
        h: f64,
        record: &mut impl Accepted,
    ) -> (BodyState, DVec3, u64) {
        use dp::*;
        let tol = self.1;
        let failed = (
            BodyState {
                p: DVec3::NAN,
                mv: DVec3::NAN,
            },
            DVec3::ZERO,
        );
        let (mut y, mut t) = (s, 0.0);
        let mut k1 = self.slope(t0, y.p, y.mv, w);
        let mut evals = 1u64;
        let mut trial = h;
        for _ in 0..DOPRI_MAX_ATTEMPTS {
            let remaining = h - t;
            let last = trial >= remaining;
            let d = if last { remaining } else { trial };
            let at = |c: [f64; 5], k: [&Slope; 5]| {
                let mut p = y.p;
                let mut m = y.mv;
                for (ci, ki) in c.iter().zip(k) {
                    if *ci != 0.0 {
                        p += (d * ci) * ki.p;
                        m += (d * ci) * ki.m;
                    }
                }
                (p, m)
            };
            let z = &k1;
            let (p, m) = at([A21, 0.0, 0.0, 0.0, 0.0], [&k1, z, z, z, z]);
            let k2 = self.slope(t0 + t + C2 * d, p, m, w);
            let (p, m) = at([A31, A32, 0.0, 0.0, 0.0], [&k1, &k2, z, z, z]);
            let k3 = self.slope(t0 + t + C3 * d, p, m, w);
            let (p, m) = at([A41, A42, A43, 0.0, 0.0], [&k1, &k2, &k3, z, z]);
            let k4 = self.slope(t0 + t + C4 * d, p, m, w);
            let (p, m) = at([A51, A52, A53, A54, 0.0], [&k1, &k2, &k3, &k4, z]);
            let k5 = self.slope(t0 + t + C5 * d, p, m, w);
            let (p, m) = at([A61, A62, A63, A64, A65], [&k1, &k2, &k3, &k4, &k5]);
            let k6 = self.slope(t0 + t + d, p, m, w);
            let next_p = y.p + d * (B1 * k1.p + B3 * k3.p + B4 * k4.p + B5 * k5.p + B6 * k6.p);
            let next_m = y.mv + d * (B1 * k1.m + B3 * k3.m + B4 * k4.m + B5 * k5.m + B6 * k6.m);
            let k7 = self.slope(t0 + t + d, next_p, next_m, w);
            evals += 6;
            let err = |k: fn(&Slope) -> DVec3| {
                d * (E1 * k(&k1)
                    + E3 * k(&k3)
                    + E4 * k(&k4)
                    + E5 * k(&k5)
                    + E6 * k(&k6)
                    + E7 * k(&k7))
            };
            let norm = scaled_error(err(|k| k.p), y.p, next_p).max(scaled_error(
                err(|k| k.m),
                y.mv,
                next_m,
            )) / tol;
            if !norm.is_finite() {
                return (failed.0, failed.1, evals);
            }
            let accepted = norm <= 1.0;
            if accepted {
                let next = BodyState {
                    p: next_p,
                    mv: next_m,
                };
                record.accepted(t, d, &y, &next, [&k1, &k2, &k3, &k4, &k5, &k6, &k7]);
                y = next;
                if last {
                    return (y, DVec3::ZERO, evals);
                }
                t += d;
                k1 = k7;
            }
            let grow = if norm == 0.0 {
                5.0
            } else {
                (0.9 / norm.sqrt().sqrt()).clamp(0.2, 5.0)
            };
            trial = d * if accepted { grow } else { grow.min(1.0) };
        }
        (failed.0, failed.1, evals)
    }
}
