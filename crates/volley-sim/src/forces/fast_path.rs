//! The fast paths: force models for the commonest scenes, chosen once per tick when a scene's
//! terms are only uniform gravity and a constant force ([`ConstantField`]) or gravity with linear
//! drag ([`DragField`]). Each computes what [`Forces`] would for the same terms, in the same
//! order, without the per-body tests of which terms are declared.

use glam::DVec3;

use super::{ForceModel, Forces, LinearPart};

/// Gravity plus a constant force, nothing else: the cheapest model, chosen automatically.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantField {
    /// Gravitational acceleration (m/s^2); zero if undeclared.
    pub gravity: DVec3,
    /// Constant force (N); zero if undeclared.
    pub force: DVec3,
}

impl ForceModel for ConstantField {
    #[inline(always)]
    fn force(&self, _p: DVec3, _v: DVec3, m: f64) -> DVec3 {
        m * self.gravity + self.force
    }

    fn velocity_dependent(&self) -> bool {
        false
    }

    #[inline(always)]
    fn linear_part(&self, m: f64) -> LinearPart {
        LinearPart {
            a0: self.gravity + self.force / m,
            kd: 0.0,
            w2: 0.0,
            anchor: DVec3::ZERO,
        }
    }

    #[inline(always)]
    fn nonlinear_force(&self, _p: DVec3, _v: DVec3, _m: f64) -> DVec3 {
        DVec3::ZERO
    }

    fn energy(&self, p: DVec3, v: DVec3, m: f64) -> f64 {
        0.5 * m * v.length_squared() - m * self.gravity.dot(p) - self.force.dot(p)
    }
}

/// Gravity and linear drag, plus a constant force when `CONSTANT`, nothing else: the model of
/// drag scenes, chosen automatically like [`ConstantField`].
///
/// Its force is [`Forces::force`] for exactly these terms, the same operations in the same
/// order, so results are bit-identical; it only drops the per-body tests of which terms are
/// declared, which keep the general loop from vectorising.
#[derive(Clone, Debug, PartialEq)]
pub struct DragField<const CONSTANT: bool> {
    forces: Forces,
    gravity: DVec3,
    constant: DVec3,
    drag: f64,
}

impl<const CONSTANT: bool> DragField<CONSTANT> {
    /// `forces` as this model, if they are gravity, linear drag and (exactly when `CONSTANT`) a
    /// constant force.
    pub fn of(forces: &Forces) -> Option<DragField<CONSTANT>> {
        let (Some(gravity), Some(drag)) = (forces.gravity, forces.linear_drag) else {
            return None;
        };
        let others = forces.quadratic_drag.is_some()
            || forces.spring.is_some()
            || forces.point_mass.is_some()
            || forces.mach_drag.is_some()
            || !forces.custom.is_empty()
            || forces.thrust.is_some();
        (forces.constant.is_some() == CONSTANT && !others).then(|| DragField {
            forces: forces.clone(),
            gravity,
            constant: forces.constant.unwrap_or(DVec3::ZERO),
            drag,
        })
    }
}

impl<const CONSTANT: bool> ForceModel for DragField<CONSTANT> {
    #[inline(always)]
    fn force(&self, _p: DVec3, v: DVec3, m: f64) -> DVec3 {
        let mut f = DVec3::ZERO;
        f += m * self.gravity;
        if CONSTANT {
            f += self.constant;
        }
        f -= self.drag * v;
        f
    }

    fn velocity_dependent(&self) -> bool {
        true
    }

    #[inline(always)]
    fn linear_part(&self, m: f64) -> LinearPart {
        let mut a0 = DVec3::ZERO;
        a0 += self.gravity;
        if CONSTANT {
            a0 += self.constant / m;
        }
        LinearPart {
            a0,
            kd: self.drag / m,
            w2: 0.0,
            anchor: DVec3::ZERO,
        }
    }

    #[inline(always)]
    fn nonlinear_force(&self, _p: DVec3, _v: DVec3, _m: f64) -> DVec3 {
        DVec3::ZERO
    }

    fn energy(&self, p: DVec3, v: DVec3, m: f64) -> f64 {
        self.forces.energy(p, v, m)
    }
}
