//! Checking a re-simulation against its recording: every stored hash and keyframe compared, and
//! the first divergence named.
//!
//! [`Verifier`] is the comparing half of a replay. It builds the [`SimLoop`] a replay runs (the
//! recording's scene or keyframe, its commands scheduled) and checks that loop's ticks, however
//! they are driven: [`Verifier::run_to`] with any frame source ([`super::Replay`], the CLI), or
//! [`Verifier::frame`] with a window's frame deltas (the window's replay, where the loop is the
//! session's own and pause, single step and time scale work as in a live run).
//!
//! A recording that starts at tick 0 is replayed from its scene (so a change in how a scene
//! becomes a world is caught at tick 0); one that starts later, or a seek, starts from the
//! keyframe at or before the wanted tick. The loop runs in segments that end at keyframes.
//! When a stored hash differs, the replay runs on to the first keyframe at or after that tick
//! and compares every field there: the recording holds no state between keyframes, and
//! re-simulating the *recorded* build is impossible, so that keyframe is the closest recorded
//! state to report against (record with `keyframe_every = 1` to get the divergent tick itself).

use std::io::{Read, Seek};
use std::time::Duration;

use crate::clock::{FrameSource, FrameTicks};
use crate::command::Stamped;
use crate::hash::state_hash;
use crate::scene::Scene;
use crate::sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
use crate::world::{Divergence, Snapshot, World};

use super::diff::{FieldDiff, diff};
use super::report::{FirstDivergence, Mismatch};
use super::{ErrorKind, Recording, ReplayError};

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

/// The comparing half of a replay: the recording, how far the comparison got, and what differed.
/// The loop it checks belongs to the caller (see the module doc).
pub struct Verifier<R> {
    recording: Recording<R>,
    scene: Scene,
    started_at: u64,
    next_keyframe: usize,
    keyframes_checked: u64,
    evals_differ: Option<(u64, FieldDiff)>,
    progress: Progress,
    first: Option<FirstDivergence>,
    recorded: Snapshot,
    replayed: Snapshot,
}

impl<R: Read + Seek> Verifier<R> {
    /// The loop that replays `recording`, from the start or from the keyframe at or before
    /// `seek`, with every recorded command from there on scheduled, and the verifier that checks
    /// it (the starting state already compared). Fails if the embedded scene no longer parses or
    /// the keyframe does not fit it.
    pub fn start(
        mut recording: Recording<R>,
        seek: Option<u64>,
    ) -> Result<(Verifier<R>, SimLoop), ReplayError> {
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
        let mut verifier = Verifier {
            next_keyframe: if from_scene { k } else { k + 1 },
            recording,
            scene,
            started_at: tick,
            keyframes_checked: 0,
            evals_differ: None,
            progress: Progress::default(),
            first: None,
            recorded: snapshot.clone(),
            replayed: snapshot,
        };
        let hashes = verifier.recording.hashes();
        verifier.progress.compare_hash(hashes, &sim.world);
        verifier.at_keyframe(&sim.world)?;
        Ok((verifier, sim))
    }

    /// The recording.
    pub fn recording(&self) -> &Recording<R> {
        &self.recording
    }

    /// The recording's scene, with its recorded timestep, substeps and integrator.
    pub fn scene(&self) -> &Scene {
        &self.scene
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

    /// The first divergence as soon as it is seen: with its field report once the replay has
    /// reached the keyframe for it ([`Verifier::first_divergence`]), with no fields and no
    /// `compared_at` before that. For a display that should not wait for the report.
    pub fn parted(&self) -> Option<&FirstDivergence> {
        self.first.as_ref().or(self.progress.pending.as_ref())
    }

    /// Whether the replay of `world` is over: at the recording's end, stopped by a reproduced
    /// divergence, or parted from the recording.
    pub fn is_done(&self, world: &World) -> bool {
        self.first.is_some()
            || world.tick() >= self.recording.end_tick()
            || world.divergence().is_some()
    }

    /// The tick the loop must stop at for the next comparison: the next keyframe, or the end.
    fn next_stop(&self) -> u64 {
        let end = self.recording.end_tick();
        self.recording
            .keyframes()
            .get(self.next_keyframe)
            .map_or(end, |k| k.tick.min(end))
    }

    /// Re-simulates `sim` up to `tick` (at most the recording's end) with frames from
    /// `source`, comparing as it goes; the observer sees every tick like any loop's. Stops early
    /// at a divergence, once its field report is complete.
    pub fn run_to(
        &mut self,
        sim: &mut SimLoop,
        source: &mut impl FrameSource,
        tick: u64,
        observer: &mut impl TickObserver,
    ) -> Result<(), ReplayError> {
        let target = tick.min(self.recording.end_tick());
        while !self.is_done(&sim.world) && sim.world.tick() < target {
            let stop = self.next_stop().min(target);
            let mut check = Check {
                hashes: self.recording.hashes(),
                progress: &mut self.progress,
                inner: observer,
            };
            let result = sim.run_until(stop, source, &mut check);
            self.after_run(&sim.world, result)?;
        }
        if sim.world.tick() >= self.recording.end_tick() {
            self.at_end(&sim.world);
        }
        Ok(())
    }

    /// One display frame of `sim`: its clock takes `delta` (paused, scaled or single-stepped
    /// as the caller set it) and the ticks it grants run, comparing as they go. A frame that
    /// would pass a keyframe stops there for the comparison and then runs the rest of its ticks,
    /// so the comparison never costs the clock any time. Nothing runs once the replay is over
    /// ([`Verifier::is_done`]). While it runs, the loop's stop tick is the verifier's.
    pub fn frame(
        &mut self,
        sim: &mut SimLoop,
        delta: Duration,
        observer: &mut impl TickObserver,
    ) -> Result<FrameTicks, ReplayError> {
        let mut total = FrameTicks::default();
        let mut delta = Some(delta);
        while !self.is_done(&sim.world) {
            sim.stop_at(Some(self.next_stop()));
            let mut check = Check {
                hashes: self.recording.hashes(),
                progress: &mut self.progress,
                inner: observer,
            };
            // After a stop, the ticks the clock took back are in its accumulator: a zero delta
            // grants them again (and nothing more).
            let result = sim.frame(delta.take().unwrap_or(Duration::ZERO), &mut check);
            sim.stop_at(None);
            let ticks = sim.clock.last_frame();
            total.steps += ticks.steps;
            total.alpha = ticks.alpha;
            total.dropped += ticks.dropped;
            self.after_run(&sim.world, result.map(|_| ()))?;
            if ticks.steps == 0 {
                break;
            }
        }
        if sim.world.tick() >= self.recording.end_tick() {
            self.at_end(&sim.world);
        }
        Ok(total)
    }

    /// After the loop stopped (at a keyframe, the target, or on an error): compares, or records
    /// what went wrong.
    fn after_run(
        &mut self,
        world: &World,
        result: Result<(), LoopError>,
    ) -> Result<(), ReplayError> {
        match result {
            Ok(()) => self.at_keyframe(world),
            Err(LoopError::Diverged(d)) => self.replay_diverged(world, d),
            Err(LoopError::Command {
                tick,
                command,
                error,
            }) => {
                let command = Stamped { tick, command };
                let error = error.to_string();
                self.progress
                    .part(tick, Mismatch::Command { command, error });
                self.at_keyframe(world)
            }
            Err(LoopError::Observer(e)) => Err(self.output_error(e)),
        }
    }

    fn output_error(&self, e: ObserverError) -> ReplayError {
        ReplayError {
            kind: ErrorKind::Output,
            ..ReplayError::input(self.recording.label(), None, e)
        }
    }

    /// At a keyframe tick: compares every field, completing a waiting report.
    fn at_keyframe(&mut self, world: &World) -> Result<(), ReplayError> {
        let tick = world.tick();
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
        world.snapshot_into(&mut self.replayed);
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
    fn replay_diverged(&mut self, world: &World, d: Divergence) -> Result<(), ReplayError> {
        let tick = world.tick();
        let hash = state_hash(world);
        let stored = self.recording.hashes().iter().find(|h| h.0 == tick);
        let recorded_end = self.recording.footer().and_then(|f| f.diverged);
        if recorded_end == Some(d) && stored.is_some_and(|h| h.1 == hash) {
            self.progress.hashes_checked += 1;
            self.progress.last_match = Some(tick);
        } else {
            self.progress.part(tick, Mismatch::ReplayDiverged(d));
        }
        self.at_keyframe(world)?;
        if let Some(p) = self.progress.pending.take() {
            self.first = Some(p);
        }
        Ok(())
    }

    /// At the recording's last tick: a waiting report completes without a keyframe, and a
    /// recorded divergence that the replay did not reproduce is a mismatch (unless the replay
    /// started at that tick, from the keyframe of the diverged state, and so stepped nothing).
    fn at_end(&mut self, world: &World) {
        let tick = world.tick();
        let recorded_end = self.recording.footer().and_then(|f| f.diverged);
        if let Some(d) = recorded_end
            && world.divergence().is_none()
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

    /// The next stored hash's tick (none once a mismatch waits for its keyframe, where the
    /// loop stops anyway), or sooner if the caller's observer needs a tick: a recording that
    /// hashes every K ticks replays the ticks between as batches.
    fn next_needed_tick(&self, tick: u64) -> u64 {
        let hash = match self.progress.pending {
            Some(_) => u64::MAX,
            None => self.hashes[self.progress.next_hash.min(self.hashes.len())..]
                .iter()
                .map(|h| h.0)
                .find(|&t| t > tick)
                .unwrap_or(u64::MAX),
        };
        hash.min(self.inner.next_needed_tick(tick))
    }
}
