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

pub use crate::body::{BodyState, Launch, Mass};
use crate::forces::{DragField, ForceModel, Forces, Rates, Reach};

mod dopri;
mod schemes;

pub(crate) use dopri::Dense;

use schemes::*;

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
    /// The closed-form solution, evaluated over each step (the `exact` module). No force
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
    /// diverging. More than `DOPRI_MAX_ATTEMPTS` attempts in one step, or a non-finite
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
pub const FOREST_RUTH_C1: f64 = 1.351_207_191_959_657_8;
/// Forest-Ruth's middle (backward) substep coefficient `1 - 2 c1`.
pub const FOREST_RUTH_C2: f64 = 1.0 - 2.0 * FOREST_RUTH_C1;

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
    /// one internal step: the fewest it can cost; velocity Verlet's carried force counted once a
    /// step; the closed form 0): what "equal cost" compares. Read from the scheme the step
    /// dispatches to (`Scheme::EVALS`), the one source of truth.
    pub fn evals_per_step(self, forces: &Forces) -> u64 {
        self.scheme_constants(forces).0
    }

    /// Whether the integrator carries the end-of-step position force to the next step under
    /// `forces` (velocity Verlet with position forces only, and Forest-Ruth always): then the
    /// carried force is part of the state a keyframe holds. Read from the scheme the step
    /// dispatches to (`Scheme::CARRIES_FORCE`), the one source of truth.
    pub fn carries_force(self, forces: &Forces) -> bool {
        self.scheme_constants(forces).1
    }

    /// `Scheme::EVALS` and `Scheme::CARRIES_FORCE` of the scheme a step of this integrator
    /// under `forces` dispatches to.
    fn scheme_constants(self, forces: &Forces) -> (u64, bool) {
        struct Constants;
        impl SchemeVisitor for Constants {
            type Out = (u64, bool);
            fn visit<S: Scheme>(self, _: S) -> (u64, bool) {
                (S::EVALS, S::CARRIES_FORCE)
            }
        }
        visit(self, forces, DEFAULT_TOLERANCE, Constants)
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
    /// Whether the force model may read a body's launch ([`ForceModel::READS_LAUNCH`]): the
    /// per-body loop fills [`Mass::launch`] only then, so the fast paths stay vectorised.
    const READS_LAUNCH: bool = false;
    /// Whether the evaluations per step vary (Dormand-Prince): then callers count them with
    /// [`Scheme::step_counted`] instead of [`Scheme::EVALS`].
    const ADAPTIVE: bool = false;
    /// How the partial step's path bends against the acceleration: `P'' = CURVATURE a`. 1 for
    /// the schemes that follow the flow (exact under constant force); 2 for semi-implicit and
    /// implicit Euler, whose partial step moves with its end velocity (`p0 + tau V0 +
    /// tau^2 a`); 0 for explicit Euler's straight line.
    const CURVATURE: f64 = 1.0;
    /// Whether a partial step from a state changes the velocity at the start's acceleration,
    /// whatever the forces (explicit and semi-implicit Euler: `mV0 + tau F(s0)`): then along a
    /// segment the velocity is linear in time and the position a polynomial, exactly.
    const CONSTANT_ACCEL_PATH: bool = false;
    /// Whether [`Scheme::step_dense`] keeps a continuous extension of the step (Dormand-Prince).
    const DENSE: bool = false;
    /// The force model's [`ForceModel::rates`] over `reach` (the event search's margins).
    fn rates(&self, reach: &Reach, w: Mass) -> Rates;
    /// [`Scheme::step_counted`], keeping the step's continuous extension in `dense` where the
    /// scheme has one ([`Scheme::DENSE`]): the same bits, no more evaluations.
    #[inline(always)]
    fn step_dense(
        &self,
        s: BodyState,
        w: Mass,
        t: f64,
        h: f64,
        carry: DVec3,
        dense: &mut Dense,
    ) -> (BodyState, DVec3, u64) {
        dense.clear();
        self.step_counted(s, w, t, h, carry)
    }
    /// Advances one body of mass `w` by `h`. `carry` is the force at the start state when
    /// [`Scheme::CARRIES_FORCE`], otherwise unused; the returned force is the end state's.
    /// `t` is the step's start on the world's clock (s), read only by a time-dependent term.
    fn step(&self, s: BodyState, w: Mass, t: f64, h: f64, carry: DVec3) -> (BodyState, DVec3);
    /// The carried force at a state at time `t` (the start of a run, after a command or a seek).
    fn start_carry(&self, s: BodyState, w: Mass, t: f64) -> DVec3;
    /// [`Scheme::step`] and the force evaluations it cost.
    #[inline(always)]
    fn step_counted(
        &self,
        s: BodyState,
        w: Mass,
        t: f64,
        h: f64,
        carry: DVec3,
    ) -> (BodyState, DVec3, u64) {
        let (s, c) = self.step(s, w, t, h, carry);
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
    visit_with(
        integrator,
        forces,
        forces.constant_field().as_ref(),
        tolerance,
        v,
    )
}

/// [`visit`] with `forces.constant_field()` already worked out (a world keeps it:
/// `world::ForceFacts`).
#[inline(always)]
pub(crate) fn visit_with<V: SchemeVisitor>(
    integrator: Integrator,
    forces: &Forces,
    constant: Option<&crate::forces::ConstantField>,
    tolerance: f64,
    v: V,
) -> V::Out {
    if let Some(field) = constant {
        return visit_model(integrator, field, tolerance, v);
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
/// cost (Verlet's and Forest-Ruth's start force included). The step starts at time 0; a
/// time-dependent term ([`crate::forces::ForceTerm`]) needs [`step_body_from`].
pub fn step_body_at(
    integrator: Integrator,
    forces: &Forces,
    tolerance: f64,
    s: BodyState,
    m: f64,
    h: f64,
) -> (BodyState, u64) {
    step_body_from(integrator, forces, tolerance, 0.0, s, m, h)
}

/// [`step_body_at`] from time `t` (s, the world's clock).
pub fn step_body_from(
    integrator: Integrator,
    forces: &Forces,
    tolerance: f64,
    t: f64,
    s: BodyState,
    m: f64,
    h: f64,
) -> (BodyState, u64) {
    struct One {
        s: BodyState,
        w: Mass,
        t: f64,
        h: f64,
    }
    impl SchemeVisitor for One {
        type Out = (BodyState, u64);
        fn visit<S: Scheme>(self, scheme: S) -> (BodyState, u64) {
            let carry = scheme.start_carry(self.s, self.w, self.t);
            let start = u64::from(S::CARRIES_FORCE);
            let (s, _, n) = scheme.step_counted(self.s, self.w, self.t, self.h, carry);
            (s, n + start)
        }
    }
    let w = Mass::new(m);
    visit(integrator, forces, tolerance, One { s, w, t, h })
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
                let mut carry = scheme.start_carry(s, w, 0.0);
                let mut out = Vec::new();
                for _ in 0..50 {
                    (s, carry) = scheme.step(s, w, 0.0, h, carry);
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
