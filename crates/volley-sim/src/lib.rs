//! # volley-sim
//!
//! A real-time game-loop sandbox that makes the numerical side of game physics visible and
//! measurable: which integrator, at which timestep, buys how much accuracy for how much time,
//! and where each one breaks.
//!
//! ## Conventions
//! - SI units throughout: metres, seconds, kilograms, newtons. Angles in scene files and on the
//!   command line are degrees; elevation is measured up from the horizontal, azimuth from +x
//!   towards +y.
//! - Right-handed, **z up**. Gravity is usually `(0, 0, -9.81)`.
//! - Physics in `f64` ([`glam::DVec3`]); rendering converts to `f32` at the last moment.
//! - A body's state is the seed's `S = <mV, p>`: momentum and position.
//! - Time is an integer tick count: the timestep is a whole number of nanoseconds, the physics
//!   step `h` is exactly that, and the time of tick `n` is `start_time + n * h`, one
//!   multiplication, never a running float sum.
//! - Determinism: no hash-map iteration in the simulation, no wall clock inside a tick, no
//!   `mul_add`, transcendental functions from the `libm` crate, the only random generator lives
//!   in the [`World`], and parallel work is combined in a fixed order. A game's own code keeps
//!   them too, or its rollback parts from itself: the [`SyncTest`] checks that.
//!
//! ## What a game uses
//! Everything a game names is at this root, one path per type, and the root is closed: every
//! type a root item's signature or public field names is exported here too (the crate denies
//! `unnameable_types`, so a leak fails its build).
//! - **A world and its scene**: [`World`] (its [`Bodies`], [`BodyId`], [`BodyState`], its
//!   [`State`] for rollback with [`World::restore`]), a [`Scene`] from a file ([`load_scene`],
//!   [`parse_scene`], with the game's own terms [`load_scene_with`], [`parse_scene_with`]), a
//!   bundled one ([`bundled_scene`]) or code ([`Scene::builder`]), changed only through
//!   [`Scene::edit`], which checks it again; its parts [`BodySpec`], [`Launcher`], [`Volley`],
//!   [`Guard`]; forces ([`Forces`], [`ForceKind`], [`Spring`], [`PointMass`], [`MachDrag`] with
//!   its [`DragCurve`], [`DragSize`], [`AirModel`], [`Wind`] and [`SpinLift`], a motor's
//!   [`Thrust`], the game's own [`ForceTerm`]s as values in [`ForceTerms`], given a
//!   [`ForceInput`]); contacts ([`Ground`], [`Wall`], [`Target`], [`Detection`]), level
//!   surfaces ([`MeshSurface`] of a [`MeshGeometry`], [`HeightfieldSurface`] of a
//!   [`HeightGrid`], placed by a [`Transform`], read from a [`LevelSource`], refused with a
//!   [`LevelError`]) and what they report ([`Event`], [`EventKind`], [`Surface`]); declared
//!   events ([`EventSpec`]: an [`EventCondition`], an [`EventDirection`], an [`EventStop`];
//!   the scene's [`EventSet`]), found on every body's own path with their exact time and
//!   state, the run they stop ([`RunStop`]) and their counts ([`Tallies`]).
//! - **The loop and the draw**: [`SimLoop`] and its [`TickObserver`]s, the [`FixedClock`] with
//!   its [`LoopPolicy`], frame sources ([`RealClock`], [`VirtualClock`]), and where to draw
//!   between ticks in one call, [`Draw`] (its [`DrawMode`]s; Volley's measured defaults
//!   [`DEFAULT_POLICY`] and [`DEFAULT_DRAW`]).
//! - **Input**: [`Command`]s, applied at tick boundaries, and command scripts
//!   ([`parse_script`]).
//! - **Checking a run**: [`state_hash`], recordings ([`Recorder`], [`Recording`]) and their
//!   [`Replay`], the rewinding [`Timeline`], and determinism under rollback: the [`SyncTest`]
//!   (every tick re-run from K ticks back; a [`SyncError`] names where runs part, a
//!   [`SyncMismatch`] with its [`TickStage`], [`StageHashes`] and [`FieldDiff`]s).
//! - **Aim**: [`solve_aim`], launches that hit in the simulation as stepped, and a rifle's
//!   zero with its [`holdover`] table.
//!
//! In a browser (wasm32 with wasm-bindgen), turn on the `web` feature: the few wall-clock reads
//! ([`RealClock`], the recorder's flush timer) then use the browser's clock. Without it the
//! crate's wasm32 build imports nothing from its host.
//!
//! docs/library.md walks through them. The modules behind these names are private. Volley's own
//! window, CLI, lab, tests, benches and fuzz targets reach them through one module that exists
//! only with the `internals` feature, `volley_sim::internals`: the per-body columns, vector
//! widths, the step's chunking, the recording format's parts and their performance knobs,
//! which are not part of the surface a game should build on. Their layers are in
//! docs/contributing.md. The measuring lab (the study, the stability pre-check, the loop lab's
//! sweeps, the state table) is its own crate, `volley-lab`, which a game does not compile.
//!
//! ```
//! use volley_sim::{SimLoop, VirtualClock, World, bundled_scene};
//!
//! let scene = bundled_scene("seed")?;
//! let mut sim = SimLoop::new(World::new(&scene));
//! sim.run_until(27, &mut VirtualClock::display(144.0), &mut ())?;
//! assert_eq!(sim.world.tick(), 27);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// The closed root: with the `internals` feature off (a game's build), a type that a root
// item's signature or public field names must itself be at the root; the build fails naming it.
#![deny(unnameable_types)]
// Without `internals`, what only that module re-exports (for Volley's own tools) looks unused.
#![cfg_attr(not(feature = "internals"), allow(unused_imports, dead_code))]

// The layers, bottom up (the crate doc above says what each is for). A module imports only
// from its own layer or the ones below it.

// 1. Plain data with no dependency inside the crate: ids, per-body state and columns; the
//    world's one seeded generator; CPU-feature dispatch for the per-body loops; the wall
//    clock's `Instant` (std's, or the browser's with the `web` feature).
mod body;
mod instant;
mod rng;
mod simd;

// 2. Physics, each on the ones before it: the standard atmosphere, drag against Mach, the
//    declared force terms (only those are evaluated); closed forms, launch solutions, times of impact; the integrators; ground, walls, targets.
mod atmosphere;
mod drag;
mod forces;

mod exact;

mod integrate;

mod contact;

// 3. What a run is made of: the validated scene; the world (state, parameters, scratch); one
//    tick as named stages.
mod scene;

mod world;

mod step;

// 4. Around a tick: commands applied at tick boundaries, the canonical state hash, the
//    fixed-timestep clock.
mod clock;
mod command;
mod hash;

// 5. The one loop every mode runs; `TickObserver` is its only seam. Where to draw between its
//    ticks: the draw modes, the measured default, and the one-call `Draw` (an observer).
mod sim_loop;

mod draw;

// 6. What runs on the loop: recordings and replays, firing solutions solved on the stepped
//    trajectory, the in-memory history for rewinding. (The lab, the study, the stability
//    pre-check, the pacing sweeps and the state table, is its own crate, volley-lab.)
mod firing;
mod replay;
mod timeline;

// 7. Checking a game's determinism under rollback: the sync test re-runs every tick from K
//    ticks back and names the tick, body, field and stage where the runs part (on the loop's
//    world, the step's stages and the replay's field diff).
mod synctest;

/// Volley's own internals, for its window, CLI, lab, tests, benches and fuzz targets (with the
/// `internals` feature only): every module behind the names above, with the per-body columns,
/// vector widths, the step's chunking, the recording format's parts, and their performance
/// knobs.
///
/// Not part of the surface a game builds on: paths here change without notice. A game that
/// finds itself reaching in for something is telling us the root lacks it.
#[doc(hidden)]
#[cfg(feature = "internals")]
pub mod internals {
    pub mod body {
        //! Re-exported from the private module of that name.
        pub use crate::body::*;
    }
    pub mod instant {
        //! Re-exported from the private module of that name.
        pub use crate::instant::*;
    }
    pub mod rng {
        //! Re-exported from the private module of that name.
        pub use crate::rng::*;
    }
    pub mod simd {
        //! Re-exported from the private module of that name.
        pub use crate::simd::*;
    }
    pub mod atmosphere {
        //! Re-exported from the private module of that name.
        pub use crate::atmosphere::*;
    }
    pub mod drag {
        //! Re-exported from the private module of that name.
        pub use crate::drag::*;
    }
    pub mod forces {
        //! Re-exported from the private module of that name.
        pub use crate::forces::*;
    }
    pub mod exact {
        //! Re-exported from the private module of that name.
        pub use crate::exact::*;
    }
    pub mod integrate {
        //! Re-exported from the private module of that name.
        pub use crate::integrate::*;
    }
    pub mod contact {
        //! Re-exported from the private module of that name.
        pub use crate::contact::*;
    }
    pub mod scene {
        //! Re-exported from the private module of that name.
        pub use crate::scene::*;
    }
    pub mod world {
        //! Re-exported from the private module of that name.
        pub use crate::world::*;
    }
    pub mod step {
        //! Re-exported from the private module of that name.
        pub use crate::step::*;
    }
    pub mod clock {
        //! Re-exported from the private module of that name.
        pub use crate::clock::*;
    }
    pub mod command {
        //! Re-exported from the private module of that name.
        pub use crate::command::*;
    }
    pub mod hash {
        //! Re-exported from the private module of that name.
        pub use crate::hash::*;
    }
    pub mod sim_loop {
        //! Re-exported from the private module of that name.
        pub use crate::sim_loop::*;
    }
    pub mod draw {
        //! Re-exported from the private module of that name.
        pub use crate::draw::*;
    }
    pub mod firing {
        //! Re-exported from the private module of that name.
        pub use crate::firing::*;
    }
    pub mod replay {
        //! Re-exported from the private module of that name.
        pub use crate::replay::*;
    }
    pub mod timeline {
        //! Re-exported from the private module of that name.
        pub use crate::timeline::*;
    }
    pub mod synctest {
        //! Re-exported from the private module of that name.
        pub use crate::synctest::*;
    }
}

// The game-facing surface (the crate doc lists it by purpose). Closed: every type a root item's
// signature or public field names is exported here too (`unnameable_types` is denied above).
pub use atmosphere::{Air, AirColumn, Atmosphere};
pub use body::{Bodies, BodyId, BodyState, Launch, Vec3s};
pub use clock::{
    ClockError, FixedClock, FrameSource, FrameTicks, LoopPolicy, RealClock, VirtualClock,
};
pub use command::{
    Command, CommandError, CommandParseError, MAX_SCRIPT_COMMANDS, ScriptError, ScriptProblem,
    Stamped, parse_script,
};
pub use contact::{
    Aabb, Contacts, Detection, Event, EventCondition, EventDirection, EventKind, EventSet,
    EventSpec, EventStop, Ground, HeightGrid, HeightfieldSurface, LevelSource, MeshGeometry,
    MeshSurface, Surface, Target, Transform, Wall,
};
pub use drag::{DragTable, DragTableError, Interpolation};
pub use draw::{
    AtTargets, DEFAULT_DRAW, DEFAULT_POLICY, Draw, DrawAt, DrawMode, LEAD_WINDOW, Lead,
    swept_position, swept_position_at,
};
pub use exact::{AimError, Arc as LaunchArc};
pub use firing::{
    Blocked as ShotBlocked, FiringError, Holdover, HoldoverRow, Mode as AimMode, Range as AimRange,
    RangeRow, RangeTable, Shot, ShotKind, Textbook as TextbookAim, holdover, range_table,
    solve as solve_aim,
};
pub use forces::{
    AirModel, CustomForce, CustomForceError, DragCurve, DragSize, ForceInput, ForceKind, ForceTerm,
    ForceTerms, Forces, LiftModel, MachDrag, PointMass, Reads, SpinDecay, SpinLift, Spring, Thrust,
    ThrustCurve, ThrustCurveError, ThrustDirection, Wind,
};
pub use hash::state_hash;
pub use integrate::{DEFAULT_TOLERANCE, Integrator, IntegratorInfo};
pub use replay::{
    ErrorKind as ReplayErrorKind, FieldDiff, FirstDivergence, FlushPolicy,
    Footer as RecordingFooter, Header as RecordingHeader, KeyframeEntry, Mismatch, RecordOptions,
    RecordStats, Recorder, Recording, Replay, ReplayError, Value as FieldValue, Verifier,
    format::Build as BuildInfo, format::LevelHash,
};
pub use rng::SplitMix64;
pub use scene::{
    BodySpec, CompareLane, Guard, IntegratorError, InvalidValue, Launcher, LevelError, MAX_BODIES,
    MAX_COMPARE_LANES, MAX_EVENTS, MAX_SUBSTEPS, MAX_TICK_WORK, MAX_VOLLEY, MIN_TOLERANCE, Scene,
    SceneBuilder, SceneError, ValueProblem, Volley, bundled as bundled_scene, load as load_scene,
    load_with as load_scene_with, parse as parse_scene, parse_with as parse_scene_with,
};
pub use sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
pub use synctest::{
    FoundBy as SyncFoundBy, MAX_CHECK_DISTANCE, StageHashes, SyncError, SyncMismatch, SyncTest,
    SyncTestError, TickStage,
};
pub use timeline::{SeekError, Timeline};
pub use world::{
    Divergence, DivergenceCause, MAX_COUNT, Params as WorldParams, RestoreError, RunStop, State,
    Tallies, World,
};

// docs/library.md's examples, compiled and run as doc tests so the page cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/library.md")]
pub struct LibraryDoc;
