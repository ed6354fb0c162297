//! The simulations a window shows: one world, or in compare mode one per integrator, all driven
//! by the same frame deltas.
//!
//! Everything that changes a simulation goes through [`SimLoop::push`] as a [`Command`], applied
//! at the next tick boundary, so a recording of the session sees it. Pause, single step and time
//! scale set the clocks: they change when ticks run, never what a tick computes. Changing dt or
//! substeps, switching compare mode, and picking or reloading a scene start the scene again at
//! tick 0, so sim time stays exactly `tick * dt`; such a restart ends a recording (with its
//! footer) first.
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
//! A call the session refuses returns why, in the words the panel shows (`Err(String)`); a frame
//! returns the last refusal it met (a command refused as it was applied, a seek while playing
//! backwards). The session keeps no text for the panel: what it keeps is data, such as the tick
//! a new command dropped the recorded future from ([`Session::future_dropped_at`]).

mod lane;
pub mod pacing;
pub mod recording;
pub mod replaying;
mod rewind;
mod setup;

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::app::display::{DEFAULT_REFRESH, Shown};
use crate::clock::{FrameTicks, LoopPolicy};
use crate::command::Command;
use crate::integrate::Integrator;
use crate::pacing::DrawMode;
use crate::render::draw;
use crate::render::{DrawAt, SceneBounds};
use crate::replay::ReplayError;
use crate::scene::{CompareLane, Scene, check_integrator};
use crate::sim_loop::{LoopError, SimLoop};
use crate::world::World;
pub use lane::{AimNote, Lane};
use recording::{FinishedRecording, LiveRecording, Recorded};
use replaying::{ReplayVerdict, SessionReplay};

/// The shot on `arc` at target `target` for this world's integrator, step, forces and launcher,
/// launched at its current tick (a moving target where it is now).
fn aim_lane(
    world: &World,
    target: usize,
    arc: crate::exact::Arc,
) -> Result<crate::firing::Shot, String> {
    use crate::firing::{self, Mode, Range, ShotKind};
    let scene = world
        .scene()
        .edit()
        .integrator(world.integrator())
        .forces(world.forces().clone())
        .launcher(*world.launcher())
        .build()
        .map_err(|e| e.to_string())?;
    let t = world.contacts().targets[target];
    let now = crate::contact::Target {
        center: t.center_at(world.tick() as f64 * world.dt()),
        ..t
    };
    let range = Range::new(&scene, now);
    let shots =
        firing::solve(&range, Mode::Speed(scene.launcher().speed)).map_err(|e| e.to_string())?;
    let kind = ShotKind::Arc(arc);
    let shot = shots
        .into_iter()
        .find(|s| s.kind == kind)
        .ok_or_else(|| format!("no {} at this speed", kind.label()))?;
    match shot.blocked {
        Some(b) => Err(format!("the {} {}", kind.label(), firing::blocked_text(&b))),
        None => Ok(shot),
    }
}

/// Clock settings that survive a restart.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ClockSettings {
    paused: bool,
    time_scale: f64,
    /// The loop policy of every lane's clock.
    policy: LoopPolicy,
}

/// The scene, its lanes, and the clock settings they share.
#[derive(Debug)]
pub struct Session {
    scene: Scene,
    path: PathBuf,
    compare: Vec<CompareLane>,
    /// Compare lanes after the first run at its force evaluations per simulated second.
    equal_cost: bool,
    lanes: Vec<Lane>,
    bounds: SceneBounds,
    clock: ClockSettings,
    last: FrameTicks,
    threads: usize,
    /// The clocks were paused by a divergence or a replay's mismatch, not by the user.
    paused_by_alarm: bool,
    /// The scene came from a recording (no file of its own to watch).
    embedded: bool,
    /// The scene file as a recording's header names it.
    scene_file: String,
    recording: Option<LiveRecording>,
    recordings: Vec<FinishedRecording>,
    replay: Option<SessionReplay>,
    last_replay: Option<ReplayVerdict>,
    /// Replays opened, a seek in one opening it again ([`Session::replays_opened`]).
    replays_opened: u64,
    /// Where recordings without a named file go ([`recording::DEFAULT_DIR`] under it); empty,
    /// the default, is the working directory.
    pub recordings_dir: PathBuf,
    /// Memory budget of each lane's timeline (bytes).
    history_budget: usize,
    /// Playing backwards: sim time owed to the reverse playback (scaled by the time scale).
    reverse: Option<Duration>,
    /// The tick from which a new command last dropped the recorded future.
    future_dropped_at: Option<u64>,
    /// How every lane is drawn between (or past) its ticks.
    draw: DrawMode,
    /// The refresh interval the snapping and quantising policies are given.
    refresh: Duration,
    /// The first lane's last frames, for the pacing view and the judder ghosts.
    pacing: pacing::PacingLog,
}

/// Why the scene refuses the compare lanes it cannot run (`exact: ...; exact: ...`), if it
/// refuses any: the window's panel and `volley window --compare` say it in the same words.
pub fn compare_refusals(lanes: &[CompareLane], scene: &Scene) -> Option<String> {
    let mut refusals: Vec<String> = lanes
        .iter()
        .filter_map(|l| l.apply(scene).err())
        .map(|e| e.message)
        .collect();
    refusals.dedup();
    (!refusals.is_empty()).then(|| refusals.join("; "))
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
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut session = Session {
            bounds: SceneBounds::of_scene(&scene),
            scene,
            path: path.to_path_buf(),
            compare,
            equal_cost,
            lanes: Vec::new(),
            clock: ClockSettings {
                paused: false,
                time_scale: 1.0,
                policy: crate::pacing::DEFAULT_POLICY.with_refresh(DEFAULT_REFRESH),
            },
            last: FrameTicks::default(),
            threads,
            paused_by_alarm: false,
            embedded: false,
            scene_file: path.display().to_string(),
            recording: None,
            recordings: Vec::new(),
            replay: None,
            last_replay: None,
            replays_opened: 0,
            recordings_dir: PathBuf::new(),
            history_budget: crate::timeline::DEFAULT_BUDGET,
            reverse: None,
            future_dropped_at: None,
            draw: crate::pacing::DEFAULT_DRAW,
            refresh: DEFAULT_REFRESH,
            pacing: pacing::PacingLog::default(),
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

    /// The scene each lane runs: its integrator, and its own dt and substeps where given; with
    /// equal cost on, every lane after the first gets the dt at which it spends the first
    /// lane's force evaluations per simulated second (`dt_i = dt_0 e_i s_i / (e_0 s_0)` for
    /// `e` evaluations a step and `s` substeps; a lane of the closed form, which spends none,
    /// keeps its own). Lanes the scene refuses are left out.
    pub fn lane_scenes(&self) -> Vec<Scene> {
        let specs = if self.compare.is_empty() {
            vec![CompareLane::of(self.scene.integrator())]
        } else {
            self.compare.clone()
        };
        let mut scenes: Vec<Scene> = specs
            .iter()
            .filter_map(|l| l.apply(&self.scene).ok())
            .collect();
        if self.equal_cost && scenes.len() > 1 {
            let cost = |s: &Scene| {
                s.integrator().evals_per_step(s.forces()) as f64 * f64::from(s.substeps())
            };
            let (dt0, cost0) = (scenes[0].dt(), cost(&scenes[0]));
            for s in scenes.iter_mut().skip(1) {
                let c = cost(s);
                if c > 0.0 && cost0 > 0.0 {
                    let _ = s.set_dt(dt0 * c / cost0);
                }
            }
        }
        scenes
    }

    /// Builds every lane afresh at tick 0. If the scene refuses every compared integrator
    /// (`exact` without a closed form), compare mode ends and one lane of the scene's integrator
    /// runs; the refusal says so. If it refuses some, the others run and the refusal names the
    /// ones left out, with the scene's reason.
    fn build_lanes(&mut self) -> Result<(), String> {
        let mut refused = Ok(());
        let mut scenes = self.lane_scenes();
        if scenes.is_empty() {
            refused = Err(format!(
                "none of the compared integrators can run this scene; showing {}",
                self.scene.integrator()
            ));
            self.compare.clear();
            scenes = self.lane_scenes();
        } else if let Some(reasons) = compare_refusals(&self.compare, &self.scene) {
            refused = Err(format!("compare mode leaves out {reasons}"));
        }
        let origin = self.bounds.center();
        self.lanes = scenes
            .into_iter()
            .map(|scene| {
                let mut world = World::new(&scene);
                world.set_threads(self.threads);
                let mut sim = SimLoop::new(world);
                self.tune(&mut sim);
                Lane::new(sim, origin, Some(self.history_budget))
            })
            .collect();
        self.last = FrameTicks::default();
        self.pacing.rebase();
        refused
    }

    /// Applies the shared clock settings (pause, time scale) to a new lane's clock.
    fn tune(&self, sim: &mut SimLoop) {
        if self.clock.paused {
            sim.clock.pause();
        }
        let _ = sim.clock.set_time_scale(self.clock.time_scale);
        sim.clock.set_policy(self.clock.policy);
    }

    /// One frame: every running lane advances its clock by `delta` and runs the ticks it grants
    /// (the first lane through its recorder or its replay, when it has one). A lane that
    /// diverges stops and pauses every clock; a recording of the first lane ends with its
    /// divergence. The frame's display time is not known ([`Session::frame_shown`]). Returns
    /// the last refusal the frame met: a command refused as it was applied, or a seek that
    /// failed while playing backwards.
    pub fn frame(&mut self, delta: Duration) -> Option<String> {
        self.frame_shown(delta, Shown::Unknown)
    }

    /// [`Session::frame`] for a frame shown at `shown`: the pacing log measures what it drew
    /// against the exact motion then.
    pub fn frame_shown(&mut self, delta: Duration, shown: Shown) -> Option<String> {
        let input = pacing::FrameInput {
            delta,
            shown,
            tick_before: self.lanes[0].sim.world.tick(),
            paused: self.clock.paused,
            reversing: self.reverse.is_some(),
            time_scale: self.clock.time_scale,
            draw: self.draw,
        };
        let refused = self.advance(delta);
        self.pacing.record(&self.lanes[0], input);
        refused
    }

    /// Runs the frame's ticks (or goes back, playing backwards); returns the last refusal met.
    fn advance(&mut self, delta: Duration) -> Option<String> {
        if self.reverse.is_some() {
            self.last = FrameTicks::default();
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
            let result = match (i, &mut self.replay, &mut self.recording) {
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
                    refused = Some(e.to_string());
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
        self.last = first.unwrap_or_default();
        if let Some(d) = self.lanes[0].stopped {
            let why =
                format!("the lane {d}; the recording ends there, and its replay reproduces it");
            self.stop_recording(&why);
        }
        if self.recording.as_ref().is_some_and(|r| r.error().is_some()) {
            self.stop_recording("a write failed");
        }
        alarm |= self.replay.as_mut().is_some_and(|r| {
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

    /// Pauses every clock on a divergence or a replay's mismatch, so the state stays on screen;
    /// a reset resumes what an alarm paused.
    fn alarm(&mut self) {
        if !self.clock.paused {
            self.set_paused(true);
            self.paused_by_alarm = true;
        }
    }

    /// While replaying, refuses `what` (it would change the simulation), saying why.
    fn refuse_while_replaying(&self, what: &str) -> Result<(), String> {
        match self.replay {
            Some(_) => Err(format!(
                "replaying: {what} is off (Go live, or L, takes over from this tick)"
            )),
            None => Ok(()),
        }
    }

    /// Queues `command` for the next tick of every lane. An integrator switch is refused in
    /// compare mode (each lane is its integrator); every command is refused while replaying.
    pub fn push(&mut self, command: Command) -> Result<(), String> {
        self.refuse_while_replaying(&format!("`{command}`"))?;
        if let (Command::SetIntegrator(_), true) = (command, self.is_comparing()) {
            return Err("compare mode runs every integrator at once".into());
        }
        if let Command::SetIntegrator(i) = command {
            check_integrator(i, self.lanes[0].sim.world.forces()).map_err(|e| e.to_string())?;
        }
        self.take_over_future();
        for lane in &mut self.lanes {
            lane.sim.push(command);
            lane.pushed += 1;
        }
        Ok(())
    }

    /// Aims every lane at the scene's target `target` on `arc` and fires: each lane solves the
    /// shot for its own integrator, dt and substeps with [`crate::firing::solve`] (speed from
    /// its launcher, the target where it is at this tick), then gets its own `launch` command
    /// with the solved angles and a `fire`, so recordings and replays see them. A lane whose
    /// solve fails fires nothing; its note says why. Refused while replaying, and for a target
    /// the scene does not have.
    pub fn aim(&mut self, arc: crate::exact::Arc, target: usize) -> Result<(), String> {
        self.refuse_while_replaying("aim")?;
        if self.scene.targets().get(target).is_none() {
            return Err(format!("aim: the scene has no target {target}"));
        }
        self.take_over_future();
        for lane in &mut self.lanes {
            let world = &lane.sim.world;
            let outcome = aim_lane(world, target, arc);
            // The shot's id: the next one, after every body the queued commands spawn.
            let spawned: u64 = lane
                .sim
                .queued()
                .map(|c| match c.command {
                    Command::Fire | Command::Spawn(_) => 1,
                    Command::Reset => {
                        let s = world.scene();
                        s.bodies().len() as u64 + s.volley().map_or(0, |v| u64::from(v.count))
                    }
                    _ => 0,
                })
                .sum();
            let body = crate::world::BodyId(world.state().next_id + spawned);
            if let Ok(shot) = &outcome {
                lane.sim.push(Command::SetLaunch {
                    speed: Some(shot.speed),
                    elevation_deg: Some(shot.elevation_deg),
                    azimuth_deg: Some(shot.azimuth_deg),
                    position: None,
                });
                lane.sim.push(Command::Fire);
                lane.pushed += 2;
            }
            lane.aim = Some(AimNote {
                target,
                tick: lane.sim.world.tick(),
                body,
                outcome,
            });
        }
        Ok(())
    }

    /// Puts the bodies back with a `Reset` command (recordable; the tick keeps counting), which
    /// also lifts a divergence: the stopped lanes run again and a pause the divergence caused
    /// ends. In compare mode after a divergence it restarts every lane at tick 0 instead, so
    /// the lanes stay on one tick. Refused while replaying.
    pub fn reset(&mut self) -> Result<(), String> {
        self.refuse_while_replaying("reset")?;
        let stopped = self.lanes.iter().any(|l| l.stopped.is_some());
        let resume = stopped && self.paused_by_alarm;
        let done = if stopped && self.is_comparing() {
            self.restart(None, "reset after a divergence in compare mode")
        } else {
            for lane in &mut self.lanes {
                lane.stopped = None;
            }
            self.push(Command::Reset)
        };
        if resume {
            self.set_paused(false);
        }
        done
    }

    /// Starts again at tick 0, with `scene` if given (a reload or a pick: the file's own dt and
    /// integrator; it ends a replay), else the same scene with the integrator chosen in the
    /// running session (refused while replaying). A recording ends first, noting `why`. If the
    /// scene refuses every compared integrator, compare mode ends and the refusal says so.
    pub fn restart(&mut self, scene: Option<(Scene, PathBuf)>, why: &str) -> Result<(), String> {
        match scene {
            Some((scene, path)) => {
                self.end_replay();
                self.bounds = SceneBounds::of_scene(&scene);
                self.scene_file = path.display().to_string();
                self.scene = scene;
                self.path = path;
                self.embedded = false;
            }
            None => {
                self.refuse_while_replaying(why)?;
                self.keep_integrator_choice();
            }
        }
        self.stop_recording(&format!("{why}: the world restarted at tick 0"));
        self.build_lanes()
    }

    /// Outside compare mode, the integrator the user switched to becomes the one a restart
    /// starts with.
    fn keep_integrator_choice(&mut self) {
        if !self.is_comparing() {
            // The lane runs it, so the scene (which it was built from) accepts it.
            let _ = self
                .scene
                .set_integrator(self.lanes[0].sim.world.integrator());
        }
    }

    /// Changes the timestep (s) and restarts at tick 0 with it.
    pub fn set_dt(&mut self, dt: f64) -> Result<(), String> {
        self.set_step(dt, self.scene.substeps())
    }

    /// Changes the timestep (s) and the integrator steps per tick, and restarts at tick 0 with
    /// them (nothing changes if either is refused, or while replaying).
    pub fn set_step(&mut self, dt: f64, substeps: u32) -> Result<(), String> {
        if self.replay.is_some() {
            return Err("replaying: the step is the recording's".into());
        }
        let mut scene = self.scene.clone();
        scene.set_dt(dt).map_err(|e| e.to_string())?;
        scene.set_substeps(substeps).map_err(|e| e.to_string())?;
        let why = match (
            scene.timestep() != self.scene.timestep(),
            scene.substeps() != self.scene.substeps(),
        ) {
            (true, true) => "dt and substeps changed",
            (false, true) => "substeps changed",
            _ => "dt changed",
        };
        // The checked scene with the new step (and nothing else changed).
        self.scene = scene;
        // The lanes were running this scene: a new step cannot make it refuse them all.
        self.restart(None, why)
    }

    /// Switches compare mode (an empty list turns it off) and restarts at tick 0; lanes of
    /// integrators already compared keep their own dt and substeps. Refused while replaying; if
    /// the scene refuses every integrator listed, one lane of its own runs and the refusal says
    /// so.
    pub fn set_compare(&mut self, integrators: Vec<Integrator>) -> Result<(), String> {
        let lanes = integrators
            .into_iter()
            .map(|i| {
                self.compare
                    .iter()
                    .find(|l| l.integrator == i)
                    .copied()
                    .unwrap_or(CompareLane::of(i))
            })
            .collect();
        self.set_compare_lanes(lanes)
    }

    /// Compare mode with these lanes (integrator, dt, substeps each) and restarts at tick 0,
    /// as [`Session::set_compare`] does.
    pub fn set_compare_lanes(&mut self, lanes: Vec<CompareLane>) -> Result<(), String> {
        self.refuse_while_replaying("compare mode")?;
        self.keep_integrator_choice();
        self.compare = lanes;
        self.stop_recording("compare mode switched: the world restarted at tick 0");
        self.build_lanes()
    }

    /// Sets compare lane `i`'s own dt and substeps (`None`: the scene's) and restarts at tick 0
    /// (nothing happens for a lane `i` that is not there). A step the scene refuses changes
    /// nothing and says why.
    pub fn set_lane_step(
        &mut self,
        i: usize,
        dt: Option<f64>,
        substeps: Option<u32>,
    ) -> Result<(), String> {
        let mut lanes = self.compare.clone();
        let Some(lane) = lanes.get_mut(i) else {
            return Ok(());
        };
        let trial = CompareLane {
            dt,
            substeps,
            ..*lane
        };
        trial.apply(&self.scene).map_err(|e| e.to_string())?;
        *lane = trial;
        self.set_compare_lanes(lanes)
    }

    /// Gives every compare lane the first lane's force evaluations per simulated second (or
    /// each its own step again) and restarts at tick 0. Refused while replaying.
    pub fn set_equal_cost(&mut self, on: bool) -> Result<(), String> {
        self.refuse_while_replaying("equal cost")?;
        self.equal_cost = on;
        self.stop_recording("equal cost switched: the world restarted at tick 0");
        self.build_lanes()
    }

    /// Whether compare lanes run at equal cost.
    pub fn is_equal_cost(&self) -> bool {
        self.equal_cost
    }

    /// Pauses or resumes every lane (the user's pause: it replaces a pause a divergence caused).
    pub fn set_paused(&mut self, paused: bool) {
        if !paused {
            self.reverse = None;
        }
        self.clock.paused = paused;
        self.paused_by_alarm = false;
        for lane in &mut self.lanes {
            if paused {
                lane.sim.clock.pause();
            } else {
                lane.sim.clock.resume();
            }
        }
    }

    /// Pauses and runs exactly one tick on the next frame, in every lane.
    pub fn single_step(&mut self) {
        self.clock.paused = true;
        for lane in &mut self.lanes {
            lane.sim.clock.single_step();
        }
    }

    /// Sets the time scale of every lane (0 to 100); a scale out of range changes nothing and
    /// says why.
    pub fn set_time_scale(&mut self, scale: f64) -> Result<(), String> {
        for lane in &mut self.lanes {
            lane.sim
                .clock
                .set_time_scale(scale)
                .map_err(|e| e.to_string())?;
        }
        self.clock.time_scale = scale;
        Ok(())
    }

    /// Whether the clocks are paused.
    pub fn is_paused(&self) -> bool {
        self.clock.paused
    }

    /// The shared time scale.
    pub fn time_scale(&self) -> f64 {
        self.clock.time_scale
    }

    /// The scene (with any dt override).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene file, or the recording the scene came from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the scene came from a recording (replayed, or gone live from a replay): there is
    /// no scene file to watch.
    pub fn is_embedded(&self) -> bool {
        self.embedded
    }

    /// Whether the clocks are paused because of a divergence or a replay's mismatch.
    pub fn paused_by_alarm(&self) -> bool {
        self.paused_by_alarm
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
        self.compare.iter().map(|l| l.integrator).collect()
    }

    /// The lanes of compare mode with their own steps (empty when off).
    pub fn compare_lanes(&self) -> &[CompareLane] {
        &self.compare
    }

    /// Whether compare mode is on.
    pub fn is_comparing(&self) -> bool {
        !self.compare.is_empty()
    }

    /// The region the scene plays in.
    pub fn bounds(&self) -> &SceneBounds {
        &self.bounds
    }

    /// What the last frame's clock decided (steps, alpha, dropped time).
    pub fn last_frame(&self) -> FrameTicks {
        self.last
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
                    mode: self.draw,
                    alpha: l.sim.clock.alpha(),
                    lead: self.pacing.lead(),
                },
                colour: l.colour(),
                // The pacing log measures the first lane.
                judder: if k == 0 { self.pacing.judder() } else { &[] },
            })
            .collect()
    }

    /// Every lane's loop policy.
    pub fn policy(&self) -> LoopPolicy {
        self.clock.policy
    }

    /// Gives every lane `policy` from the next frame (what the old one carried from frame to
    /// frame is forgotten; the accumulator and the tick stay). A policy decides how many ticks
    /// a frame runs, never what a tick computes, so it is not a command: a recording is the
    /// same under any.
    pub fn set_policy(&mut self, policy: LoopPolicy) {
        self.clock.policy = policy;
        for lane in &mut self.lanes {
            lane.sim.clock.set_policy(policy);
        }
    }

    /// [`Session::set_policy`] by name ([`LoopPolicy::NAMES`]), with the session's refresh; an
    /// unknown name is refused.
    pub fn set_policy_named(&mut self, name: &str) -> Result<(), String> {
        let policy = LoopPolicy::from_name(name, self.refresh).ok_or_else(|| {
            format!(
                "loop policy: unknown `{name}`, expected one of {}",
                LoopPolicy::NAMES.join(", ")
            )
        })?;
        self.set_policy(policy);
        Ok(())
    }

    /// The refresh interval the snapping and quantising policies are given.
    pub fn refresh(&self) -> Duration {
        self.refresh
    }

    /// Sets the refresh interval the game believes in (the emulated display's, or the
    /// monitor's); the policy in use takes it.
    pub fn set_refresh(&mut self, refresh: Duration) {
        self.refresh = refresh;
        self.set_policy(self.clock.policy.with_refresh(refresh));
    }

    /// How every lane is drawn.
    pub fn draw_mode(&self) -> DrawMode {
        self.draw
    }

    /// Draws every lane with `mode` from the next frame.
    pub fn set_draw_mode(&mut self, mode: DrawMode) {
        self.draw = mode;
    }

    /// The first lane's last frames.
    pub fn pacing(&self) -> &pacing::PacingLog {
        &self.pacing
    }

    /// Measures body `i` (storage index in the first lane) in the pacing view.
    pub fn set_pacing_body(&mut self, i: usize) {
        self.pacing.body = i;
    }
}
