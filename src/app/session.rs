//! The simulations a window shows: one world, or in compare mode one per integrator, all driven
//! by the same frame deltas.
//!
//! Everything that changes a simulation goes through [`SimLoop::push`] as a [`Command`], applied
//! at the next tick boundary, so a recording of the session sees it (`session/commands.rs`).
//! Pause, single step and time scale set the clocks: they change when ticks run, never what a
//! tick computes (`session/clock.rs`). Changing dt or substeps, switching compare mode, and
//! picking or reloading a scene start the scene again at tick 0, so sim time stays exactly
//! `tick * dt`; such a restart ends a recording (with its footer) first (`session/restart.rs`).
//!
//! A divergence stops its lane and pauses every clock, so the bad state stays on screen. Reset
//! after it is the `Reset` command like any reset (recordable; the tick keeps counting; the
//! clocks resume if the divergence paused them), except in compare mode, where it restarts
//! every lane at tick 0 so the lanes stay on one tick.
//!
//! The first lane can be recorded ([`Session::start_recording`], in compare mode too: the first
//! integrator's world) or can be a replay of a recording ([`Session::start_replay`], one lane,
//! see [`replaying`]). Every lane carries the stability pre-check of its world
//! ([`crate::stability::check_world`]), recomputed when its integrator, dt, substeps or scene
//! change.
//!
//! A call the session refuses returns why as a [`SessionError`], whose `Display` is the line the
//! panel shows; a frame returns the last refusal it met (a command refused as it was applied, a
//! seek while playing backwards). The session keeps no text for the panel: what it keeps is
//! data, such as the tick a new command dropped the recorded future from
//! ([`Session::future_dropped_at`]).
//!
//! [`SimLoop::push`]: crate::SimLoop::push
//! [`Command`]: crate::Command

mod clock;
mod commands;
mod error;
mod lane;
pub mod pacing;
pub mod recording;
pub mod replaying;
mod restart;
mod rewind;
mod setup;

use std::path::Path;
use std::time::Duration;

use crate::app::display::Shown;
use crate::clock::FrameTicks;
use crate::integrate::Integrator;
use crate::render::draw;
use crate::render::{DrawAt, SceneBounds};
use crate::replay::ReplayError;
use crate::scene::{CompareLane, Scene};
use crate::sim_loop::LoopError;
use crate::world::World;
use clock::Clocks;
pub use error::{Change, FileStep, IoError, SessionError};
pub use lane::{AimNote, Lane};
use pacing::Pacing;
use recording::{Recorded, Recordings};
use replaying::{Replays, SessionReplay};
use rewind::Rewind;
use setup::Setup;
pub use setup::compare_refusals;

/// The scene, its lanes, and what they share, each part in a file of its own.
#[derive(Debug)]
pub struct Session {
    /// What the lanes are built from: the scene and its file, the compare lanes, equal cost.
    setup: Setup,
    /// The simulations: one, or in compare mode one per integrator.
    lanes: Vec<Lane>,
    /// What every lane's clock shares: pause, time scale, and what the last frame ran.
    clock: Clocks,
    /// The loop lab: the loop policy, the refresh it is given, the draw mode, and the first
    /// lane's last frames.
    pacing: Pacing,
    /// Rewinding: each lane's timeline budget, playing backwards, the future a command dropped.
    rewind: Rewind,
    /// Recording the first lane: the recording running, those finished, where they go.
    recording: Recordings,
    /// Replaying into the first lane: the replay, the last one's verdict, how many were opened.
    replay: Replays,
}

impl Session {
    /// A session on `scene` (read from `path`); `compare` lists the integrators of compare mode
    /// (empty: one lane with the scene's integrator).
    pub fn new(scene: Scene, path: &Path, compare: Vec<Integrator>) -> Session {
        let lanes = compare.into_iter().map(CompareLane::of).collect();
        Session::with_lanes(scene, path, lanes, false)
    }

    /// A session whose compare lanes each have an integrator and their own dt and substeps,
    /// at equal cost (every lane the first one's force evaluations per simulated second) or
    /// not. If the scene refuses every compared integrator, the session runs one lane of the
    /// scene's own (the window's `--compare` refuses such a list before the window opens).
    pub fn with_lanes(
        scene: Scene,
        path: &Path,
        compare: Vec<CompareLane>,
        equal_cost: bool,
    ) -> Session {
        let mut session = Session {
            setup: Setup::new(scene, path, compare, equal_cost),
            lanes: Vec::new(),
            clock: Clocks::default(),
            pacing: Pacing::default(),
            rewind: Rewind::default(),
            recording: Recordings::default(),
            replay: Replays::default(),
        };
        // The fallback's refusal has no panel to go to yet (see the doc comment).
        let _ = session.build_lanes();
        session
    }

    /// A session replaying the recording `path` (from the keyframe at or before `seek`, then
    /// re-simulated to `seek`), or why it cannot.
    pub fn for_replay(path: &Path, seek: Option<u64>) -> Result<Session, ReplayError> {
        Session::for_replay_from(replaying::ReplaySource::File(path.to_path_buf()), seek)
    }

    /// [`Session::for_replay`] from any source: a file, or bytes a browser fetched.
    pub fn for_replay_from(
        source: replaying::ReplaySource,
        seek: Option<u64>,
    ) -> Result<Session, ReplayError> {
        let path = source.name().to_path_buf();
        let (replay, sim) = SessionReplay::open_from(source, seek)?;
        let scene = replay.verifier().scene().clone();
        let mut session = Session::new(scene, &path, Vec::new());
        session.install_replay(replay, sim);
        Ok(session)
    }

    /// One frame: every running lane advances its clock by `delta` and runs the ticks it grants
    /// (the first lane through its recorder or its replay, when it has one). A lane that
    /// diverges stops and pauses every clock; a recording of the first lane ends with its
    /// divergence. The frame's display time is not known ([`Session::frame_shown`]). Returns
    /// the last refusal the frame met: a command refused as it was applied, or a seek that
    /// failed while playing backwards.
    pub fn frame(&mut self, delta: Duration) -> Option<SessionError> {
        self.frame_shown(delta, Shown::Unknown)
    }

    /// [`Session::frame`] for a frame shown at `shown`: the pacing log measures what it drew
    /// against the exact motion then.
    pub fn frame_shown(&mut self, delta: Duration, shown: Shown) -> Option<SessionError> {
        let input = pacing::FrameInput {
            delta,
            shown,
            tick_before: self.lanes[0].sim.world.tick(),
            paused: self.clock.paused,
            reversing: self.rewind.reverse.is_some(),
            time_scale: self.clock.time_scale,
            draw: self.pacing.draw,
        };
        let refused = self.advance(delta);
        self.pacing.log.record(&self.lanes[0], input);
        refused
    }

    /// Runs the frame's ticks (or goes back, playing backwards); returns the last refusal met.
    fn advance(&mut self, delta: Duration) -> Option<SessionError> {
        if self.rewind.reverse.is_some() {
            self.clock.last = FrameTicks::default();
            return self.reverse_frame(delta).err();
        }
        let mut refused = None;
        let mut first = None;
        let mut alarm = false;
        for (i, lane) in self.lanes.iter_mut().enumerate() {
            if lane.stopped.is_some() {
                continue;
            }
            // A world still diverged here has a reset waiting for its tick.
            let before = lane.sim.world.divergence();
            let result = match (i, &mut self.replay.current, &mut self.recording.current) {
                (0, Some(replay), _) => replaying::frame(replay, lane, delta),
                (0, None, Some(recording)) => {
                    let mut observer = Recorded {
                        recording,
                        history: &mut lane.history,
                    };
                    lane.sim.frame(delta, &mut observer)
                }
                _ => lane.sim.frame(delta, &mut lane.history),
            };
            match result {
                Ok(ticks) => {
                    first.get_or_insert(ticks);
                }
                Err(LoopError::Diverged(_)) => {}
                Err(e) => {
                    lane.refused += 1;
                    refused = Some(SessionError::Loop(e));
                }
            }
            // A replay's verifier takes the loop's divergence in; the world still has it.
            let now = lane.sim.world.divergence();
            if now.is_some() && now != before {
                lane.stopped = now;
                alarm = true;
            }
            lane.refresh_stability();
        }
        self.clock.last = first.unwrap_or_default();
        if let Some(d) = self.lanes[0].stopped {
            let why =
                format!("the lane {d}; the recording ends there, and its replay reproduces it");
            self.stop_recording(&why);
        }
        if self
            .recording
            .current
            .as_ref()
            .is_some_and(|r| r.error().is_some())
        {
            self.stop_recording("a write failed");
        }
        alarm |= self.replay.current.as_mut().is_some_and(|r| {
            let now = r.error().is_some() || r.verifier().first_divergence().is_some();
            let first_time = now && !r.alarmed;
            r.alarmed |= now;
            first_time
        });
        if alarm {
            self.alarm();
        }
        refused
    }

    /// The scene (with any dt override).
    pub fn scene(&self) -> &Scene {
        &self.setup.scene
    }

    /// The scene file, or the recording the scene came from.
    pub fn path(&self) -> &Path {
        &self.setup.path
    }

    /// Whether the scene came from a recording (replayed, or gone live from a replay): there is
    /// no scene file to watch.
    pub fn is_embedded(&self) -> bool {
        self.setup.embedded
    }

    /// The lanes.
    pub fn lanes(&self) -> &[Lane] {
        &self.lanes
    }

    /// The first lane's world (every lane shares the tick and the launcher).
    pub fn world(&self) -> &World {
        &self.lanes[0].sim.world
    }

    /// The integrators of compare mode (empty when off).
    pub fn compare(&self) -> Vec<Integrator> {
        self.setup.compare.iter().map(|l| l.integrator).collect()
    }

    /// The lanes of compare mode with their own steps (empty when off).
    pub fn compare_lanes(&self) -> &[CompareLane] {
        &self.setup.compare
    }

    /// Whether compare mode is on.
    pub fn is_comparing(&self) -> bool {
        !self.setup.compare.is_empty()
    }

    /// The region the scene plays in.
    pub fn bounds(&self) -> &SceneBounds {
        &self.setup.bounds
    }

    /// The lanes as the renderer takes them.
    pub fn draw_lanes(&self) -> Vec<draw::Lane<'_>> {
        self.lanes
            .iter()
            .enumerate()
            .map(|(k, l)| draw::Lane {
                world: &l.sim.world,
                history: &l.history,
                at: DrawAt {
                    mode: self.pacing.draw,
                    alpha: l.sim.clock.alpha(),
                    lead: self.pacing.log.lead(),
                },
                colour: l.colour(),
                // The pacing log measures the first lane.
                judder: if k == 0 {
                    self.pacing.log.judder()
                } else {
                    &[]
                },
            })
            .collect()
    }
}
