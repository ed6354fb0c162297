//! # Volley
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
//! ## The path through `src/`
//! [`scene`] file -> [`World`] ([`world`]) -> [`clock`] decides the ticks of a frame ->
//! [`sim_loop`] applies [`command`]s and calls [`World::step`] ([`step`]: [`forces`],
//! [`integrate`], [`contact`]) -> [`hash`] -> an observer: the [`table`] writer, a recorder, a
//! renderer, or nothing. [`exact`] holds the closed forms everything is measured against.
//!
//! ```
//! use volley::{scene, SimLoop, World};
//! use volley::clock::VirtualClock;
//!
//! let scene = scene::load(std::path::Path::new("assets/scenes/seed.ron")).unwrap();
//! let mut sim = SimLoop::new(World::new(&scene));
//! sim.run_until(27, &mut VirtualClock::display(144.0), &mut ()).unwrap();
//! assert_eq!(sim.world.tick(), 27);
//! ```

pub mod app;
pub mod clock;
pub mod command;
pub mod contact;
pub mod exact;
pub mod forces;
pub mod hash;
pub mod integrate;
pub mod render;
pub mod replay;
pub mod scene;
pub mod sim_loop;
pub mod stability;
pub mod step;
pub mod study;
pub mod table;
pub mod world;

pub use clock::{FixedClock, FrameSource, FrameTicks, RealClock, VirtualClock};
pub use command::{Command, Stamped};
pub use contact::{Event, EventKind};
pub use forces::{ForceKind, Forces};
pub use integrate::{BodyState, Integrator};
pub use scene::{Scene, SceneError};
pub use sim_loop::{LoopError, SimLoop, TickObserver};
pub use world::{BodyId, Divergence, World};
