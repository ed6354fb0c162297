//! Scene files (RON) to a validated [`Scene`]: pure data, every value checked, errors located.
//!
//! The format is documented in the docs/scenes.md. Syntax and type errors carry the
//! file, line and column from the RON parser; value errors name the field path
//! (`bodies[1].mass`) and what was expected. Nothing here panics on any input.

use std::path::Path;
use std::time::Duration;

use glam::DVec3;
use serde::Deserialize;

use crate::contact::{
    Detection, EventCondition, EventDirection, EventSpec, EventStop, Ground, HeightfieldSurface,
    MeshSurface, Target, Wall,
};
use crate::drag::Interpolation;
use crate::exact::{AimError, Arc, aim};
use crate::forces::{
    AirModel, DragCurve, DragSize, ForceKind, ForceTerms, Forces, KG_M2_PER_LB_IN2, LiftModel,
    MachDrag, PointMass, RAD_S_PER_RPM, SpinDecay, SpinLift, Spring, Thrust, ThrustDirection, Wind,
};
use crate::integrate::{DEFAULT_TOLERANCE, Integrator};

mod builder;
mod bundled;
mod error;
mod levels;
mod raw;
mod ron_error;
#[cfg(test)]
mod tests;
mod validate;

pub use builder::{BUILT, SceneBuilder};
pub use bundled::{BUNDLED, bundled};
pub use error::{IntegratorError, InvalidValue, SceneError, ValueProblem};
pub(crate) use levels::LevelFiles;
pub use levels::{
    BUNDLED_LEVELS, LevelError, MAX_HEIGHTFIELD_CELLS, MAX_LEVEL_FILE_BYTES, MAX_LEVEL_TRIANGLES,
    read_gltf, read_heightmap_png, read_obj, write_heightmap_png,
};
use raw::*;
use validate::*;
pub use validate::{check_integrator, timestep_from_secs};

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

/// Most events a scene may declare: each is searched for on every body's every step, and
/// each that stops after more than one occurrence is a count every body keeps.
pub const MAX_EVENTS: usize = 64;

/// A scene after parsing and validation; everything a [`crate::World`] is built from.
///
/// Checked once and never changed after: its fields are read through methods, and a change
/// goes through [`Scene::edit`] (a builder seeded with the scene, whose `build` checks it again
/// and writes its [`Scene::source`] anew) or a setter that checks its one value. So the text a
/// recording embeds is always the scene the run stepped, and a replay of it cannot part from
/// the run because the scene was changed behind the text's back.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (defaults to the file stem).
    pub(crate) name: String,
    /// One line on what the scene shows.
    pub(crate) description: String,
    /// The scene file's text, verbatim (recordings embed it).
    pub(crate) source: String,
    /// Fixed timestep, in whole nanoseconds; the physics step `h` is exactly this.
    pub(crate) timestep: Duration,
    /// Sim time (s) of tick 0; the time of tick n is `start_time + n * h`.
    pub(crate) start_time: f64,
    /// Sim time (s) a headless run covers unless told otherwise (default 10 s).
    pub(crate) duration: f64,
    /// Integrator unless a run overrides it.
    pub(crate) integrator: Integrator,
    /// Integrator steps per tick (each `h / substeps` long). 1 unless stiffness asks for more.
    pub(crate) substeps: u32,
    /// Error tolerance of the adaptive integrator ([`Integrator::Dopri5`]), from
    /// [`MIN_TOLERANCE`] to 1 (default [`crate::integrate::DEFAULT_TOLERANCE`]); the fixed-step
    /// integrators ignore it.
    pub(crate) tolerance: f64,
    /// Declared force terms.
    pub(crate) forces: Forces,
    /// Ground plane, if any.
    pub(crate) ground: Option<Ground>,
    /// Thin walls (slabs).
    pub(crate) walls: Vec<Wall>,
    /// Target spheres.
    pub(crate) targets: Vec<Target>,
    /// Static triangle meshes (level geometry), read when the scene is.
    pub(crate) meshes: Vec<MeshSurface>,
    /// Heightfields (terrain), read when the scene is.
    pub(crate) heightfields: Vec<HeightfieldSurface>,
    /// The folder the level files its text names are read from (the scene file's own), so an
    /// edit of the scene finds them again.
    pub(crate) level_dir: std::path::PathBuf,
    /// Swept (time of impact inside the step) or discrete (overlap at the end of the step).
    pub(crate) detection: Detection,
    /// Bodies present at tick 0, in id order.
    pub(crate) bodies: Vec<BodySpec>,
    /// Where fired projectiles start and how they are launched.
    pub(crate) launcher: Launcher,
    /// Extra bodies fired at tick 0 from the launcher with seeded random spread.
    pub(crate) volley: Option<Volley>,
    /// Seed of the world's random number generator.
    pub(crate) seed: u64,
    /// Divergence guard settings.
    pub(crate) guard: Guard,
    /// Lanes the window opens in compare mode (empty: one lane); headless runs ignore it and
    /// step [`Scene::integrator`].
    pub(crate) compare: Vec<CompareLane>,
    /// Declared events, in order (an event names its declaration by the index here).
    pub(crate) events: Vec<EventSpec>,
}

impl Scene {
    /// Short name (defaults to the file stem).
    #[inline]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One line on what the scene shows.
    #[inline]
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The scene file's text, verbatim (recordings embed it).
    #[inline]
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Fixed timestep, in whole nanoseconds; the physics step `h` is exactly this.
    #[inline]
    pub fn timestep(&self) -> Duration {
        self.timestep
    }

    /// Sim time (s) of tick 0; the time of tick n is `start_time + n * h`.
    #[inline]
    pub fn start_time(&self) -> f64 {
        self.start_time
    }

    /// Sim time (s) a headless run covers unless told otherwise (default 10 s).
    #[inline]
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Integrator unless a run overrides it.
    #[inline]
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Integrator steps per tick (each `h / substeps` long). 1 unless stiffness asks for more.
    #[inline]
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Error tolerance of the adaptive integrator ([`Integrator::Dopri5`]), from
    /// [`MIN_TOLERANCE`] to 1 (default [`crate::integrate::DEFAULT_TOLERANCE`]); the fixed-step
    /// integrators ignore it.
    #[inline]
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Declared force terms.
    #[inline]
    pub fn forces(&self) -> &Forces {
        &self.forces
    }

    /// Ground plane, if any.
    #[inline]
    pub fn ground(&self) -> Option<Ground> {
        self.ground
    }

    /// Thin walls (slabs).
    #[inline]
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Target spheres.
    #[inline]
    pub fn targets(&self) -> &[Target] {
        &self.targets
    }

    /// Swept (time of impact inside the step) or discrete (overlap at the end of the step).
    #[inline]
    pub fn detection(&self) -> Detection {
        self.detection
    }

    /// Bodies present at tick 0, in id order.
    #[inline]
    pub fn bodies(&self) -> &[BodySpec] {
        &self.bodies
    }

    /// Where fired projectiles start and how they are launched.
    #[inline]
    pub fn launcher(&self) -> Launcher {
        self.launcher
    }

    /// Extra bodies fired at tick 0 from the launcher with seeded random spread.
    #[inline]
    pub fn volley(&self) -> Option<Volley> {
        self.volley
    }

    /// Seed of the world's random number generator.
    #[inline]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Divergence guard settings.
    #[inline]
    pub fn guard(&self) -> Guard {
        self.guard
    }

    /// Lanes the window opens in compare mode (empty: one lane); headless runs ignore it and
    /// step [`Scene::integrator`].
    #[inline]
    pub fn compare(&self) -> &[CompareLane] {
        &self.compare
    }

    /// Declared events, in order (an [`crate::EventKind::Declared`] names its declaration by
    /// the index here).
    #[inline]
    pub fn events(&self) -> &[EventSpec] {
        &self.events
    }
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
    /// Static triangle meshes (level geometry), read when the scene was.
    #[inline]
    pub fn meshes(&self) -> &[MeshSurface] {
        &self.meshes
    }

    /// Heightfields (terrain), read when the scene was.
    #[inline]
    pub fn heightfields(&self) -> &[HeightfieldSurface] {
        &self.heightfields
    }

    /// Whether `other` is this scene in everything a world is built from: every field but
    /// the [`Scene::source`] text and the folder its level files were read from (a saved setup
    /// reads back to the same scene in other words).
    pub fn same_as(&self, other: &Scene) -> bool {
        let mut copy = other.clone();
        copy.source.clone_from(&self.source);
        copy.level_dir.clone_from(&self.level_dir);
        *self == copy
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
    /// Angular velocity at launch (rad/s, world axes): read only by a spun Mach drag.
    pub spin: DVec3,
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
    /// Backspin of a fired projectile (rpm): about the horizontal axis across the shot, the
    /// spin that lifts a ball hit or thrown forwards.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub backspin: f64,
    /// Sidespin of a fired projectile (rpm): about the vertical, positive counter-clockwise
    /// seen from above, which curves the flight to the left of the shot.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub sidespin: f64,
}

impl Launcher {
    /// Launch velocity (m/s) from speed, elevation and azimuth.
    pub fn velocity(&self) -> DVec3 {
        angles_to_velocity(self.speed, self.elevation_deg, self.azimuth_deg)
    }

    /// Angular velocity (rad/s, world axes) of a projectile fired at `azimuth_deg`: the
    /// backspin about `(sin az, -cos az, 0)`, the sidespin about +z.
    pub fn spin_at(&self, azimuth_deg: f64) -> DVec3 {
        let az = azimuth_deg.to_radians();
        let rpm = crate::forces::RAD_S_PER_RPM;
        DVec3::new(libm::sin(az), -libm::cos(az), 0.0) * (self.backspin * rpm)
            + DVec3::Z * (self.sidespin * rpm)
    }

    /// The body a `Fire` spawns: the launcher's mass, size, muzzle, velocity and spin.
    pub fn body(&self) -> BodySpec {
        self.body_at(self.speed, self.elevation_deg, self.azimuth_deg)
    }

    /// [`Launcher::body`] at another speed and angles (a volley's spread).
    pub fn body_at(&self, speed: f64, elevation_deg: f64, azimuth_deg: f64) -> BodySpec {
        BodySpec {
            mass: self.mass,
            radius: self.radius,
            position: self.position,
            velocity: angles_to_velocity(speed, elevation_deg, azimuth_deg),
            spin: self.spin_at(azimuth_deg),
        }
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

/// Settings of the divergence guard (the stepping code checks it after every tick).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Guard {
    /// A body whose energy exceeds its start energy by more than `(energy_factor - 1)` times its
    /// start energy scale stops the run. Every built-in term but the motor conserves or
    /// dissipates energy, so only a numerical instability can trip it; with a motor or a game's
    /// own term (which may add energy) only finiteness is checked. Default 10 (the reference's
    /// "10x its start").
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

fn is_zero(x: &f64) -> bool {
    *x == 0.0
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

/// Reads and validates a scene file that names no game's own term ([`load_with`] takes the
/// program's terms).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &ForceTerms::new())
}

/// Reads and validates a scene file, resolving the game's own terms it names in `terms`.
pub fn load_with(path: &Path, terms: &ForceTerms) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let text = read_text(path).map_err(|e| SceneError {
        file: file.clone(),
        position: None,
        field: None,
        message: format!("cannot read: {e}"),
    })?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    parse_with(&text, &file, stem.as_deref().unwrap_or("scene"), terms)
}

/// Parses and validates scene text that names no game's own term; `file` labels errors,
/// `default_name` is used if the scene has no `name` ([`parse_with`] takes the program's
/// terms). Level files the scene names (`meshes`, `heightfields`) are read relative to
/// `file`'s folder (the current one if it has none); one not on disk whose path ends in
/// `levels/NAME` for a file Volley ships (`BUNDLED_LEVELS`) is that file.
pub fn parse(text: &str, file: &str, default_name: &str) -> Result<Scene, SceneError> {
    parse_with(text, file, default_name, &ForceTerms::new())
}

/// [`parse`], resolving the game's own terms the text names in `terms`.
pub fn parse_with(
    text: &str,
    file: &str,
    default_name: &str,
    terms: &ForceTerms,
) -> Result<Scene, SceneError> {
    parse_levels_in(text, file, default_name, terms, &LevelFiles::beside(file))
}

/// [`parse_with`] with the level files read from `files` (a scene's own folder, for an edit of
/// a scene read from a file).
pub(crate) fn parse_levels_in(
    text: &str,
    file: &str,
    default_name: &str,
    terms: &ForceTerms,
    files: &LevelFiles,
) -> Result<Scene, SceneError> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let raw: RawScene = options.from_str(text).map_err(|e| SceneError {
        file: file.to_string(),
        position: Some((e.span.start.line, e.span.start.col)),
        field: None,
        message: ron_error::describe(&e.code),
    })?;
    validate(raw, text, default_name, terms, files).map_err(|e| SceneError {
        file: file.to_string(),
        position: None,
        message: e.problem.to_string(),
        field: Some(e.field),
    })
}
