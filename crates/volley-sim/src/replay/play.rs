//! Re-simulating a recording on its own: the same [`SimLoop`], the recorded commands, frames of
//! [`crate::sim_loop::UNPACED_FRAME_TICKS`] ticks from a steady clock (so the ticks between
//! stored hashes, keyframes and commands of a world without contacts run as batches: the same
//! bits), every stored hash and keyframe compared by a [`Verifier`], and the first divergence
//! named.
//!
//! A recording that starts at tick 0 is replayed from its scene (so a change in how a scene
//! becomes a world is caught at tick 0); one that starts later, or a seek, starts from the
//! keyframe at or before the wanted tick. The loop runs in segments that end at keyframes.
//! When a stored hash differs, the replay runs on to the first keyframe at or after that tick
//! and compares every field there: the recording holds no state between keyframes, and
//! re-simulating the *recorded* build is impossible, so that keyframe is the closest recorded
//! state to report against (record with `keyframe_every = 1` to get the divergent tick itself).

use std::io::{Read, Seek};

use crate::clock::VirtualClock;
use crate::sim_loop::{SimLoop, TickObserver};
use crate::world::World;

use super::diff::FieldDiff;
use super::report::FirstDivergence;
use super::verify::Verifier;
use super::{Recording, ReplayError};

/// A recording being re-simulated, with the loop and the clock it runs on.
pub struct Replay<R> {
    verifier: Verifier<R>,
    sim: SimLoop,
    source: VirtualClock,
}

impl<R: Read + Seek> Replay<R> {
    /// Prepares a replay from the start, or from the keyframe at or before `seek`. Fails if the
    /// embedded scene no longer parses or the keyframe does not fit it.
    pub fn start(recording: Recording<R>, seek: Option<u64>) -> Result<Self, ReplayError> {
        let (verifier, mut sim) = Verifier::start(recording, seek)?;
        Ok(Replay {
            source: sim.unpaced_source(crate::sim_loop::UNPACED_FRAME_TICKS),
            verifier,
            sim,
        })
    }

    /// Sets the worker threads of the replaying world (results do not depend on it).
    pub fn set_threads(&mut self, threads: usize) {
        self.sim.world.set_threads(threads);
    }

    /// The replayed world.
    pub fn world(&self) -> &World {
        &self.sim.world
    }

    /// The comparison so far.
    pub fn verifier(&self) -> &Verifier<R> {
        &self.verifier
    }

    /// The recording.
    pub fn recording(&self) -> &Recording<R> {
        self.verifier.recording()
    }

    /// The tick the replay started from (0, the recording's start, or a keyframe for a seek).
    pub fn started_at(&self) -> u64 {
        self.verifier.started_at()
    }

    /// Stored hashes compared so far.
    pub fn hashes_checked(&self) -> u64 {
        self.verifier.hashes_checked()
    }

    /// Keyframes compared field by field so far.
    pub fn keyframes_checked(&self) -> u64 {
        self.verifier.keyframes_checked()
    }

    /// See [`Verifier::force_evals_differ`].
    pub fn force_evals_differ(&self) -> Option<(u64, &FieldDiff)> {
        self.verifier.force_evals_differ()
    }

    /// The first divergence, once it is known with its field report.
    pub fn first_divergence(&self) -> Option<&FirstDivergence> {
        self.verifier.first_divergence()
    }

    /// Whether the replay is over: at the recording's end, stopped by a reproduced divergence,
    /// or parted from the recording.
    pub fn is_done(&self) -> bool {
        self.verifier.is_done(&self.sim.world)
    }

    /// Re-simulates up to `tick` (at most the recording's end), comparing as it goes; the
    /// observer sees every tick like any loop's. Stops early at a divergence, once its field
    /// report is complete.
    pub fn run_to(
        &mut self,
        tick: u64,
        observer: &mut impl TickObserver,
    ) -> Result<(), ReplayError> {
        self.verifier
            .run_to(&mut self.sim, &mut self.source, tick, observer)
    }
}
