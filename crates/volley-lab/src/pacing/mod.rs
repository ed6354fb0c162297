//! The loop lab: what the player sees between ticks, under a display's real timing.
//!
//! A stepped world can only be shown at tick boundaries or between them, while the exact motion
//! is known at any time, so every displayed frame carries a temporal error on top of the
//! integrator's truncation error. This module measures it: a display timing (a model of a
//! monitor, or a real PresentMon capture) says when the game samples its frame clock and when
//! each frame reaches the screen; a loop policy ([`volley_sim::internals::clock::LoopPolicy`]) decides how many
//! ticks each frame runs; a draw mode decides which time between (or past) the ticks the frame
//! shows; the metrics compare what was drawn with the exact position at the moment the frame was
//! displayed.
//!
//! - [`display`]: display timings and the models that produce them (fixed refresh with a noisy
//!   frame clock, variable refresh, missed vsyncs, a hitch).
//! - [`capture`]: the PresentMon CSV reader (also OCAT's and CapFrameX's exports).
//! - [`lab`]: one run, every draw mode evaluated on the same frames.
//! - [`metrics`]: display error, animation error, judder, latency, cadence, drift.
//! - [`sweep`]: every policy x display x tick rate, and the default chosen from it.
//! - [`report`]: the sweep as CSV and as the generated page.
//! - [`shard`]: a sweep split over machines, and the merge of its parts.

pub mod capture;
pub mod display;
pub mod lab;
pub mod metrics;
pub mod report;
pub mod shard;
pub mod sweep;

pub use capture::{CaptureError, read_capture};
pub use display::{DisplayModel, DisplayTiming, Present};
pub use lab::{DrawMode, LEAD_WINDOW, Lead, RunConfig, Subject, run, swept_position};
pub use metrics::{Metrics, ModeMetrics, Stats};
pub use sweep::{Choice, OverallChoice, Row, Sweep, SweepDisplay, choose, choose_all};

pub use volley_sim::internals::draw::{DEFAULT_DRAW, DEFAULT_POLICY};
