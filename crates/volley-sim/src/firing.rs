//! Firing solutions that hit in the simulation, not on paper.
//!
//! A game aims with the textbook formula and then steps the shot with its integrator at its
//! tick, with drag and wind: the shot misses, by `g T h / 2` from semi-implicit Euler alone. This
//! module solves the launch by **shooting** on the simulated trajectory itself: the shot is
//! stepped by the scene's integrator at the scene's tick and substeps, exactly as a [`World`]
//! steps it, and the launch velocity is corrected until that stepped path passes through the
//! target's centre.
//!
//! ## What "passes the target" means
//! Between two integrator steps the path is the integrator's own step of the partial length, the
//! same path the contact stage's swept detection follows (for explicit Euler a straight segment,
//! for the closed form the exact arc). The shot hits when that path passes the target's centre;
//! [`solve`] then checks every solution independently in a [`World`] with the target in it:
//! the engine's own closest-approach event ([`crate::EventKind::Approach`]) gives the miss,
//! and a contact with the ground, a wall or a level surface (a mesh, a heightfield) before
//! arrival marks the shot blocked: an impact, or a rest (what a surface of restitution 0
//! reports for any contact).
//!
//! ## How
//! For an arrival time `T` after launch (a tick count and a fraction of a step, never a float
//! sum of steps) the launch velocity `v(T)` that puts the stepped body on the target's centre at
//! `T` is three equations in three unknowns, solved by Newton's method with a finite-difference
//! Jacobian (exact in one step when every force is linear in the state, since every integrator
//! is then an affine map of the launch velocity). The free parameter `T` is then chosen for the
//! question asked:
//! - **speed given** ([`Mode::Speed`]): `|v(T)| = speed` has two roots, the low arc (earlier)
//!   and the high arc (later), either side of the minimum of `|v(T)|`;
//! - **elevation given** ([`Mode::Elevation`]): the elevation of `v(T)` equals the one given;
//! - **minimum speed** ([`Mode::MinSpeed`]): the `T` that minimises `|v(T)|`.
//!
//! `T` is first scanned on a logarithmic grid from [`MIN_FLIGHT_TIME`] to the range's maximum
//! flight time (so the roots are bracketed, never guessed), then refined by golden-section
//! search (the minimum) and by bracketed root finding (the roots). A moving target (constant
//! velocity) only changes where the centre is at `T`, so the lead is part of the same solve.
//!
//! Without drag, wind or springs, explicit and semi-implicit Euler have a closed form of their
//! own (an arithmetic series, [`discrete_position`]); [`solve_discrete`] aims with it, which
//! the tests use to check the shooting.

use glam::{DMat3, DVec3};

use crate::body::{BodyState, Mass};
use crate::contact::{EventKind, Surface, Target, bracketed_root};
use crate::exact::{self, Arc};
use crate::forces::{ForceModel, Forces};
use crate::integrate::{Integrator, Scheme, SchemeVisitor, visit};
use crate::scene::{BodySpec, Scene};
use crate::world::World;

mod error;
mod flight;
mod holdover;
mod range_table;
mod search;
mod shooter;
mod trajectory;

pub use error::{FiringError, blocked_text};
use flight::*;
pub use holdover::{Holdover, HoldoverRow, MOA_PER_MRAD, holdover, sight_point};
pub use range_table::{RangeRow, RangeTable, range_table};
use search::*;
pub use shooter::discrete_position;
use shooter::*;
pub use trajectory::rounding_floor;
use trajectory::*;

/// Shortest arrival time (s) the scan considers.
pub const MIN_FLIGHT_TIME: f64 = 1e-4;
/// Default longest flight (s) a solution may take.
pub const DEFAULT_MAX_FLIGHT_TIME: f64 = 120.0;
/// Arrival times sampled by the scan, log-spaced from [`MIN_FLIGHT_TIME`] to the maximum.
const SCAN_POINTS: usize = 97;
/// Newton iterations allowed for one arrival time by default ([`Range::newton_iterations`]).
pub const NEWTON_ITERATIONS: u32 = 40;
/// A converged solve puts the stepped shot this close to the centre, relative to the distance
/// from launch to target (at least 1 m): far below the 1e-9 m promised, far above rounding.
const RESIDUAL_TOLERANCE: f64 = 1e-12;

/// Everything a shot's flight depends on: the scene's forces, integrator, tick and substeps,
/// its ground and walls, where the shot starts, and the target.
#[derive(Clone, Debug)]
pub struct Range {
    /// The scene the shot flies in (its bodies, volley and targets are ignored).
    pub scene: Scene,
    /// Launch point (m).
    pub from: DVec3,
    /// Mass of the shot (kg), which drag divides by.
    pub mass: f64,
    /// Radius of the shot (m), for contacts.
    pub radius: f64,
    /// The target: its centre at the moment of launch, its radius and velocity.
    pub target: Target,
    /// Whether the scene's ground, walls and level surfaces can block the shot.
    pub contacts: bool,
    /// Longest flight (s) a solution may take.
    pub max_flight_time: f64,
    /// Newton iterations allowed for one arrival time before the solve is called stalled.
    pub newton_iterations: u32,
}

impl Range {
    /// A range on `scene`: the launcher's position, mass and radius; the scene's target
    /// `index` (the first by default); its ground, walls and level surfaces on.
    pub fn new(scene: &Scene, target: Target) -> Range {
        Range {
            scene: scene.clone(),
            from: scene.launcher.position,
            mass: scene.launcher.mass,
            radius: scene.launcher.radius,
            target,
            contacts: true,
            max_flight_time: DEFAULT_MAX_FLIGHT_TIME,
            newton_iterations: NEWTON_ITERATIONS,
        }
    }

    /// The target's centre `t` seconds after launch.
    pub fn target_at(&self, t: f64) -> DVec3 {
        self.target.center_at(t)
    }

    fn sub_step(&self) -> f64 {
        self.scene.dt() / f64::from(self.scene.substeps)
    }

    fn scale(&self) -> f64 {
        (self.target.center - self.from).length().max(1.0)
    }
}

/// What to solve for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    /// Launch speed (m/s) given; both arcs where both exist.
    Speed(f64),
    /// Elevation (degrees above the horizontal) given; the speed and azimuth are solved.
    Elevation(f64),
    /// The slowest launch that reaches the target.
    MinSpeed,
}

/// Which solution a [`Shot`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShotKind {
    /// One of the two arcs at a given speed.
    Arc(Arc),
    /// The arc at a given elevation.
    Elevation,
    /// The slowest shot.
    MinSpeed,
}

impl ShotKind {
    /// A short label: "high arc", "low arc", "elevation", "min speed".
    pub fn label(self) -> &'static str {
        match self {
            ShotKind::Arc(Arc::High) => "high arc",
            ShotKind::Arc(Arc::Low) => "low arc",
            ShotKind::Elevation => "elevation",
            ShotKind::MinSpeed => "min speed",
        }
    }
}

/// A surface the shot hits before it reaches the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blocked {
    /// The surface.
    pub surface: Surface,
    /// Time after launch of the impact (s).
    pub time: f64,
    /// The tick whose step has the impact.
    pub tick: u64,
}

/// How the textbook aim (the closed form under gravity alone) does under the simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Textbook {
    /// The textbook's launch velocity (m/s).
    pub velocity: DVec3,
    /// Closest approach (m) of the stepped shot to the target's centre: the textbook's miss.
    pub miss: f64,
    /// When that closest approach happens, after launch (s).
    pub time: f64,
}

/// One firing solution, checked in a world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shot {
    /// Which solution this is.
    pub kind: ShotKind,
    /// Launch velocity (m/s).
    pub velocity: DVec3,
    /// Its magnitude (m/s).
    pub speed: f64,
    /// Elevation above the horizontal (degrees).
    pub elevation_deg: f64,
    /// Azimuth from +x towards +y (degrees); 0 for a vertical shot.
    pub azimuth_deg: f64,
    /// Time of arrival at the target's centre after launch (s).
    pub flight_time: f64,
    /// The tick whose step carries the shot through the target (the first tick past it).
    pub arrival_tick: u64,
    /// Closest approach (m) to the target's centre of the shot stepped in a [`World`], from the
    /// engine's approach event: the solution's own miss. `NaN` if the world saw no approach.
    pub miss: f64,
    /// The ground, wall or level surface the shot hits first, if it hits one before arriving.
    pub blocked: Option<Blocked>,
    /// The textbook aim for the same question, and its miss; `None` where the closed form has
    /// no answer (out of reach under gravity alone, or no gravity).
    pub textbook: Option<Textbook>,
}

/// Solves `mode` for `range` by shooting on the stepped trajectory, and checks every solution
/// (and the textbook aim) in a world.
///
/// ```
/// use volley_sim::{AimMode, AimRange, bundled_scene, solve_aim};
/// let scene = bundled_scene("drag").unwrap();
/// let mut range = AimRange::new(&scene, bundled_scene("seed").unwrap().targets()[0]);
/// range.from = glam::DVec3::new(10.0, 0.0, 2.0);
/// let shots = solve_aim(&range, AimMode::Speed(30.0)).unwrap();
/// assert_eq!(shots.len(), 2);
/// assert!(shots.iter().all(|s| s.miss < 1e-9));
/// ```
pub fn solve(range: &Range, mode: Mode) -> Result<Vec<Shot>, FiringError> {
    check(range)?;
    let shooter = Stepped::new(range);
    let found = solve_with(range, mode, &shooter)?;
    finish(range, mode, found)
}

/// [`solve`] with the discrete closed form of explicit or semi-implicit Euler in place of
/// stepping; for scenes whose only forces are gravity and a constant force.
pub fn solve_discrete(range: &Range, mode: Mode) -> Result<Vec<Shot>, FiringError> {
    check(range)?;
    let forces = &range.scene.forces;
    if forces.linear_drag.is_some()
        || forces.quadratic_drag.is_some()
        || forces.spring.is_some()
        || forces.point_mass.is_some()
        || forces.mach_drag.is_some()
        || !forces.custom.is_empty()
    {
        return Err(FiringError::Invalid(
            "the discrete closed form covers gravity and constant forces only".into(),
        ));
    }
    let shooter = Discrete {
        range,
        a: forces.linear_part(range.mass).a0,
        hs: range.sub_step(),
    };
    let found = solve_with(range, mode, &shooter)?;
    finish(range, mode, found)
}

fn check(range: &Range) -> Result<(), FiringError> {
    let finite3 = |name: &str, v: DVec3| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(FiringError::Invalid(format!(
                "{name}: expected finite coordinates, got {v}"
            )))
        }
    };
    finite3("launch point", range.from)?;
    finite3("target", range.target.center)?;
    finite3("target velocity", range.target.velocity)?;
    if !(range.mass.is_finite() && range.mass > 0.0) {
        return Err(FiringError::Invalid(format!(
            "mass: expected a positive number, got {}",
            range.mass
        )));
    }
    if !(range.max_flight_time.is_finite() && range.max_flight_time > MIN_FLIGHT_TIME) {
        return Err(FiringError::Invalid(format!(
            "max flight time: expected more than {MIN_FLIGHT_TIME} s, got {}",
            range.max_flight_time
        )));
    }
    if range.scene.forces.thrust.is_some() {
        return Err(FiringError::Invalid(
            "a scene with Thrust: a motor's flight is steered, not aimed by its launch alone"
                .into(),
        ));
    }
    if range.target.center == range.from && range.target.velocity == DVec3::ZERO {
        return Err(FiringError::Invalid(
            "launch point and target are the same point".into(),
        ));
    }
    if let Some(g) = range.scene.ground
        && range.contacts
        && range.target.center.z < g.height
    {
        return Err(FiringError::BelowGround {
            target_z: range.target.center.z,
            ground: g.height,
        });
    }
    Ok(())
}

/// Elevation and azimuth (degrees) of a velocity; azimuth 0 when vertical.
pub fn angles_of(v: DVec3) -> (f64, f64) {
    let horizontal = (v.x * v.x + v.y * v.y).sqrt();
    let elevation = libm::atan2(v.z, horizontal).to_degrees();
    let azimuth = if horizontal == 0.0 {
        0.0
    } else {
        libm::atan2(v.y, v.x).to_degrees()
    };
    (elevation, azimuth)
}
