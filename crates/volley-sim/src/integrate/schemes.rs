//! The fixed-step schemes, one `Scheme` each: explicit and semi-implicit Euler, velocity Verlet
//! (and its predicted-velocity form for velocity-dependent forces), midpoint, RK4, implicit Euler,
//! the closed-form step, Forest-Ruth and the implicit midpoint rules.

use glam::DVec3;

use super::*;

pub(super) struct ExplicitEuler<'a, F>(pub(super) &'a F);
pub(super) struct SemiImplicitEuler<'a, F>(pub(super) &'a F);
pub(super) struct Verlet<'a, F>(pub(super) &'a F);
pub(super) struct VerletPredicted<'a, F>(pub(super) &'a F);
pub(super) struct Midpoint<'a, F>(pub(super) &'a F);
pub(super) struct Rk4<'a, F>(pub(super) &'a F);
pub(super) struct ImplicitEuler<'a, F>(pub(super) &'a F);
pub(super) struct Exact<'a, F>(pub(super) &'a F);
pub(super) struct ForestRuth<'a, F>(pub(super) &'a F);
pub(super) struct Dopri5<'a, F>(pub(super) &'a F, pub(super) f64);
pub(super) struct ImplicitMidpoint<'a, F>(pub(super) &'a F);
pub(super) struct ImplicitMidpointSplit<'a, F>(pub(super) &'a F);

impl<F: ForceModel> Scheme for ExplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    const CURVATURE: f64 = 0.0;
    const CONSTANT_ACCEL_PATH: bool = true;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let v = s.mv * w.inv;
        let f = self.0.force_at(t, s.p, v, w);
        let next = BodyState {
            p: s.p + h * v,
            mv: s.mv + h * f,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for SemiImplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    const CURVATURE: f64 = 2.0;
    const CONSTANT_ACCEL_PATH: bool = true;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let f = self.0.force_at(t, s.p, s.mv * w.inv, w);
        let mv = s.mv + h * f;
        let next = BodyState {
            p: s.p + h * (mv * w.inv),
            mv,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Verlet<'_, F> {
    const EVALS: u64 = 1;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    const CARRIES_FORCE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, f0: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let mv_half = s.mv + half * f0;
        let v_half = mv_half * w.inv;
        let p = s.p + h * v_half;
        // Position-only model: the velocity argument is not read.
        let f1 = self.0.force_at(t + h, p, v_half, w);
        let next = BodyState {
            p,
            mv: mv_half + half * f1,
        };
        (next, f1)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, s: BodyState, w: Mass, t: f64) -> DVec3 {
        self.0.force_at(t, s.p, s.mv * w.inv, w)
    }
}

impl<F: ForceModel> Scheme for VerletPredicted<'_, F> {
    const EVALS: u64 = 2;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let f0 = self.0.force_at(t, s.p, s.mv * w.inv, w);
        let mv_half = s.mv + half * f0;
        let p = s.p + h * (mv_half * w.inv);
        // Euler-predicted end velocity: its O(h^2) error enters the kick times h/2, so the local
        // error stays O(h^3) and the method keeps order 2 with drag.
        let v_pred = (mv_half + half * f0) * w.inv;
        let f1 = self.0.force_at(t + h, p, v_pred, w);
        let next = BodyState {
            p,
            mv: mv_half + half * f1,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Midpoint<'_, F> {
    const EVALS: u64 = 2;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let v = s.mv * w.inv;
        let f = self.0.force_at(t, s.p, v, w);
        let p_mid = s.p + half * v;
        let mv_mid = s.mv + half * f;
        let v_mid = mv_mid * w.inv;
        let f_mid = self.0.force_at(t + half, p_mid, v_mid, w);
        let next = BodyState {
            p: s.p + h * v_mid,
            mv: s.mv + h * f_mid,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Rk4<'_, F> {
    const EVALS: u64 = 4;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let f = self.0;
        let k1p = s.mv * w.inv;
        let k1m = f.force_at(t, s.p, k1p, w);
        let k2p = (s.mv + half * k1m) * w.inv;
        let k2m = f.force_at(t + half, s.p + half * k1p, k2p, w);
        let k3p = (s.mv + half * k2m) * w.inv;
        let k3m = f.force_at(t + half, s.p + half * k2p, k3p, w);
        let k4p = (s.mv + h * k3m) * w.inv;
        let k4m = f.force_at(t + h, s.p + h * k3p, k4p, w);
        let sixth = h / 6.0;
        let next = BodyState {
            p: s.p + sixth * (k1p + 2.0 * k2p + 2.0 * k3p + k4p),
            mv: s.mv + sixth * (k1m + 2.0 * k2m + 2.0 * k3m + k4m),
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for ImplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    const CURVATURE: f64 = 2.0;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let lin = self.0.linear_part(w.m);
        let v = s.mv * w.inv;
        let a_nl = self.0.nonlinear_force_at(t, s.p, v, w) * w.inv;
        let rhs = v + h * (lin.a0 + a_nl - lin.w2 * (s.p - lin.anchor));
        let v1 = rhs / (1.0 + h * lin.kd + h * h * lin.w2);
        let next = BodyState {
            p: s.p + h * v1,
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Exact<'_, F> {
    const EVALS: u64 = 0;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, _: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        // The fast-path models have no point mass and no spring: these tests fold away for
        // them, leaving the drag flow, the same operations as before springs were covered.
        if let Some(pm) = self.0.lone_point_mass() {
            // A collision of a radial orbit with the centre: NaN stops the run at this tick.
            let (p, mv) = crate::exact::kepler_flow_momentum(s.p, s.mv, w.m, &pm, h)
                .unwrap_or((DVec3::NAN, DVec3::NAN));
            return (BodyState { p, mv }, DVec3::ZERO);
        }
        let lin = self.0.linear_part(w.m);
        if lin.w2 != 0.0 {
            let (p, mv) = crate::exact::linear_flow_momentum(s.p, s.mv, w.m, &lin, h);
            return (BodyState { p, mv }, DVec3::ZERO);
        }
        // Always inlined (see it), so the fast-path models' constant `kd` of 0 folds its test
        // into the vectorised loop.
        let (p, v) = crate::exact::linear_drag_flow(s.p, s.mv * w.inv, lin.a0, lin.kd, h);
        (BodyState { p, mv: w.m * v }, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

/// Velocity terms' coefficients for one body: `a_vel(V) = -(kd + q |V|) V`.
#[derive(Clone, Copy)]
pub(super) struct VelocityTerms {
    pub(super) kd: f64,
    pub(super) q: f64,
}

impl VelocityTerms {
    #[inline(always)]
    pub(super) fn of<F: ForceModel>(f: &F, w: Mass) -> VelocityTerms {
        // Zero written as a constant where the model has no quadratic drag (`0 * inv` is not
        // a constant to the compiler), so the models without it compile to the plain
        // Störmer-Verlet substeps, without the quadratic solve's square roots and divisions.
        let c = f.quadratic_drag();
        VelocityTerms {
            kd: f.linear_part(w.m).kd,
            q: if c == 0.0 { 0.0 } else { c * w.inv },
        }
    }

    /// Solves `v (1 + h/2 (kd + q |v|)) = rhs` for `v`. With `q = 0` it is `rhs / a`,
    /// `a = 1 + h kd / 2` (`rhs` exactly with no velocity terms). Otherwise `v` is parallel to
    /// `rhs`, scaled by `s / |rhs|` for the root `s` of `(h q / 2) s^2 + a s - |rhs| = 0` that
    /// tends to `|rhs| / a` as `h q -> 0`: `2 / (a + sqrt(a^2 + 2 h q |rhs|))`, written so that
    /// nothing cancels, or for `a <= 0` (a backward substep past the drag's stability limit)
    /// `(sqrt(..) - a) / (h q |rhs|)`. A negative discriminant (a backward substep with strong
    /// quadratic drag) has no real root: the state turns NaN and the world reports the
    /// divergence.
    #[inline(always)]
    pub(super) fn solve_half_kick(self, rhs: DVec3, h: f64) -> DVec3 {
        if self.q == 0.0 {
            // No velocity terms: `a` is exactly 1 and `rhs / 1` is `rhs`, without the divisions.
            if self.kd == 0.0 {
                return rhs;
            }
            return rhs / (1.0 + 0.5 * h * self.kd);
        }
        let a = 1.0 + 0.5 * h * self.kd;
        let r = rhs.length();
        if r == 0.0 {
            return rhs;
        }
        let hq = h * self.q;
        let root = (a * a + 2.0 * hq * r).sqrt();
        let scale = if a > 0.0 {
            2.0 / (a + root)
        } else {
            (root - a) / (hq * r)
        };
        rhs * scale
    }

    /// `-(kd + q |v|) v`; without quadratic drag `-kd v`, the same bits for a finite `v`
    /// (`kd + 0 = kd`) without the square root.
    #[inline(always)]
    pub(super) fn accel(self, v: DVec3) -> DVec3 {
        if self.q == 0.0 {
            return -self.kd * v;
        }
        -(self.kd + self.q * v.length()) * v
    }
}

/// One generalised Störmer-Verlet step of length `h` from `s` with position force `fp0` at
/// `s.p`, ending at time `t_end`: the new state and the position force at its position.
#[inline(always)]
pub(super) fn generalized_verlet<F: ForceModel>(
    f: &F,
    vt: VelocityTerms,
    s: BodyState,
    w: Mass,
    (t_end, h): (f64, f64),
    fp0: DVec3,
) -> (BodyState, DVec3) {
    let half = 0.5 * h;
    let v_half = vt.solve_half_kick((s.mv + half * fp0) * w.inv, h);
    let p = s.p + h * v_half;
    let fp1 = f.force_at(t_end, p, DVec3::ZERO, w);
    let mv = w.m * v_half + half * (fp1 + w.m * vt.accel(v_half));
    (BodyState { p, mv }, fp1)
}

impl<F: ForceModel> Scheme for ForestRuth<'_, F> {
    const EVALS: u64 = 3;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    const CARRIES_FORCE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, fp0: DVec3) -> (BodyState, DVec3) {
        let vt = VelocityTerms::of(self.0, w);
        let (c1, c2) = (FOREST_RUTH_C1, FOREST_RUTH_C2);
        let (s, fp) = generalized_verlet(self.0, vt, s, w, (t + c1 * h, c1 * h), fp0);
        let (s, fp) = generalized_verlet(self.0, vt, s, w, (t + (c1 + c2) * h, c2 * h), fp);
        generalized_verlet(self.0, vt, s, w, (t + h, c1 * h), fp)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, s: BodyState, w: Mass, t: f64) -> DVec3 {
        self.0.force_at(t, s.p, DVec3::ZERO, w)
    }
}

/// The linear terms' midpoint-rule velocity update: `V'` from `V`, the position offset
/// `d = p - anchor` and the explicit acceleration `a_ex` (the constant part plus any other
/// terms).
#[inline(always)]
pub(super) fn midpoint_linear(
    lin: &crate::forces::LinearPart,
    v: DVec3,
    d: DVec3,
    a_ex: DVec3,
    h: f64,
) -> DVec3 {
    let damp = 0.5 * h * lin.kd + 0.25 * h * h * lin.w2;
    (v * (1.0 - damp) + h * (a_ex - lin.w2 * d)) / (1.0 + damp)
}

impl<F: ForceModel> Scheme for ImplicitMidpoint<'_, F> {
    const EVALS: u64 = 1;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, _: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let lin = self.0.linear_part(w.m);
        let v = s.mv * w.inv;
        let v1 = midpoint_linear(&lin, v, s.p - lin.anchor, lin.a0, h);
        let next = BodyState {
            p: s.p + (0.5 * h) * (v + v1),
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for ImplicitMidpointSplit<'_, F> {
    const EVALS: u64 = 2;
    const READS_LAUNCH: bool = F::READS_LAUNCH;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let f = self.0;
        let lin = f.linear_part(w.m);
        let v = s.mv * w.inv;
        let half = 0.5 * h;
        let (pm, vm) = (
            s.p + half * v,
            v + half * (f.force_at(t, s.p, v, w) * w.inv),
        );
        let a_ex = lin.a0 + f.nonlinear_force_at(t + half, pm, vm, w) * w.inv;
        let v1 = midpoint_linear(&lin, v, s.p - lin.anchor, a_ex, h);
        let next = BodyState {
            p: s.p + half * (v + v1),
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.0.rates(reach, w)
    }
    fn start_carry(&self, _: BodyState, _: Mass, _: f64) -> DVec3 {
        DVec3::ZERO
    }
}
