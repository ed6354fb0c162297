//! The world: the bodies ([`crate::body`]), the seeded generator ([`crate::rng`]), the scene's
//! parameters and the scratch the step reuses.

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use crate::body::{Bodies, BodyId, Vec3s};
use crate::contact::{Contacts, Event};
use crate::forces::Forces;
use crate::integrate::Integrator;
pub use crate::rng::SplitMix64;
use crate::scene::{BodySpec, Launcher, Scene};

/// Where a run's state went non-finite or gained energy it cannot have.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Divergence {
    /// The tick whose step produced the bad state.
    pub tick: u64,
    /// The first body (lowest id) affected.
    pub body: BodyId,
    /// Why the run was stopped.
    pub cause: DivergenceCause,
}

/// Why the guard stopped a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum DivergenceCause {
    /// A position or momentum component became NaN or infinite.
    NonFinite,
    /// The body's energy grew past the guard's bound in a scene that cannot add energy.
    EnergyGrowth {
        /// Energy at the check (J).
        energy: f64,
        /// The bound it passed (J).
        bound: f64,
    },
}

impl std::fmt::Display for Divergence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "diverged at tick {} (body {}): ", self.tick, self.body)?;
        match self.cause {
            DivergenceCause::NonFinite => f.write_str("state is no longer finite"),
            DivergenceCause::EnergyGrowth { energy, bound } => write!(
                f,
                "energy {energy:.6e} J passed the guard's bound {bound:.6e} J although no force \
                 adds energy (a numerical instability)"
            ),
        }
    }
}

impl std::error::Error for Divergence {}

/// The state [`World::step_ticks`] saves before a batch, to undo it.
#[derive(Clone, Debug, Default)]
pub(crate) struct BatchBackup {
    pub(crate) p: Vec3s,
    pub(crate) mv: Vec3s,
    pub(crate) carry: Vec3s,
}

/// The simulation state and everything that decides how it advances.
#[derive(Clone, Debug)]
pub struct World {
    pub(crate) scene: Scene,
    pub(crate) bodies: Bodies,
    pub(crate) next_id: u64,
    pub(crate) tick: u64,
    pub(crate) h: f64,
    pub(crate) integrator: Integrator,
    pub(crate) substeps: u32,
    /// Active force terms: the declared ones minus those toggled off.
    pub(crate) forces: Forces,
    pub(crate) contacts: Contacts,
    pub(crate) launcher: Launcher,
    pub(crate) rng: SplitMix64,
    /// Events of the last tick.
    pub(crate) events: Vec<Event>,
    /// Force evaluations since tick 0.
    pub(crate) force_evals: u64,
    /// Velocity Verlet's carried end-of-step force, per body; empty for other integrators.
    pub(crate) carry: Vec3s,
    pub(crate) carry_valid: bool,
    pub(crate) diverged: Option<Divergence>,
    pub(crate) threads: usize,
    pub(crate) chunk_events: Vec<Vec<Event>>,
    /// The state a batch of ticks started from ([`World::step_ticks`]); grown on first use.
    pub(crate) batch_backup: BatchBackup,
}

impl World {
    /// Builds the world of a scene at tick 0: its bodies, then its volley if it declares one.
    ///
    /// ```
    /// let scene = volley_sim::scene::parse(
    ///     "Scene(dt: 0.5, integrator: Exact, forces: [Gravity((0, 0, -10))],
    ///            bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((1, 0, 10)))])",
    ///     "inline.ron", "inline").unwrap();
    /// let mut world = volley_sim::World::new(&scene);
    /// world.step().unwrap();
    /// assert_eq!(world.bodies().state(0).p.z, 10.0 * 0.5 - 0.5 * 10.0 * 0.25);
    /// ```
    pub fn new(scene: &Scene) -> World {
        let mut world = World {
            scene: scene.clone(),
            bodies: Bodies::default(),
            next_id: 0,
            tick: 0,
            h: scene.timestep.as_nanos() as f64 * 1e-9,
            integrator: scene.integrator,
            substeps: scene.substeps,
            forces: scene.forces,
            contacts: Contacts {
                ground: scene.ground,
                walls: scene.walls.clone(),
                targets: scene.targets.clone(),
                detection: scene.detection,
            },
            launcher: scene.launcher,
            rng: SplitMix64(scene.seed),
            events: Vec::new(),
            force_evals: 0,
            carry: Vec3s::default(),
            carry_valid: false,
            diverged: None,
            threads: 1,
            chunk_events: Vec::new(),
            batch_backup: Default::default(),
        };
        world.populate();
        world
    }

    /// Spawns the scene's bodies and volley.
    pub(crate) fn populate(&mut self) {
        for spec in self.scene.bodies.clone() {
            self.spawn(&spec);
        }
        if let Some(volley) = self.scene.volley {
            for _ in 0..volley.count {
                let l = self.launcher;
                let speed = l.speed + volley.speed_spread * self.rng.next_signed();
                let el = l.elevation_deg + volley.angle_spread_deg * self.rng.next_signed();
                let az = l.azimuth_deg + volley.angle_spread_deg * self.rng.next_signed();
                self.spawn(&BodySpec {
                    mass: l.mass,
                    radius: l.radius,
                    position: l.position,
                    velocity: crate::scene::angles_to_velocity(speed.max(0.0), el, az),
                });
            }
        }
    }

    /// Adds a body at the end of the id order and returns its id.
    pub fn spawn(&mut self, spec: &BodySpec) -> BodyId {
        let id = BodyId(self.next_id);
        self.next_id += 1;
        self.bodies
            .push(id, spec.position, spec.velocity, spec.mass, spec.radius);
        let i = self.bodies.len() - 1;
        self.bodies.energy_cap[i] = self.energy_cap_of(i);
        self.carry_valid = false;
        id
    }

    /// Removes a body, keeping the others in order. Returns whether it existed.
    pub fn despawn(&mut self, id: BodyId) -> bool {
        match self.bodies.index_of(id) {
            Some(i) => {
                self.bodies.remove(i);
                self.carry_valid = false;
                true
            }
            None => false,
        }
    }

    /// Removes every body (ids keep counting).
    pub fn clear_bodies(&mut self) {
        self.bodies.clear();
        self.carry_valid = false;
    }

    /// The guard's energy bound for body `i`: start energy plus `(factor - 1)` times its scale.
    ///
    /// The scale is the sum of the magnitudes of the kinetic and each potential term at the
    /// start, so it does not vanish when the terms cancel (a circular orbit, a body at rest).
    pub(crate) fn energy_cap_of(&self, i: usize) -> f64 {
        use crate::forces::ForceModel;
        let (s, m) = (self.bodies.state(i), self.bodies.mass[i]);
        let v = self.bodies.velocity(i);
        let energy = self.forces.energy(s.p, v, m);
        let scale = crate::forces::ForceKind::ALL
            .into_iter()
            .filter(|k| self.forces.has(*k))
            .map(|k| {
                let only = self.forces.filtered(|j| j == k);
                (only.energy(s.p, v, m) - 0.5 * m * v.length_squared()).abs()
            })
            .sum::<f64>()
            + 0.5 * m * v.length_squared();
        let floor = f64::MIN_POSITIVE.max(1e-12 * m);
        energy + (self.scene.guard.energy_factor - 1.0) * scale.max(floor)
    }

    /// Resets every body's energy bound to its current state (after commands add energy).
    pub(crate) fn rebase_energy_caps(&mut self) {
        for i in 0..self.bodies.len() {
            self.bodies.energy_cap[i] = self.energy_cap_of(i);
        }
    }

    /// The bodies.
    pub fn bodies(&self) -> &Bodies {
        &self.bodies
    }

    /// Ticks stepped since tick 0.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// The physics step h (s), exactly the clock's timestep in nanoseconds.
    pub fn dt(&self) -> f64 {
        self.h
    }

    /// Sim time (s) of the current tick: `start_time + tick * h`, one multiplication, no sum.
    pub fn time(&self) -> f64 {
        self.time_of(self.tick)
    }

    /// Sim time (s) of tick `tick`.
    pub fn time_of(&self, tick: u64) -> f64 {
        self.scene.start_time + tick as f64 * self.h
    }

    /// Integrator in use.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Active force terms.
    pub fn forces(&self) -> &Forces {
        &self.forces
    }

    /// Contacts of the scene.
    pub fn contacts(&self) -> &Contacts {
        &self.contacts
    }

    /// The scene the world was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The launcher used by `Fire` commands.
    pub fn launcher(&self) -> &Launcher {
        &self.launcher
    }

    /// Events of the last tick, in body order.
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// Force evaluations since tick 0 (every body, stage and contact search included).
    pub fn force_evals(&self) -> u64 {
        self.force_evals
    }

    /// Integrator steps per tick.
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// The divergence that stopped the run, if any.
    pub fn divergence(&self) -> Option<Divergence> {
        self.diverged
    }

    /// The world's random generator (part of the hashed state).
    pub fn rng(&self) -> SplitMix64 {
        self.rng
    }

    /// Worker threads used for stepping (1 = on the caller's thread). Results are bit-identical
    /// for every thread count.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Sets the number of worker threads (at least 1).
    pub fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    /// Velocity of body `i` (m/s).
    pub fn velocity(&self, i: usize) -> DVec3 {
        self.bodies.velocity(i)
    }

    /// Net force (N) on body `i` from the active terms, at its current state.
    pub fn force_on(&self, i: usize) -> DVec3 {
        use crate::forces::ForceModel;
        let m = self.bodies.mass[i];
        self.forces.force(self.bodies.p.get(i), self.velocity(i), m)
    }

    /// Mechanical energy (J) of body `i` under the active terms.
    pub fn energy_of(&self, i: usize) -> f64 {
        use crate::forces::ForceModel;
        let m = self.bodies.mass[i];
        self.forces
            .energy(self.bodies.p.get(i), self.velocity(i), m)
    }
}

/// A world's whole mutable state at a tick boundary: what a replay keyframe stores.
///
/// Restoring it ([`World::restore`]) onto a world built from the same scene and stepping on gives
/// the same bits as stepping on from the world it was taken from. What the scene fixes (timestep,
/// substeps, contacts, declared forces, guard) is not in it; `inv_mass` is recomputed as
/// `1 / mass`, exactly as at spawn. Events of the last tick and the thread count are not state.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Ticks stepped since tick 0.
    pub tick: u64,
    /// Id the next spawned body gets.
    pub next_id: u64,
    /// The random generator.
    pub rng: SplitMix64,
    /// Integrator in use.
    pub integrator: Integrator,
    /// Active force terms: a subset of the scene's declared terms, with the declared values.
    pub forces: Forces,
    /// The launcher `Fire` uses.
    pub launcher: Launcher,
    /// Force evaluations since tick 0.
    pub force_evals: u64,
    /// Body ids, strictly increasing.
    pub ids: Vec<BodyId>,
    /// Positions (m).
    pub p: Vec3s,
    /// Momenta (kg m/s).
    pub mv: Vec3s,
    /// Masses (kg).
    pub mass: Vec<f64>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// The energy guard's bound per body (J).
    pub energy_cap: Vec<f64>,
    /// Velocity Verlet's carried force (N) per body when it is valid; empty otherwise.
    pub carry: Vec3s,
}

impl World {
    /// The state now, for keyframes and seeking. See [`World::snapshot_into`] to reuse buffers.
    pub fn snapshot(&self) -> Snapshot {
        let mut s = Snapshot {
            tick: 0,
            next_id: 0,
            rng: self.rng,
            integrator: self.integrator,
            forces: self.forces,
            launcher: self.launcher,
            force_evals: 0,
            ids: Vec::new(),
            p: Vec3s::default(),
            mv: Vec3s::default(),
            mass: Vec::new(),
            radius: Vec::new(),
            energy_cap: Vec::new(),
            carry: Vec3s::default(),
        };
        self.snapshot_into(&mut s);
        s
    }

    /// Like [`World::snapshot`], reusing `out`'s allocations (no allocation once they fit).
    pub fn snapshot_into(&self, out: &mut Snapshot) {
        let b = &self.bodies;
        (out.tick, out.next_id, out.rng) = (self.tick, self.next_id, self.rng);
        (out.integrator, out.forces) = (self.integrator, self.forces);
        (out.launcher, out.force_evals) = (self.launcher, self.force_evals);
        out.ids.clone_from(&b.id);
        out.p.copy_from(&b.p);
        out.mv.copy_from(&b.mv);
        out.mass.clone_from(&b.mass);
        out.radius.clone_from(&b.radius);
        out.energy_cap.clone_from(&b.energy_cap);
        if self.carries_force() {
            out.carry.copy_from(&self.carry);
        } else {
            out.carry.resize(0);
        }
    }

    /// Whether the carried force is state: velocity Verlet in its carrying form (forces of
    /// position only) after a step. In its predicted form (drag) the buffer is not read, and
    /// any switch between the forms goes through a command, which invalidates it.
    fn carries_force(&self) -> bool {
        use crate::forces::ForceModel;
        self.carry_valid
            && self.carry.len() == self.bodies.len()
            && self.integrator == Integrator::VelocityVerlet
            && !self.forces.velocity_dependent()
    }

    /// Puts `s` back, or says why it cannot belong to this world's scene (lengths that differ,
    /// ids not increasing or not below `next_id`, a mass not > 0, a radius not >= 0, a force
    /// term the scene does not declare, an integrator the forces refuse, a carried force
    /// without velocity Verlet). The divergence flag and the last tick's events are cleared.
    pub fn restore(&mut self, s: &Snapshot) -> Result<(), RestoreError> {
        use crate::forces::ForceModel;
        let n = s.ids.len();
        let lengths = [s.p.len(), s.mv.len(), s.mass.len(), s.radius.len()];
        if lengths.iter().chain([&s.energy_cap.len()]).any(|&l| l != n) {
            return Err(RestoreError::Lengths { ids: n });
        }
        if !s.ids.windows(2).all(|w| w[0] < w[1])
            || s.ids.last().is_some_and(|id| id.0 >= s.next_id)
        {
            return Err(RestoreError::Ids);
        }
        if let Some(i) = (0..n).find(|&i| !(s.mass[i].is_finite() && s.mass[i] > 0.0)) {
            return Err(RestoreError::Mass {
                body: s.ids[i],
                mass: s.mass[i],
            });
        }
        if let Some(i) = (0..n).find(|&i| !(s.radius[i].is_finite() && s.radius[i] >= 0.0)) {
            return Err(RestoreError::Radius {
                body: s.ids[i],
                radius: s.radius[i],
            });
        }
        if s.forces != self.scene.forces.filtered(|k| s.forces.has(k)) {
            return Err(RestoreError::Forces);
        }
        crate::scene::check_integrator(s.integrator, &s.forces)
            .map_err(RestoreError::Integrator)?;
        let l = &s.launcher;
        let numbers = [l.speed, l.elevation_deg, l.azimuth_deg, l.mass, l.radius];
        let finite = numbers.iter().all(|x| x.is_finite()) && l.position.is_finite();
        if !(finite && l.speed >= 0.0 && l.mass > 0.0 && l.radius >= 0.0) {
            return Err(RestoreError::Launcher);
        }
        let verlet = s.integrator == Integrator::VelocityVerlet;
        if !s.carry.is_empty() && (s.carry.len() != n || !verlet || s.forces.velocity_dependent()) {
            return Err(RestoreError::Carry);
        }
        let b = &mut self.bodies;
        b.id.clone_from(&s.ids);
        b.p.copy_from(&s.p);
        b.mv.copy_from(&s.mv);
        b.mass.clone_from(&s.mass);
        b.inv_mass.clear();
        b.inv_mass.extend(s.mass.iter().map(|m| 1.0 / m));
        b.radius.clone_from(&s.radius);
        b.energy_cap.clone_from(&s.energy_cap);
        self.carry.copy_from(&s.carry);
        self.carry_valid = !s.carry.is_empty();
        (self.tick, self.next_id, self.rng) = (s.tick, s.next_id, s.rng);
        (self.integrator, self.forces) = (s.integrator, s.forces);
        (self.launcher, self.force_evals) = (s.launcher, s.force_evals);
        self.events.clear();
        self.diverged = None;
        Ok(())
    }
}

/// Why [`World::restore`] refused a snapshot: the check it failed, with the values it names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RestoreError {
    /// The body arrays are not all as long as the ids.
    Lengths {
        /// How many ids the snapshot has.
        ids: usize,
    },
    /// The ids do not increase, or one is not below `next_id`.
    Ids,
    /// A body's mass is not a finite number > 0.
    Mass {
        /// The body.
        body: BodyId,
        /// Its mass (kg).
        mass: f64,
    },
    /// A body's radius is not a finite number >= 0.
    Radius {
        /// The body.
        body: BodyId,
        /// Its radius (m).
        radius: f64,
    },
    /// A force term is active that the scene does not declare (or with other values).
    Forces,
    /// The integrator is one the active forces refuse.
    Integrator(crate::scene::IntegratorError),
    /// The launcher has a value that is not finite, a negative speed or radius, or a mass not
    /// > 0.
    Launcher,
    /// A carried force without velocity Verlet, with velocity-dependent forces, or not one
    /// entry per body.
    Carry,
}

impl std::fmt::Display for RestoreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RestoreError::Lengths { ids } => {
                write!(f, "body arrays of different lengths ({ids} ids)")
            }
            RestoreError::Ids => f.write_str("body ids must increase and stay below next_id"),
            RestoreError::Mass { body, mass } => {
                write!(f, "body {body}: mass must be > 0, got {mass}")
            }
            RestoreError::Radius { body, radius } => {
                write!(f, "body {body}: radius must be >= 0, got {radius}")
            }
            RestoreError::Forces => {
                f.write_str("active forces are not a subset of the scene's declared terms")
            }
            RestoreError::Integrator(e) => write!(f, "{e}"),
            RestoreError::Launcher => {
                f.write_str("launcher: values must be finite, speed and radius >= 0, mass > 0")
            }
            RestoreError::Carry => f.write_str(
                "a carried force needs velocity Verlet, forces of position only and one entry \
                 per body",
            ),
        }
    }
}

impl std::error::Error for RestoreError {}
