//! The force terms a scene can declare.
//!
//! A scene lists its terms; [`Forces`] holds one optional slot per kind and a step evaluates only
//! the slots that are filled, summed in the fixed order of the fields below (the order is part of
//! the bit-exact result). Scenes whose only terms are uniform gravity and a constant force are
//! stepped through [`ConstantField`], a model whose force is a compile-time constant expression
//! per body, so such scenes pay for nothing else; the choice is made once per tick, never per body.
//! Gravity with linear drag (and optionally a constant force) likewise gets [`DragField`].
//!
//! Every built-in term but the motor is conservative or dissipative, so without [`Thrust`] or a
//! game's own term a body's mechanical energy (`ForceModel::energy`) never grows between
//! commands; the divergence guard relies on that, and checks only finiteness while either is
//! declared ([`Forces::adds_energy`]).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::body::Mass;

mod custom;
mod fast_path;
mod kind;
mod mach_drag;
mod rates;
mod thrust;

pub use custom::{CustomForce, CustomForceError, ForceInput, ForceTerm, ForceTerms, Reads};
pub use fast_path::{ConstantField, DragField};
pub use kind::ForceKind;
pub use mach_drag::{
    AirModel, DragCurve, DragSize, KG_M2_PER_LB_IN2, LiftModel, MachDrag, NATHAN_DECAY_SPEED,
    RAD_S_PER_RPM, SpinDecay, SpinLift, Wind,
};
pub use rates::{Rates, Reach};
pub use thrust::{Thrust, ThrustCurve, ThrustCurveError, ThrustDirection};

/// Net force on one body, the only physics a step needs from a force description.
///
/// Implemented by [`ConstantField`] (gravity and constant force only) and [`Forces`] (any
/// declared terms). Integrators are generic over it, so the choice of model is resolved at
/// compile time inside the per-body loop.
pub trait ForceModel: Sync {
    /// Whether [`ForceModel::force_at`] may read `w.launch`: false for the fast paths, whose
    /// per-body loop then never loads the launch columns (and stays vectorised).
    const READS_LAUNCH: bool = false;

    /// Net force (N) on a body of mass `m` (kg) at position `p` (m) with velocity `v` (m/s).
    fn force(&self, p: DVec3, v: DVec3, m: f64) -> DVec3;
    /// [`ForceModel::force`] at time `t` (s, the world's clock) on a body of mass `w.m` launched
    /// as `w.launch` says: what the integrators call, with each stage's own time. Only the
    /// terms that need them read the time and the launch (a game's own term, [`ForceTerm`]; a
    /// spin's lift; a motor's thrust); for every other model this is `force`, and `t` and the
    /// launch compile away.
    #[inline(always)]
    fn force_at(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        let _ = t;
        self.force(p, v, w.m)
    }
    /// Whether [`ForceModel::force`] reads `v`. Velocity Verlet uses it to pick its variant.
    fn velocity_dependent(&self) -> bool;
    /// The terms that are linear in (p, v), as used by implicit Euler, for a body of mass `m`.
    fn linear_part(&self, m: f64) -> LinearPart;
    /// Force from the terms [`ForceModel::linear_part`] leaves out (treated explicitly).
    fn nonlinear_force(&self, p: DVec3, v: DVec3, m: f64) -> DVec3;
    /// [`ForceModel::nonlinear_force`] at time `t`, as [`ForceModel::force_at`] is `force`.
    #[inline(always)]
    fn nonlinear_force_at(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        let _ = t;
        self.nonlinear_force(p, v, w.m)
    }
    /// Whether any term is left to [`ForceModel::nonlinear_force`] (implicit midpoint picks its
    /// form by it). The fast-path models have none.
    #[inline(always)]
    fn has_nonlinear(&self) -> bool {
        false
    }
    /// The quadratic drag coefficient c (kg/m) of `-c |v| v`, 0 if undeclared (Forest-Ruth
    /// solves its velocity terms in closed form).
    #[inline(always)]
    fn quadratic_drag(&self) -> f64 {
        0.0
    }
    /// Mechanical energy (J) of one body: kinetic plus the potential of every conservative term.
    fn energy(&self, p: DVec3, v: DVec3, m: f64) -> f64;
    /// The point mass, when it is the only declared term (Kepler's problem, which the `exact`
    /// integrator solves in closed form); `None` for every other force set.
    #[inline(always)]
    fn lone_point_mass(&self) -> Option<PointMass> {
        None
    }
    /// Bounds on how fast the acceleration can change along a piece of path within `reach`
    /// ([`Rates`]), for the event search's margins. The linear part's coefficients by default:
    /// exact for the fast paths (gravity and a constant force: none; linear drag: `b/m`).
    #[inline(always)]
    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        let _ = reach;
        let l = self.linear_part(w.m);
        Rates {
            p: l.w2,
            v: l.kd,
            t: 0.0,
        }
    }
}

/// The linear part of an acceleration: `a = a0 - kd v - w2 (p - anchor)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearPart {
    /// Constant acceleration (m/s^2): gravity plus constant force over mass.
    pub a0: DVec3,
    /// Velocity damping rate (1/s): linear drag and spring damping over mass.
    pub kd: f64,
    /// Squared angular frequency (1/s^2) of a zero-rest-length spring, k/m.
    pub w2: f64,
    /// Anchor of that spring (m); irrelevant when `w2` is 0.
    pub anchor: DVec3,
}

/// A spring from every body to a fixed anchor: `F = -k (|d| - L) d/|d| - c v`, `d = p - anchor`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    /// Anchor point (m).
    pub anchor: DVec3,
    /// Stiffness k (N/m).
    pub stiffness: f64,
    /// Rest length L (m). With 0 the spring is linear in p and implicit Euler treats it implicitly.
    #[serde(default)]
    pub rest_length: f64,
    /// Damping c (N s/m) against the body's velocity.
    #[serde(default)]
    pub damping: f64,
}

/// Newtonian attraction to a fixed point mass: `F = -m mu d/|d|^3`, `d = p - center`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMass {
    /// Position of the attracting mass (m).
    pub center: DVec3,
    /// Gravitational parameter mu = G M (m^3/s^2).
    pub mu: f64,
}

/// The kinds that can add energy ([`Forces::potential`]), in the order `ForceModel::energy`
/// sums them.
const ENERGY_KINDS: [ForceKind; 5] = [
    ForceKind::Gravity,
    ForceKind::ConstantForce,
    ForceKind::Spring,
    ForceKind::PointMass,
    ForceKind::MachDrag,
];

/// The declared force terms of a scene, at most one of each kind.
///
/// An empty slot is never evaluated. Fields are public plain data, as in a scene file. Not
/// `Copy`: a Mach drag holds its curve and air column behind `Arc`s, so a clone is cheap.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Forces {
    /// Gravitational acceleration g (m/s^2), usually (0, 0, -9.81): `F = m g`.
    pub gravity: Option<DVec3>,
    /// A constant force (N) on every body, e.g. wind or thrust.
    pub constant: Option<DVec3>,
    /// Linear drag coefficient b (N s/m = kg/s): `F = -b v`.
    pub linear_drag: Option<f64>,
    /// Quadratic drag coefficient c (N s^2/m^2 = kg/m): `F = -c |v| v`.
    pub quadratic_drag: Option<f64>,
    /// Spring to an anchor.
    pub spring: Option<Spring>,
    /// Attraction to a point mass.
    pub point_mass: Option<PointMass>,
    /// Drag against a Mach-dependent curve, in a standard or uniform atmosphere and the wind.
    pub mach_drag: Option<MachDrag>,
    /// A game's own terms ([`ForceTerm`]), evaluated in this order after the built-in terms
    /// (but a motor's thrust).
    pub custom: Vec<CustomForce>,
    /// A motor, added last; with it every force is evaluated at the mass the motor has left
    /// ([`Thrust`] has how momentum and mass change together).
    pub thrust: Option<Thrust>,
}

impl Forces {
    /// Whether the term of `kind` is declared.
    pub fn has(&self, kind: ForceKind) -> bool {
        match kind {
            ForceKind::Gravity => self.gravity.is_some(),
            ForceKind::ConstantForce => self.constant.is_some(),
            ForceKind::LinearDrag => self.linear_drag.is_some(),
            ForceKind::QuadraticDrag => self.quadratic_drag.is_some(),
            ForceKind::Spring => self.spring.is_some(),
            ForceKind::PointMass => self.point_mass.is_some(),
            ForceKind::MachDrag => self.mach_drag.is_some(),
            ForceKind::Custom => !self.custom.is_empty(),
            ForceKind::Thrust => self.thrust.is_some(),
        }
    }

    /// The declared kinds, in evaluation order.
    pub fn kinds(&self) -> impl Iterator<Item = ForceKind> + '_ {
        ForceKind::ALL.into_iter().filter(|k| self.has(*k))
    }

    /// A copy with the term of `kind` removed.
    pub fn without(mut self, kind: ForceKind) -> Forces {
        match kind {
            ForceKind::Gravity => self.gravity = None,
            ForceKind::ConstantForce => self.constant = None,
            ForceKind::LinearDrag => self.linear_drag = None,
            ForceKind::QuadraticDrag => self.quadratic_drag = None,
            ForceKind::Spring => self.spring = None,
            ForceKind::PointMass => self.point_mass = None,
            ForceKind::MachDrag => self.mach_drag = None,
            ForceKind::Custom => self.custom.clear(),
            ForceKind::Thrust => self.thrust = None,
        }
        self
    }

    /// A copy keeping only the kinds for which `keep` is true.
    pub fn filtered(&self, keep: impl Fn(ForceKind) -> bool) -> Forces {
        ForceKind::ALL
            .into_iter()
            .filter(|k| !keep(*k))
            .fold(self.clone(), |f, k| f.without(k))
    }

    /// The same forces as a [`ConstantField`], if gravity and a constant force are all there is.
    pub(crate) fn constant_field(&self) -> Option<ConstantField> {
        // Direct field tests rather than `kinds()`: this runs every tick.
        let only_constant = self.linear_drag.is_none()
            && self.quadratic_drag.is_none()
            && self.spring.is_none()
            && self.point_mass.is_none()
            && self.mach_drag.is_none()
            && self.custom.is_empty()
            && self.thrust.is_none();
        only_constant.then(|| ConstantField {
            gravity: self.gravity.unwrap_or(DVec3::ZERO),
            force: self.constant.unwrap_or(DVec3::ZERO),
        })
    }

    /// The first declared term (in evaluation order) that has no closed-form solution in
    /// `exact` together with the others, if any.
    ///
    /// Every linear force set has one: gravity, constant force, linear drag and a spring with
    /// rest length 0 (any stiffness and damping), in any combination. So does a point mass
    /// alone (Kepler's problem). Refused, because `exact` evaluates the solution rather than
    /// approximating it: quadratic drag, Mach drag, a game's own term and thrust; a spring with a rest length (its pull is
    /// not linear in the position); a point mass with any other term (named as the point mass).
    pub fn without_closed_form(&self) -> Option<ForceKind> {
        let alone = self.kinds().count() == 1;
        self.kinds().find(|k| match k {
            ForceKind::QuadraticDrag
            | ForceKind::MachDrag
            | ForceKind::Custom
            | ForceKind::Thrust => true,
            ForceKind::Spring => self.spring.is_some_and(|s| s.rest_length != 0.0),
            ForceKind::PointMass => !alone,
            ForceKind::Gravity | ForceKind::ConstantForce | ForceKind::LinearDrag => false,
        })
    }

    /// Uniform acceleration (m/s^2) from gravity plus constant force, for a body of mass `m`.
    #[inline]
    fn uniform_accel(&self, m: f64) -> DVec3 {
        let mut a = DVec3::ZERO;
        if let Some(g) = self.gravity {
            a += g;
        }
        if let Some(f) = self.constant {
            a += f / m;
        }
        a
    }

    /// The energy (J) term `kind` adds to the kinetic energy of a body of mass `m` at `p`
    /// moving at `v`: its potential, or with wind the Mach drag's change to the kinetic energy
    /// in the air's frame (drag only ever takes energy away there; exact for a uniform wind
    /// with gravity, and with a profile the frame at the body's height). `None` where the term
    /// is undeclared or adds none. What `ForceModel::energy` sums and the guard's energy
    /// scale takes term by term.
    #[inline]
    pub fn potential(&self, kind: ForceKind, p: DVec3, v: DVec3, m: f64) -> Option<f64> {
        match kind {
            ForceKind::Gravity => self.gravity.map(|g| -(m * g.dot(p))),
            ForceKind::ConstantForce => self.constant.map(|c| -c.dot(p)),
            ForceKind::Spring => self.spring.map(|s| {
                let stretch = (p - s.anchor).length() - s.rest_length;
                0.5 * s.stiffness * stretch * stretch
            }),
            ForceKind::PointMass => self
                .point_mass
                .map(|pm| -(m * pm.mu / (p - pm.center).length())),
            ForceKind::MachDrag => self
                .mach_drag
                .as_ref()
                .and_then(|d| d.wind)
                .map(|w| 0.5 * m * ((v - w.at(p.z)).length_squared() - v.length_squared())),
            ForceKind::LinearDrag
            | ForceKind::QuadraticDrag
            | ForceKind::Custom
            | ForceKind::Thrust => None,
        }
    }

    /// `f` plus the terms that read the time or the launch: a spun Mach drag's lift and spin
    /// drag, and a game's own term, if declared (always explicit, so the full force and the
    /// explicit part both take them). `f` holds the Mach drag already unless it is spun.
    #[inline(always)]
    fn plus_timed(&self, f: DVec3, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        let mut f = f;
        if let Some(d) = self.spun_drag() {
            f += d.spun_force(t, p, v, w);
        }
        for c in &self.custom {
            f += c.force(t, p, v, w);
        }
        f
    }

    /// The Mach drag, if it is declared with a spin.
    #[inline]
    pub fn spun_drag(&self) -> Option<&MachDrag> {
        self.mach_drag.as_ref().filter(|d| d.spin.is_some())
    }

    /// Whether a declared term may add mechanical energy (a game's own, a motor): then the
    /// guard checks only that the state stays finite.
    #[inline]
    pub fn adds_energy(&self) -> bool {
        !self.custom.is_empty() || self.thrust.is_some()
    }

    /// Whether a declared term reads the clock or a body's launch (a game's own, a spin, a
    /// motor): a derivative of the state alone does not describe them.
    #[inline]
    pub fn timed(&self) -> bool {
        !self.custom.is_empty() || self.reads_launch()
    }

    /// Whether no declared term reads the clock or the launch: then [`ForceModel::force`] is
    /// the whole force, and the general model's evaluation is what it was before such terms.
    #[inline(always)]
    fn untimed(&self) -> bool {
        self.custom.is_empty()
            && self.thrust.is_none()
            && self.mach_drag.as_ref().is_none_or(|d| d.spin.is_none())
    }

    /// [`ForceModel::force_at`] with a term that reads the clock or the launch: out of line, so
    /// the scenes without one keep a small inlined evaluation.
    #[inline(never)]
    fn timed_force(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        self.with_motor(t, v, w, |w| {
            self.plus_timed(self.force(p, v, w.m), t, p, v, w)
        })
    }

    /// [`ForceModel::nonlinear_force_at`] with such a term, out of line.
    #[inline(never)]
    fn timed_nonlinear_force(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        if self.thrust.is_some() {
            // With a motor everything is explicit: the scaling is not linear in (p, v).
            return self.timed_force(t, p, v, w);
        }
        self.plus_timed(self.nonlinear_force(p, v, w.m), t, p, v, w)
    }

    /// Whether any declared term reads a body's [`crate::body::Launch`] (a spin, a motor):
    /// only then does the step fill it.
    #[inline]
    pub fn reads_launch(&self) -> bool {
        self.thrust.is_some()
            || self.spun_drag().is_some()
            || self.custom.iter().any(|c| c.reads().launch)
    }

    /// `part(t, w)`, the force on a body of mass `w.m`, or with a motor declared that force
    /// evaluated at the mass `m(t)` the motor has left, thrust added, and scaled by
    /// `w.m / m(t)` ([`Thrust`]: the step's momentum is `w.m V`).
    #[inline(always)]
    fn with_motor(&self, t: f64, v: DVec3, w: Mass, part: impl Fn(Mass) -> DVec3) -> DVec3 {
        match &self.thrust {
            None => part(w),
            Some(motor) => {
                let tau = t - w.launch.time;
                let now = Mass::launched(motor.mass_at(tau, w.launch.mass), w.launch);
                (part(now) + motor.force(tau, v)) * (w.m * now.inv)
            }
        }
    }

    /// Linear drag rate b/m (1/s) for a body of mass `m`, 0 if undeclared.
    #[inline]
    pub fn drag_rate(&self, m: f64) -> f64 {
        self.linear_drag.map_or(0.0, |b| b / m)
    }
}

impl ForceModel for Forces {
    const READS_LAUNCH: bool = true;

    fn rates(&self, reach: &Reach, w: Mass) -> Rates {
        self.rates_over(reach, w)
    }

    /// Every term but those that need the time or the launch ([`ForceModel::force_at`]): a
    /// game's own, a spun Mach drag (the whole term) and a motor.
    #[inline]
    fn force(&self, p: DVec3, v: DVec3, m: f64) -> DVec3 {
        let mut f = DVec3::ZERO;
        if let Some(g) = self.gravity {
            f += m * g;
        }
        if let Some(c) = self.constant {
            f += c;
        }
        if let Some(b) = self.linear_drag {
            f -= b * v;
        }
        if let Some(c) = self.quadratic_drag {
            f -= (c * v.length()) * v;
        }
        if let Some(s) = self.spring {
            f += spring_force(&s, p, v);
        }
        if let Some(pm) = self.point_mass {
            f += point_mass_force(&pm, p, m);
        }
        if let Some(d) = &self.mach_drag
            && d.spin.is_none()
        {
            f += d.force(p, v, m);
        }
        f
    }

    #[inline]
    fn force_at(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        if self.untimed() {
            self.force(p, v, w.m)
        } else {
            self.timed_force(t, p, v, w)
        }
    }

    #[inline]
    fn nonlinear_force_at(&self, t: f64, p: DVec3, v: DVec3, w: Mass) -> DVec3 {
        if self.untimed() {
            self.nonlinear_force(p, v, w.m)
        } else {
            self.timed_nonlinear_force(t, p, v, w)
        }
    }

    fn velocity_dependent(&self) -> bool {
        self.linear_drag.is_some()
            || self.quadratic_drag.is_some()
            || self.mach_drag.is_some()
            || self
                .thrust
                .as_ref()
                .is_some_and(|t| matches!(t.direction, ThrustDirection::Velocity { .. }))
            || self.custom.iter().any(|c| c.reads().velocity)
            || self.spring.is_some_and(|s| s.damping != 0.0)
    }

    #[inline]
    fn has_nonlinear(&self) -> bool {
        self.quadratic_drag.is_some()
            || self.spring.is_some_and(|s| s.rest_length != 0.0)
            || self.point_mass.is_some()
            || self.mach_drag.is_some()
            || !self.custom.is_empty()
            || self.thrust.is_some()
    }

    #[inline]
    fn quadratic_drag(&self) -> f64 {
        self.quadratic_drag.unwrap_or(0.0)
    }

    #[inline]
    fn linear_part(&self, m: f64) -> LinearPart {
        if self.thrust.is_some() {
            // Everything is explicit with a motor ([`ForceModel::nonlinear_force_at`]).
            return LinearPart {
                a0: DVec3::ZERO,
                kd: 0.0,
                w2: 0.0,
                anchor: DVec3::ZERO,
            };
        }
        let mut part = LinearPart {
            a0: self.uniform_accel(m),
            kd: self.drag_rate(m),
            w2: 0.0,
            anchor: DVec3::ZERO,
        };
        if let Some(s) = self.spring {
            part.kd += s.damping / m;
            if s.rest_length == 0.0 {
                part.w2 = s.stiffness / m;
                part.anchor = s.anchor;
            }
        }
        part
    }

    #[inline]
    fn nonlinear_force(&self, p: DVec3, v: DVec3, m: f64) -> DVec3 {
        let mut f = DVec3::ZERO;
        if let Some(c) = self.quadratic_drag {
            f -= (c * v.length()) * v;
        }
        if let Some(s) = self.spring
            && s.rest_length != 0.0
        {
            f += spring_force(&Spring { damping: 0.0, ..s }, p, v);
        }
        if let Some(pm) = self.point_mass {
            f += point_mass_force(&pm, p, m);
        }
        if let Some(d) = &self.mach_drag
            && d.spin.is_none()
        {
            f += d.force(p, v, m);
        }
        f
    }

    fn energy(&self, p: DVec3, v: DVec3, m: f64) -> f64 {
        let mut e = 0.5 * m * v.length_squared();
        // `e + (-x)` is `e - x` to the bit, so this is the sum as the terms were once written
        // out one by one.
        for kind in ENERGY_KINDS {
            if let Some(x) = self.potential(kind, p, v, m) {
                e += x;
            }
        }
        e
    }

    #[inline]
    fn lone_point_mass(&self) -> Option<PointMass> {
        let others = self.gravity.is_some()
            || self.constant.is_some()
            || self.linear_drag.is_some()
            || self.quadratic_drag.is_some()
            || self.spring.is_some()
            || self.mach_drag.is_some()
            || !self.custom.is_empty()
            || self.thrust.is_some();
        self.point_mass.filter(|_| !others)
    }
}

#[inline]
fn spring_force(s: &Spring, p: DVec3, v: DVec3) -> DVec3 {
    let d = p - s.anchor;
    let pull = if s.rest_length == 0.0 {
        -s.stiffness * d
    } else {
        let len = d.length();
        if len == 0.0 {
            // Direction undefined at the anchor: no spring force (the rest length is a sphere).
            DVec3::ZERO
        } else {
            (-s.stiffness * (len - s.rest_length) / len) * d
        }
    };
    pull - s.damping * v
}

#[inline]
fn point_mass_force(pm: &PointMass, p: DVec3, m: f64) -> DVec3 {
    let d = p - pm.center;
    let r2 = d.length_squared();
    let r = r2.sqrt();
    (-m * pm.mu / (r2 * r)) * d
}

#[cfg(test)]
mod tests;
