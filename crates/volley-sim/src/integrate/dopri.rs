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
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t0: f64, h: f64, c: DVec3) -> (BodyState, DVec3) {
        let (s, c, _) = self.step_counted(s, w, t0, h, c);
        (s, c)
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
                y = BodyState {
                    p: next_p,
                    mv: next_m,
                };
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
