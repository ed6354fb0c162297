//! Re-simulating a recording: the same [`SimLoop`], the recorded commands, every stored hash and
//! keyframe compared, and the first divergence named.
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
use crate::command::Stamped;
use crate::hash::{hex, state_hash};
use crate::scene::Scene;
use crate::sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
use crate::world::{Divergence, Snapshot, World};

use super::diff::{FieldDiff, diff};
use super::{ErrorKind, Recording, ReplayError};

/// What differed first.
#[derive(Clone, Debug, PartialEq)]
pub enum Mismatch {
    /// The stored state hash differs from the replay's.
    Hash {
        /// The recording's hash.
        recorded: u64,
        /// The replay's hash.
        replayed: u64,
    },
    /// Every hash agreed, but a keyframe differs in a field the hash does not cover and that
    /// decides the future (launcher, force toggles, integrator, energy caps, carried force).
    Fields,
    /// The replay's divergence guard stopped it where the recording went on.
    ReplayDiverged(Divergence),
    /// The recording ended in a divergence the replay did not reproduce.
    RecordingDiverged(Divergence),
    /// A recorded command could not be applied to the replayed world.
    Command {
        /// The command.
        command: Stamped,
        /// Why it failed.
        error: String,
    },
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Mismatch::Hash { recorded, replayed } => write!(
                f,
                "state hash recorded {} replayed {}",
                hex(*recorded),
                hex(*replayed)
            ),
            Mismatch::Fields => f.write_str("the hashes agree but keyframe fields differ"),
            Mismatch::ReplayDiverged(d) => write!(f, "the replay {d}; the recording did not"),
            Mismatch::RecordingDiverged(d) => write!(f, "the recording {d}; the replay did not"),
            Mismatch::Command { command, error } => {
                write!(f, "recorded command `{command}` failed on replay: {error}")
            }
        }
    }
}

/// Where a replay first parted from its recording, and every field that differs.
#[derive(Clone, Debug, PartialEq)]
pub struct FirstDivergence {
    /// The first checked tick that differs.
    pub tick: u64,
    /// The last tick before it whose stored hash matched, if any: the state first differed
    /// somewhere in `last_match + 1 ..= tick` (exactly `tick` when hashes are stored every tick).
    pub last_match: Option<u64>,
    /// What differed.
    pub mismatch: Mismatch,
    /// The keyframe tick `fields` were compared at: the first at or after `tick`, if any.
    pub compared_at: Option<u64>,
    /// Every field that differs at `compared_at`.
    pub fields: Vec<FieldDiff>,
}

impl FirstDivergence {
    /// The report as lines of text, listing at most `limit` fields (all for `None`).
    pub fn report(&self, limit: Option<usize>) -> String {
        let mut out = format!(
            "first divergence at tick {}: {}\n",
            self.tick, self.mismatch
        );
        match self.last_match {
            Some(m) if m + 1 == self.tick => out += &format!("the state matched at tick {m}\n"),
            Some(m) => {
                out += &format!(
                    "the state matched at tick {m} (the last stored hash before), so it first \
                     differed in ticks {}..={}\n",
                    m + 1,
                    self.tick
                )
            }
            None => {}
        }
        let t = self.tick;
        match self.compared_at {
            Some(k) if self.fields.is_empty() => {
                out += &format!("no field differs at tick {k}: the runs agree again there\n")
            }
            Some(k) if k == t => out += &format!("fields that differ at tick {k} (a keyframe):\n"),
            Some(k) => {
                out += &format!(
                    "fields that differ at tick {k}, the first keyframe at or after tick {t} \
                     (the recording holds no state at tick {t}; record with --keyframe-every 1 \
                     for it):\n"
                )
            }
            None => {
                out += &format!("the recording has no keyframe at or after tick {t} to compare\n")
            }
        }
        let shown = limit.unwrap_or(usize::MAX).min(self.fields.len());
        for d in &self.fields[..shown] {
            out += &format!("  {d}\n");
        }
        if shown < self.fields.len() {
            out += &format!("  ... and {} more\n", self.fields.len() - shown);
        }
        out
    }
}

/// How far the comparison got.
#[derive(Default)]
struct Progress {
    /// Index of the next stored hash to compare.
    next_hash: usize,
    last_match: Option<u64>,
    hashes_checked: u64,
    /// A mismatch waiting for the keyframe of its field report.
    pending: Option<FirstDivergence>,
}

impl Progress {
    /// Records a mismatch at `tick` unless an earlier one is already waiting for its report.
    fn part(&mut self, tick: u64, mismatch: Mismatch) {
        if self.pending.is_none() {
            self.pending = Some(FirstDivergence {
                tick,
                last_match: self.last_match,
                mismatch,
                compared_at: None,
                fields: Vec::new(),
            });
        }
    }

    /// Compares the stored hash of the world's tick, if there is one.
    fn compare_hash(&mut self, hashes: &[(u64, u64)], world: &World) {
        let tick = world.tick();
        while hashes.get(self.next_hash).is_some_and(|h| h.0 < tick) {
            self.next_hash += 1;
        }
        let Some(&(t, recorded)) = hashes.get(self.next_hash) else {
            return;
        };
        if t != tick || self.pending.is_some() {
            return;
        }
        self.next_hash += 1;
        self.hashes_checked += 1;
        let replayed = state_hash(world);
        if replayed == recorded {
            self.last_match = Some(tick);
        } else {
            self.part(tick, Mismatch::Hash { recorded, replayed });
        }
    }
}

/// A recording being re-simulated.
pub struct Replay<R> {
    recording: Recording<R>,
    scene: Scene,
    sim: SimLoop,
    source: VirtualClock,
    started_at: u64,
    next_keyframe: usize,
    keyframes_checked: u64,
    evals_differ: Option<(u64, FieldDiff)>,
    progress: Progress,
    first: Option<FirstDivergence>,
    recorded: Snapshot,
    replayed: Snapshot,
}

impl<R: Read + Seek> Replay<R> {
    /// Prepares a replay from the start, or from the keyframe at or before `seek`. Fails if the
    /// embedded scene no longer parses or the keyframe does not fit it.
    pub fn start(mut recording: Recording<R>, seek: Option<u64>) -> Result<Self, ReplayError> {
        let scene = recording.scene()?;
        let k = recording.keyframe_at_or_before(seek.unwrap_or(0));
        let from_scene = k == 0 && recording.start_tick() == 0;
        let world = if from_scene {
            World::new(&scene)
        } else {
            recording.world_at(k, &scene)?
        };
        let tick = world.tick();
        let mut sim = SimLoop::new(world);
        let due = recording.commands().iter().filter(|c| c.tick >= tick);
        sim.schedule(due.copied());
        let snapshot = sim.world.snapshot();
        let mut replay = Replay {
            next_keyframe: if from_scene { k } else { k + 1 },
            source: VirtualClock::Steady(scene.timestep),
            recording,
            scene,
            sim,
            started_at: tick,
            keyframes_checked: 0,
            evals_differ: None,
            progress: Progress::default(),
            first: None,
            recorded: snapshot.clone(),
            replayed: snapshot,
        };
        let hashes = replay.recording.hashes();
        replay.progress.compare_hash(hashes, &replay.sim.world);
        replay.at_keyframe()?;
        Ok(replay)
    }

    /// Sets the worker threads of the replaying world (results do not depend on it).
    pub fn set_threads(&mut self, threads: usize) {
        self.sim.world.set_threads(threads);
    }

    /// The replayed world.
    pub fn world(&self) -> &World {
        &self.sim.world
    }

    /// The recording.
    pub fn recording(&self) -> &Recording<R> {
        &self.recording
    }

    /// The tick the replay started from (0, the recording's start, or a keyframe for a seek).
    pub fn started_at(&self) -> u64 {
        self.started_at
    }

    /// Stored hashes compared so far.
    pub fn hashes_checked(&self) -> u64 {
        self.progress.hashes_checked
    }

    /// Keyframes compared field by field so far.
    pub fn keyframes_checked(&self) -> u64 {
        self.keyframes_checked
    }

    /// The first keyframe tick whose force-evaluation count differs, with both counts. The
    /// count is a cost counter, not state (it never changes what happens next), so this is a
    /// warning, not a divergence: it means the evaluation bookkeeping changed.
    pub fn force_evals_differ(&self) -> Option<(u64, &FieldDiff)> {
        self.evals_differ.as_ref().map(|(t, f)| (*t, f))
    }

    /// The first divergence, once it is known with its field report.
    pub fn first_divergence(&self) -> Option<&FirstDivergence> {
        self.first.as_ref()
    }

    /// Whether the replay is over: at the recording's end, stopped by a reproduced divergence,
    /// or parted from the recording.
    pub fn is_done(&self) -> bool {
        self.first.is_some()
            || self.sim.world.tick() >= self.recording.end_tick()
            || self.sim.world.divergence().is_some()
    }

    /// Re-simulates up to `tick` (at most the recording's end), comparing as it goes; the
    /// observer sees every tick like any loop's. Stops early at a divergence, once its field
    /// report is complete.
    pub fn run_to(
        &mut self,
        tick: u64,
        observer: &mut impl TickObserver,
    ) -> Result<(), ReplayError> {
        let target = tick.min(self.recording.end_tick());
        while !self.is_done() && self.sim.world.tick() < target {
            let stop = match self.recording.keyframes().get(self.next_keyframe) {
                Some(k) => k.tick.min(target),
                None => target,
            };
            let mut check = Check {
                hashes: self.recording.hashes(),
                progress: &mut self.progress,
                inner: observer,
            };
            let result = self.sim.run_until(stop, &mut self.source, &mut check);
            match result {
                Ok(()) => self.at_keyframe()?,
                Err(LoopError::Diverged(d)) => self.replay_diverged(d)?,
                Err(LoopError::Command {
                    tick,
                    command,
                    error,
                }) => {
                    let command = Stamped { tick, command };
                    let error = error.to_string();
                    self.progress
                        .part(tick, Mismatch::Command { command, error });
                    self.at_keyframe()?;
                }
                Err(LoopError::Observer(e)) => return Err(self.output_error(e)),
            }
        }
        if self.sim.world.tick() >= self.recording.end_tick() {
            self.at_end();
        }
        Ok(())
    }

    fn output_error(&self, e: ObserverError) -> ReplayError {
        ReplayError {
            kind: ErrorKind::Output,
            ..ReplayError::input(self.recording.label(), None, e)
        }
    }

    /// At a keyframe tick: compares every field, completing a waiting report.
    fn at_keyframe(&mut self) -> Result<(), ReplayError> {
        let tick = self.sim.world.tick();
        let Some(k) = self.recording.keyframes().get(self.next_keyframe) else {
            return Ok(());
        };
        if k.tick != tick {
            return Ok(());
        }
        let index = self.next_keyframe;
        self.next_keyframe += 1;
        self.keyframes_checked += 1;
        self.recording
            .read_keyframe(index, &self.scene, &mut self.recorded)?;
        self.sim.world.snapshot_into(&mut self.replayed);
        let fields = diff(&self.recorded, &self.replayed);
        let counter = |f: &FieldDiff| f.body.is_none() && f.field == "force_evals";
        if self.progress.pending.is_none() && fields.iter().any(|f| !counter(f)) {
            self.progress.part(tick, Mismatch::Fields);
        }
        if self.evals_differ.is_none() {
            self.evals_differ = fields
                .iter()
                .find(|f| counter(f))
                .map(|f| (tick, f.clone()));
        }
        if let Some(mut p) = self.progress.pending.take() {
            p.compared_at = Some(tick);
            p.fields = fields;
            self.first = Some(p);
        }
        Ok(())
    }

    /// The replay's guard stopped it: a reproduction of the recording's own end, or a
    /// divergence of the replay.
    fn replay_diverged(&mut self, d: Divergence) -> Result<(), ReplayError> {
        let tick = self.sim.world.tick();
        let hash = state_hash(&self.sim.world);
        let stored = self.recording.hashes().iter().find(|h| h.0 == tick);
        let recorded_end = self.recording.footer().and_then(|f| f.diverged);
        if recorded_end == Some(d) && stored.is_some_and(|h| h.1 == hash) {
            self.progress.hashes_checked += 1;
            self.progress.last_match = Some(tick);
        } else {
            self.progress.part(tick, Mismatch::ReplayDiverged(d));
        }
        self.at_keyframe()?;
        if let Some(p) = self.progress.pending.take() {
            self.first = Some(p);
        }
        Ok(())
    }

    /// At the recording's last tick: a waiting report completes without a keyframe, and a
    /// recorded divergence that the replay did not reproduce is a mismatch (unless the replay
    /// started at that tick, from the keyframe of the diverged state, and so stepped nothing).
    fn at_end(&mut self) {
        let tick = self.sim.world.tick();
        let recorded_end = self.recording.footer().and_then(|f| f.diverged);
        if let Some(d) = recorded_end
            && self.sim.world.divergence().is_none()
            && self.started_at < tick
        {
            self.progress.part(tick, Mismatch::RecordingDiverged(d));
        }
        if let Some(p) = self.progress.pending.take() {
            self.first = Some(p);
        }
    }
}

/// The observer a replay runs with: compares stored hashes, then hands the tick to the user's.
struct Check<'a, O> {
    hashes: &'a [(u64, u64)],
    progress: &'a mut Progress,
    inner: &'a mut O,
}

impl<O: TickObserver> TickObserver for Check<'_, O> {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        self.inner.on_command(world, stamped)
    }

    fn before_last_tick(&mut self, world: &World) {
        self.inner.before_last_tick(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.progress.compare_hash(self.hashes, world);
        self.inner.after_tick(world)
    }

    fn on_divergence(&mut self, world: &World, divergence: &Divergence) {
        self.inner.on_divergence(world, divergence);
    }
}
