//! What a scene file can fail with: where ([`SceneError`]), which value and why
//! ([`InvalidValue`], [`ValueProblem`]), and an integrator the forces refuse
//! ([`IntegratorError`]).

use super::*;

/// An error in a scene file: where, and what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The file (or a label for in-memory text).
    pub file: String,
    /// Line and column (1-based) for syntax and type errors.
    pub position: Option<(usize, usize)>,
    /// Field path for value errors, e.g. `bodies[0].mass`.
    pub field: Option<String>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((line, col)) = self.position {
            write!(f, ":{line}:{col}")?;
        }
        if let Some(field) = &self.field {
            write!(f, ": {field}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneError {}

/// A value that fails its check: the field path it was given for (`bodies[1].mass`, `dt`) and
/// what is wrong with it. Displays as `FIELD: PROBLEM`.
#[derive(Clone, Debug, PartialEq)]
pub struct InvalidValue {
    /// Field path, e.g. `bodies[0].mass`, `dt`, `substeps`.
    pub field: String,
    /// What is wrong and what was expected.
    pub problem: ValueProblem,
}

impl std::fmt::Display for InvalidValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.problem)
    }
}

impl std::error::Error for InvalidValue {}

/// What is wrong with a value in a scene (or an override of one), carrying the value given.
#[derive(Clone, Debug, PartialEq)]
pub enum ValueProblem {
    /// A number that must be finite is not.
    NotFinite(f64),
    /// A number that must be finite and > 0 is not.
    NotPositive(f64),
    /// A number that must be finite and >= 0 is not.
    NotNonNegative(f64),
    /// A number that must be from 0 to 1 is not.
    NotUnitInterval(f64),
    /// A vector with a component that is not finite.
    NotFiniteVector(DVec3),
    /// A vector that must have a direction (a wall normal) is zero.
    ZeroVector,
    /// A timestep (s) that rounds to less than 1 ns or more than 1000 s.
    Step(f64),
    /// Substeps per tick outside 1 to [`MAX_SUBSTEPS`].
    Substeps(u32),
    /// An adaptive tolerance outside [`MIN_TOLERANCE`] to 1.
    Tolerance(f64),
    /// A volley of more than [`MAX_VOLLEY`] bodies.
    VolleyCount(u32),
    /// More than [`MAX_BODIES`] bodies listed and in the volley together.
    TooManyBodies(u64),
    /// More than [`MAX_TICK_WORK`] body-steps a tick: bodies and substeps.
    TickWork {
        /// Bodies at tick 0.
        bodies: u64,
        /// Substeps per tick.
        substeps: u32,
    },
    /// More than [`MAX_COMPARE_LANES`] compare lanes.
    TooManyLanes(usize),
    /// A guard energy factor that is not a finite number > 1.
    EnergyFactor(f64),
    /// A force term declared a second time.
    DuplicateForce(ForceKind),
    /// A game's own term declared twice (by name).
    DuplicateTerm(String),
    /// An `Aim` launch in a scene without gravity along -z.
    AimNeedsGravity,
    /// An `Aim` launch with no solution.
    CannotAim(AimError),
    /// An integrator the declared forces refuse.
    Integrator(IntegratorError),
    /// A drag curve that is not one.
    DragTable(crate::drag::DragTableError),
    /// A Mach drag with neither or both of a ballistic coefficient and a diameter.
    DragSize,
    /// A custom force term this program has not registered.
    Custom(crate::forces::CustomForceError),
    /// A standard atmosphere's ground altitude outside -1000 m to 20 000 m.
    Altitude(f64),
    /// A thrust curve that is not one.
    ThrustCurve(crate::forces::ThrustCurveError),
    /// A spin on a Mach drag sized by a ballistic coefficient (the lift needs the diameter).
    SpinNeedsDiameter,
    /// A level surface (mesh or heightfield) that cannot be used: its file and what is wrong,
    /// or what the inline geometry lacks.
    Level(String),
    /// A Mach event in a scene without a Mach drag, whose air (its speed of sound and wind)
    /// the Mach number is read in.
    MachNeedsAir,
    /// An event naming a target the scene does not have.
    UnknownTarget {
        /// The index it names.
        index: u32,
        /// How many targets the scene has.
        targets: usize,
    },
    /// A stop after 0 occurrences.
    StopCount,
    /// More than [`MAX_EVENTS`] declared events.
    TooManyEvents(usize),
    /// A body whose mass at launch is not more than its motor's propellant.
    Propellant {
        /// The body's mass (kg).
        mass: f64,
        /// The motor's propellant (kg).
        propellant: f64,
    },
}

impl std::fmt::Display for ValueProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ValueProblem::NotFinite(x) => write!(f, "expected a finite number, got {x}"),
            ValueProblem::NotPositive(x) => write!(f, "expected a finite number > 0, got {x}"),
            ValueProblem::NotNonNegative(x) => {
                write!(f, "expected a finite number >= 0, got {x}")
            }
            ValueProblem::NotUnitInterval(x) => {
                write!(f, "expected a number from 0 to 1, got {x}")
            }
            ValueProblem::NotFiniteVector(v) => write!(f, "expected finite components, got {v}"),
            ValueProblem::ZeroVector => f.write_str("expected a non-zero vector"),
            ValueProblem::Level(m) => f.write_str(m),
            ValueProblem::Step(dt) => {
                write!(f, "expected a step from 1 ns to 1000 s, got {dt} s")
            }
            ValueProblem::Substeps(n) => write!(f, "expected 1 to {MAX_SUBSTEPS}, got {n}"),
            ValueProblem::Tolerance(x) => write!(
                f,
                "expected a tolerance from {MIN_TOLERANCE:e} to 1 (smaller cannot be met in f64), got {x}"
            ),
            ValueProblem::VolleyCount(n) => {
                write!(f, "expected at most {MAX_VOLLEY} bodies, got {n}")
            }
            ValueProblem::TooManyBodies(n) => write!(
                f,
                "expected at most {MAX_BODIES} bodies listed and in the volley together, got {n}"
            ),
            ValueProblem::TickWork { bodies, substeps } => write!(
                f,
                "expected at most {MAX_TICK_WORK} body-steps a tick, got {substeps} substeps \
                 for {bodies} bodies ({} body-steps)",
                bodies * u64::from(*substeps)
            ),
            ValueProblem::TooManyLanes(n) => {
                write!(f, "expected at most {MAX_COMPARE_LANES} lanes, got {n}")
            }
            ValueProblem::EnergyFactor(x) => write!(f, "expected a finite number > 1, got {x}"),
            ValueProblem::DuplicateTerm(name) => write!(
                f,
                "custom term `{name}` is declared twice; declare each term once"
            ),
            ValueProblem::DuplicateForce(kind) => write!(
                f,
                "{} is declared twice; declare each term once",
                kind.name()
            ),
            ValueProblem::AimNeedsGravity => {
                f.write_str("Aim needs a Gravity term pointing along -z")
            }
            ValueProblem::CannotAim(e) => write!(f, "cannot aim: {e}"),
            ValueProblem::Integrator(e) => write!(f, "{e}"),
            ValueProblem::DragTable(e) => write!(f, "{e}"),
            ValueProblem::Custom(e) => write!(f, "{e}"),
            ValueProblem::ThrustCurve(e) => write!(f, "{e}"),
            ValueProblem::Altitude(x) => {
                write!(f, "expected an altitude from -1000 m to 20000 m, got {x}")
            }
            ValueProblem::SpinNeedsDiameter => f.write_str(
                "a spin's lift needs the body's `diameter` (m), not a ballistic coefficient",
            ),
            ValueProblem::MachNeedsAir => f.write_str(
                "a Mach event needs an atmosphere: declare a MachDrag term, whose air (speed of \
                 sound, wind) the Mach number is read in",
            ),
            ValueProblem::UnknownTarget { index, targets } => write!(
                f,
                "expected a target of the scene (0 to {}), got {index}: it has {targets}",
                targets.saturating_sub(1)
            ),
            ValueProblem::TooManyEvents(n) => {
                write!(f, "expected at most {MAX_EVENTS} events, got {n}")
            }
            ValueProblem::StopCount => {
                f.write_str("expected Never, Body(n) or Run(n) with a count n of at least 1")
            }
            ValueProblem::Propellant { mass, propellant } => write!(
                f,
                "expected a mass at launch above the motor's {propellant} kg of propellant, \
                 got {mass} kg"
            ),
            ValueProblem::DragSize => f.write_str(
                "expected either `bc` (lb/in^2) or `diameter` (m) with an optional \
                 `form_factor`, not both or neither",
            ),
        }
    }
}

/// Why an integrator cannot run a scene's forces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorError {
    /// `exact` was asked for, and this declared force term has no closed form.
    NoClosedForm(ForceKind),
    /// Forest-Ruth was asked for, and this declared velocity term has no closed-form velocity
    /// solve (its half kicks solve linear and quadratic drag exactly, nothing else).
    NoVelocitySolve(ForceKind),
}

impl std::fmt::Display for IntegratorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IntegratorError::NoClosedForm(kind) => {
                let why = match kind {
                    ForceKind::Spring => "has none with a rest length",
                    ForceKind::PointMass => "has one only alone",
                    _ => "has none",
                };
                write!(
                    f,
                    "`exact` needs a closed form, and force term {} {why} (exact covers any mix \
                     of {COVERED}); choose another integrator",
                    kind.name()
                )
            }
            IntegratorError::NoVelocitySolve(kind) => write!(
                f,
                "`forest-ruth` solves its velocity terms in closed form (LinearDrag and \
                 QuadraticDrag), and force term {} has none; choose another integrator",
                kind.name()
            ),
        }
    }
}

/// What `exact` covers, as the refusal names it.
const COVERED: &str =
    "Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, or a PointMass alone";

impl std::error::Error for IntegratorError {}
