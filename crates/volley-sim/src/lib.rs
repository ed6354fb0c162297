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
//! ## Layers
//! Bottom up, with no import from a lower layer to a higher one: [`body`], [`rng`], [`simd`] ->
//! [`forces`] -> [`exact`] -> [`integrate`] -> [`contact`] -> [`scene`] -> [`world`] -> [`step`]
//! -> [`command`], [`hash`], [`clock`] -> [`sim_loop`] -> [`table`], [`replay`], [`study`],
//! [`stability`], [`firing`], [`timeline`]. Above this crate, in the `volley` package: the renderer and the window, then
//! the CLI. Nothing here depends on a GPU, window, plotting or command-line crate.
//!
//! ## The path through `src/`
//! [`scene`] file -> [`World`] ([`world`]) -> [`clock`] decides the ticks of a frame ->
//! [`sim_loop`] applies [`command`]s and calls [`World::step`] ([`step`]: [`forces`],
//! [`integrate`], [`contact`]) -> [`hash`] -> an observer: the [`table`] writer, a recorder, a
//! renderer, or nothing. [`exact`] holds the closed forms everything is measured against.
//!
//! ```
//! use volley_sim::{scene, SimLoop, World};
//! use volley_sim::clock::VirtualClock;
//!
//! let scene = scene::bundled("seed")?;
//! let mut sim = SimLoop::new(World::new(&scene));
//! sim.run_until(27, &mut VirtualClock::display(144.0), &mut ())?;
//! assert_eq!(sim.world.tick(), 27);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// The layers, bottom up (the crate doc above says what each is for). A module imports only
// from its own layer or the ones below it.

// 1. Plain data with no dependency inside the crate: ids, per-body state and columns; the
//    world's one seeded generator; CPU-feature dispatch for the per-body loops.
pub mod body;
pub mod rng;
pub mod simd;

// 2. Physics, each on the ones before it: declared force terms (only those are evaluated);
//    closed forms, launch solutions, times of impact; the integrators; ground, walls, targets.
pub mod forces;

pub mod exact;

pub mod integrate;

pub mod contact;

// 3. What a run is made of: the validated scene; the world (state, parameters, scratch); one
//    tick as named stages.
pub mod scene;

pub mod world;

pub mod step;

// 4. Around a tick: commands applied at tick boundaries, the canonical state hash, the
//    fixed-timestep clock.
pub mod clock;
pub mod command;
pub mod hash;

// 5. The one loop every mode runs; `TickObserver` is its only seam.
pub mod sim_loop;

// 6. What runs on the loop: the state table, recordings and replays, the study, the stability
//    pre-check, firing solutions solved on the stepped trajectory, the in-memory history for
//    rewinding.
pub mod firing;
pub mod pacing;
pub mod replay;
pub mod stability;
pub mod study;
pub mod table;
pub mod timeline;

pub use clock::{FixedClock, FrameSource, FrameTicks, RealClock, VirtualClock};
pub use command::{Command, Stamped};
pub use contact::{Event, EventKind};
pub use forces::{ForceKind, Forces};
pub use integrate::Integrator;
pub use scene::{Scene, SceneError};
pub use sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
pub use world::{BodyId, Divergence, World};

// docs/library.md's examples, compiled and run as doc tests so the page cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/library.md")]
pub struct LibraryDoc;
