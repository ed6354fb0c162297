//! The integrators: one step of one body, in the seed's state S = <mV, p>.
//!
//! Each [`Integrator`] variant documents its update, order, cost and stability limit (see
//! docs/physics.md, "Integrators"). The hot loop never matches on the integrator per body:
//! `visit` picks the force model and the scheme once, and the per-body loop is monomorphised
//! over the resulting `Scheme`, so a step costs exactly the arithmetic of its update.
//!
//! Notation: `h` is the step (s), `m` the mass (kg), `V = mV / m`, `F(p, V)` the net force of
//! the declared terms, `a = F / m`. No update uses `mul_add`: fused and unfused results differ in
//! the last bit, and which one a platform picks must not decide a replay.

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use crate::body::{BodyState, Mass};
use crate::forces::{DragField, ForceModel, Forces};

/// How a scene's bodies are advanced by one step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Integrator {
    /// Explicit (forward) Euler, exactly the seed's update:
    /// `p' = p + h V`, `mV' = mV + h F(p, V)`.
    ///
    /// Global order 1; 1 force evaluation per step; not symplectic. Unstable on an undamped
    /// oscillator at every step size (amplitude grows by `sqrt(1 + (w h)^2)` per step); on linear
    /// drag `v' = -k v` stable for `k h <= 2`. Under constant force it ends `g T h / 2` high.
    ExplicitEuler,
    /// Semi-implicit (symplectic) Euler, the update of Box2D, Rapier, Jolt and PhysX:
    /// `mV' = mV + h F(p, V)`, `p' = p + h V'`.
    ///
    /// Global order 1; 1 force evaluation; symplectic, so an oscillator's energy error stays
    /// bounded. Stable for `w h < 2` and `k h <= 2`. Under constant force it ends `g T h / 2` low.
    SemiImplicitEuler,
    /// Velocity Verlet (kick, drift, kick):
    /// `mV½ = mV + h/2 F(p)`, `p' = p + h V½`, `mV' = mV½ + h/2 F(p')`.
    ///
    /// Global order 2; symplectic; stable for `w h < 2`; exact under constant force.
    /// For position-only forces the end force `F(p')` is carried to the next step, so the cost is
    /// 1 evaluation per step. With velocity-dependent terms (drag, spring damping) the naive
    /// scheme drops to order 1; Volley instead evaluates the end force at the predicted velocity
    /// `V* = (mV½ + h/2 F(p, V)) / m`, which keeps order 2 at 2 evaluations per step.
    VelocityVerlet,
    /// Explicit midpoint (RK2): `y' = y + h f(y + h/2 f(y))` on y = (p, mV).
    ///
    /// Global order 2; 2 force evaluations; not symplectic (an oscillator's energy grows slowly,
    /// by `(w h)^4 / 4` per step); stable for `k h <= 2`; exact under constant force.
    Midpoint,
    /// Classical fourth-order Runge-Kutta on y = (p, mV).
    ///
    /// Global order 4; 4 force evaluations; not symplectic (an oscillator's energy decays slowly
    /// inside the stability region). Stable for `w h <= 2 sqrt 2 = 2.828` and `k h <= 2.785`;
    /// exact under constant force.
    Rk4,
    /// Implicit (backward) Euler on the linear terms, explicit on the rest:
    /// `V' = (V + h (a0 + a_nl(p, V) - w^2 (p - anchor))) / (1 + h kd + h^2 w^2)`, `p' = p + h V'`,
    /// with `a0` gravity plus constant force over mass, `kd` the linear damping rate (drag and
    /// spring damping over mass), `w^2 = k / m` of a zero-rest-length spring, and `a_nl` every
    /// other term (quadratic drag, point mass, a spring with rest length) evaluated at the start.
    ///
    /// Global order 1; 1 force evaluation plus a scalar solve. Unconditionally stable on the
    /// linear terms (it damps an oscillator and decays drag monotonically at any step).
    ImplicitEuler,
    /// The closed-form solution, evaluated over each step ([`crate::exact`]). No force
    /// evaluations.
    ///
    /// Exact on every linear scene (gravity, constant force, linear drag and a zero-rest-length
    /// spring with any damping: the drag flow without a spring, bit for bit as before springs
    /// were covered, and the damped-oscillator flow with one) and on a lone point mass (Kepler's
    /// problem in universal variables). Scenes declaring any other combination are refused when
    /// the integrator is chosen ([`Forces::without_closed_form`]). A radial orbit that reaches
    /// the point mass's centre within a step has no solution past it: the step returns a
    /// non-finite state, so the world stops there with a non-finite divergence naming the tick
    /// and the body, as any integrator does that lands on the centre.
    Exact,
    /// Forest-Ruth (Yoshida's triple jump): three generalised Verlet steps of `c1 h`, `c2 h`,
    /// `c1 h` with `c1 = 1 / (2 - 2^(1/3)) = 1.3512`, `c2 = 1 - 2 c1 = -1.7024` (a step back in
    /// time in the middle). Each generalised Verlet step (`h` here its own length) is
    /// `V½ = V + h/2 (Fpos(p)/m + a_vel(V½))`, `p' = p + h V½`,
    /// `mV' = m V½ + h/2 (Fpos(p') + m a_vel(V½))`, where `Fpos` is the force of the position
    /// terms (gravity, constant force, springs without their damping, point mass) and `a_vel`
    /// the velocity terms (`-kd V - (c/m)|V| V`: linear drag, spring damping, quadratic drag).
    /// The first kick is implicit in `V½`, solved in closed form (`V½` is parallel to its
    /// right-hand side, so a scalar quadratic); with position forces alone it is velocity Verlet.
    ///
    /// Why that form: the composition reaches order 4 only from a *symmetric* order-2 step, and
    /// this one is (the generalised Störmer-Verlet method); velocity Verlet's predicted form
    /// (what `verlet` uses with drag) is not, and composed it gives order 3 with drag.
    ///
    /// Global order 4; symplectic on position forces (energy error bounded on an orbit). 3
    /// position-force evaluations per step (the end force carried to the next substep and the
    /// next step, as velocity Verlet does); the velocity terms are evaluated in closed form, not
    /// counted. Stable on an undamped oscillator for `w h < 1.5734` (the largest substep is
    /// 1.35 h); on linear drag for `k h < 1.1344` and again past 1.2006 (the backward substep's
    /// factor `(1 + 0.85 k h) / (1 - 0.85 k h)` has its pole between); exact under constant
    /// force. With quadratic drag the backward substep's implicit solve has no real root once
    /// `2 |c2| h c |v| / m > 1` (the linearised `k h > 0.29`): the step turns NaN and the world
    /// reports it, and the stability pre-check flags it.
    ForestRuth,
    /// Dormand-Prince 5(4), adaptive inside the tick: embedded Runge-Kutta steps on
    /// y = (p, mV), the 5th-order solution kept, the 4th-order one giving the error estimate.
    /// Each tick (each substep) starts with one internal step of the whole length and splits
    /// it as the estimate needs: a step is accepted when every component of the error is at
    /// most `tol (1 + |y|)` (the scene's `tolerance`, mixed absolute and relative), and the next
    /// internal step is `0.9 / err^(1/4)` times the last, between 0.2 and 5 times (a quartic
    /// root, two correctly rounded square roots, instead of the usual fifth root: `powf` is not
    /// correctly rounded, so its bits could differ between platforms and decide a replay). The
    /// choice depends on the state and `h` only, never on earlier ticks, so replays and seeks
    /// are exact.
    ///
    /// Global order 5 while a tick is one internal step, and error proportional to the
    /// tolerance once the controller splits ticks. 7 force evaluations for a tick taken in one
    /// internal step, 6 more per further attempt (first-same-as-last); every evaluation of
    /// rejected attempts is counted. No step-size stability limit: the controller shrinks the
    /// internal step until the estimate passes, so a stiff scene costs evaluations instead of
    /// diverging. More than [`DOPRI_MAX_ATTEMPTS`] attempts in one step, or a non-finite
    /// estimate, ends the step with a non-finite state, which the world reports as a divergence.
    Dopri5,
    /// Implicit midpoint on the linear terms, explicit midpoint on the rest:
    /// `V' = (V (1 - h kd/2 - h^2 w^2/4) + h (a0 + a_nl(pm, Vm) - w^2 (p - anchor))) /
    /// (1 + h kd/2 + h^2 w^2/4)`, `p' = p + h (V + V')/2`, with `a0`, `kd`, `w^2`, `anchor` as
    /// for implicit Euler and `a_nl` the other terms at the Euler-predicted midpoint
    /// `pm = p + h/2 V`, `Vm = V + h/2 F(p, V)/m`.
    ///
    /// Global order 2. On the linear terms it is the Cayley transform of the flow: symplectic
    /// and time-symmetric, so an undamped oscillator keeps its energy (to rounding) at any step,
    /// with a phase lag instead of growth; drag decays at any step (but overshoots sign for
    /// `k h > 2`). 1 force evaluation plus a scalar solve with linear terms only; 2 with other
    /// terms (the start force for the predictor and the other terms at the midpoint). On those
    /// other terms the step is a kick with the midpoint force and a trapezoidal drift: on an
    /// oscillator its matrix has determinant 1 and trace `2 - (w h)^2`, so a point mass or a
    /// spring with rest length is stable for `w h < 2`, with no energy drift.
    ImplicitMidpoint,
}

/// Internal steps Dormand-Prince may attempt in one step before it gives up (the step ends
/// non-finite and the world reports the divergence): bounds the work a stiff or hostile scene
/// can ask of one tick.
pub const DOPRI_MAX_ATTEMPTS: u32 = 10_000;

/// The tolerance of [`Integrator::Dopri5`] when a scene gives none.
pub const DEFAULT_TOLERANCE: f64 = 1e-8;

/// Forest-Ruth's outer substep coefficient `1 / (2 - 2^(1/3))`.
pub(crate) const FOREST_RUTH_C1: f64 = 1.351_207_191_959_657_8;
/// Forest-Ruth's middle (backward) substep coefficient `1 - 2 c1`.
pub(crate) const FOREST_RUTH_C2: f64 = 1.0 - 2.0 * FOREST_RUTH_C1;

/// Facts about an integrator, as used by the stability pre-check and the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorInfo {
    /// Global order of accuracy.
    pub order: u32,
    /// Whether the method is symplectic.
    pub symplectic: bool,
    /// Largest stable `w h` on an undamped oscillator (`None`: never stable; infinite: always).
    pub oscillator_limit: Option<f64>,
    /// Largest stable `k h` on linear drag (infinite: always).
    pub drag_limit: f64,
}

impl Integrator {
    /// Every integrator, in the order tables list them.
    ///
    /// The position is also the integrator's tag in keyframes, so new integrators are appended.
    pub const ALL: [Integrator; 10] = [
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::VelocityVerlet,
        Integrator::Midpoint,
        Integrator::Rk4,
        Integrator::ImplicitEuler,
        Integrator::Exact,
        Integrator::ForestRuth,
        Integrator::Dopri5,
        Integrator::ImplicitMidpoint,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::ExplicitEuler => "explicit-euler",
            Integrator::SemiImplicitEuler => "semi-implicit-euler",
            Integrator::VelocityVerlet => "verlet",
            Integrator::Midpoint => "midpoint",
            Integrator::Rk4 => "rk4",
            Integrator::ImplicitEuler => "implicit-euler",
            Integrator::Exact => "exact",
            Integrator::ForestRuth => "forest-ruth",
            Integrator::Dopri5 => "dopri5",
            Integrator::ImplicitMidpoint => "implicit-midpoint",
        }
    }

    /// Parses a command-line name or a scene-file variant name (`ExplicitEuler`), any case.
    pub fn parse(name: &str) -> Option<Integrator> {
        let squashed: String = name
            .chars()
            .filter(|c| *c != '-' && *c != '_')
            .collect::<String>()
            .to_ascii_lowercase();
        Integrator::ALL.into_iter().find(|i| {
            let own = i.name().replace('-', "");
            own == squashed || format!("{i:?}").to_ascii_lowercase() == squashed
        })
    }

    /// Order, symplecticity and linear stability limits.
    pub fn info(self) -> IntegratorInfo {
        let (order, symplectic, oscillator_limit, drag_limit) = match self {
            Integrator::ExplicitEuler => (1, false, None, 2.0),
            Integrator::SemiImplicitEuler => (1, true, Some(2.0), 2.0),
            Integrator::VelocityVerlet => (2, true, Some(2.0), 2.0),
            Integrator::Midpoint => (2, false, None, 2.0),
            Integrator::Rk4 => (4, false, Some(2.0 * 2f64.sqrt()), 2.785_293_563_405_282),
            Integrator::ImplicitEuler => (1, false, Some(f64::INFINITY), f64::INFINITY),
            Integrator::Exact => (u32::MAX, false, Some(f64::INFINITY), f64::INFINITY),
            Integrator::ForestRuth => (4, true, Some(1.573_401_947_434_54), 1.134_424_004_107_53),
            Integrator::Dopri5 => (5, false, Some(f64::INFINITY), f64::INFINITY),
            Integrator::ImplicitMidpoint => (2, true, Some(f64::INFINITY), f64::INFINITY),
        };
        IntegratorInfo {
            order,
            symplectic,
            oscillator_limit,
            drag_limit,
        }
    }

    /// Force evaluations per body per step under `forces` (for Dormand-Prince, a step taken in
    /// one internal step: the fewest it can cost).
    pub fn evals_per_step(self, forces: &Forces) -> u64 {
        match self {
            Integrator::ExplicitEuler
            | Integrator::SemiImplicitEuler
            | Integrator::ImplicitEuler => 1,
            Integrator::VelocityVerlet => 1 + u64::from(forces.velocity_dependent()),
            Integrator::Midpoint => 2,
            Integrator::Rk4 => 4,
            Integrator::Exact => 0,
            Integrator::ForestRuth => 3,
            Integrator::Dopri5 => 7,
            Integrator::ImplicitMidpoint => 1 + u64::from(forces.has_nonlinear()),
        }
    }

    /// Whether the integrator carries the end-of-step position force to the next step under
    /// `forces` (velocity Verlet with position forces only, and Forest-Ruth always): then the
    /// carried force is part of the state a keyframe holds.
    pub fn carries_force(self, forces: &Forces) -> bool {
        match self {
            Integrator::VelocityVerlet => !forces.velocity_dependent(),
            Integrator::ForestRuth => true,
            _ => false,
        }
    }
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One integrator bound to one force model: the per-body update the hot loop is generic over.
pub(crate) trait Scheme: Sync {
    /// Force evaluations per step.
    const EVALS: u64;
    /// Whether the end-of-step force is carried to the next step (velocity Verlet).
    const CARRIES_FORCE: bool = false;
    /// Whether the evaluations per step vary (Dormand-Prince): then callers count them with
    /// [`Scheme::step_counted`] instead of [`Scheme::EVALS`].
    const ADAPTIVE: bool = false;
    /// Advances one body of mass `w` by `h`. `carry` is the force at the start state when
    /// [`Scheme::CARRIES_FORCE`], otherwise unused; the returned force is the end state's.
    fn step(&self, s: BodyState, w: Mass, h: f64, carry: DVec3) -> (BodyState, DVec3);
    /// The carried force at a state (the start of a run, after a command or a seek).
    fn start_carry(&self, s: BodyState, w: Mass) -> DVec3;
    /// [`Scheme::step`] and the force evaluations it cost.
    #[inline(always)]
    fn step_counted(&self, s: BodyState, w: Mass, h: f64, carry: DVec3) -> (BodyState, DVec3, u64) {
        let (s, c) = self.step(s, w, h, carry);
        (s, c, Self::EVALS)
    }
}

/// Receives the [`Scheme`] chosen for a tick; the way to be generic over it.
pub(crate) trait SchemeVisitor {
    /// What the visit produces.
    type Out;
    /// Called once with the scheme for the current integrator and forces.
    fn visit<S: Scheme>(self, scheme: S) -> Self::Out;
}

/// Picks the force model (the [`crate::forces::ConstantField`] or [`DragField`] fast path when
/// one applies, else the general [`Forces`]) and the scheme, once. Inlined into its callers
/// (the step's stages): out of line, the visitor (a few hundred bytes of lane views) would be
/// copied into each call.
/// `tolerance` is Dormand-Prince's (the scene's `tolerance`); the other schemes ignore it.
#[inline(always)]
pub(crate) fn visit<V: SchemeVisitor>(
    integrator: Integrator,
    forces: &Forces,
    tolerance: f64,
    v: V,
) -> V::Out {
    if let Some(field) = forces.constant_field() {
        return visit_model(integrator, &field, tolerance, v);
    }
    if let Some(field) = DragField::<false>::of(forces) {
        return visit_model(integrator, &field, tolerance, v);
    }
    if let Some(field) = DragField::<true>::of(forces) {
        return visit_model(integrator, &field, tolerance, v);
    }
    visit_model(integrator, forces, tolerance, v)
}

#[inline(always)]
fn visit_model<F: ForceModel, V: SchemeVisitor>(
    integrator: Integrator,
    f: &F,
    tolerance: f64,
    v: V,
) -> V::Out {
    match integrator {
        Integrator::ExplicitEuler => v.visit(ExplicitEuler(f)),
        Integrator::SemiImplicitEuler => v.visit(SemiImplicitEuler(f)),
        Integrator::VelocityVerlet if f.velocity_dependent() => v.visit(VerletPredicted(f)),
        Integrator::VelocityVerlet => v.visit(Verlet(f)),
        Integrator::Midpoint => v.visit(Midpoint(f)),
        Integrator::Rk4 => v.visit(Rk4(f)),
        Integrator::ImplicitEuler => v.visit(ImplicitEuler(f)),
        Integrator::Exact => v.visit(Exact(f)),
        Integrator::ForestRuth => v.visit(ForestRuth(f)),
        Integrator::Dopri5 => v.visit(Dopri5(f, tolerance)),
        Integrator::ImplicitMidpoint if f.has_nonlinear() => v.visit(ImplicitMidpointSplit(f)),
        Integrator::ImplicitMidpoint => v.visit(ImplicitMidpoint(f)),
    }
}

/// Force evaluations one step of `integrator` costs per body on `forces` (velocity Verlet's
/// carried force counted once a step; the closed form 0): what "equal cost" compares.
pub fn evals_per_step(integrator: Integrator, forces: &Forces) -> u64 {
    struct Evals;
    impl SchemeVisitor for Evals {
        type Out = u64;
        fn visit<S: Scheme>(self, _: S) -> u64 {
            S::EVALS
        }
    }
    visit(integrator, forces, DEFAULT_TOLERANCE, Evals)
}

/// Advances one body by `h` with any integrator: the reference path for tests and studies.
///
/// The stepping loop uses the same `Scheme` code, so results are bit-identical to a world's.
/// `exact` on forces without a closed form returns the flow of their linear part alone (the
/// other terms ignored); check [`Forces::without_closed_form`] first (scenes do).
/// Dormand-Prince runs at [`DEFAULT_TOLERANCE`]; [`step_body_at`] takes one.
pub fn step_body(
    integrator: Integrator,
    forces: &Forces,
    s: BodyState,
    m: f64,
    h: f64,
) -> BodyState {
    step_body_at(integrator, forces, DEFAULT_TOLERANCE, s, m, h).0
}

/// [`step_body`] at Dormand-Prince tolerance `tolerance`, with the force evaluations the step
/// cost (Verlet's and Forest-Ruth's start force included).
pub fn step_body_at(
    integrator: Integrator,
    forces: &Forces,
    tolerance: f64,
    s: BodyState,
    m: f64,
    h: f64,
) -> (BodyState, u64) {
    struct One {
        s: BodyState,
        w: Mass,
        h: f64,
    }
    impl SchemeVisitor for One {
        type Out = (BodyState, u64);
        fn visit<S: Scheme>(self, scheme: S) -> (BodyState, u64) {
            let carry = scheme.start_carry(self.s, self.w);
            let start = u64::from(S::CARRIES_FORCE);
            let (s, _, n) = scheme.step_counted(self.s, self.w, self.h, carry);
            (s, n + start)
        }
    }
    let w = Mass::new(m);
    visit(integrator, forces, tolerance, One { s, w, h })
}

struct ExplicitEuler<'a, F>(&'a F);
struct SemiImplicitEuler<'a, F>(&'a F);
struct Verlet<'a, F>(&'a F);
struct VerletPredicted<'a, F>(&'a F);
struct Midpoint<'a, F>(&'a F);
struct Rk4<'a, F>(&'a F);
struct ImplicitEuler<'a, F>(&'a F);
struct Exact<'a, F>(&'a F);
struct ForestRuth<'a, F>(&'a F);
struct Dopri5<'a, F>(&'a F, f64);
struct ImplicitMidpoint<'a, F>(&'a F);
struct ImplicitMidpointSplit<'a, F>(&'a F);

impl<F: ForceModel> Scheme for ExplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let v = s.mv * w.inv;
        let f = self.0.force(s.p, v, w.m);
        let next = BodyState {
            p: s.p + h * v,
            mv: s.mv + h * f,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for SemiImplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let f = self.0.force(s.p, s.mv * w.inv, w.m);
        let mv = s.mv + h * f;
        let next = BodyState {
            p: s.p + h * (mv * w.inv),
            mv,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Verlet<'_, F> {
    const EVALS: u64 = 1;
    const CARRIES_FORCE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, f0: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let mv_half = s.mv + half * f0;
        let v_half = mv_half * w.inv;
        let p = s.p + h * v_half;
        // Position-only model: the velocity argument is not read.
        let f1 = self.0.force(p, v_half, w.m);
        let next = BodyState {
            p,
            mv: mv_half + half * f1,
        };
        (next, f1)
    }
    fn start_carry(&self, s: BodyState, w: Mass) -> DVec3 {
        self.0.force(s.p, s.mv * w.inv, w.m)
    }
}

impl<F: ForceModel> Scheme for VerletPredicted<'_, F> {
    const EVALS: u64 = 2;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let f0 = self.0.force(s.p, s.mv * w.inv, w.m);
        let mv_half = s.mv + half * f0;
        let p = s.p + h * (mv_half * w.inv);
        // Euler-predicted end velocity: its O(h^2) error enters the kick times h/2, so the local
        // error stays O(h^3) and the method keeps order 2 with drag.
        let v_pred = (mv_half + half * f0) * w.inv;
        let f1 = self.0.force(p, v_pred, w.m);
        let next = BodyState {
            p,
            mv: mv_half + half * f1,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Midpoint<'_, F> {
    const EVALS: u64 = 2;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let v = s.mv * w.inv;
        let f = self.0.force(s.p, v, w.m);
        let p_mid = s.p + half * v;
        let mv_mid = s.mv + half * f;
        let v_mid = mv_mid * w.inv;
        let f_mid = self.0.force(p_mid, v_mid, w.m);
        let next = BodyState {
            p: s.p + h * v_mid,
            mv: s.mv + h * f_mid,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Rk4<'_, F> {
    const EVALS: u64 = 4;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let half = 0.5 * h;
        let f = self.0;
        let k1p = s.mv * w.inv;
        let k1m = f.force(s.p, k1p, w.m);
        let k2p = (s.mv + half * k1m) * w.inv;
        let k2m = f.force(s.p + half * k1p, k2p, w.m);
        let k3p = (s.mv + half * k2m) * w.inv;
        let k3m = f.force(s.p + half * k2p, k3p, w.m);
        let k4p = (s.mv + h * k3m) * w.inv;
        let k4m = f.force(s.p + h * k3p, k4p, w.m);
        let sixth = h / 6.0;
        let next = BodyState {
            p: s.p + sixth * (k1p + 2.0 * k2p + 2.0 * k3p + k4p),
            mv: s.mv + sixth * (k1m + 2.0 * k2m + 2.0 * k3m + k4m),
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for ImplicitEuler<'_, F> {
    const EVALS: u64 = 1;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let lin = self.0.linear_part(w.m);
        let v = s.mv * w.inv;
        let a_nl = self.0.nonlinear_force(s.p, v, w.m) * w.inv;
        let rhs = v + h * (lin.a0 + a_nl - lin.w2 * (s.p - lin.anchor));
        let v1 = rhs / (1.0 + h * lin.kd + h * h * lin.w2);
        let next = BodyState {
            p: s.p + h * v1,
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for Exact<'_, F> {
    const EVALS: u64 = 0;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
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
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

/// Velocity terms' coefficients for one body: `a_vel(V) = -(kd + q |V|) V`.
#[derive(Clone, Copy)]
struct VelocityTerms {
    kd: f64,
    q: f64,
}

impl VelocityTerms {
    #[inline(always)]
    fn of<F: ForceModel>(f: &F, w: Mass) -> VelocityTerms {
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
    fn solve_half_kick(self, rhs: DVec3, h: f64) -> DVec3 {
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
    fn accel(self, v: DVec3) -> DVec3 {
        if self.q == 0.0 {
            return -self.kd * v;
        }
        -(self.kd + self.q * v.length()) * v
    }
}

/// One generalised Störmer-Verlet step of length `h` from `s` with position force `fp0` at
/// `s.p`: the new state and the position force at its position.
#[inline(always)]
fn generalized_verlet<F: ForceModel>(
    f: &F,
    vt: VelocityTerms,
    s: BodyState,
    w: Mass,
    h: f64,
    fp0: DVec3,
) -> (BodyState, DVec3) {
    let half = 0.5 * h;
    let v_half = vt.solve_half_kick((s.mv + half * fp0) * w.inv, h);
    let p = s.p + h * v_half;
    let fp1 = f.force(p, DVec3::ZERO, w.m);
    let mv = w.m * v_half + half * (fp1 + w.m * vt.accel(v_half));
    (BodyState { p, mv }, fp1)
}

impl<F: ForceModel> Scheme for ForestRuth<'_, F> {
    const EVALS: u64 = 3;
    const CARRIES_FORCE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, fp0: DVec3) -> (BodyState, DVec3) {
        let vt = VelocityTerms::of(self.0, w);
        let (c1, c2) = (FOREST_RUTH_C1, FOREST_RUTH_C2);
        let (s, fp) = generalized_verlet(self.0, vt, s, w, c1 * h, fp0);
        let (s, fp) = generalized_verlet(self.0, vt, s, w, c2 * h, fp);
        generalized_verlet(self.0, vt, s, w, c1 * h, fp)
    }
    fn start_carry(&self, s: BodyState, w: Mass) -> DVec3 {
        self.0.force(s.p, DVec3::ZERO, w.m)
    }
}

/// The Dormand-Prince 5(4) tableau: stage coefficients `a`, the 5th-order weights (the last
/// row of `a`, so the 7th stage is the next step's first) and the error weights `b5 - b4`.
mod dp {
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
struct Slope {
    p: DVec3,
    m: DVec3,
}

impl<F: ForceModel> Dopri5<'_, F> {
    #[inline(always)]
    fn slope(&self, p: DVec3, mv: DVec3, w: Mass) -> Slope {
        let v = mv * w.inv;
        Slope {
            p: v,
            m: self.0.force(p, v, w.m),
        }
    }
}

/// Largest of `|e_i| / (1 + max(|y0_i|, |y1_i|))` over the components of `e`.
#[inline(always)]
fn scaled_error(e: DVec3, y0: DVec3, y1: DVec3) -> f64 {
    let scale = DVec3::ONE + y0.abs().max(y1.abs());
    (e.abs() / scale).max_element()
}

impl<F: ForceModel> Scheme for Dopri5<'_, F> {
    const EVALS: u64 = 7;
    const ADAPTIVE: bool = true;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, c: DVec3) -> (BodyState, DVec3) {
        let (s, c, _) = self.step_counted(s, w, h, c);
        (s, c)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
    #[inline(never)]
    fn step_counted(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3, u64) {
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
        let mut k1 = self.slope(y.p, y.mv, w);
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
            let k2 = self.slope(p, m, w);
            let (p, m) = at([A31, A32, 0.0, 0.0, 0.0], [&k1, &k2, z, z, z]);
            let k3 = self.slope(p, m, w);
            let (p, m) = at([A41, A42, A43, 0.0, 0.0], [&k1, &k2, &k3, z, z]);
            let k4 = self.slope(p, m, w);
            let (p, m) = at([A51, A52, A53, A54, 0.0], [&k1, &k2, &k3, &k4, z]);
            let k5 = self.slope(p, m, w);
            let (p, m) = at([A61, A62, A63, A64, A65], [&k1, &k2, &k3, &k4, &k5]);
            let k6 = self.slope(p, m, w);
            let next_p = y.p + d * (B1 * k1.p + B3 * k3.p + B4 * k4.p + B5 * k5.p + B6 * k6.p);
            let next_m = y.mv + d * (B1 * k1.m + B3 * k3.m + B4 * k4.m + B5 * k5.m + B6 * k6.m);
            let k7 = self.slope(next_p, next_m, w);
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

/// The linear terms' midpoint-rule velocity update: `V'` from `V`, the position offset
/// `d = p - anchor` and the explicit acceleration `a_ex` (the constant part plus any other
/// terms).
#[inline(always)]
fn midpoint_linear(
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
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let lin = self.0.linear_part(w.m);
        let v = s.mv * w.inv;
        let v1 = midpoint_linear(&lin, v, s.p - lin.anchor, lin.a0, h);
        let next = BodyState {
            p: s.p + (0.5 * h) * (v + v1),
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

impl<F: ForceModel> Scheme for ImplicitMidpointSplit<'_, F> {
    const EVALS: u64 = 2;
    #[inline(always)]
    fn step(&self, s: BodyState, w: Mass, h: f64, _: DVec3) -> (BodyState, DVec3) {
        let f = self.0;
        let lin = f.linear_part(w.m);
        let v = s.mv * w.inv;
        let half = 0.5 * h;
        let (pm, vm) = (s.p + half * v, v + half * (f.force(s.p, v, w.m) * w.inv));
        let a_ex = lin.a0 + f.nonlinear_force(pm, vm, w.m) * w.inv;
        let v1 = midpoint_linear(&lin, v, s.p - lin.anchor, a_ex, h);
        let next = BodyState {
            p: s.p + half * (v + v1),
            mv: w.m * v1,
        };
        (next, DVec3::ZERO)
    }
    fn start_carry(&self, _: BodyState, _: Mass) -> DVec3 {
        DVec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gravity() -> Forces {
        Forces {
            gravity: Some(DVec3::new(0.0, 0.0, -9.81)),
            ..Forces::default()
        }
    }

    #[test]
    fn names_round_trip_through_parse() {
        for i in Integrator::ALL {
            assert_eq!(Integrator::parse(i.name()), Some(i));
            assert_eq!(Integrator::parse(&format!("{i:?}")), Some(i));
        }
        assert_eq!(Integrator::parse("RK-4"), Some(Integrator::Rk4));
        assert_eq!(Integrator::parse("leapfrog"), None);
    }

    #[test]
    fn explicit_euler_moves_with_the_start_velocity() {
        let s = BodyState {
            p: DVec3::new(10.0, 0.0, 2.0),
            mv: DVec3::new(19.2, 0.0, 72.5),
        };
        let next = step_body(Integrator::ExplicitEuler, &gravity(), s, 2.5, 0.2);
        assert_eq!(next.p, s.p + 0.2 * (s.mv * (1.0 / 2.5)));
        assert_eq!(next.mv, s.mv + 0.2 * DVec3::new(0.0, 0.0, 2.5 * -9.81));
    }

    /// The `exact` step on force sets it covered before springs is still the drag flow, bit for
    /// bit, on every model `visit` picks for them (pinned hashes depend on it).
    /// Force sets that reach every model `visit` picks: the constant field (with and without a
    /// constant force), the drag field (both forms) and the general model (drag without gravity).
    fn model_cases() -> [Forces; 5] {
        let constant = Some(DVec3::new(1.5, -0.5, 0.0));
        [
            gravity(),
            Forces {
                constant,
                ..gravity()
            },
            Forces {
                linear_drag: Some(0.3),
                ..gravity()
            },
            Forces {
                linear_drag: Some(0.3),
                constant,
                ..gravity()
            },
            Forces {
                linear_drag: Some(0.3),
                constant,
                ..Forces::default()
            },
        ]
    }

    #[test]
    fn exact_without_a_spring_is_the_drag_flow_bit_for_bit() {
        let cases = model_cases();
        let s = BodyState {
            p: DVec3::new(10.0, 0.0, 2.0),
            mv: DVec3::new(19.2, 0.0, 72.5),
        };
        let (m, h) = (2.5, 1.0 / 60.0);
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        for forces in cases {
            let a0 =
                forces.gravity.unwrap_or(DVec3::ZERO) + forces.constant.unwrap_or(DVec3::ZERO) / m;
            let k = forces.drag_rate(m);
            let v0 = s.mv * (1.0 / m);
            let (p, v) = crate::exact::linear_drag_flow(s.p, v0, a0, k, h);
            let next = step_body(Integrator::Exact, &forces, s, m, h);
            assert_eq!(bits(next.p), bits(p), "{forces:?}");
            assert_eq!(bits(next.mv), bits(m * v), "{forces:?}");
        }
    }

    /// Every integrator steps to the same bits through the fast-path model `visit` picks
    /// (`ConstantField`, `DragField`) and through the general `Forces`: a shortcut taken only
    /// where a model's term is a constant zero (Forest-Ruth's quadratic solve) changes no bit.
    #[test]
    fn fast_path_models_step_to_the_general_models_bits() {
        struct Steps(BodyState, Mass, f64);
        impl SchemeVisitor for Steps {
            type Out = Vec<[u64; 6]>;
            fn visit<S: Scheme>(self, scheme: S) -> Self::Out {
                let Steps(mut s, w, h) = self;
                let mut carry = scheme.start_carry(s, w);
                let mut out = Vec::new();
                for _ in 0..50 {
                    (s, carry) = scheme.step(s, w, h, carry);
                    let (p, mv) = (s.p.to_array(), s.mv.to_array());
                    out.push([p[0], p[1], p[2], mv[0], mv[1], mv[2]].map(f64::to_bits));
                }
                out
            }
        }
        let cases = model_cases();
        let s = BodyState {
            p: DVec3::new(10.0, 0.0, 2.0),
            mv: DVec3::new(19.2, 0.0, 72.5),
        };
        let (w, h) = (Mass::new(2.5), 1.0 / 60.0);
        for forces in cases {
            for integrator in Integrator::ALL {
                let fast = visit(integrator, &forces, DEFAULT_TOLERANCE, Steps(s, w, h));
                let general = visit_model(integrator, &forces, DEFAULT_TOLERANCE, Steps(s, w, h));
                assert_eq!(fast, general, "{integrator:?} on {forces:?}");
            }
        }
    }

    #[test]
    fn evaluation_counts_follow_the_forces() {
        let mut f = gravity();
        assert_eq!(Integrator::VelocityVerlet.evals_per_step(&f), 1);
        f.linear_drag = Some(0.1);
        assert_eq!(Integrator::VelocityVerlet.evals_per_step(&f), 2);
        assert_eq!(Integrator::Rk4.evals_per_step(&f), 4);
        assert_eq!(Integrator::Exact.evals_per_step(&f), 0);
    }
}
