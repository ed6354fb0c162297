//! A recording played back in the window: the recording's scene and its stamped commands drive
//! the session's loop (scheduled with [`crate::SimLoop::schedule`] by [`Verifier::start`]),
//! the window's frame deltas drive its clock (pause, single step and time scale work as in a
//! live run), and a [`Verifier`] compares every stored hash and keyframe as the ticks run.
//!
//! While a replay runs, nothing may change the simulation (fire, launch, integrator, reset, dt,
//! substeps, compare mode): the panel disables those controls and the keys say why. Going live
//! ends the replay and keeps the state, so the user can take over from any tick.

use std::fs::File;
use std::io::{BufReader, Cursor, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use super::{Lane, Session};
use crate::clock::{FrameTicks, VirtualClock};
use crate::hash::{hex, state_hash};
use crate::render::SceneBounds;
use crate::replay::{FirstDivergence, Recording, ReplayError, Verifier};
use crate::sim_loop::{LoopError, SimLoop};
use crate::world::{Divergence, World};

/// The session's replays into its first lane.
#[derive(Debug, Default)]
pub(super) struct Replays {
    /// The replay being played.
    pub(super) current: Option<SessionReplay>,
    /// The verdict of the last replay that ended.
    pub(super) last: Option<ReplayVerdict>,
    /// Replays opened, a seek in one opening it again ([`Session::replays_opened`]).
    pub(super) opened: u64,
}

impl Session {
    /// Replays the recording `path` in this session (from the keyframe at or before `seek`,
    /// then re-simulated to `seek`): one lane, the recording's scene, step and integrator. A
    /// recording in progress ends first; compare mode ends. On an error nothing changes.
    pub fn start_replay(&mut self, path: &Path, seek: Option<u64>) -> Result<(), ReplayError> {
        self.start_replay_from(ReplaySource::File(path.to_path_buf()), seek)
    }

    /// [`Session::start_replay`] from any source: a file, or bytes a browser fetched.
    pub fn start_replay_from(
        &mut self,
        source: ReplaySource,
        seek: Option<u64>,
    ) -> Result<(), ReplayError> {
        let (replay, sim) = SessionReplay::open_from(source, seek)?;
        self.stop_recording("a replay started");
        self.end_replay();
        self.setup.compare.clear();
        self.install_replay(replay, sim);
        Ok(())
    }

    /// Makes `replay` (with its loop) the session's only lane.
    pub(super) fn install_replay(&mut self, replay: SessionReplay, mut sim: SimLoop) {
        let setup = &mut self.setup;
        setup.scene = replay.verifier().scene().clone();
        setup.bounds = SceneBounds::of_scene(&setup.scene);
        setup.path = replay.file().to_path_buf();
        setup.scene_file = replay.verifier().recording().header().scene_file.clone();
        setup.embedded = true;
        sim.world.set_threads(setup.threads);
        self.tune(&mut sim);
        // A replay seeks in its file (`seek`), so the lane keeps no timeline of its own.
        self.lanes = vec![Lane::new(sim, self.setup.bounds.center(), None)];
        self.clock.last = FrameTicks::default();
        self.replay.opened += 1;
        self.replay.current = Some(replay);
        self.pacing.log.rebase();
    }

    /// Ends the replay and keeps its state: the lane runs on live from the tick it reached,
    /// without the recording's remaining commands. Returns false if nothing was replaying.
    pub fn go_live(&mut self) -> bool {
        if self.replay.current.is_none() {
            return false;
        }
        self.end_replay();
        let lane = &mut self.lanes[0];
        let mut live = SimLoop::new(lane.sim.world.clone());
        live.clock = lane.sim.clock.clone();
        lane.sim = live;
        // The replayed commands count as applied; nothing pushed is pending.
        lane.pushed = lane.history.commands_applied() + lane.refused;
        true
    }

    /// Forgets the replay, keeping its verdict.
    pub(super) fn end_replay(&mut self) {
        if let Some(replay) = self.replay.current.take() {
            self.replay.last = Some(replay.verdict(&self.lanes[0].sim.world));
        }
    }

    /// How many times this session opened a replay: started one, or opened it again at
    /// another tick for a seek in it. The panel drops a refusal made before the last opening.
    pub fn replays_opened(&self) -> u64 {
        self.replay.opened
    }

    /// The replay being played.
    pub fn replay(&self) -> Option<&SessionReplay> {
        self.replay.current.as_ref()
    }

    /// The verdict of the replay being played, or else of the last one this session played.
    pub fn replay_verdict(&self) -> Option<ReplayVerdict> {
        match &self.replay.current {
            Some(r) => Some(r.verdict(&self.lanes[0].sim.world)),
            None => self.replay.last.clone(),
        }
    }
}

/// One frame of the replay's lane: the verifier runs the lane's loop with the lane's history as
/// the observer. A read error stops the replay (kept for the panel), not the window.
pub(super) fn frame(
    replay: &mut SessionReplay,
    lane: &mut Lane,
    delta: Duration,
) -> Result<FrameTicks, LoopError> {
    if replay.error.is_some() {
        return Ok(FrameTicks::default());
    }
    match replay
        .verifier
        .frame(&mut lane.sim, delta, &mut lane.history)
    {
        Ok(ticks) => Ok(ticks),
        Err(e) => {
            replay.error = Some(e.to_string());
            Ok(FrameTicks::default())
        }
    }
}

/// Where a replayed recording comes from: its file, or its bytes (a browser's page fetches a
/// recording from a URL or reads the one picked in a file input: it has no files to open).
#[derive(Clone, Debug)]
pub enum ReplaySource {
    /// A recording file.
    File(PathBuf),
    /// A recording's bytes, with the name errors and the panel give it.
    Bytes {
        /// The name (the URL or the picked file's name).
        name: PathBuf,
        /// The file's bytes.
        bytes: Arc<[u8]>,
    },
}

impl ReplaySource {
    /// The name the panel and errors give it.
    pub fn name(&self) -> &Path {
        match self {
            ReplaySource::File(path) => path,
            ReplaySource::Bytes { name, .. } => name,
        }
    }

    fn open(&self) -> Result<Recording<ReplayReader>, ReplayError> {
        match self {
            ReplaySource::File(path) => {
                let label = path.display().to_string();
                let file = File::open(path).map_err(|e| ReplayError::input(&label, None, e))?;
                Recording::from_reader(ReplayReader::File(BufReader::new(file)), &label)
            }
            ReplaySource::Bytes { name, bytes } => Recording::from_reader(
                ReplayReader::Bytes(Cursor::new(bytes.clone())),
                &name.display().to_string(),
            ),
        }
    }
}

/// A replay's reader: the file's, or a cursor over the bytes.
#[derive(Debug)]
pub enum ReplayReader {
    /// A recording file.
    File(BufReader<File>),
    /// A recording's bytes.
    Bytes(Cursor<Arc<[u8]>>),
}

impl Read for ReplayReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self {
            ReplayReader::File(r) => r.read(buf),
            ReplayReader::Bytes(r) => r.read(buf),
        }
    }
}

impl Seek for ReplayReader {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        match self {
            ReplayReader::File(r) => r.seek(pos),
            ReplayReader::Bytes(r) => r.seek(pos),
        }
    }
}

/// The replay a session is playing.
pub struct SessionReplay {
    verifier: Verifier<ReplayReader>,
    source: ReplaySource,
    warnings: Vec<String>,
    error: Option<String>,
    /// Whether the session has already paused for this replay's mismatch.
    pub(crate) alarmed: bool,
}

impl std::fmt::Debug for SessionReplay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SessionReplay")
            .field("file", &self.source.name())
            .field("hashes_checked", &self.verifier.hashes_checked())
            .field("error", &self.error)
            .finish()
    }
}

impl SessionReplay {
    /// Opens `path` and prepares its loop, at the keyframe at or before `seek` and then
    /// re-simulated to `seek` itself (checked as it goes). Warnings (another Volley version or
    /// target, a truncated file) are kept for the panel.
    pub fn open(path: &Path, seek: Option<u64>) -> Result<(SessionReplay, SimLoop), ReplayError> {
        SessionReplay::open_from(ReplaySource::File(path.to_path_buf()), seek)
    }

    /// [`SessionReplay::open`] from any source.
    pub fn open_from(
        source: ReplaySource,
        seek: Option<u64>,
    ) -> Result<(SessionReplay, SimLoop), ReplayError> {
        let recording = source.open()?;
        let mut warnings: Vec<String> = recording
            .build_warnings()
            .into_iter()
            .map(|w| format!("{w}; replaying anyway and verifying honestly"))
            .collect();
        if recording.truncated_at().is_some() {
            warnings.push(format!(
                "truncated after tick {} (no footer): replaying the ticks it holds",
                recording.end_tick()
            ));
        }
        let end = recording.end_tick();
        if let Some(s) = seek.filter(|&s| s > end) {
            let file = source.name().display().to_string();
            return Err(ReplayError::input(
                &file,
                None,
                format!("seek {s}: the recording ends at tick {end}"),
            ));
        }
        let (mut verifier, mut sim) = Verifier::start(recording, seek)?;
        if let Some(tick) = seek {
            let mut source = VirtualClock::Steady(verifier.scene().timestep());
            verifier.run_to(&mut sim, &mut source, tick, &mut ())?;
        }
        let replay = SessionReplay {
            verifier,
            source,
            warnings,
            error: None,
            alarmed: false,
        };
        Ok((replay, sim))
    }

    /// The verifier (what was compared, what differed).
    pub fn verifier(&self) -> &Verifier<ReplayReader> {
        &self.verifier
    }

    /// The recording file (or, for bytes, their name).
    pub fn file(&self) -> &Path {
        self.source.name()
    }

    /// Where the recording came from (a seek opens it again from there).
    pub fn source(&self) -> &ReplaySource {
        &self.source
    }

    /// The recording's last tick.
    pub fn end_tick(&self) -> u64 {
        self.verifier.recording().end_tick()
    }

    /// Warnings about the file: another build, truncation.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The read error that stopped the replay, if one did.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Whether nothing more will run: the end, a divergence, a mismatch or an error.
    pub fn is_over(&self, world: &World) -> bool {
        self.error.is_some() || self.verifier.is_done(world)
    }

    /// The outcome so far, for the panel and for the command line when the window closes.
    pub fn verdict(&self, world: &World) -> ReplayVerdict {
        let v = &self.verifier;
        ReplayVerdict {
            file: self.file().display().to_string(),
            from: v.started_at(),
            at: world.tick(),
            end: self.end_tick(),
            hashes: v.hashes_checked(),
            keyframes: v.keyframes_checked(),
            final_hash: state_hash(world),
            parted: v.parted().cloned(),
            reproduced: world.divergence(),
            error: self.error.clone(),
        }
    }
}

/// Where a replay stands: how far it got, what it compared, and whether it parted.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayVerdict {
    /// The recording.
    pub file: String,
    /// The tick the replay started at.
    pub from: u64,
    /// The tick it reached.
    pub at: u64,
    /// The recording's last tick.
    pub end: u64,
    /// Stored hashes compared.
    pub hashes: u64,
    /// Keyframes compared field by field.
    pub keyframes: u64,
    /// The state hash at `at`.
    pub final_hash: u64,
    /// The first divergence, if the replay parted (its field list is empty until the keyframe
    /// that completes the report was reached).
    pub parted: Option<FirstDivergence>,
    /// A divergence of the replayed world (the recording's own, reproduced, unless `parted`
    /// says otherwise).
    pub reproduced: Option<Divergence>,
    /// A read error that stopped the replay.
    pub error: Option<String>,
}

impl ReplayVerdict {
    /// One line: verified (the whole recording), matching so far (stopped early), or parted.
    pub fn line(&self) -> String {
        let compared = format!(
            "{} hashes and {} keyframes compared",
            self.hashes, self.keyframes
        );
        if let Some(d) = &self.parted {
            return format!(
                "{}: the replay parts from the recording at tick {}",
                self.file, d.tick
            );
        }
        let mut line = if self.at >= self.end {
            format!(
                "verified {} ticks, final hash {} (ticks {}..={}: {compared}",
                self.at - self.from,
                hex(self.final_hash),
                self.from,
                self.at
            )
        } else {
            format!(
                "replayed ticks {}..={} of {} (it ends at tick {}): all equal so far ({compared}",
                self.from, self.at, self.file, self.end
            )
        };
        if let Some(d) = &self.reproduced {
            line += &format!("; the recorded divergence reproduced: {d}");
        }
        line + ")"
    }
}
