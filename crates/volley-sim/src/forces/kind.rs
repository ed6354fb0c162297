//! The kinds of force term, by name: what a command toggles and an error names.

use serde::{Deserialize, Serialize};

#[cfg(doc)]
use super::ForceTerm;

/// The kinds of force term, used to toggle a term and to name one in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum ForceKind {
    /// Uniform gravitational acceleration.
    Gravity,
    /// A constant force such as wind or thrust.
    ConstantForce,
    /// Drag proportional to velocity.
    LinearDrag,
    /// Drag proportional to speed squared.
    QuadraticDrag,
    /// Spring to an anchor.
    Spring,
    /// Attraction to a point mass.
    PointMass,
    /// Drag against a Mach-dependent curve in moving air.
    MachDrag,
    /// A game's own term ([`ForceTerm`]).
    Custom,
    /// A motor's thrust, the body's mass falling as it burns.
    Thrust,
}

impl ForceKind {
    /// Every kind, in evaluation order.
    pub const ALL: [ForceKind; 9] = [
        ForceKind::Gravity,
        ForceKind::ConstantForce,
        ForceKind::LinearDrag,
        ForceKind::QuadraticDrag,
        ForceKind::Spring,
        ForceKind::PointMass,
        ForceKind::MachDrag,
        ForceKind::Custom,
        ForceKind::Thrust,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ForceKind::Gravity => "Gravity",
            ForceKind::ConstantForce => "ConstantForce",
            ForceKind::LinearDrag => "LinearDrag",
            ForceKind::QuadraticDrag => "QuadraticDrag",
            ForceKind::Spring => "Spring",
            ForceKind::PointMass => "PointMass",
            ForceKind::MachDrag => "MachDrag",
            ForceKind::Custom => "Custom",
            ForceKind::Thrust => "Thrust",
        }
    }

    /// Parses a name as written by [`ForceKind::name`], ignoring ASCII case.
    pub fn parse(name: &str) -> Option<ForceKind> {
        ForceKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name))
    }
}
