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
//! and an impact on the ground or a wall before arrival marks the shot blocked.
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
    /// Whether the scene's ground and walls can block the shot.
    pub contacts: bool,
    /// Longest flight (s) a solution may take.
    pub max_flight_time: f64,
    /// Newton iterations allowed for one arrival time before the solve is called stalled.
    pub newton_iterations: u32,
}

impl Range {
    /// A range on `scene`: the launcher's position, mass and radius; the scene's target
    /// `index` (the first by default); its ground and walls on.
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
    /// The ground or wall the shot hits first, if it hits one before arriving.
    pub blocked: Option<Blocked>,
    /// The textbook aim for the same question, and its miss; `None` where the closed form has
    /// no answer (out of reach under gravity alone, or no gravity).
    pub textbook: Option<Textbook>,
}

/// Why no firing solution was found.
#[derive(Clone, Debug, PartialEq)]
pub enum FiringError {
    /// An input is not usable; names it.
    Invalid(String),
    /// The target's centre is below the ground plane.
    BelowGround {
        /// Height of the target's centre (m).
        target_z: f64,
        /// Height of the ground (m).
        ground: f64,
    },
    /// No launch at this speed reaches the target within the maximum flight time.
    OutOfReach {
        /// The speed asked for (m/s).
        speed: f64,
        /// The slowest launch that reaches the target (m/s), if one was found.
        min_speed: Option<f64>,
        /// Closest the stepped shot gets at the speed asked for (m), over elevations.
        best_miss: f64,
        /// The elevation of that closest shot (degrees).
        best_elevation_deg: f64,
    },
    /// No arrival time gives this elevation (below the line of sight, or vertical with the
    /// target off to the side); gives the range of elevations that do reach it.
    NoArcAtElevation {
        /// Elevation asked for (degrees).
        elevation_deg: f64,
        /// The lowest elevation that reaches the target (degrees): the line of sight.
        lowest_deg: f64,
        /// The highest elevation reached within the maximum flight time (degrees).
        highest_deg: f64,
    },
    /// The target is straight above or below the launch point: any speed above the minimum
    /// reaches it vertically, so an elevation does not pick one.
    VerticalNeedsSpeed {
        /// The slowest vertical launch that reaches it (m/s).
        min_speed: f64,
    },
    /// The only solutions are blocked by the ground or a wall.
    Blocked(Vec<(ShotKind, Blocked)>),
    /// Newton's method did not converge for an arrival time the answer needs.
    Stalled {
        /// The arrival time being solved for (s after launch).
        flight_time: f64,
        /// The tick that arrival falls in.
        tick: u64,
        /// Iterations done.
        iterations: u32,
        /// Distance left between the stepped shot and the target's centre (m).
        residual: f64,
    },
    /// The stepped shot stopped being finite, or the world's divergence guard stopped it (the
    /// integrator is unstable at this step).
    Diverged {
        /// Arrival time being solved for (s).
        flight_time: f64,
        /// The tick the world stopped at, when the check in a world found it.
        tick: Option<u64>,
    },
    /// The shot fired in a world never came closest to the target: the solution is not
    /// trusted.
    Unverified {
        /// Arrival time of the solution (s).
        flight_time: f64,
    },
}

impl std::fmt::Display for FiringError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FiringError::Invalid(what) => f.write_str(what),
            FiringError::BelowGround { target_z, ground } => write!(
                f,
                "the target's centre (z = {target_z} m) is below the ground (z = {ground} m)"
            ),
            FiringError::OutOfReach {
                speed,
                min_speed,
                best_miss,
                best_elevation_deg,
            } => {
                write!(
                    f,
                    "out of reach at {speed} m/s: the closest shot (elevation \
                     {best_elevation_deg:.4} deg) passes {best_miss:.4} m from the target's centre"
                )?;
                match min_speed {
                    Some(v) => write!(f, "; it needs at least {v:.4} m/s"),
                    None => f.write_str("; no speed reaches it within the maximum flight time"),
                }
            }
            FiringError::NoArcAtElevation {
                elevation_deg,
                lowest_deg,
                highest_deg,
            } => write!(
                f,
                "no arc at elevation {elevation_deg} deg: elevations from {lowest_deg:.4} deg (the \
                 line of sight) to {highest_deg:.4} deg reach the target"
            ),
            FiringError::VerticalNeedsSpeed { min_speed } => write!(
                f,
                "the target is straight above or below: every vertical launch from {min_speed:.4} \
                 m/s reaches it, so give a speed, not an elevation"
            ),
            FiringError::Blocked(shots) => {
                f.write_str("every solution is blocked:")?;
                for (kind, b) in shots {
                    write!(f, " the {} {}", kind.label(), blocked_text(b))?;
                }
                Ok(())
            }
            FiringError::Stalled {
                flight_time,
                tick,
                iterations,
                residual,
            } => write!(
                f,
                "the solver stalled solving for arrival at {flight_time} s (tick {tick}): \
                 {residual:e} m from the target after {iterations} Newton iterations"
            ),
            FiringError::Diverged { flight_time, tick } => {
                write!(f, "the shot for arrival at {flight_time} s diverges")?;
                if let Some(tick) = tick {
                    write!(f, " at tick {tick}")?;
                }
                f.write_str(": the integrator is unstable at this step")
            }
            FiringError::Unverified { flight_time } => write!(
                f,
                "the solution for arrival at {flight_time} s never passed the target when fired \
                 in a world"
            ),
        }
    }
}

impl std::error::Error for FiringError {}

/// "hits the ground at 1.2 s (tick 6)".
pub fn blocked_text(b: &Blocked) -> String {
    let surface = match b.surface {
        Surface::Ground => "the ground".to_string(),
        Surface::Wall(i) => format!("wall {i}"),
    };
    format!("hits {surface} at {:.4} s (tick {})", b.time, b.tick)
}

/// The state of a body launched from `from` at `v0`, `t` seconds later, on the path the
/// integrator steps (whole steps of `hs`, then one step of the remainder).
struct At {
    s0: BodyState,
    w: Mass,
    hs: f64,
    steps: u64,
    tau: f64,
}

impl SchemeVisitor for At {
    type Out = BodyState;
    fn visit<S: Scheme>(self, scheme: S) -> BodyState {
        let (s, carry) = fly(&scheme, self.s0, self.w, self.hs, self.steps, |_, _| true);
        if self.tau > 0.0 {
            scheme.step(s, self.w, self.tau, carry).0
        } else {
            s
        }
    }
}

/// `steps` whole steps of `hs` from `s0` as a world takes them (the carried force started as
/// at a spawn), calling `each` with every state reached and stopping early when it says so.
/// Returns the last state and carry.
fn fly<S: Scheme>(
    scheme: &S,
    s0: BodyState,
    w: Mass,
    hs: f64,
    steps: u64,
    mut each: impl FnMut(BodyState, DVec3) -> bool,
) -> (BodyState, DVec3) {
    let (mut s, mut carry) = (s0, scheme.start_carry(s0, w));
    for _ in 0..steps {
        (s, carry) = scheme.step(s, w, hs, carry);
        if !each(s, carry) {
            break;
        }
    }
    (s, carry)
}

/// The state and carried force at every step boundary `0..=count` of a body launched as in
/// [`At`] (stopping early where it stops being finite).
struct Samples {
    s0: BodyState,
    w: Mass,
    hs: f64,
    count: u64,
}

impl SchemeVisitor for Samples {
    type Out = Vec<(BodyState, DVec3)>;
    fn visit<S: Scheme>(self, scheme: S) -> Self::Out {
        let mut out = Vec::with_capacity(self.count as usize + 1);
        out.push((self.s0, scheme.start_carry(self.s0, self.w)));
        fly(&scheme, self.s0, self.w, self.hs, self.count, |s, carry| {
            out.push((s, carry));
            s.p.is_finite()
        });
        out
    }
}

/// One partial step of `tau` from a state and its carried force.
struct Partial {
    s: BodyState,
    carry: DVec3,
    w: Mass,
    tau: f64,
}

impl SchemeVisitor for Partial {
    type Out = BodyState;
    fn visit<S: Scheme>(self, scheme: S) -> BodyState {
        if self.tau > 0.0 {
            scheme.step(self.s, self.w, self.tau, self.carry).0
        } else {
            self.s
        }
    }
}

/// The rounding floor of a position stepped `steps` times at coordinates of magnitude `size`:
/// `steps` ulps of `size` (each step rounds by up to half an ulp, and the partial step and the
/// target's own position once more). Below this no launch correction is meaningful.
pub fn rounding_floor(steps: f64, size: f64) -> f64 {
    steps * f64::EPSILON * size
}

/// Whole steps of `hs` and the remainder in `t`.
fn split_time(t: f64, hs: f64) -> (u64, f64) {
    let mut steps = (t / hs).floor().max(0.0) as u64;
    let mut tau = t - steps as f64 * hs;
    if tau < 0.0 && steps > 0 {
        steps -= 1;
        tau += hs;
    }
    if tau >= hs {
        steps += 1;
        tau -= hs;
    }
    (steps, tau.max(0.0))
}

/// A shooter: the launch velocity for an arrival time, one way or another.
trait Shooter {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError>;
}

/// Shooting on the stepped trajectory.
struct Stepped<'a> {
    range: &'a Range,
    integrator: Integrator,
    forces: Forces,
    tolerance: f64,
    w: Mass,
    hs: f64,
}

impl<'a> Stepped<'a> {
    fn new(range: &'a Range) -> Stepped<'a> {
        Stepped {
            range,
            integrator: range.scene.integrator,
            forces: range.scene.forces,
            tolerance: range.scene.tolerance,
            w: Mass::new(range.mass),
            hs: range.sub_step(),
        }
    }

    fn launch_state(&self, v0: DVec3) -> BodyState {
        BodyState {
            p: self.range.from,
            mv: self.range.mass * v0,
        }
    }

    fn samples(&self, v0: DVec3, count: u64) -> Vec<(BodyState, DVec3)> {
        let samples = Samples {
            s0: self.launch_state(v0),
            w: self.w,
            hs: self.hs,
            count,
        };
        visit(self.integrator, &self.forces, self.tolerance, samples)
    }

    fn position(&self, v0: DVec3, t: f64) -> DVec3 {
        let (steps, tau) = split_time(t, self.hs);
        let at = At {
            s0: self.launch_state(v0),
            w: self.w,
            hs: self.hs,
            steps,
            tau,
        };
        visit(self.integrator, &self.forces, self.tolerance, at).p
    }

    /// The textbook guess: constant acceleration, no drag.
    fn guess(&self, t: f64) -> DVec3 {
        let a = self.forces.linear_part(self.range.mass).a0;
        (self.range.target_at(t) - self.range.from - (0.5 * t * t) * a) / t
    }
}

impl Shooter for Stepped<'_> {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError> {
        let goal = self.range.target_at(t);
        let tolerance = RESIDUAL_TOLERANCE * self.range.scale();
        // What rounding alone leaves: each of the `n` steps rounds the position by up to half
        // an ulp of its size, so `p(T)` is only defined to about `n ulp(|p|)`; far from the
        // origin over a long flight that exceeds the tolerance, and no Newton step helps.
        let steps = split_time(t, self.hs).0 as f64 + 1.0;
        let size = goal
            .abs()
            .max_element()
            .max(self.range.from.abs().max_element());
        let floor = rounding_floor(steps, size);
        let residual = |v: DVec3| self.position(v, t) - goal;
        let jacobian = |v: DVec3, r: DVec3| {
            let delta = 1e-5 * v.length().max(1.0);
            let column = |e: DVec3| (residual(v + delta * e) - r) / delta;
            DMat3::from_cols(column(DVec3::X), column(DVec3::Y), column(DVec3::Z))
        };
        let tick = split_time(t, self.range.scene.dt()).0 + 1;
        let stalled = |iterations, residual: f64| FiringError::Stalled {
            flight_time: t,
            tick,
            iterations,
            residual,
        };
        let mut v = self.guess(t);
        let mut r = residual(v);
        if !r.is_finite() {
            return Err(FiringError::Diverged {
                flight_time: t,
                tick: None,
            });
        }
        let mut inverse = jacobian(v, r).inverse();
        let mut last = r.length();
        let iterations = self.range.newton_iterations;
        for iteration in 1..=iterations {
            if last <= tolerance {
                return Ok(v);
            }
            if !inverse.is_finite() {
                return Err(stalled(iteration, last));
            }
            let next = v - inverse * r;
            let r_next = residual(next);
            let size = r_next.length();
            if !size.is_finite() {
                return Err(FiringError::Diverged {
                    flight_time: t,
                    tick: None,
                });
            }
            if size > 0.5 * last {
                // Slow: the Jacobian is stale (a nonlinear force); take it afresh.
                inverse = jacobian(next, r_next).inverse();
            }
            if size >= last && last <= tolerance + floor {
                // At the rounding floor: no iteration makes it smaller.
                return Ok(v);
            }
            (v, r, last) = (next, r_next, size);
        }
        if last <= tolerance {
            Ok(v)
        } else {
            Err(stalled(iterations, last))
        }
    }
}

/// The closed form of explicit and semi-implicit Euler under a constant acceleration `a`, from
/// `p0` with velocity `v0`, at `t` after launch with step `hs`: after `k` steps,
/// `v_k = v0 + k hs a` and `p_k = p0 + k hs v0 + hs^2 a k (k -+ 1) / 2` (the sum of the
/// velocities before each step for explicit Euler, after it for semi-implicit), then the
/// partial step `tau` as the integrator takes it: `p_k + tau v_k` (explicit) or
/// `p_k + tau v_k + tau^2 a` (semi-implicit). `None` for other integrators.
pub fn discrete_position(
    integrator: Integrator,
    (p0, v0, a): (DVec3, DVec3, DVec3),
    hs: f64,
    t: f64,
) -> Option<DVec3> {
    let (k, tau) = split_time(t, hs);
    let k = k as f64;
    let vk = v0 + (k * hs) * a;
    match integrator {
        Integrator::ExplicitEuler => {
            let pk = p0 + (k * hs) * v0 + (hs * hs * k * (k - 1.0) * 0.5) * a;
            Some(pk + tau * vk)
        }
        Integrator::SemiImplicitEuler => {
            let pk = p0 + (k * hs) * v0 + (hs * hs * k * (k + 1.0) * 0.5) * a;
            Some(pk + tau * vk + (tau * tau) * a)
        }
        _ => None,
    }
}

/// Aiming with the discrete closed form: `p(T)` is affine in `v0`, so `v(T)` is one division.
struct Discrete<'a> {
    range: &'a Range,
    a: DVec3,
    hs: f64,
}

impl Shooter for Discrete<'_> {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError> {
        let r = self.range;
        let integrator = r.scene.integrator;
        let base = discrete_position(integrator, (r.from, DVec3::ZERO, self.a), self.hs, t)
            .ok_or_else(|| {
                FiringError::Invalid(format!(
                    "{} has no discrete closed form here",
                    integrator.name()
                ))
            })?;
        Ok((r.target_at(t) - base) / t)
    }
}

/// Solves `mode` for `range` by shooting on the stepped trajectory, and checks every solution
/// (and the textbook aim) in a world.
///
/// ```
/// use volley_sim::{firing, scene};
/// let scene = scene::bundled("drag").unwrap();
/// let mut range = firing::Range::new(&scene, scene::bundled("seed").unwrap().targets[0]);
/// range.from = glam::DVec3::new(10.0, 0.0, 2.0);
/// let shots = firing::solve(&range, firing::Mode::Speed(30.0)).unwrap();
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

/// One sample of the scan: an arrival time and its launch, if the solve succeeded.
#[derive(Clone, Copy)]
struct Sample {
    t: f64,
    v: Option<DVec3>,
}

impl Sample {
    fn speed(&self) -> f64 {
        self.v.map_or(f64::INFINITY, DVec3::length)
    }
}

/// The scan, and the first failure among its arrival times (if any failed).
fn scan(range: &Range, shooter: &dyn Shooter) -> (Vec<Sample>, Option<FiringError>) {
    let (lo, hi) = (MIN_FLIGHT_TIME, range.max_flight_time);
    let mut first_error = None;
    let samples: Vec<Sample> = (0..SCAN_POINTS)
        .map(|k| {
            let t = if k + 1 == SCAN_POINTS {
                hi
            } else {
                lo * libm::pow(hi / lo, k as f64 / (SCAN_POINTS - 1) as f64)
            };
            let v = shooter
                .launch_for(t)
                .map_err(|e| {
                    first_error.get_or_insert(e);
                })
                .ok();
            Sample { t, v }
        })
        .collect();
    (samples, first_error)
}

/// The arrival time minimising `|v(T)|` near the slowest sample, by golden-section search.
fn slowest(samples: &[Sample], shooter: &dyn Shooter) -> Option<Sample> {
    let k = (0..samples.len())
        .filter(|&k| samples[k].v.is_some())
        .min_by(|&a, &b| samples[a].speed().total_cmp(&samples[b].speed()))?;
    let bracket = (
        samples[k.saturating_sub(1)].t,
        samples[(k + 1).min(samples.len() - 1)].t,
    );
    let speed = |t: f64| shooter.launch_for(t).map_or(f64::INFINITY, |v| v.length());
    let (t, _) = golden(speed, bracket, 1e-13 * bracket.1);
    let best = Sample {
        t,
        v: shooter.launch_for(t).ok(),
    };
    Some(if best.speed() <= samples[k].speed() {
        best
    } else {
        samples[k]
    })
}

/// The minimum of `f` on `[a, b]` by golden-section search, until the bracket is below `tol`
/// (at most 200 steps): returns `(x, f(x))` at the bracket's middle.
fn golden(mut f: impl FnMut(f64) -> f64, (mut a, mut b): (f64, f64), tol: f64) -> (f64, f64) {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    let x = 0.5 * (a + b);
    (x, f(x))
}

/// The root of `f` in the bracket `(a, b)` (values of opposite sign), then the launch there.
fn root(
    shooter: &dyn Shooter,
    f: impl Fn(&Sample) -> f64,
    a: Sample,
    b: Sample,
) -> Result<(f64, DVec3), FiringError> {
    let value = |t: f64| {
        f(&Sample {
            t,
            v: shooter.launch_for(t).ok(),
        })
    };
    let (t, _) = bracketed_root(value, (a.t, f(&a)), (b.t, f(&b)));
    Ok((t, shooter.launch_for(t)?))
}

/// What the solve found, before the checks: kind, arrival time, launch.
type Found = Vec<(ShotKind, f64, DVec3)>;

fn solve_with(range: &Range, mode: Mode, shooter: &dyn Shooter) -> Result<Found, FiringError> {
    let (mut samples, failure) = scan(range, shooter);
    // Where no arrival time could be solved, the solver's own failure is the answer, except
    // at a given speed, where an independent search says whether the target is in reach.
    let nothing = samples.iter().all(|s| s.v.is_none());
    if let (true, Some(e), false) = (nothing, &failure, matches!(mode, Mode::Speed(_))) {
        return Err(e.clone());
    }
    match mode {
        Mode::MinSpeed => {
            let best =
                slowest(&samples, shooter).ok_or_else(|| out_of_reach(range, f64::NAN, None))?;
            let v = shooter.launch_for(best.t)?;
            Ok(vec![(ShotKind::MinSpeed, best.t, v)])
        }
        Mode::Speed(speed) => {
            if !(speed.is_finite() && speed > 0.0) {
                return Err(FiringError::Invalid(format!(
                    "speed: expected a positive number of m/s, got {speed}"
                )));
            }
            let best = slowest(&samples, shooter);
            let Some(best) = best.filter(|b| b.speed() <= speed) else {
                let answer = out_of_reach(range, speed, best.map(|b| b.speed()));
                // A shot at this speed that touches the target does reach it: then the solver
                // failed, and says where.
                if let (FiringError::OutOfReach { best_miss, .. }, Some(e)) = (&answer, failure)
                    && *best_miss <= range.target.radius + range.radius
                {
                    return Err(e);
                }
                return Err(answer);
            };
            let at = samples.partition_point(|s| s.t < best.t);
            samples.insert(at, best);
            let f = |s: &Sample| s.speed() - speed;
            let mut found = Vec::new();
            // Low arc: the last sample before the minimum still too slow to need... the last
            // one above the speed, going down towards the minimum.
            if let Some(k) = (0..at).rev().find(|&k| f(&samples[k]) > 0.0) {
                let (t, v) = root(shooter, f, samples[k], samples[k + 1])?;
                found.push((ShotKind::Arc(Arc::Low), t, v));
            }
            if let Some(k) = (at + 1..samples.len()).find(|&k| f(&samples[k]) > 0.0) {
                let (t, v) = root(shooter, f, samples[k - 1], samples[k])?;
                found.push((ShotKind::Arc(Arc::High), t, v));
            }
            // High arc first, as `exact::aim` orders them.
            found.reverse();
            Ok(found)
        }
        Mode::Elevation(elevation) => {
            if !(elevation.is_finite() && elevation.abs() <= 90.0) {
                return Err(FiringError::Invalid(format!(
                    "elevation: expected -90 to 90 degrees, got {elevation}"
                )));
            }
            let d = range.target.center - range.from;
            let a = range.scene.forces.linear_part(range.mass).a0;
            let straight_up = d.x == 0.0 && d.y == 0.0;
            if straight_up
                && a.x == 0.0
                && a.y == 0.0
                && range.target.velocity.truncate() == glam::DVec2::ZERO
            {
                let min_speed = slowest(&samples, shooter).map_or(f64::NAN, |s| s.speed());
                return Err(FiringError::VerticalNeedsSpeed { min_speed });
            }
            let elevation_of = |s: &Sample| s.v.map_or(90.0, |v| angles_of(v).0);
            let f = |s: &Sample| elevation_of(s) - elevation;
            let valid: Vec<&Sample> = samples.iter().filter(|s| s.v.is_some()).collect();
            let lowest = valid.first().map_or(f64::NAN, |s| elevation_of(s));
            let highest = valid
                .iter()
                .map(|s| elevation_of(s))
                .fold(f64::NEG_INFINITY, f64::max);
            let k = (1..samples.len()).find(|&k| {
                samples[k - 1].v.is_some() && f(&samples[k - 1]) < 0.0 && f(&samples[k]) >= 0.0
            });
            let Some(k) = k else {
                return Err(FiringError::NoArcAtElevation {
                    elevation_deg: elevation,
                    lowest_deg: lowest,
                    highest_deg: highest,
                });
            };
            let (t, v) = root(shooter, f, samples[k - 1], samples[k])?;
            Ok(vec![(ShotKind::Elevation, t, v)])
        }
    }
}

/// The out-of-reach answer at `speed`, with the closest shot at that speed.
fn out_of_reach(range: &Range, speed: f64, min_speed: Option<f64>) -> FiringError {
    let (best_miss, best_elevation_deg) = if speed.is_finite() {
        best_miss(range, speed)
    } else {
        (f64::NAN, f64::NAN)
    };
    FiringError::OutOfReach {
        speed,
        min_speed: min_speed.filter(|v| v.is_finite()),
        best_miss,
        best_elevation_deg,
    }
}

/// The closest the stepped shot gets to the target at `speed`: the best of a 5 degree grid of
/// elevations towards the target, then golden-section searches on elevation and azimuth in
/// turn (six rounds, the windows shrinking), so a crosswind's drift is searched out too.
/// Returns (miss, elevation).
fn best_miss(range: &Range, speed: f64) -> (f64, f64) {
    let d = range.target.center - range.from;
    let miss_at = |elevation: f64, azimuth: f64| {
        let v = crate::scene::angles_to_velocity(speed, elevation, azimuth);
        closest_approach(range, v, range.max_flight_time).map_or(f64::INFINITY, |(m, _)| m)
    };
    let mut azimuth = libm::atan2(d.y, d.x).to_degrees();
    let (mut best, mut elevation) = (f64::INFINITY, 0.0);
    for k in 0..=36 {
        let e = -90.0 + 5.0 * k as f64;
        let m = miss_at(e, azimuth);
        if m < best {
            (best, elevation) = (m, e);
        }
    }
    let mut window = 5.0;
    for _ in 0..6 {
        let around = |x: f64, lo: f64, hi: f64| ((x - window).max(lo), (x + window).min(hi));
        let (e, m) = golden(
            |e| miss_at(e, azimuth),
            around(elevation, -90.0, 90.0),
            1e-9,
        );
        if m < best {
            (best, elevation) = (m, e);
        }
        let (a, m) = golden(
            |a| miss_at(elevation, a),
            around(azimuth, -360.0, 360.0),
            1e-9,
        );
        if m < best {
            (best, azimuth) = (m, a);
        }
        window *= 0.3;
    }
    (best, elevation)
}

/// A world with one shot fired at `v0` and the target, over `duration` seconds.
fn flight_world(range: &Range, v0: DVec3, contacts: bool) -> World {
    let mut scene = range.scene.clone();
    scene.start_time = 0.0;
    scene.volley = None;
    scene.bodies = vec![BodySpec {
        mass: range.mass,
        radius: range.radius,
        position: range.from,
        velocity: v0,
    }];
    scene.targets = vec![Target {
        radius: range.target.radius,
        ..range.target
    }];
    scene.detection = crate::contact::Detection::Swept;
    if !contacts {
        scene.ground = None;
        scene.walls.clear();
    }
    World::new(&scene)
}

/// Closest approach (distance, time after launch) of the stepped path at `v0` to the target's
/// centre over at most `duration`: the nearest substep boundary, refined by golden-section
/// search over the steps either side of it on the path the integrator steps.
///
/// This is the minimum of the distance along the path itself. (The engine's approach event
/// finds where `(p - c) . V` changes sign with the *state's* velocity, which for most
/// integrators is not the slope of the path inside a step, so its distance can be a few
/// micrometres above this one at coarse steps.)
fn closest_approach(range: &Range, v0: DVec3, duration: f64) -> Option<(f64, f64)> {
    let stepped = Stepped::new(range);
    let hs = stepped.hs;
    let count = ((duration / hs).ceil() as u64).min(u64::from(u32::MAX));
    let path = stepped.samples(v0, count);
    let dist = |k: usize| (path[k].0.p - range.target_at(k as f64 * hs)).length();
    let k = (0..path.len())
        .filter(|&k| dist(k).is_finite())
        .min_by(|&a, &b| dist(a).total_cmp(&dist(b)))?;
    // Inside the steps either side of boundary k: a partial step from the boundary before.
    let at = |t: f64| {
        let j = ((t / hs).floor() as usize).min(path.len() - 1);
        let (s, carry) = path[j];
        let partial = Partial {
            s,
            carry,
            w: stepped.w,
            tau: t - j as f64 * hs,
        };
        let p = visit(
            stepped.integrator,
            &stepped.forces,
            stepped.tolerance,
            partial,
        )
        .p;
        (p - range.target_at(t)).length()
    };
    let bracket = (k.saturating_sub(1) as f64 * hs, (k + 1) as f64 * hs);
    let (t, d) = golden(at, bracket, 1e-15 * bracket.1.max(hs));
    let best = (d, t);
    Some(if best.0 <= dist(k) {
        best
    } else {
        (dist(k), k as f64 * hs)
    })
}

/// Fires each found launch in a world: the engine's miss, a block before arrival, the
/// textbook's miss.
fn finish(range: &Range, mode: Mode, found: Found) -> Result<Vec<Shot>, FiringError> {
    let h = range.scene.dt();
    let mut shots = Vec::new();
    for (kind, flight_time, velocity) in found {
        let mut world = flight_world(range, velocity, range.contacts);
        let arrival_tick = split_time(flight_time, h).0 + 1;
        let mut blocked = None;
        let mut approaches = Vec::new();
        for _ in 0..=arrival_tick {
            if let Err(d) = world.step() {
                return Err(FiringError::Diverged {
                    flight_time,
                    tick: Some(d.tick),
                });
            }
            for e in world.events() {
                match e.kind {
                    EventKind::Impact { surface, .. }
                        if blocked.is_none() && e.time < flight_time =>
                    {
                        blocked = Some(Blocked {
                            surface,
                            time: e.time,
                            tick: e.tick,
                        });
                    }
                    EventKind::Approach { distance, .. } => approaches.push((distance, e.time)),
                    _ => {}
                }
            }
        }
        let miss = if blocked.is_some() {
            // Whatever comes after a bounce is not this shot: measure it with contacts off.
            closest_approach(range, velocity, flight_time + h).map_or(f64::NAN, |m| m.0)
        } else {
            approaches
                .iter()
                .min_by(|a, b| {
                    (a.1 - flight_time)
                        .abs()
                        .total_cmp(&(b.1 - flight_time).abs())
                })
                .map_or(f64::NAN, |a| a.0)
        };
        if miss.is_nan() {
            return Err(FiringError::Unverified { flight_time });
        }
        let (elevation_deg, azimuth_deg) = angles_of(velocity);
        let textbook = textbook_velocity(range, mode, kind).map(|v| {
            let horizon = (2.0 * flight_time + 1.0).min(range.max_flight_time);
            let (miss, time) = closest_approach(range, v, horizon).unwrap_or((f64::NAN, f64::NAN));
            Textbook {
                velocity: v,
                miss,
                time,
            }
        });
        shots.push(Shot {
            kind,
            velocity,
            speed: velocity.length(),
            elevation_deg,
            azimuth_deg,
            flight_time,
            arrival_tick,
            miss,
            blocked,
            textbook,
        });
    }
    if !shots.is_empty() && shots.iter().all(|s| s.blocked.is_some()) {
        return Err(FiringError::Blocked(
            shots.iter().map(|s| (s.kind, s.blocked.unwrap())).collect(),
        ));
    }
    Ok(shots)
}

/// The textbook answer to the same question: the closed form under the scene's gravity alone,
/// at the target's centre at launch (it knows no drag, wind, step or target motion).
fn textbook_velocity(range: &Range, mode: Mode, kind: ShotKind) -> Option<DVec3> {
    let g = range.scene.forces.gravity.map_or(0.0, |g| -g.z);
    let (from, to) = (range.from, range.target.center);
    let d = to - from;
    let dh = (d.x * d.x + d.y * d.y).sqrt();
    let azimuth = libm::atan2(d.y, d.x).to_degrees();
    match (mode, kind) {
        (Mode::Speed(speed), ShotKind::Arc(arc)) => {
            let [high, low] = exact::aim(from, to, speed, g).ok()?;
            Some(if arc == Arc::High {
                high.velocity
            } else {
                low.velocity
            })
        }
        (Mode::Elevation(elevation), _) => {
            // v^2 = g dh^2 / (2 cos^2 e (dh tan e - dz)).
            let e = elevation.to_radians();
            let (s, c) = (libm::sin(e), libm::cos(e));
            let lift = dh * s / c - d.z;
            if !(g > 0.0 && lift > 0.0 && c > 0.0) {
                return None;
            }
            let speed = (g * dh * dh / (2.0 * c * c * lift)).sqrt();
            Some(crate::scene::angles_to_velocity(speed, elevation, azimuth))
        }
        (Mode::MinSpeed, _) if g > 0.0 && dh > 0.0 => {
            // tan e = (dz + r) / dh, v^2 = g (dz + r).
            let r = d.length();
            let elevation = libm::atan2(d.z + r, dh).to_degrees();
            Some(crate::scene::angles_to_velocity(
                (g * (d.z + r)).sqrt(),
                elevation,
                azimuth,
            ))
        }
        _ => None,
    }
}
