//! # volley-lab
//!
//! Volley's measuring lab, on top of the simulation crate `volley-sim`: what the window and the
//! command line measure a game loop with, kept apart so a game that depends on `volley-sim`
//! compiles none of it.
//!
//! - [`study`]: integrators x timesteps, error against cost, against the best reference the
//!   scene allows (`volley study`, docs/study.md), split over machines as shards.
//! - [`stability`]: the pre-check that says, before a run, which integrator will diverge at
//!   the scene's step and what substeps would fix it.
//! - [`pacing`]: the loop lab: loop policies x draw modes x displays, what the player sees
//!   against the exact motion at each frame's display time (`volley pacing`, docs/pacing.md).
//!   The defaults it chose, and the draw modes, are the simulation crate's
//!   (`volley_sim::DEFAULT_POLICY`, `volley_sim::DEFAULT_DRAW`, `volley_sim::Draw`).
//! - [`table`]: the headless state table and summary (`volley headless`).
//!
//! Layers, bottom up: `table`, `stability` -> `study` -> `pacing`. Everything here reaches the
//! simulation through `volley_sim::internals` (this crate is Volley's own) and never changes
//! what a tick computes.

pub mod pacing;
pub mod stability;
pub mod study;
pub mod table;
