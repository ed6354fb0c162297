//! Volley's fixed-timestep world, recordings and measured draw inside Bevy.
//!
//! [`VolleyPlugin`] steps a [`volley_sim`] world one tick per run of Bevy's fixed schedule
//! (`FixedPostUpdate`, under `Time<Fixed>` set to the scene's timestep), so Bevy's accumulator
//! decides how many ticks a frame runs, as it does for every fixed-step system of the game. In
//! `PostUpdate`, before transforms propagate, it writes each body's [`Transform`] where
//! [`Draw`] places it at the frame's `Time<Fixed>` overstep: Volley's measured default
//! ([`DrawMode::Swept`]) unless the game chose another mode.
//!
//! - Bodies are entities with a [`VolleyBody`] component, spawned when the world gains a body
//!   (a scene's bodies at start, a `fire`, a `spawn`) and despawned when it loses one. The game
//!   adds its meshes to them (a query on `Added<VolleyBody>`).
//! - Every event a tick produces (impacts, rests, target hits and approaches, declared events)
//!   arrives once as a [`VolleyEvent`] message, with the body's entity.
//! - The game's input reaches the world as [`VolleyCommand`] messages (or [`Volley::push`]),
//!   applied at the next tick boundary as Volley's window and recordings apply them;
//!   [`VolleyKeys`] maps keys to `fire` and to an aim at the scene's first target.
//! - A run is recorded with Volley's [`Recorder`] ([`VolleyPlugin::recording`],
//!   [`Volley::finish_recording`]) and a recording replayed and verified tick by tick through
//!   the same schedule ([`VolleyPlugin::replay`]).
//!
//! The draw never changes the world: switching draw mode changes where bodies are drawn, never
//! a hash. Coordinates: Volley's world is z-up and f64, Bevy's y-up and f32; [`to_bevy`] turns
//! one into the other (a rotation, so handedness is kept) after taking off a render origin in
//! f64 ([`Volley::set_origin`]), so a scene far from its origin keeps its precision on screen.

use std::collections::BTreeMap;
use std::io::Cursor;

use bevy::app::{
    App, FixedPostUpdate, Plugin, PostUpdate, RunFixedMainLoop, RunFixedMainLoopSystems, Startup,
};
use bevy::ecs::message::{Message, MessageReader, MessageWriter};
use bevy::ecs::prelude::*;
use bevy::input::ButtonInput;
use bevy::input::keyboard::KeyCode;
use bevy::math::Vec3;
use bevy::time::{Fixed, Time};
use bevy::transform::TransformSystems;
use bevy::transform::components::Transform;
use glam::DVec3;
use volley_sim::{
    AimMode, AimRange, BodyId, Command, DEFAULT_POLICY, Draw, DrawMode, Event, FirstDivergence,
    LoopError, ObserverError, RecordOptions, RecordStats, Recorder, Recording, Replay, ReplayError,
    Scene, SimLoop, Stamped, TickObserver, World, solve_aim,
};

/// Steps a Volley scene (or replays a recording) in Bevy's fixed schedule and draws its bodies.
pub struct VolleyPlugin {
    source: Source,
    mode: DrawMode,
    record: Option<RecordOptions>,
}

enum Source {
    Scene(Box<Scene>),
    Replay { bytes: Vec<u8>, label: String },
}

impl VolleyPlugin {
    /// Steps `scene` from its start, drawn in Volley's measured default.
    pub fn new(scene: Scene) -> VolleyPlugin {
        VolleyPlugin {
            source: Source::Scene(Box::new(scene)),
            mode: volley_sim::DEFAULT_DRAW,
            record: None,
        }
    }

    /// Replays the recording in `bytes` (a `.vrec` file's contents; `label` names it in
    /// messages), verifying every stored hash and keyframe as it goes
    /// ([`Volley::replay_divergence`]). The recording's scene and commands drive the world;
    /// [`VolleyCommand`]s are refused.
    pub fn replay(bytes: Vec<u8>, label: impl Into<String>) -> VolleyPlugin {
        VolleyPlugin {
            source: Source::Replay {
                bytes,
                label: label.into(),
            },
            mode: volley_sim::DEFAULT_DRAW,
            record: None,
        }
    }

    /// Draws in `mode` from the first frame.
    pub fn draw_mode(mut self, mode: DrawMode) -> VolleyPlugin {
        self.mode = mode;
        self
    }

    /// Records the run with Volley's recorder under `options`, in memory, until
    /// [`Volley::finish_recording`] (a live run only).
    pub fn recording(mut self, options: RecordOptions) -> VolleyPlugin {
        self.record = Some(options);
        self
    }

    fn volley(&self) -> Result<Volley, String> {
        let run = match &self.source {
            Source::Scene(scene) => {
                let mut sim = SimLoop::new(World::new(scene));
                sim.clock.set_policy(DEFAULT_POLICY);
                Run::Live(Box::new(sim))
            }
            Source::Replay { bytes, label } => {
                let recording = Recording::from_reader(Cursor::new(bytes.clone()), label)
                    .map_err(|e| e.to_string())?;
                Run::Replay(Box::new(
                    Replay::start(recording, None).map_err(|e| e.to_string())?,
                ))
            }
        };
        let recorder = match (&self.record, &run) {
            (Some(options), Run::Live(sim)) => Some(
                Recorder::start(Vec::new(), &sim.world, options.clone())
                    .map_err(|e| format!("the recorder could not start: {e}"))?,
            ),
            _ => None,
        };
        let draw = Draw::new(run.world(), self.mode);
        Ok(Volley {
            run,
            draw,
            recorder,
            stopped: None,
            origin: DVec3::ZERO,
            entities: BTreeMap::new(),
            events: Vec::new(),
            stop_at: None,
            warned_timestep: false,
        })
    }
}

impl Plugin for VolleyPlugin {
    fn build(&self, app: &mut App) {
        let volley = match self.volley() {
            Ok(volley) => volley,
            // A plugin cannot fail its build: the world stays empty and says why.
            Err(why) => Volley::failed(why),
        };
        let timestep = volley.timestep();
        app.insert_resource(Time::<Fixed>::from_duration(timestep))
            .insert_resource(volley)
            .add_message::<VolleyEvent>()
            .add_message::<VolleyCommand>()
            .configure_sets(
                PostUpdate,
                VolleySystems::Draw.before(TransformSystems::Propagate),
            )
            .add_systems(
                RunFixedMainLoop,
                (keys_to_commands, queue_commands)
                    .chain()
                    .in_set(RunFixedMainLoopSystems::BeforeFixedMainLoop)
                    .in_set(VolleySystems::Input),
            )
            .add_systems(FixedPostUpdate, step.in_set(VolleySystems::Step))
            // The scene's bodies have entities from the start, before the first tick.
            .add_systems(Startup, spawn_bodies)
            .add_systems(PostUpdate, draw.in_set(VolleySystems::Draw));
    }
}

/// The plugin's systems, for ordering a game's own around them.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolleySystems {
    /// Before the fixed loop, every frame: [`VolleyKeys`] and [`VolleyCommand`] messages queued
    /// for the next tick boundary.
    Input,
    /// In `FixedPostUpdate`: one tick, its [`VolleyEvent`]s, the body entities spawned and
    /// despawned.
    Step,
    /// In `PostUpdate`, before transforms propagate: each body's [`Transform`] from the draw.
    Draw,
}

/// A body of the world: its entity carries this and a [`Transform`] the plugin writes.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct VolleyBody {
    /// The body's id in the world (stable for its life, never reused).
    pub id: BodyId,
    /// Its radius (m), to size a mesh by.
    pub radius: f64,
}

/// Something that happened to a body during a tick, once per event.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct VolleyEvent {
    /// The event as the world reported it (its tick, time, body and kind).
    pub event: Event,
    /// The body's entity, if it still had one when the event was written (a body despawned in
    /// the same tick has none).
    pub entity: Option<Entity>,
}

/// A command for the world, applied at the next tick boundary (`fire`, `spawn`, a launch,
/// ...), as Volley's window and recordings apply them.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct VolleyCommand(pub Command);

/// Keys that fire the scene's launcher and aim it, read before each frame's fixed loop. Insert
/// it to turn them on (the example does); a game with its own input writes
/// [`VolleyCommand`]s instead.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct VolleyKeys {
    /// Fires the launcher.
    pub fire: KeyCode,
    /// Aims the launcher at the scene's first target with Volley's aim solver (the low arc
    /// at the launcher's speed, as stepped by the scene's integrator and timestep).
    pub aim: KeyCode,
}

impl Default for VolleyKeys {
    /// Space fires, A aims: the keys of Volley's own window.
    fn default() -> VolleyKeys {
        VolleyKeys {
            fire: KeyCode::Space,
            aim: KeyCode::KeyA,
        }
    }
}

/// The world, its draw and what maps its bodies to entities.
#[derive(Resource)]
pub struct Volley {
    run: Run,
    draw: Draw,
    recorder: Option<Recorder<Vec<u8>>>,
    stopped: Option<String>,
    origin: DVec3,
    entities: BTreeMap<BodyId, Entity>,
    events: Vec<Event>,
    stop_at: Option<u64>,
    warned_timestep: bool,
}

enum Run {
    Live(Box<SimLoop>),
    Replay(Box<Replay<Cursor<Vec<u8>>>>),
    Failed(Box<World>),
}

impl Run {
    fn world(&self) -> &World {
        match self {
            Run::Live(sim) => &sim.world,
            Run::Replay(replay) => replay.world(),
            Run::Failed(world) => world,
        }
    }
}

impl Volley {
    fn failed(why: String) -> Volley {
        let scene = Scene::builder("failed", 1.0 / 60.0)
            .build()
            .expect("an empty scene at 60 Hz is valid");
        let world = World::new(&scene);
        Volley {
            draw: Draw::measured(&world),
            run: Run::Failed(Box::new(world)),
            recorder: None,
            stopped: Some(why),
            origin: DVec3::ZERO,
            entities: BTreeMap::new(),
            events: Vec::new(),
            stop_at: None,
            warned_timestep: false,
        }
    }

    /// The world as of its last tick.
    pub fn world(&self) -> &World {
        self.run.world()
    }

    /// The scene's timestep in whole nanoseconds: `Time<Fixed>`'s.
    pub fn timestep(&self) -> std::time::Duration {
        self.world().scene().timestep()
    }

    /// Why the world stopped stepping (a divergence, a command that failed, a replay that
    /// parted from its recording, a plugin that could not start), if it did.
    pub fn stopped(&self) -> Option<&str> {
        self.stopped.as_deref()
    }

    /// Queues `command` for the next tick boundary. Refused (false) while replaying: a replay's
    /// commands are the recording's.
    pub fn push(&mut self, command: Command) -> bool {
        match &mut self.run {
            Run::Live(sim) => {
                sim.push(command);
                true
            }
            Run::Replay(_) | Run::Failed(_) => false,
        }
    }

    /// Runs no tick past `tick` (a test's or a cut-scene's end): the fixed schedule goes on,
    /// the world waits.
    pub fn stop_at(&mut self, tick: Option<u64>) {
        self.stop_at = tick;
    }

    /// The draw mode.
    pub fn draw_mode(&self) -> DrawMode {
        self.draw.mode()
    }

    /// Draws in `mode` from the next frame. The world is not touched.
    pub fn set_draw_mode(&mut self, mode: DrawMode) {
        self.draw.set_mode(mode);
    }

    /// The draw, for its lead and [`Draw::set_at_targets`].
    pub fn draw(&self) -> &Draw {
        &self.draw
    }

    /// The draw, mutably ([`Draw::set_at_targets`], [`Draw::set_time_scale`]).
    pub fn draw_mut(&mut self) -> &mut Draw {
        &mut self.draw
    }

    /// The render origin: world positions are drawn relative to it ([`to_bevy`]).
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Moves the render origin (in f64, before positions become f32).
    pub fn set_origin(&mut self, origin: DVec3) {
        self.origin = origin;
    }

    /// The entity of body `id`, while it has one.
    pub fn entity(&self, id: BodyId) -> Option<Entity> {
        self.entities.get(&id).copied()
    }

    /// The replay's first divergence from its recording, as Volley's replay names it (tick,
    /// body, field: [`FirstDivergence::report`]), if replaying and it parted.
    pub fn replay_divergence(&self) -> Option<&FirstDivergence> {
        match &self.run {
            Run::Replay(replay) => replay.first_divergence(),
            _ => None,
        }
    }

    /// How many stored hashes the replay has checked so far (0 when not replaying).
    pub fn replay_hashes_checked(&self) -> u64 {
        match &self.run {
            Run::Replay(replay) => replay.hashes_checked(),
            _ => 0,
        }
    }

    /// Ends the recording at the current tick and gives its bytes (a `.vrec` file) and
    /// statistics; `None` when the plugin was not recording or already finished. The run goes
    /// on unrecorded.
    pub fn finish_recording(&mut self) -> Option<std::io::Result<(Vec<u8>, RecordStats)>> {
        let recorder = self.recorder.take()?;
        Some(recorder.finish(self.run.world()))
    }

    /// One tick, or none if the world is stopped or at its stop tick.
    fn tick(&mut self) {
        if self.stopped.is_some() || self.stop_at.is_some_and(|t| self.world().tick() >= t) {
            return;
        }
        let mut sink = Sink {
            draw: &mut self.draw,
            recorder: self.recorder.as_mut(),
            events: &mut self.events,
        };
        let failed = match &mut self.run {
            Run::Live(sim) => {
                // Exactly one timestep: the loop's clock grants exactly one tick.
                let step = sim.clock.timestep();
                match sim.frame(step, &mut sink) {
                    Ok(ticks) if ticks.steps == 1 => None,
                    Ok(ticks) => Some(format!(
                        "a fixed step ran {} ticks of the world, not 1",
                        ticks.steps
                    )),
                    Err(e) => Some(loop_error(&e)),
                }
            }
            Run::Replay(replay) => {
                if replay.is_done() {
                    return;
                }
                let next = replay.world().tick() + 1;
                match replay.run_to(next, &mut sink) {
                    Ok(()) => replay.first_divergence().map(|d| {
                        format!(
                            "the replay parted from its recording: {}",
                            d.report(Some(5))
                        )
                    }),
                    Err(e) => Some(replay_error(&e)),
                }
            }
            Run::Failed(_) => None,
        };
        if failed.is_some() {
            self.stopped = failed;
        }
    }

    /// The launch that hits the scene's first target from the launcher, at its speed, as the
    /// scene steps it (Volley's aim solver, [`solve_aim`], on the lower arc): a `set_launch`
    /// command to push, or why there is none.
    pub fn aim_command(&self) -> Result<Command, String> {
        let world = self.world();
        let scene = world.scene();
        let target = *scene
            .targets()
            .first()
            .ok_or("the scene has no target to aim at")?;
        let launcher = world.launcher();
        let mut range = AimRange::new(scene, target);
        range.from = launcher.position;
        let shots = solve_aim(&range, AimMode::Speed(launcher.speed)).map_err(|e| e.to_string())?;
        let shot = shots
            .iter()
            .min_by(|a, b| a.elevation_deg.total_cmp(&b.elevation_deg))
            .ok_or("no launch at this speed reaches the target")?;
        Ok(Command::SetLaunch {
            speed: None,
            elevation_deg: Some(shot.elevation_deg),
            azimuth_deg: Some(shot.azimuth_deg),
            position: None,
        })
    }
}

fn loop_error(e: &LoopError) -> String {
    format!("the world stopped: {e}")
}

fn replay_error(e: &ReplayError) -> String {
    format!("the replay stopped: {e}")
}

/// What the loop's ticks are shown to: the draw (the state before the frame's last tick), the
/// recorder, and the events of each tick.
struct Sink<'a> {
    draw: &'a mut Draw,
    recorder: Option<&'a mut Recorder<Vec<u8>>>,
    events: &'a mut Vec<Event>,
}

impl TickObserver for Sink<'_> {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        match self.recorder.as_mut() {
            Some(r) => r.on_command(world, stamped),
            None => Ok(()),
        }
    }

    fn before_last_tick(&mut self, world: &World) {
        self.draw.before_last_tick(world);
        if let Some(r) = self.recorder.as_mut() {
            r.before_last_tick(world);
        }
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.events.extend_from_slice(world.events());
        match self.recorder.as_mut() {
            Some(r) => r.after_tick(world),
            None => Ok(()),
        }
    }

    fn on_divergence(&mut self, world: &World, divergence: &volley_sim::Divergence) {
        if let Some(r) = self.recorder.as_mut() {
            r.on_divergence(world, divergence);
        }
    }
}

/// Volley's z-up world position `p`, less the render `origin` (in f64), as Bevy's y-up f32:
/// `(x, y, z)` becomes `(x, z, -y)`, a quarter turn about x.
pub fn to_bevy(p: DVec3, origin: DVec3) -> Vec3 {
    let d = p - origin;
    Vec3::new(d.x as f32, d.z as f32, -d.y as f32)
}

/// [`to_bevy`]'s inverse: a Bevy position back in Volley's world, in f64.
pub fn from_bevy(p: Vec3, origin: DVec3) -> DVec3 {
    origin + DVec3::new(f64::from(p.x), -f64::from(p.z), f64::from(p.y))
}

/// [`VolleyKeys`] to commands: fire and aim.
fn keys_to_commands(
    keys: Option<Res<VolleyKeys>>,
    input: Option<Res<ButtonInput<KeyCode>>>,
    mut volley: ResMut<Volley>,
) {
    let (Some(keys), Some(input)) = (keys, input) else {
        return;
    };
    if input.just_pressed(keys.aim) {
        match volley.aim_command() {
            Ok(command) => {
                volley.push(command);
            }
            Err(why) => log::warn!("volley: no aim: {why}"),
        }
    }
    if input.just_pressed(keys.fire) {
        volley.push(Command::Fire);
    }
}

/// [`VolleyCommand`] messages to the loop's queue, every frame (a frame that runs no fixed step
/// still queues them, for the next tick boundary).
fn queue_commands(mut commands: MessageReader<VolleyCommand>, mut volley: ResMut<Volley>) {
    for VolleyCommand(command) in commands.read() {
        if !volley.push(*command) {
            log::warn!("volley: `{command}` refused: a replay's commands are its recording's");
        }
    }
}

/// One tick of the world, the entities of the bodies it gained or lost, and its events as
/// messages (after the entities, so a body fired in the tick has its entity in its events).
fn step(
    mut volley: ResMut<Volley>,
    fixed: Res<Time<Fixed>>,
    mut events: MessageWriter<VolleyEvent>,
    mut commands: Commands,
) {
    let was = volley.stopped.is_some();
    if fixed.timestep() != volley.timestep() && !volley.warned_timestep {
        // Each fixed run is still one tick of the scene's dt (the world stays the world), but
        // it no longer keeps time with the wall clock.
        log::warn!(
            "volley: Time<Fixed> runs every {:?}, the scene's timestep is {:?}: the world runs \
             at the wrong speed",
            fixed.timestep(),
            volley.timestep()
        );
        volley.warned_timestep = true;
    }
    volley.tick();
    if !was && let Some(why) = &volley.stopped {
        log::error!("volley: {why}");
    }
    let volley = &mut *volley;
    volley.sync_entities(&mut commands);
    for event in volley.events.drain(..) {
        events.write(VolleyEvent {
            event,
            entity: volley.entities.get(&event.body).copied(),
        });
    }
}

/// The scene's bodies' entities, before the first tick.
fn spawn_bodies(mut volley: ResMut<Volley>, mut commands: Commands) {
    volley.sync_entities(&mut commands);
}

impl Volley {
    /// An entity for each body the world gained, none for each it lost (ids are sorted in
    /// both, so one merge pass pairs them).
    fn sync_entities(&mut self, commands: &mut Commands) {
        let bodies = self.run.world().bodies();
        let ids = bodies.ids();
        let gone: Vec<BodyId> = self
            .entities
            .keys()
            .filter(|id| ids.binary_search(id).is_err())
            .copied()
            .collect();
        for id in gone {
            if let Some(entity) = self.entities.remove(&id) {
                commands.entity(entity).despawn();
            }
        }
        for (i, &id) in ids.iter().enumerate() {
            if self.entities.contains_key(&id) {
                continue;
            }
            let body = VolleyBody {
                id,
                radius: bodies.radii()[i],
            };
            // Placed at its current position until the frame's draw moves it.
            let at = to_bevy(bodies.positions().get(i), self.origin);
            let entity = commands.spawn((body, Transform::from_translation(at))).id();
            self.entities.insert(id, entity);
        }
    }
}

/// Each body's transform where the draw places it this frame.
fn draw(
    mut volley: ResMut<Volley>,
    fixed: Res<Time<Fixed>>,
    time: Res<Time>,
    mut bodies: Query<&mut Transform, With<VolleyBody>>,
) {
    let volley = &mut *volley;
    volley.draw.frame(time.delta());
    let alpha = fixed.overstep_fraction_f64();
    let world = volley.run.world();
    let ids = world.bodies().ids();
    let origin = volley.origin;
    let entities = &volley.entities;
    volley.draw.positions(world, alpha, |i, p| {
        let Some(entity) = entities.get(&ids[i]) else {
            return;
        };
        if let Ok(mut transform) = bodies.get_mut(*entity) {
            transform.translation = to_bevy(p, origin);
        }
    });
}

// The README's example, compiled as a doc test (not run: it opens a window) so it cannot go
// stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
