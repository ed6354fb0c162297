//! Scene files (RON) to a validated [`Scene`]: pure data, every value checked, errors located.
//!
//! The format is documented in the docs/scenes.md. Syntax and type errors carry the
//! file, line and column from the RON parser; value errors name the field path
//! (`bodies[1].mass`) and what was expected. Nothing here panics on any input.

use std::path::Path;
use std::time::Duration;

use glam::DVec3;
use serde::Deserialize;

use crate::contact::{Detection, Ground, Target, Wall};
use crate::exact::{AimError, Arc, aim};
use crate::forces::{ForceKind, Forces, PointMass, Spring};
use crate::integrate::{DEFAULT_TOLERANCE, Integrator};

mod bundled;
pub use bundled::{BUNDLED, bundled};

/// Most integrator steps per tick a scene may ask for: beyond this a stiff scene wants implicit
/// Euler, and a typo should not make a run take forever.
pub const MAX_SUBSTEPS: u32 = 10_000;

/// The smallest adaptive tolerance a scene may ask for: an error estimate of about 100 ulps of
/// the state, below which rounding alone fails the test and the step would shrink to nothing.
pub const MIN_TOLERANCE: f64 = 1e-14;

fn check_tolerance(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if (MIN_TOLERANCE..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::Tolerance(x)))
    }
}
/// Most bodies a world may hold: the scene's bodies and volley together, and what commands
/// spawn later (a few hundred megabytes of state, keyframe and scratch at this count): a typo
/// or a hostile file should be an error, not an allocation of gigabytes. The limits are listed in
/// docs/limits.md.
pub const MAX_BODIES: usize = 1_000_000;

/// Most bodies a `volley` may spawn: [`MAX_BODIES`] less the listed bodies.
pub const MAX_VOLLEY: u32 = MAX_BODIES as u32;

/// Most body-steps one tick may ask for (bodies times substeps): about a second of one core's
/// work with the slowest fixed-step integrators, so no file makes a tick take minutes.
pub const MAX_TICK_WORK: u64 = 100_000_000;

/// Most compare lanes a scene (`compare`) or `--compare` may ask for: each lane is a whole world.
pub const MAX_COMPARE_LANES: usize = 16;

/// A scene after parsing and validation; everything a [`crate::World`] is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (defaults to the file stem).
    pub name: String,
    /// One line on what the scene shows.
    pub description: String,
    /// The scene file's text, verbatim (recordings embed it).
    pub source: String,
    /// Fixed timestep, in whole nanoseconds; the physics step `h` is exactly this.
    pub timestep: Duration,
    /// Sim time (s) of tick 0; the time of tick n is `start_time + n * h`.
    pub start_time: f64,
    /// Sim time (s) a headless run covers unless told otherwise (default 10 s).
    pub duration: f64,
    /// Integrator unless a run overrides it.
    pub integrator: Integrator,
    /// Integrator steps per tick (each `h / substeps` long). 1 unless stiffness asks for more.
    pub substeps: u32,
    /// Error tolerance of the adaptive integrator ([`Integrator::Dopri5`]), from
    /// [`MIN_TOLERANCE`] to 1 (default [`crate::integrate::DEFAULT_TOLERANCE`]); the fixed-step
    /// integrators ignore it.
    pub tolerance: f64,
    /// Declared force terms.
    pub forces: Forces,
    /// Ground plane, if any.
    pub ground: Option<Ground>,
    /// Thin walls (slabs).
    pub walls: Vec<Wall>,
    /// Target spheres.
    pub targets: Vec<Target>,
    /// Swept (time of impact inside the step) or discrete (overlap at the end of the step).
    pub detection: Detection,
    /// Bodies present at tick 0, in id order.
    pub bodies: Vec<BodySpec>,
    /// Where fired projectiles start and how they are launched.
    pub launcher: Launcher,
    /// Extra bodies fired at tick 0 from the launcher with seeded random spread.
    pub volley: Option<Volley>,
    /// Seed of the world's random number generator.
    pub seed: u64,
    /// Divergence guard settings.
    pub guard: Guard,
    /// Lanes the window opens in compare mode (empty: one lane); headless runs ignore it and
    /// step [`Scene::integrator`].
    pub compare: Vec<CompareLane>,
}

/// One lane of compare mode: an integrator, and its own dt and substeps where given (else the
/// scene's). Written `(integrator: Rk4, dt: 0.05, substeps: 2)` in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompareLane {
    /// The lane's integrator.
    pub integrator: Integrator,
    /// Its timestep (s), rounded to whole nanoseconds; the scene's if absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Its integrator steps per tick; the scene's if absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substeps: Option<u32>,
}

impl CompareLane {
    /// A lane of `integrator` at the scene's step.
    pub fn of(integrator: Integrator) -> CompareLane {
        CompareLane {
            integrator,
            dt: None,
            substeps: None,
        }
    }

    /// `scene` as this lane runs it: its integrator, and its dt and substeps where given.
    pub fn apply(&self, scene: &Scene) -> Result<Scene, SceneError> {
        let mut s = scene.clone();
        let field = |what: String| SceneError {
            file: scene.name.clone(),
            position: None,
            field: Some(what.clone()),
            message: what,
        };
        s.set_integrator(self.integrator)
            .map_err(|e| field(format!("{}: {e}", self.integrator)))?;
        if let Some(dt) = self.dt {
            s.set_dt(dt).map_err(|e| field(e.to_string()))?;
        }
        if let Some(n) = self.substeps {
            s.set_substeps(n).map_err(|e| field(e.to_string()))?;
        }
        Ok(s)
    }
}

impl Scene {
    /// The scene as a scene file that parses back to it: every force term, surface, target
    /// and body (launches as velocities), the launcher, the volley, the seed, the guard and the
    /// compare lanes. What the window's "Save setup" writes; `parse` of it gives a scene that
    /// steps to the same bits.
    pub fn to_ron(&self) -> String {
        let f = &self.forces;
        let mut forces = Vec::new();
        if let Some(g) = f.gravity {
            forces.push(ForceTerm::Gravity(g));
        }
        if let Some(c) = f.constant {
            forces.push(ForceTerm::ConstantForce(c));
        }
        if let Some(b) = f.linear_drag {
            forces.push(ForceTerm::LinearDrag(b));
        }
        if let Some(c) = f.quadratic_drag {
            forces.push(ForceTerm::QuadraticDrag(c));
        }
        if let Some(sp) = f.spring {
            forces.push(ForceTerm::Spring {
                anchor: sp.anchor,
                stiffness: sp.stiffness,
                rest_length: sp.rest_length,
                damping: sp.damping,
            });
        }
        if let Some(pm) = f.point_mass {
            forces.push(ForceTerm::PointMass {
                center: pm.center,
                mu: pm.mu,
            });
        }
        let raw = RawScene {
            name: Some(self.name.clone()),
            description: self.description.clone(),
            dt: self.dt(),
            start_time: self.start_time,
            duration: self.duration,
            integrator: self.integrator,
            substeps: self.substeps,
            tolerance: (self.tolerance != DEFAULT_TOLERANCE).then_some(self.tolerance),
            forces,
            ground: self.ground,
            walls: self.walls.clone(),
            targets: self.targets.clone(),
            detection: self.detection,
            bodies: self
                .bodies
                .iter()
                .map(|b| RawBody {
                    mass: b.mass,
                    radius: b.radius,
                    position: b.position,
                    launch: Launch::Velocity(b.velocity),
                })
                .collect(),
            launcher: Some(self.launcher),
            volley: self.volley,
            seed: self.seed,
            guard: self.guard,
            compare: self.compare.clone(),
        };
        let config = ron::ser::PrettyConfig::new()
            .struct_names(true)
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
        let body = ron::ser::to_string_pretty(&raw, config)
            .unwrap_or_else(|e| format!("// could not write the scene: {e}\n"));
        format!(
            "// Written by Volley's \"Save setup\": the scene `{}` as set up in the window (its\n\
             // launcher, targets, integrator, step and compare lanes), bodies as launch\n\
             // velocities. `volley window FILE` and `volley headless FILE` open it.\n{body}\n",
            // Escaped: a name with a line break would end the comment and break the file.
            self.name.escape_debug()
        )
    }
    /// Overrides the integrator, refusing `exact` where a declared force has no closed form.
    pub fn set_integrator(&mut self, integrator: Integrator) -> Result<(), IntegratorError> {
        check_integrator(integrator, &self.forces)?;
        self.integrator = integrator;
        Ok(())
    }

    /// Overrides the timestep (s), rounded to whole nanoseconds.
    pub fn set_dt(&mut self, dt: f64) -> Result<(), InvalidValue> {
        self.timestep = timestep_from_secs("dt", dt)?;
        Ok(())
    }

    /// Overrides the adaptive integrator's tolerance ([`MIN_TOLERANCE`] to 1).
    pub fn set_tolerance(&mut self, tolerance: f64) -> Result<(), InvalidValue> {
        self.tolerance = check_tolerance("tolerance", tolerance)?;
        Ok(())
    }

    /// Overrides the substeps per tick (1 to [`MAX_SUBSTEPS`], and at most [`MAX_TICK_WORK`]
    /// body-steps a tick with the scene's bodies).
    pub fn set_substeps(&mut self, substeps: u32) -> Result<(), InvalidValue> {
        if !(1..=MAX_SUBSTEPS).contains(&substeps) {
            return Err(invalid("substeps", ValueProblem::Substeps(substeps)));
        }
        let bodies = self.body_count() as u64;
        if bodies.max(1) * u64::from(substeps) > MAX_TICK_WORK {
            return Err(invalid(
                "substeps",
                ValueProblem::TickWork { bodies, substeps },
            ));
        }
        self.substeps = substeps;
        Ok(())
    }

    /// Bodies a world of this scene starts with: the listed ones and the volley.
    pub fn body_count(&self) -> usize {
        self.bodies.len() + self.volley.map_or(0, |v| v.count as usize)
    }

    /// The physics step h (s): the timestep's nanoseconds over 1e9.
    pub fn dt(&self) -> f64 {
        self.timestep.as_nanos() as f64 * 1e-9
    }

    /// Ticks from `start_time` to sim time `t`: `(t - start_time) / h`, rounded when within
    /// 1e-9 of a whole number (so `--until 10.4` at h = 0.2 from 5.0 is 27 ticks, not 28),
    /// rounded up otherwise. Negative spans give 0.
    pub fn ticks_until(&self, t: f64) -> u64 {
        let n = (t - self.start_time) / self.dt();
        if n.is_nan() || n <= 0.0 {
            return 0;
        }
        let nearest = n.round();
        let ticks = if (n - nearest).abs() <= 1e-9 * nearest.max(1.0) {
            nearest
        } else {
            n.ceil()
        };
        ticks.min(u64::MAX as f64) as u64
    }
}

/// A body at spawn: mass, size and initial state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodySpec {
    /// Mass (kg), > 0.
    pub mass: f64,
    /// Radius (m), >= 0; used by contacts and targets and for drawing.
    pub radius: f64,
    /// Initial position (m).
    pub position: DVec3,
    /// Initial velocity (m/s), resolved from the scene's launch description.
    pub velocity: DVec3,
}

/// The launcher the window's fire button and `Fire` commands use.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Launcher {
    /// Muzzle position (m).
    pub position: DVec3,
    /// Launch speed (m/s).
    pub speed: f64,
    /// Elevation above the horizontal (degrees).
    pub elevation_deg: f64,
    /// Azimuth from +x towards +y (degrees).
    pub azimuth_deg: f64,
    /// Mass of a fired projectile (kg).
    #[serde(default = "one")]
    pub mass: f64,
    /// Radius of a fired projectile (m).
    #[serde(default = "tenth")]
    pub radius: f64,
}

impl Launcher {
    /// Launch velocity (m/s) from speed, elevation and azimuth.
    pub fn velocity(&self) -> DVec3 {
        angles_to_velocity(self.speed, self.elevation_deg, self.azimuth_deg)
    }
}

/// Many projectiles fired at once from the launcher, spread by the world's seeded generator.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Volley {
    /// How many.
    pub count: u32,
    /// Uniform spread of launch speed, +- (m/s).
    #[serde(default)]
    pub speed_spread: f64,
    /// Uniform spread of elevation and azimuth, +- (degrees).
    #[serde(default)]
    pub angle_spread_deg: f64,
}

/// Settings of the divergence guard (see [`crate::step`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Guard {
    /// A body whose energy exceeds its start energy by more than `(energy_factor - 1)` times its
    /// start energy scale stops the run. Every force term conserves or dissipates energy, so only
    /// a numerical instability can trip it. Default 10 (the reference's "10x its start").
    pub energy_factor: f64,
    /// Check energy every this many ticks; 0 turns the energy check off (the non-finite check
    /// always runs). Default 1.
    pub every: u32,
}

impl Default for Guard {
    fn default() -> Self {
        Guard {
            energy_factor: 10.0,
            every: 1,
        }
    }
}

fn one() -> f64 {
    1.0
}
fn tenth() -> f64 {
    0.1
}

/// Velocity from speed (m/s), elevation and azimuth (degrees), z up.
pub fn angles_to_velocity(speed: f64, elevation_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (el, az) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let horizontal = speed * libm::cos(el);
    DVec3::new(
        horizontal * libm::cos(az),
        horizontal * libm::sin(az),
        speed * libm::sin(el),
    )
}

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

/// One force term as written in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
enum ForceTerm {
    Gravity(DVec3),
    ConstantForce(DVec3),
    LinearDrag(f64),
    QuadraticDrag(f64),
    Spring {
        anchor: DVec3,
        stiffness: f64,
        #[serde(default)]
        rest_length: f64,
        #[serde(default)]
        damping: f64,
    },
    PointMass {
        center: DVec3,
        mu: f64,
    },
}

impl ForceTerm {
    fn kind(&self) -> ForceKind {
        match self {
            ForceTerm::Gravity(_) => ForceKind::Gravity,
            ForceTerm::ConstantForce(_) => ForceKind::ConstantForce,
            ForceTerm::LinearDrag(_) => ForceKind::LinearDrag,
            ForceTerm::QuadraticDrag(_) => ForceKind::QuadraticDrag,
            ForceTerm::Spring { .. } => ForceKind::Spring,
            ForceTerm::PointMass { .. } => ForceKind::PointMass,
        }
    }
}

/// A launch as written in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
enum Launch {
    Velocity(DVec3),
    Angles {
        speed: f64,
        elevation_deg: f64,
        #[serde(default)]
        azimuth_deg: f64,
    },
    Aim {
        target: DVec3,
        speed: f64,
        arc: Arc,
    },
}

#[derive(Debug, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBody {
    mass: f64,
    #[serde(default = "tenth")]
    radius: f64,
    position: DVec3,
    #[serde(default = "at_rest")]
    launch: Launch,
}

fn at_rest() -> Launch {
    Launch::Velocity(DVec3::ZERO)
}

#[derive(Debug, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
struct RawScene {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    description: String,
    dt: f64,
    #[serde(default)]
    start_time: f64,
    #[serde(default = "ten")]
    duration: f64,
    integrator: Integrator,
    #[serde(default = "one_u32")]
    substeps: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tolerance: Option<f64>,
    #[serde(default)]
    forces: Vec<ForceTerm>,
    #[serde(default)]
    ground: Option<Ground>,
    #[serde(default)]
    walls: Vec<Wall>,
    #[serde(default)]
    targets: Vec<Target>,
    #[serde(default)]
    detection: Detection,
    #[serde(default)]
    bodies: Vec<RawBody>,
    #[serde(default)]
    launcher: Option<Launcher>,
    #[serde(default)]
    volley: Option<Volley>,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    guard: Guard,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    compare: Vec<CompareLane>,
}

fn one_u32() -> u32 {
    1
}

fn ten() -> f64 {
    10.0
}

/// Most bytes of any text file Volley reads (scenes, command and input scripts, shard files):
/// far past any real one, and a bound on what a file that never ends (`/dev/zero`) can cost.
pub const MAX_TEXT_BYTES: u64 = 256 << 20;

/// Reads a text file of at most [`MAX_TEXT_BYTES`]; a longer one is an error saying so.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut text = String::new();
    std::fs::File::open(path)?
        .take(MAX_TEXT_BYTES + 1)
        .read_to_string(&mut text)?;
    if text.len() as u64 > MAX_TEXT_BYTES {
        return Err(std::io::Error::other(format!(
            "longer than {} MiB, the most a text file Volley reads may be",
            MAX_TEXT_BYTES >> 20
        )));
    }
    Ok(text)
}

/// Reads and validates a scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let text = read_text(path).map_err(|e| SceneError {
        file: file.clone(),
        position: None,
        field: None,
        message: format!("cannot read: {e}"),
    })?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    parse(&text, &file, stem.as_deref().unwrap_or("scene"))
}

/// Parses and validates scene text; `file` labels errors, `default_name` is used if the scene
/// has no `name`.
pub fn parse(text: &str, file: &str, default_name: &str) -> Result<Scene, SceneError> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let raw: RawScene = options.from_str(text).map_err(|e| SceneError {
        file: file.to_string(),
        position: Some((e.span.start.line, e.span.start.col)),
        field: None,
        message: e.code.to_string(),
    })?;
    validate(raw, text, default_name).map_err(|e| SceneError {
        file: file.to_string(),
        position: None,
        message: e.problem.to_string(),
        field: Some(e.field),
    })
}

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
#[derive(Clone, Copy, Debug, PartialEq)]
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
    /// An `Aim` launch in a scene without gravity along -z.
    AimNeedsGravity,
    /// An `Aim` launch with no solution.
    CannotAim(AimError),
    /// An integrator the declared forces refuse.
    Integrator(IntegratorError),
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
        }
    }
}

/// Why an integrator cannot run a scene's forces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorError {
    /// `exact` was asked for, and this declared force term has no closed form.
    NoClosedForm(ForceKind),
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
        }
    }
}

/// What `exact` covers, as the refusal names it.
const COVERED: &str =
    "Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, or a PointMass alone";

impl std::error::Error for IntegratorError {}

/// At most [`MAX_TICK_WORK`] body-steps a tick in the scene's own lane and in each compare lane.
fn check_tick_work(raw: &RawScene, bodies: u64) -> Result<(), InvalidValue> {
    let lanes = raw.compare.iter().enumerate();
    let asked = std::iter::once(("substeps".to_string(), raw.substeps)).chain(
        lanes.filter_map(|(i, l)| l.substeps.map(|n| (format!("compare[{i}].substeps"), n))),
    );
    for (field, substeps) in asked {
        if bodies.max(1) * u64::from(substeps) > MAX_TICK_WORK {
            return Err(invalid(field, ValueProblem::TickWork { bodies, substeps }));
        }
    }
    Ok(())
}

fn invalid(field: impl Into<String>, problem: ValueProblem) -> InvalidValue {
    InvalidValue {
        field: field.into(),
        problem,
    }
}

fn finite(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotFinite(x)))
    }
}

fn positive(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotPositive(x)))
    }
}

fn non_negative(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotNonNegative(x)))
    }
}

fn unit_interval(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if (0.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotUnitInterval(x)))
    }
}

fn finite3(field: &str, v: DVec3) -> Result<DVec3, InvalidValue> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(field, ValueProblem::NotFiniteVector(v)))
    }
}

/// Converts a step in seconds to whole nanoseconds, the clock's unit; errors name `field`.
pub fn timestep_from_secs(field: &str, dt: f64) -> Result<Duration, InvalidValue> {
    let dt = positive(field, dt)?;
    let nanos = (dt * 1e9).round();
    if !(1.0..=1e12).contains(&nanos) {
        return Err(invalid(field, ValueProblem::Step(dt)));
    }
    Ok(Duration::from_nanos(nanos as u64))
}

fn validate(raw: RawScene, text: &str, default_name: &str) -> Result<Scene, InvalidValue> {
    let timestep = timestep_from_secs("dt", raw.dt)?;
    let start_time = finite("start_time", raw.start_time)?;
    let duration = non_negative("duration", raw.duration)?;
    let integrator = raw.integrator;
    if !(1..=MAX_SUBSTEPS).contains(&raw.substeps) {
        return Err(invalid("substeps", ValueProblem::Substeps(raw.substeps)));
    }
    let tolerance = match raw.tolerance {
        Some(x) => check_tolerance("tolerance", x)?,
        None => DEFAULT_TOLERANCE,
    };
    let forces = validate_forces(&raw.forces)?;
    check_integrator(integrator, &forces)
        .map_err(|e| invalid("integrator", ValueProblem::Integrator(e)))?;
    if raw.compare.len() > MAX_COMPARE_LANES {
        return Err(invalid(
            "compare",
            ValueProblem::TooManyLanes(raw.compare.len()),
        ));
    }
    // A volley too large on its own is said of its count, below.
    let total = raw.bodies.len() as u64 + raw.volley.map_or(0, |v| u64::from(v.count));
    if total > MAX_BODIES as u64 && raw.volley.is_none_or(|v| v.count <= MAX_VOLLEY) {
        let field = if raw.volley.is_some() {
            "volley.count"
        } else {
            "bodies"
        };
        return Err(invalid(field, ValueProblem::TooManyBodies(total)));
    }
    for (i, lane) in raw.compare.iter().enumerate() {
        check_integrator(lane.integrator, &forces).map_err(|e| {
            invalid(
                format!("compare[{i}].integrator"),
                ValueProblem::Integrator(e),
            )
        })?;
        if let Some(dt) = lane.dt {
            timestep_from_secs(&format!("compare[{i}].dt"), dt)?;
        }
        if let Some(n) = lane.substeps
            && !(1..=MAX_SUBSTEPS).contains(&n)
        {
            return Err(invalid(
                format!("compare[{i}].substeps"),
                ValueProblem::Substeps(n),
            ));
        }
    }
    check_tick_work(&raw, total)?;
    let ground = raw
        .ground
        .map(|g| -> Result<Ground, InvalidValue> {
            finite("ground.height", g.height)?;
            unit_interval("ground.restitution", g.restitution)?;
            Ok(g)
        })
        .transpose()?;
    let walls = raw
        .walls
        .iter()
        .enumerate()
        .map(|(i, w)| validate_wall(i, w))
        .collect::<Result<Vec<_>, _>>()?;
    for (i, t) in raw.targets.iter().enumerate() {
        finite3(&format!("targets[{i}].center"), t.center)?;
        finite3(&format!("targets[{i}].velocity"), t.velocity)?;
        positive(&format!("targets[{i}].radius"), t.radius)?;
    }
    let bodies = raw
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| validate_body(i, b, &forces))
        .collect::<Result<Vec<_>, _>>()?;
    let launcher = match raw.launcher {
        Some(l) => validate_launcher(l)?,
        None => default_launcher(bodies.first()),
    };
    if let Some(v) = raw.volley {
        if v.count > MAX_VOLLEY {
            return Err(invalid("volley.count", ValueProblem::VolleyCount(v.count)));
        }
        non_negative("volley.speed_spread", v.speed_spread)?;
        non_negative("volley.angle_spread_deg", v.angle_spread_deg)?;
    }
    if !(raw.guard.energy_factor.is_finite() && raw.guard.energy_factor > 1.0) {
        return Err(invalid(
            "guard.energy_factor",
            ValueProblem::EnergyFactor(raw.guard.energy_factor),
        ));
    }
    Ok(Scene {
        name: raw.name.unwrap_or_else(|| default_name.to_string()),
        description: raw.description,
        source: text.to_string(),
        timestep,
        start_time,
        duration,
        integrator,
        substeps: raw.substeps,
        forces,
        ground,
        walls,
        targets: raw.targets,
        compare: raw.compare,
        tolerance,
        detection: raw.detection,
        bodies,
        launcher,
        volley: raw.volley,
        seed: raw.seed,
        guard: raw.guard,
    })
}

/// Refuses `exact` for forces without a closed form, naming the force.
pub fn check_integrator(integrator: Integrator, forces: &Forces) -> Result<(), IntegratorError> {
    match (integrator, forces.without_closed_form()) {
        (Integrator::Exact, Some(kind)) => Err(IntegratorError::NoClosedForm(kind)),
        _ => Ok(()),
    }
}

fn validate_forces(terms: &[ForceTerm]) -> Result<Forces, InvalidValue> {
    let mut forces = Forces::default();
    for (i, term) in terms.iter().enumerate() {
        let field = format!("forces[{i}]");
        if forces.has(term.kind()) {
            return Err(invalid(field, ValueProblem::DuplicateForce(term.kind())));
        }
        match *term {
            ForceTerm::Gravity(g) => forces.gravity = Some(finite3(&field, g)?),
            ForceTerm::ConstantForce(f) => forces.constant = Some(finite3(&field, f)?),
            ForceTerm::LinearDrag(b) => forces.linear_drag = Some(non_negative(&field, b)?),
            ForceTerm::QuadraticDrag(c) => forces.quadratic_drag = Some(non_negative(&field, c)?),
            ForceTerm::Spring {
                anchor,
                stiffness,
                rest_length,
                damping,
            } => {
                forces.spring = Some(Spring {
                    anchor: finite3(&format!("{field}.anchor"), anchor)?,
                    stiffness: non_negative(&format!("{field}.stiffness"), stiffness)?,
                    rest_length: non_negative(&format!("{field}.rest_length"), rest_length)?,
                    damping: non_negative(&format!("{field}.damping"), damping)?,
                });
            }
            ForceTerm::PointMass { center, mu } => {
                forces.point_mass = Some(PointMass {
                    center: finite3(&format!("{field}.center"), center)?,
                    mu: positive(&format!("{field}.mu"), mu)?,
                });
            }
        }
    }
    Ok(forces)
}

fn validate_wall(i: usize, w: &Wall) -> Result<Wall, InvalidValue> {
    finite3(&format!("walls[{i}].point"), w.point)?;
    let n = finite3(&format!("walls[{i}].normal"), w.normal)?;
    // A normal already of unit length to rounding is kept as written: normalising it again
    // could move its last bit, and a saved setup (which writes the normal used) would then step
    // to other bits than the scene it was saved from.
    let unit = if (n.length_squared() - 1.0).abs() <= 8.0 * f64::EPSILON {
        n
    } else {
        n.try_normalize()
            .ok_or_else(|| invalid(format!("walls[{i}].normal"), ValueProblem::ZeroVector))?
    };
    positive(&format!("walls[{i}].thickness"), w.thickness)?;
    unit_interval(&format!("walls[{i}].restitution"), w.restitution)?;
    Ok(Wall { normal: unit, ..*w })
}

fn validate_body(i: usize, b: &RawBody, forces: &Forces) -> Result<BodySpec, InvalidValue> {
    let at = |f: &str| format!("bodies[{i}].{f}");
    let mass = positive(&at("mass"), b.mass)?;
    let radius = non_negative(&at("radius"), b.radius)?;
    let position = finite3(&at("position"), b.position)?;
    let velocity = match b.launch {
        Launch::Velocity(v) => finite3(&at("launch"), v)?,
        Launch::Angles {
            speed,
            elevation_deg,
            azimuth_deg,
        } => {
            non_negative(&at("launch.speed"), speed)?;
            finite(&at("launch.elevation_deg"), elevation_deg)?;
            finite(&at("launch.azimuth_deg"), azimuth_deg)?;
            angles_to_velocity(speed, elevation_deg, azimuth_deg)
        }
        Launch::Aim { target, speed, arc } => {
            finite3(&at("launch.target"), target)?;
            positive(&at("launch.speed"), speed)?;
            let g = forces.gravity.unwrap_or(DVec3::ZERO);
            if g.x != 0.0 || g.y != 0.0 || g.z >= 0.0 {
                return Err(invalid(at("launch"), ValueProblem::AimNeedsGravity));
            }
            let [high, low] = aim(position, target, speed, -g.z)
                .map_err(|e| invalid(at("launch"), ValueProblem::CannotAim(e)))?;
            match arc {
                Arc::High => high.velocity,
                Arc::Low => low.velocity,
            }
        }
    };
    Ok(BodySpec {
        mass,
        radius,
        position,
        velocity,
    })
}

fn validate_launcher(l: Launcher) -> Result<Launcher, InvalidValue> {
    finite3("launcher.position", l.position)?;
    non_negative("launcher.speed", l.speed)?;
    finite("launcher.elevation_deg", l.elevation_deg)?;
    finite("launcher.azimuth_deg", l.azimuth_deg)?;
    positive("launcher.mass", l.mass)?;
    non_negative("launcher.radius", l.radius)?;
    Ok(l)
}

/// The launcher implied by the first body (its position, mass, size and launch), or a 20 m/s,
/// 45 degree launcher at the origin for a scene without bodies.
fn default_launcher(first: Option<&BodySpec>) -> Launcher {
    match first {
        Some(b) => {
            let v = b.velocity;
            let horizontal = (v.x * v.x + v.y * v.y).sqrt();
            Launcher {
                position: b.position,
                speed: v.length(),
                elevation_deg: libm::atan2(v.z, horizontal).to_degrees(),
                azimuth_deg: libm::atan2(v.y, v.x).to_degrees(),
                mass: b.mass,
                radius: b.radius,
            }
        }
        None => Launcher {
            position: DVec3::ZERO,
            speed: 20.0,
            elevation_deg: 45.0,
            azimuth_deg: 0.0,
            mass: 1.0,
            radius: 0.1,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str =
        r#"Scene(dt: 0.01, integrator: Rk4, bodies: [(mass: 1, position: (0, 0, 1))])"#;

    #[test]
    fn a_minimal_scene_parses_with_defaults() {
        let scene = parse(MINIMAL, "mem.ron", "mem").unwrap();
        assert_eq!(scene.timestep, Duration::from_millis(10));
        assert_eq!(scene.integrator, Integrator::Rk4);
        assert_eq!(scene.bodies[0].radius, 0.1);
        assert_eq!(scene.name, "mem");
    }

    #[test]
    fn syntax_errors_carry_line_and_column() {
        let err = parse(
            "Scene(\n  dt: 0.1,\n  integrator: Rk4\n  bodies: [],\n)",
            "x.ron",
            "x",
        )
        .unwrap_err();
        assert_eq!(err.file, "x.ron");
        assert_eq!(err.position.map(|p| p.0), Some(4), "{err}");
    }

    #[test]
    fn value_errors_name_the_field() {
        let text = MINIMAL.replace("mass: 1", "mass: -1");
        let err = parse(&text, "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some("bodies[0].mass"), "{err}");
        let err = parse(&MINIMAL.replace("0.01", "NaN"), "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some("dt"), "{err}");
    }

    #[test]
    fn exact_is_refused_with_the_force_that_has_no_closed_form() {
        let text = r#"Scene(dt: 0.01, integrator: Exact, forces: [Gravity((0,0,-9.81)), QuadraticDrag(0.1)])"#;
        let err = parse(text, "x.ron", "x").unwrap_err();
        assert!(err.message.contains("QuadraticDrag"), "{err}");
    }

    #[test]
    fn overrides_refuse_with_the_field_and_the_problem() {
        let mut scene = parse(MINIMAL, "mem.ron", "mem").unwrap();
        let e = scene.set_dt(-1.0).unwrap_err();
        assert_eq!(e.field, "dt");
        assert_eq!(e.problem, ValueProblem::NotPositive(-1.0));
        assert!(matches!(
            scene.set_dt(1e-12),
            Err(InvalidValue {
                problem: ValueProblem::Step(_),
                ..
            })
        ));
        assert_eq!(
            scene.set_substeps(0).unwrap_err().problem,
            ValueProblem::Substeps(0)
        );
        scene.forces.quadratic_drag = Some(0.1);
        assert_eq!(
            scene.set_integrator(Integrator::Exact),
            Err(IntegratorError::NoClosedForm(ForceKind::QuadraticDrag))
        );
    }

    /// A text file past the limit is refused after reading just past it, saying so; one at the
    /// limit is read (and then fails to parse, as zeros do).
    #[test]
    fn a_text_file_longer_than_the_limit_is_refused() {
        let dir = std::env::temp_dir().join(format!("volley-text-limit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("huge.ron");
        let file = std::fs::File::create(&path).unwrap();
        // Sparse: no disk is written for the zeros.
        file.set_len(MAX_TEXT_BYTES + 1).unwrap();
        let err = load(&path).unwrap_err();
        assert!(err.message.contains("longer than 256 MiB"), "{err}");
        file.set_len(MAX_TEXT_BYTES).unwrap();
        assert_eq!(read_text(&path).unwrap().len() as u64, MAX_TEXT_BYTES);
        drop(file);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A wall normal is normalised once: the normal a saved setup writes reads back to the
    /// same bits (a second normalisation moved the last bit of (1, 0, 1)'s; found by fuzzing).
    #[test]
    fn a_normalised_wall_normal_is_kept_bit_for_bit() {
        for n in [
            (1.0, 0.0, 1.0),
            (1.0, 2.0, 3.0),
            (0.3, -0.7, 0.1),
            (0.0, 0.0, -5.0),
        ] {
            let wall = Wall {
                point: DVec3::ZERO,
                normal: DVec3::from(n),
                thickness: 0.1,
                restitution: 0.5,
            };
            let once = validate_wall(0, &wall).unwrap();
            let twice = validate_wall(0, &once).unwrap();
            assert_eq!(
                once.normal.to_array().map(f64::to_bits),
                twice.normal.to_array().map(f64::to_bits)
            );
            assert!((once.normal.length() - 1.0).abs() < 1e-15);
        }
    }

    /// What a small file could ask for beyond reason is refused, naming the field (the limits
    /// of docs/limits.md).
    #[test]
    fn limits_on_bodies_work_and_lanes_name_the_field() {
        let field = |text: &str| parse(text, "x.ron", "x").unwrap_err().field.unwrap();
        let volley = |n: u64| MINIMAL.replace("])", &format!("], volley: (count: {n}))"));
        assert!(parse(&volley(MAX_BODIES as u64 - 1), "x.ron", "x").is_ok());
        // One listed body and a volley of the maximum is one body too many.
        let err = parse(&volley(MAX_BODIES as u64), "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some("volley.count"), "{err}");
        assert!(err.message.contains("got 1000001"), "{err}");
        assert_eq!(field(&volley(20_000_000)), "volley.count");
        let substeps = |n: u32, count: u64| {
            volley(count).replace(
                "integrator: Rk4",
                &format!("integrator: Rk4, substeps: {n}"),
            )
        };
        assert!(parse(&substeps(100, 999_999), "x.ron", "x").is_ok());
        let err = parse(&substeps(101, 999_999), "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some("substeps"), "{err}");
        assert!(
            err.message.contains("101 substeps for 1000000 bodies"),
            "{err}"
        );
        let lanes = |n: usize| {
            let lane = "(integrator: Rk4, substeps: 200)";
            MINIMAL.replace("])", &format!("], compare: [{}])", vec![lane; n].join(",")))
        };
        assert!(parse(&lanes(MAX_COMPARE_LANES), "x.ron", "x").is_ok());
        assert_eq!(field(&lanes(MAX_COMPARE_LANES + 1)), "compare");
        let heavy_lane = MINIMAL.replace(
            "])",
            "], volley: (count: 999999), compare: [(integrator: Rk4, substeps: 200)])",
        );
        assert_eq!(field(&heavy_lane), "compare[0].substeps");
        let mut scene = parse(&volley(999_999), "x.ron", "x").unwrap();
        assert!(matches!(
            scene.set_substeps(1000).unwrap_err().problem,
            ValueProblem::TickWork {
                bodies: 1_000_000,
                substeps: 1000
            }
        ));
    }

    /// Every problem prints the message it printed when these errors were strings.
    #[test]
    fn error_messages_are_pinned() {
        let at = |field: &str, problem| InvalidValue {
            field: field.into(),
            problem,
        };
        let no_closed_form = IntegratorError::NoClosedForm(ForceKind::Spring);
        let cases: [(InvalidValue, &str); 14] = [
            (
                at("start_time", ValueProblem::NotFinite(f64::NAN)),
                "start_time: expected a finite number, got NaN",
            ),
            (
                at("bodies[0].mass", ValueProblem::NotPositive(-1.0)),
                "bodies[0].mass: expected a finite number > 0, got -1",
            ),
            (
                at("duration", ValueProblem::NotNonNegative(-0.5)),
                "duration: expected a finite number >= 0, got -0.5",
            ),
            (
                at("ground.restitution", ValueProblem::NotUnitInterval(1.5)),
                "ground.restitution: expected a number from 0 to 1, got 1.5",
            ),
            (
                at(
                    "walls[0].point",
                    ValueProblem::NotFiniteVector(DVec3::new(1.0, f64::INFINITY, 0.0)),
                ),
                "walls[0].point: expected finite components, got [1, inf, 0]",
            ),
            (
                at("walls[1].normal", ValueProblem::ZeroVector),
                "walls[1].normal: expected a non-zero vector",
            ),
            (
                timestep_from_secs("dt", 1e-12).unwrap_err(),
                "dt: expected a step from 1 ns to 1000 s, got 0.000000000001 s",
            ),
            (
                at("substeps", ValueProblem::Substeps(0)),
                "substeps: expected 1 to 10000, got 0",
            ),
            (
                at("volley.count", ValueProblem::VolleyCount(20_000_000)),
                "volley.count: expected at most 1000000 bodies, got 20000000",
            ),
            (
                at("guard.energy_factor", ValueProblem::EnergyFactor(1.0)),
                "guard.energy_factor: expected a finite number > 1, got 1",
            ),
            (
                at(
                    "forces[1]",
                    ValueProblem::DuplicateForce(ForceKind::Gravity),
                ),
                "forces[1]: Gravity is declared twice; declare each term once",
            ),
            (
                at("bodies[0].launch", ValueProblem::AimNeedsGravity),
                "bodies[0].launch: Aim needs a Gravity term pointing along -z",
            ),
            (
                at(
                    "bodies[0].launch",
                    ValueProblem::CannotAim(AimError::SamePoint),
                ),
                "bodies[0].launch: cannot aim: launch point and target are the same point",
            ),
            (
                at("integrator", ValueProblem::Integrator(no_closed_form)),
                "integrator: `exact` needs a closed form, and force term Spring has none with a \
                 rest length (exact covers any mix of Gravity, ConstantForce, LinearDrag and a \
                 Spring with rest length 0, or a PointMass alone); choose another integrator",
            ),
        ];
        for (error, message) in cases {
            assert_eq!(error.to_string(), message, "{error:?}");
        }
        // A scene file's value error is the same text after the file name.
        let err = parse(&MINIMAL.replace("0.01", "0"), "x.ron", "x").unwrap_err();
        assert_eq!(
            err.to_string(),
            "x.ron: dt: expected a finite number > 0, got 0"
        );
    }
}
