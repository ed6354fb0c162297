//! Deterministic replays: record a run, play it back, verify it bit for bit, and name the first
//! divergence down to the body and field.
//!
//! A recording holds what decides a run and what checks it: the scene text verbatim, the
//! timestep, substeps and integrator, the tick-stamped [`crate::Command`]s, the canonical state
//! hash ([`crate::hash`]) after every tick (or every K), keyframes (full [`Snapshot`]s, see
//! [`keyframe`]) every K ticks for seeking and for the field report, and a footer with the final
//! tick and hash. The byte layout is in [`self::format`].
//!
//! - [`Recorder`] writes one, as a [`crate::TickObserver`], so the window and headless runs
//!   record through the same loop. It writes append-only with a CRC per record and flushes as
//!   it goes ([`FlushPolicy`]): a run killed mid-way leaves a file that opens as "truncated
//!   after tick N" with every tick flushed before the kill.
//! - [`Recording`] opens one: checks every record, keeps the index, reads keyframes on demand.
//! - [`Replay`] re-simulates one through [`crate::SimLoop`], compares every stored hash and
//!   every keyframe, and reports the [`FirstDivergence`] with every differing field ([`diff`]).
//!   The comparing is done by a [`Verifier`], which checks any loop however it is driven (the
//!   window replays through it with its own frame deltas).
//!
//! ```
//! use volley_sim::{
//!     RecordOptions, Recorder, Recording, Replay, SimLoop, VirtualClock, World, bundled_scene,
//! };
//!
//! let scene = bundled_scene("seed").unwrap();
//! let mut sim = SimLoop::new(World::new(&scene));
//! let mut recorder = Recorder::start(Vec::new(), &sim.world, RecordOptions::default()).unwrap();
//! sim.run_until(27, &mut VirtualClock::Steady(scene.timestep()), &mut recorder).unwrap();
//! let (bytes, _stats) = recorder.finish(&sim.world).unwrap();
//!
//! let recording = Recording::from_reader(std::io::Cursor::new(bytes), "seed.vrec").unwrap();
//! let mut replay = Replay::start(recording, None).unwrap();
//! replay.run_to(u64::MAX, &mut ()).unwrap();
//! assert!(replay.first_divergence().is_none());
//! assert_eq!(replay.world().tick(), 27);
//! ```

pub mod diff;
pub mod format;
pub mod keyframe;
mod play;
mod reader;
mod recorder;
mod report;
mod verify;

pub use diff::{FieldDiff, Value, ulps};
pub use format::{Footer, Header};
pub use play::Replay;
pub use reader::{KeyframeEntry, Recording};
pub use recorder::{FlushPolicy, RecordOptions, RecordStats, Recorder};
pub use report::{FirstDivergence, Mismatch};
pub use verify::Verifier;

pub use crate::world::Snapshot;

/// Whether a replay error is the file's fault or the machine's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The recording is missing, damaged, of another format version, or does not fit its
    /// scene (the CLI's exit code 2).
    Input,
    /// Writing the playback's output failed (exit code 4).
    Output,
}

/// Why a recording cannot be read or replayed: one line naming the file, the byte offset when
/// there is one, and what was expected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReplayError {
    /// The file.
    pub file: String,
    /// Byte offset of the record at fault, if one is.
    pub at: Option<u64>,
    /// What is wrong.
    pub message: String,
    /// Input or output.
    pub kind: ErrorKind,
}

impl ReplayError {
    /// An error in the recording `file` at byte `at`.
    pub fn input(file: &str, at: Option<u64>, message: impl std::fmt::Display) -> ReplayError {
        ReplayError {
            file: file.to_string(),
            at,
            message: message.to_string(),
            kind: ErrorKind::Input,
        }
    }
}

impl std::fmt::Display for ReplayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(at) = self.at {
            write!(f, ": byte {at}")?;
        }
        // One line, whatever a nested error (JSON, RON) put in its message.
        write!(f, ": {}", self.message.replace(['\n', '\r'], " "))
    }
}

impl std::error::Error for ReplayError {}
