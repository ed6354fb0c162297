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
//!   in the [`World`], and parallel work is combined in a fixed order.
//!
//! ## What a game uses
//! Everything a game names is at this root, one path per type:
//! - **A world and its scene**: [`World`] (its [`Bodies`], [`BodyId`], [`BodyState`]), a
//!   [`Scene`] from a file ([`load_scene`], [`parse_scene`]), a bundled one ([`bundled_scene`])
//!   or code ([`Scene::builder`]); its parts [`BodySpec`], [`Launcher`], [`Volley`], [`Guard`];
//!   forces ([`Forces`], [`ForceKind`], [`Spring`], [`PointMass`], [`MachDrag`] with its
//!   [`DragTable`], [`Atmosphere`] and [`SpinLift`], a motor's [`Thrust`], a game's own
//!   [`ForceTerm`] with [`register_force_term`]); contacts ([`Ground`],
//!   [`Wall`], [`Target`], [`Detection`]), level surfaces ([`MeshSurface`] of a
//!   [`MeshGeometry`], [`HeightfieldSurface`] of a [`HeightGrid`], placed by a [`Transform`],
//!   read from a [`LevelSource`], refused with a [`LevelError`]) and what they report
//!   ([`Event`], [`EventKind`], [`Surface`]).
//! - **The loop**: [`SimLoop`] and its [`TickObserver`]s, the [`FixedClock`] with its
//!   [`LoopPolicy`], frame sources ([`RealClock`], [`VirtualClock`]), and where to draw between
//!   ticks ([`DrawMode`]; Volley's measured defaults [`DEFAULT_POLICY`] and [`DEFAULT_DRAW`]).
//! - **Input**: [`Command`]s, applied at tick boundaries, and command scripts
//!   ([`parse_script`]).
//! - **Checking a run**: [`state_hash`], recordings ([`Recorder`], [`Recording`]) and their
//!   [`Replay`], the rewinding [`Timeline`].
//! - **Aim**: [`solve_aim`], launches that hit in the simulation as stepped, and a rifle's
//!   zero with its [`holdover`] table.
//!
//! In a browser (wasm32 with wasm-bindgen), turn on the `web` feature: the few wall-clock reads
//! ([`RealClock`], the recorder's flush timer) then use the browser's clock. Without it the
//! crate's wasm32 build imports nothing from its host.
//!
//! docs/library.md walks through them. The modules behind these names are private. Volley's own
//! window, CLI, tests, benches and fuzz targets reach them through one hidden module,
//! `volley_sim::internals`: the per-body columns, vector widths, the step's chunking, the study,
//! the stability pre-check, the loop lab's sweep and their performance knobs, which are not part
//! of the surface a game should build on. Their layers are in docs/contributing.md.
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

// 5. The one loop every mode runs; `TickObserver` is its only seam.
mod sim_loop;

// 6. What runs on the loop: the state table, recordings and replays, the study, the stability
//    pre-check, firing solutions solved on the stepped trajectory, the in-memory history for
//    rewinding.
mod firing;
mod pacing;
mod replay;
mod stability;
mod study;
mod table;
mod timeline;

/// Volley's own internals, for its window, CLI, tests, benches and fuzz targets: every module
/// behind the names above, with the per-body columns, vector widths, the step's chunking, the
/// study, the stability pre-check and the loop lab's sweep, and their performance knobs.
///
/// Not part of the surface a game builds on: paths here change without notice. A game that
/// finds itself reaching in for something is telling us the root lacks it.
#[doc(hidden)]
pub mod internals {
    pub mod body {
        //! Re-exported from the private module of that name.
        pub use crate::body::*;
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
    pub mod firing {
        //! Re-exported from the private module of that name.
        pub use crate::firing::*;
    }
    pub mod pacing {
        //! Re-exported from the private module of that name.
        pub use crate::pacing::*;
    }
    pub mod replay {
        //! Re-exported from the private module of that name.
        pub use crate::replay::*;
    }
    pub mod stability {
        //! Re-exported from the private module of that name.
        pub use crate::stability::*;
    }
    pub mod study {
        //! Re-exported from the private module of that name.
        pub use crate::study::*;
    }
    pub mod table {
        //! Re-exported from the private module of that name.
        pub use crate::table::*;
    }
    pub mod timeline {
        //! Re-exported from the private module of that name.
        pub use crate::timeline::*;
    }
}

// The game-facing surface (the crate doc lists it by purpose).
pub use atmosphere::Atmosphere;
pub use body::{Bodies, BodyId, BodyState};
pub use clock::{
    ClockError, FixedClock, FrameSource, FrameTicks, LoopPolicy, RealClock, VirtualClock,
};
pub use command::{Command, CommandError, CommandParseError, ScriptError, Stamped, parse_script};
pub use contact::{
    Aabb, Detection, Event, EventKind, Ground, HeightGrid, HeightfieldSurface, LevelSource,
    MeshGeometry, MeshSurface, Surface, Target, Transform, Wall,
};
pub use drag::DragTable;
pub use firing::{
    FiringError, Holdover, Mode as AimMode, Range as AimRange, Shot, holdover, solve as solve_aim,
};
pub use forces::{
    ForceKind, ForceTerm, Forces, MachDrag, PointMass, SpinLift, Spring, Thrust,
    register as register_force_term,
};
pub use hash::state_hash;
pub use integrate::Integrator;
pub use pacing::{DEFAULT_DRAW, DEFAULT_POLICY, DrawMode};
pub use replay::{FirstDivergence, RecordOptions, Recorder, Recording, Replay};
pub use scene::{
    BodySpec, Guard, Launcher, LevelError, Scene, SceneBuilder, SceneError, Volley,
    bundled as bundled_scene, load as load_scene, parse as parse_scene,
};
pub use sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
pub use timeline::Timeline;
pub use world::{Divergence, World};

// docs/library.md's examples, compiled and run as doc tests so the page cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/library.md")]
pub struct LibraryDoc;
