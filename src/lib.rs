//! # Volley
//!
//! The sandbox around the simulation: the window ([`app`]), the wgpu renderer ([`render`]) and
//! the study's work-precision plot ([`plot`]). Everything that steps, records and measures lives
//! in the `volley-sim` crate, which has no GPU, window, plotting or CLI crate in its dependency
//! tree; it is re-exported here whole, so `volley::world::World` and `volley_sim::world::World`
//! are one type.

pub use volley_sim::*;

pub mod app;
pub mod palette;
pub mod plot;
pub mod render;
