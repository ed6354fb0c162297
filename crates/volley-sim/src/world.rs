//! The world: the bodies ([`crate::body`]), the seeded generator ([`crate::rng`]), the scene's
//! parameters and the scratch the step reuses.

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use crate::body::{Bodies, BodyId, COLUMNS, Vec3s};
use crate::contact::{Contacts, Event, EventKind, EventSet, EventStop};
use crate::forces::Forces;
use crate::integrate::Integrator;
pub use crate::rng::SplitMix64;
use crate::scene::{BodySpec, Guard, Launcher, Scene};

mod restore;

pub use restore::{MAX_COUNT, RestoreError};

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

/// What a run is at a tick boundary: everything that steps and nothing that is fixed. A
/// keyframe holds exactly this (a replay keyframe), the state hash covers its tick,
/// generator and hashed body columns ([`crate::state_hash`]), and [`World::restore`] validates one
/// against the scene, then assigns it.
///
/// Restoring a state onto a world built from the same scene and stepping on gives the same bits
/// as stepping on from the world it was taken from. What the scene fixes ([`Params`]) is not in
/// it; `1 / mass` is recomputed on restore, exactly as at spawn. The last tick's events, the
/// divergence flag and the thread count are not state.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
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
    /// The bodies, in id order.
    pub bodies: Bodies,
    /// Velocity Verlet's carried force (N) per body. In a keyframe, and in what
    /// [`World::snapshot`] returns, it is there only when it is valid and empty otherwise; in a
    /// world it is a buffer whose validity the world tracks.
    pub carry: Vec3s,
    /// How often the declared events that stop after more than one occurrence have occurred
    /// ([`Tallies`]); empty in a scene without such an event.
    pub tallies: Tallies,
}

/// How often each declared event that stops a body or the run after its `n`-th occurrence
/// (`n` > 1) has occurred so far: state, since it decides when a body or the run stops. Empty
/// in a scene without such an event, whose keyframes and hashes are then what they were before
/// events.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tallies {
    /// Per body, in body order, one count per body-stopping event with `n` > 1 (the
    /// scene's [`EventSet::body_slots`]): `per_body[i * slots + k]`.
    pub per_body: Vec<u32>,
    /// One count per run-stopping event with `n` > 1 ([`EventSet::run_slots`]).
    pub run: Vec<u32>,
}

impl Tallies {
    /// Whether there is nothing to count.
    pub fn is_empty(&self) -> bool {
        self.per_body.is_empty() && self.run.is_empty()
    }
}

/// Where a declared event stopped the run ([`EventStop::Run`]): the world steps no further.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunStop {
    /// The tick whose step held the event (the world stays at it).
    pub tick: u64,
    /// Sim time of the event (s).
    pub time: f64,
    /// The body it happened to.
    pub body: BodyId,
    /// Index of the event in the scene's `events`.
    pub event: u32,
}

impl std::fmt::Display for RunStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "stopped at tick {} by event {} (body {}, t = {} s)",
            self.tick, self.event, self.body, self.time
        )
    }
}

impl State {
    /// Makes this state a copy of `src`, reusing its allocations (none once they fit): every
    /// field and column, `1 / mass` recomputed as at spawn, and the carried force only if
    /// `carry` (otherwise it is left empty).
    pub(crate) fn assign_from(&mut self, src: &State, carry: bool) {
        (self.tick, self.next_id, self.rng) = (src.tick, src.next_id, src.rng);
        (self.integrator, self.forces) = (src.integrator, src.forces.clone());
        (self.launcher, self.force_evals) = (src.launcher, src.force_evals);
        self.tallies.per_body.clone_from(&src.tallies.per_body);
        self.tallies.run.clone_from(&src.tallies.run);
        self.bodies.id.clone_from(&src.bodies.id);
        for column in &COLUMNS {
            column
                .get_mut(&mut self.bodies)
                .clone_from(column.get(&src.bodies));
        }
        self.bodies.recompute_inv_mass();
        if carry {
            self.carry.copy_from(&src.carry);
        } else {
            self.carry.resize(0);
        }
    }
}

/// A world's [`State`] under the name replays use for it.
pub type Snapshot = State;

/// How a world advances: plain data copied from its scene when the world is built, fixed for
/// the world's life (a new dt or substep count builds a new world).
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// The physics step h (s): exactly the scene's timestep, a whole number of nanoseconds.
    pub h: f64,
    /// Integrator steps per tick (1 to [`crate::scene::MAX_SUBSTEPS`]).
    pub substeps: u32,
    /// The adaptive integrator's tolerance (the scene's `tolerance`).
    pub tolerance: f64,
    /// Sim time (s) of tick 0; tick n is at `start_time + n * h`.
    pub start_time: f64,
    /// Ground, walls, targets and how contacts are detected.
    pub contacts: Contacts,
    /// The divergence guard: how often it checks and its energy factor.
    pub guard: Guard,
    /// The force terms the scene declares; the state's active terms are a subset of them.
    pub declared: Forces,
}

impl Params {
    /// The parameters of `scene`.
    pub fn of_scene(scene: &Scene) -> Params {
        Params {
            h: scene.timestep.as_nanos() as f64 * 1e-9,
            substeps: scene.substeps,
            tolerance: scene.tolerance,
            start_time: scene.start_time,
            contacts: Contacts {
                ground: scene.ground,
                walls: scene.walls.clone(),
                targets: scene.targets.clone(),
                meshes: scene.meshes.clone(),
                heightfields: scene.heightfields.clone(),
                detection: scene.detection,
                events: EventSet::prepare(
                    &scene.events,
                    (scene.launcher.position, scene.launcher.azimuth_deg),
                    &scene.targets,
                    scene.forces.mach_drag.as_ref(),
                ),
            },
            guard: scene.guard,
            declared: scene.forces.clone(),
        }
    }
}

impl World {
    /// After a substep with declared events, from the `first` of its events on: each event
    /// that stops counts, a body whose event stops it leaves the world (its later events in the
    /// tick dropped), and an event that stops the run marks the world stopped.
    pub(crate) fn apply_stops(&mut self, first: usize) {
        let events = &self.params.contacts.events;
        if !events.stops() {
            return;
        }
        let slots = events.body_slots();
        let mut leaving: Vec<(BodyId, f64)> = Vec::new();
        let mut kept = first;
        for k in first..self.scratch.events.len() {
            let e = self.scratch.events[k];
            if leaving.iter().any(|(id, t)| *id == e.body && e.time > *t) {
                continue;
            }
            self.scratch.events[kept] = e;
            kept += 1;
            let EventKind::Declared { event, .. } = e.kind else {
                continue;
            };
            let spec = &events.specs()[event as usize];
            let reached = |count: &mut u32, n: u32| {
                *count += 1;
                *count >= n
            };
            match spec.stop {
                EventStop::Never => {}
                EventStop::Body(n) => {
                    let stop = match events.body_slot(event as usize) {
                        Some(slot) if n > 1 => {
                            let i = self.state.bodies.index_of(e.body);
                            i.is_some_and(|i| {
                                reached(&mut self.state.tallies.per_body[i * slots + slot], n)
                            })
                        }
                        _ => true,
                    };
                    if stop && !leaving.iter().any(|(id, _)| *id == e.body) {
                        leaving.push((e.body, e.time));
                    }
                }
                EventStop::Run(n) => {
                    let stop = match events.run_slot(event as usize) {
                        Some(slot) if n > 1 => reached(&mut self.state.tallies.run[slot], n),
                        _ => true,
                    };
                    if stop && self.halt == Halt::Running {
                        self.halt = Halt::Stopped(RunStop {
                            tick: e.tick,
                            time: e.time,
                            body: e.body,
                            event,
                        });
                    }
                }
            }
        }
        self.scratch.events.truncate(kept);
        for (id, _) in leaving {
            self.despawn(id);
        }
    }
}

/// Buffers the step reuses from tick to tick; never state, never compared.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    /// Events of the last tick.
    pub(crate) events: Vec<Event>,
    /// One event buffer per parallel chunk, concatenated in chunk order after a tick.
    pub(crate) chunk_events: Vec<Vec<Event>>,
    /// The state a batch of ticks started from ([`World::step_ticks`]); grown on first use.
    pub(crate) batch_backup: BatchBackup,
    /// Bodies spawned since the last tick, in id order, in a world with declared events: their
    /// first segment reports an event whose function is zero at the spawn.
    pub(crate) fresh: Vec<BodyId>,
    /// Per body, the step number from which its declared events are searched again
    /// ([`crate::contact::events::horizon`]): a cache the step keeps only in a world with
    /// events whose forces are a constant field. Valid only while as long as the bodies;
    /// cleared whenever anything but a step changes them.
    pub(crate) due: crate::contact::events::horizon::Due,
    /// Keep no horizons (the tests that show they change nothing).
    pub(crate) horizons_off: bool,
}

/// The state [`World::step_ticks`] saves before a batch, to undo it.
#[derive(Clone, Debug, Default)]
pub(crate) struct BatchBackup {
    pub(crate) p: Vec3s,
    pub(crate) mv: Vec3s,
    pub(crate) carry: Vec3s,
}

/// What a tick asks of the active force terms, worked out once whenever they change (at build,
/// a force command, a reset, a restore) instead of every tick: the fast-path model, whether a
/// term reads the launch, may add energy, or is a motor. Never state: it follows from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ForceFacts {
    /// The terms as a [`crate::forces::ConstantField`], if gravity and a constant force are all.
    pub(crate) constant: Option<crate::forces::ConstantField>,
    /// [`Forces::reads_launch`].
    pub(crate) reads_launch: bool,
    /// [`Forces::adds_energy`].
    pub(crate) adds_energy: bool,
    /// Whether a motor is declared.
    pub(crate) motor: bool,
    /// |g| (m/s^2), 0 without gravity: the contact stage's rest speed is `|g| h`.
    pub(crate) gravity: f64,
}

impl ForceFacts {
    /// The facts of `forces`.
    pub(crate) fn of(forces: &Forces) -> ForceFacts {
        ForceFacts {
            constant: forces.constant_field(),
            reads_launch: forces.reads_launch(),
            adds_energy: forces.adds_energy(),
            motor: forces.thrust.is_some(),
            gravity: forces.gravity.map_or(0.0, DVec3::length),
        }
    }
}

/// One run: its [`State`], the [`Params`] it advances by, and the scratch buffers of the step.
#[derive(Clone, Debug)]
pub struct World {
    /// The scene the world was built from (for `Reset` and its bodies' start states).
    pub(crate) scene: Scene,
    pub(crate) state: State,
    pub(crate) params: Params,
    pub(crate) scratch: Scratch,
    /// Whether `state.carry` holds velocity Verlet's force from the last step.
    pub(crate) carry_valid: bool,
    /// Whether the run goes on, or what stopped it (a divergence, a declared event).
    pub(crate) halt: Halt,
    /// Worker threads (a runtime knob: the bits do not depend on it).
    pub(crate) threads: usize,
    /// Which per-body loop the step runs (fixed by the scene).
    pub(crate) kind: LoopKind,
    /// Force evaluations the declared events' search has spent (not counted in
    /// [`World::force_evals`], which the stepping alone decides).
    pub(crate) event_evals: u64,
    /// The active terms' facts ([`ForceFacts`]), kept with them.
    pub(crate) facts: ForceFacts,
}

/// Which per-body loop a world's step runs, fixed by its scene: no contact stage at all,
/// contacts only, or contacts and declared events. (The sync test's [`crate::step::Stage`] is
/// a stage *of* a tick; this is the kind of loop the whole tick runs.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum LoopKind {
    /// Neither contacts nor events.
    #[default]
    Bare,
    /// Contacts, no declared events.
    Contacts,
    /// Declared events (and any contacts).
    Events,
}

impl LoopKind {
    /// The loop a scene's contacts and events need.
    pub(crate) fn of(contacts: &crate::contact::Contacts) -> LoopKind {
        if !contacts.events.is_empty() {
            LoopKind::Events
        } else if contacts.is_empty() {
            LoopKind::Bare
        } else {
            LoopKind::Contacts
        }
    }
}

/// Whether a world steps on, or what stopped it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) enum Halt {
    /// It steps.
    #[default]
    Running,
    /// A divergence stopped it ([`World::divergence`]).
    Diverged(Divergence),
    /// A declared event stopped it ([`World::stopped`]).
    Stopped(RunStop),
}

impl World {
    /// Builds the world of a scene at tick 0: its bodies, then its volley if it declares one.
    ///
    /// ```
    /// let scene = volley_sim::parse_scene(
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
            state: State {
                tick: 0,
                next_id: 0,
                rng: SplitMix64(scene.seed),
                integrator: scene.integrator,
                forces: scene.forces.clone(),
                launcher: scene.launcher,
                force_evals: 0,
                bodies: Bodies::default(),
                carry: Vec3s::default(),
                tallies: Tallies::default(),
            },
            params: Params::of_scene(scene),
            scratch: Scratch::default(),
            carry_valid: false,
            halt: Halt::Running,
            threads: 1,
            kind: LoopKind::Bare,
            event_evals: 0,
            facts: ForceFacts::of(&scene.forces),
        };
        world.kind = LoopKind::of(&world.params.contacts);
        world.state.tallies.run = vec![0; world.params.contacts.events.run_slots()];
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
                let l = self.state.launcher;
                let speed = l.speed + volley.speed_spread * self.state.rng.next_signed();
                let el = l.elevation_deg + volley.angle_spread_deg * self.state.rng.next_signed();
                let az = l.azimuth_deg + volley.angle_spread_deg * self.state.rng.next_signed();
                self.spawn(&l.body_at(speed.max(0.0), el, az));
            }
        }
    }

    /// Adds a body at the end of the id order and returns its id.
    pub fn spawn(&mut self, spec: &BodySpec) -> BodyId {
        let id = BodyId(self.state.next_id);
        self.state.next_id += 1;
        // A world whose declared terms never read a launch keeps the canonical one (time 0,
        // no spin), so its keyframes leave the launch columns out.
        let launch = if self.params.declared.reads_launch() {
            crate::body::Launch {
                time: self.time(),
                mass: spec.mass,
                spin: spec.spin,
            }
        } else {
            crate::body::Launch {
                time: 0.0,
                mass: spec.mass,
                spin: DVec3::ZERO,
            }
        };
        self.state
            .bodies
            .push(id, spec.position, spec.velocity, spec.radius, launch);
        let i = self.state.bodies.len() - 1;
        self.state.bodies.energy_cap[i] = self.energy_cap_of(i);
        self.carry_valid = false;
        if self.scratch.due.len() == i {
            // The others' horizons stand; the new body is due at once.
            self.scratch.due.push();
        }
        let events = &self.params.contacts.events;
        if !events.is_empty() {
            self.scratch.fresh.push(id);
            let slots = events.body_slots();
            let per_body = &mut self.state.tallies.per_body;
            per_body.resize(per_body.len() + slots, 0);
        }
        id
    }

    /// Removes a body, keeping the others in order. Returns whether it existed.
    pub fn despawn(&mut self, id: BodyId) -> bool {
        match self.state.bodies.index_of(id) {
            Some(i) => {
                if self.scratch.due.len() == self.state.bodies.len() {
                    self.scratch.due.remove(i);
                }
                self.state.bodies.remove(i);
                let slots = self.params.contacts.events.body_slots();
                if slots > 0 {
                    self.state
                        .tallies
                        .per_body
                        .drain(i * slots..(i + 1) * slots);
                }
                self.carry_valid = false;
                true
            }
            None => false,
        }
    }

    /// Removes every body (ids keep counting).
    pub fn clear_bodies(&mut self) {
        self.state.bodies.clear();
        self.state.tallies.per_body.clear();
        self.carry_valid = false;
        self.scratch.due.clear();
    }

    /// The guard's energy bound for body `i`: start energy plus `(factor - 1)` times its scale.
    ///
    /// The scale is the sum of the magnitudes of the kinetic and each potential term at the
    /// start, so it does not vanish when the terms cancel (a circular orbit, a body at rest).
    pub(crate) fn energy_cap_of(&self, i: usize) -> f64 {
        use crate::forces::ForceModel;
        let (s, m) = (self.state.bodies.state(i), self.state.bodies.mass[i]);
        let v = self.state.bodies.velocity(i);
        let energy = self.state.forces.energy(s.p, v, m);
        let kinetic = 0.5 * m * v.length_squared();
        // Each term's energy alone minus the kinetic, as `(kinetic + x) - kinetic`: the bits
        // the scale had when it was computed from a copy of the forces with that term alone.
        let scale = crate::forces::ForceKind::ALL
            .into_iter()
            .filter(|k| self.state.forces.has(*k))
            .map(|k| {
                let only = kinetic + self.state.forces.potential(k, s.p, v, m).unwrap_or(0.0);
                (only - kinetic).abs()
            })
            .sum::<f64>()
            + kinetic;
        let floor = f64::MIN_POSITIVE.max(1e-12 * m);
        energy + (self.params.guard.energy_factor - 1.0) * scale.max(floor)
    }

    /// Resets every body's energy bound to its current state (after commands add energy).
    pub(crate) fn rebase_energy_caps(&mut self) {
        for i in 0..self.state.bodies.len() {
            self.state.bodies.energy_cap[i] = self.energy_cap_of(i);
        }
    }

    /// The bodies.
    #[inline]
    pub fn bodies(&self) -> &Bodies {
        &self.state.bodies
    }

    /// Ticks stepped since tick 0.
    #[inline]
    pub fn tick(&self) -> u64 {
        self.state.tick
    }

    /// The physics step h (s), exactly the clock's timestep in nanoseconds.
    #[inline]
    pub fn dt(&self) -> f64 {
        self.params.h
    }

    /// Sim time (s) of the current tick: `start_time + tick * h`, one multiplication, no sum.
    #[inline]
    pub fn time(&self) -> f64 {
        self.time_of(self.state.tick)
    }

    /// Sim time (s) of tick `tick`.
    #[inline]
    pub fn time_of(&self, tick: u64) -> f64 {
        self.params.start_time + tick as f64 * self.params.h
    }

    /// Integrator in use.
    #[inline]
    pub fn integrator(&self) -> Integrator {
        self.state.integrator
    }

    /// Active force terms.
    #[inline]
    pub fn forces(&self) -> &Forces {
        &self.state.forces
    }

    /// Contacts of the scene.
    #[inline]
    pub fn contacts(&self) -> &Contacts {
        &self.params.contacts
    }

    /// The scene the world was built from.
    #[inline]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The launcher used by `Fire` commands.
    #[inline]
    pub fn launcher(&self) -> &Launcher {
        &self.state.launcher
    }

    /// Events of the last tick, in body order.
    #[inline]
    pub fn events(&self) -> &[Event] {
        &self.scratch.events
    }

    /// Force evaluations since tick 0 (every body, stage and contact search included).
    #[inline]
    pub fn force_evals(&self) -> u64 {
        self.state.force_evals
    }

    /// Integrator steps per tick.
    #[inline]
    pub fn substeps(&self) -> u32 {
        self.params.substeps
    }

    /// The divergence that stopped the run, if any.
    #[inline]
    pub fn divergence(&self) -> Option<Divergence> {
        match self.halt {
            Halt::Diverged(d) => Some(d),
            _ => None,
        }
    }

    /// The declared event that stopped the run ([`EventStop::Run`]), if one did: the world
    /// then steps no further ([`World::step`] returns at once).
    #[inline]
    pub fn stopped(&self) -> Option<RunStop> {
        match self.halt {
            Halt::Stopped(s) => Some(s),
            _ => None,
        }
    }

    /// The scene's declared events.
    #[inline]
    pub fn declared_events(&self) -> &EventSet {
        &self.params.contacts.events
    }

    /// Force evaluations the declared events' search has spent since the world was built: the
    /// partial steps it took (none on Dormand-Prince's continuous extension). Not in
    /// [`World::force_evals`], which is the stepping's alone and the same with or without
    /// events.
    #[inline]
    pub fn event_evals(&self) -> u64 {
        self.event_evals
    }

    /// The world's random generator (part of the hashed state).
    #[inline]
    pub fn rng(&self) -> SplitMix64 {
        self.state.rng
    }

    /// Worker threads used for stepping (1 = on the caller's thread). Results are bit-identical
    /// for every thread count.
    #[inline]
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Sets the number of worker threads (at least 1).
    pub fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    /// Velocity of body `i` (m/s).
    #[inline]
    pub fn velocity(&self, i: usize) -> DVec3 {
        self.state.bodies.velocity(i)
    }

    /// Net force (N) on body `i` from the active terms, at its current state and time.
    pub fn force_on(&self, i: usize) -> DVec3 {
        use crate::forces::ForceModel;
        let w = self.state.bodies.mass_of(i);
        self.state
            .forces
            .force_at(self.time(), self.state.bodies.p.get(i), self.velocity(i), w)
    }

    /// The Magnus lift (N) on body `i` now, if a spun Mach drag is active.
    pub fn lift_on(&self, i: usize) -> Option<DVec3> {
        let d = self.state.forces.spun_drag()?;
        let b = &self.state.bodies;
        let (_, lift) = d.spun_parts(self.time(), b.p.get(i), self.velocity(i), b.mass_of(i));
        Some(lift)
    }

    /// The thrust (N) on body `i` now, if a motor is active.
    pub fn thrust_on(&self, i: usize) -> Option<DVec3> {
        let motor = self.state.forces.thrust.as_ref()?;
        let age = self.time() - self.state.bodies.launch_time[i];
        Some(motor.force(age, self.velocity(i)))
    }

    /// Mechanical energy (J) of body `i` under the active terms.
    pub fn energy_of(&self, i: usize) -> f64 {
        use crate::forces::ForceModel;
        let m = self.state.bodies.mass[i];
        self.state
            .forces
            .energy(self.state.bodies.p.get(i), self.velocity(i), m)
    }
}
