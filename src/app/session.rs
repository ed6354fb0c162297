//! The simulations a window shows: one world, or in compare mode one per integrator, all driven
//! by the same frame deltas.
//!
//! Everything that changes a simulation goes through [`SimLoop::push`] as a [`Command`], applied
//! at the next tick boundary, so a recording of the session sees it. Pause, single step and time
//! scale set the clocks: they change when ticks run, never what a tick computes. Changing dt,
//! switching compare mode, picking or reloading a scene, and resetting a diverged run start the
//! scene again at tick 0, so sim time stays exactly `tick * dt`.

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::clock::FrameTicks;
use crate::command::Command;
use crate::integrate::Integrator;
use crate::render::draw::{self, Rgba};
use crate::render::{SceneBounds, TickHistory};
use crate::scene::{Scene, check_integrator};
use crate::sim_loop::{LoopError, SimLoop};
use crate::world::World;

/// One simulation of the session.
#[derive(Debug)]
pub struct Lane {
    /// The loop (world, clock, queued commands).
    pub sim: SimLoop,
    /// Previous state, trails and references for drawing.
    pub history: TickHistory,
    /// Why the lane stopped (a divergence), if it did.
    pub stopped: Option<String>,
    /// Commands pushed to this lane so far.
    pub pushed: u64,
    /// Commands the loop refused.
    pub refused: u64,
}

impl Lane {
    /// The colour of the lane's integrator.
    pub fn colour(&self) -> Rgba {
        draw::integrator_colour(self.sim.world.integrator())
    }

    /// Commands pushed but not yet applied (they wait for the next tick).
    pub fn pending(&self) -> u64 {
        self.pushed - self.history.commands_applied() - self.refused
    }
}

/// Clock settings that survive a restart.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ClockSettings {
    paused: bool,
    time_scale: f64,
}

/// The scene, its lanes, and the clock settings they share.
#[derive(Debug)]
pub struct Session {
    scene: Scene,
    path: PathBuf,
    compare: Vec<Integrator>,
    lanes: Vec<Lane>,
    bounds: SceneBounds,
    clock: ClockSettings,
    last: FrameTicks,
    threads: usize,
    /// The last command or setting that was refused, for the panel.
    pub last_error: Option<String>,
}

impl Session {
    /// A session on `scene` (read from `path`); `compare` lists the integrators of compare mode
    /// (empty: one lane with the scene's integrator).
    pub fn new(scene: Scene, path: &Path, compare: Vec<Integrator>) -> Session {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut session = Session {
            bounds: SceneBounds::of_scene(&scene),
            scene,
            path: path.to_path_buf(),
            compare,
            lanes: Vec::new(),
            clock: ClockSettings {
                paused: false,
                time_scale: 1.0,
            },
            last: FrameTicks::default(),
            threads,
            last_error: None,
        };
        session.build_lanes();
        session
    }

    fn build_lanes(&mut self) {
        let integrators = if self.compare.is_empty() {
            vec![self.scene.integrator]
        } else {
            self.compare.clone()
        };
        let origin = self.bounds.center();
        self.lanes = integrators
            .into_iter()
            .filter(|i| check_integrator(*i, &self.scene.forces).is_ok())
            .map(|integrator| {
                let mut scene = self.scene.clone();
                scene.integrator = integrator;
                let mut world = World::new(&scene);
                world.set_threads(self.threads);
                let mut sim = SimLoop::new(world);
                if self.clock.paused {
                    sim.clock.pause();
                }
                let _ = sim.clock.set_time_scale(self.clock.time_scale);
                let history = TickHistory::new(&sim.world, origin);
                Lane {
                    sim,
                    history,
                    stopped: None,
                    pushed: 0,
                    refused: 0,
                }
            })
            .collect();
        if self.lanes.is_empty() {
            // Every compared integrator was refused (exact without a closed form): fall back.
            self.last_error = Some(format!(
                "none of the compared integrators can run this scene; showing {}",
                self.scene.integrator
            ));
            self.compare.clear();
            self.build_lanes();
        }
        self.last = FrameTicks::default();
    }

    /// One frame: every running lane advances its clock by `delta` and runs the ticks it grants.
    pub fn frame(&mut self, delta: Duration) {
        let mut first = None;
        for lane in &mut self.lanes {
            if lane.stopped.is_some() {
                continue;
            }
            match lane.sim.frame(delta, &mut lane.history) {
                Ok(ticks) => {
                    first.get_or_insert(ticks);
                }
                Err(LoopError::Diverged(d)) => lane.stopped = Some(d.to_string()),
                Err(e) => {
                    lane.refused += 1;
                    self.last_error = Some(e.to_string());
                }
            }
        }
        self.last = first.unwrap_or_default();
    }

    /// Queues `command` for the next tick of every lane. An integrator switch is refused in
    /// compare mode (each lane is its integrator).
    pub fn push(&mut self, command: Command) {
        if let (Command::SetIntegrator(_), true) = (command, self.is_comparing()) {
            self.last_error = Some("compare mode runs every integrator at once".into());
            return;
        }
        if let Command::SetIntegrator(i) = command
            && let Err(e) = check_integrator(i, self.lanes[0].sim.world.forces())
        {
            self.last_error = Some(e);
            return;
        }
        for lane in &mut self.lanes {
            lane.sim.push(command);
            lane.pushed += 1;
        }
    }

    /// Puts the bodies back: a `Reset` command, or a restart at tick 0 when a lane has
    /// diverged (a stopped world cannot step again).
    pub fn reset(&mut self) {
        if self.lanes.iter().any(|l| l.stopped.is_some()) {
            self.restart(None);
        } else {
            self.push(Command::Reset);
        }
    }

    /// Starts again at tick 0, with `scene` if given (a reload or a pick: the file's own dt and
    /// integrator), else the same scene with the integrator chosen in the running session.
    pub fn restart(&mut self, scene: Option<(Scene, PathBuf)>) {
        match scene {
            Some((scene, path)) => {
                self.bounds = SceneBounds::of_scene(&scene);
                self.scene = scene;
                self.path = path;
            }
            None => self.keep_integrator_choice(),
        }
        self.build_lanes();
    }

    /// Outside compare mode, the integrator the user switched to becomes the one a restart
    /// starts with.
    fn keep_integrator_choice(&mut self) {
        if !self.is_comparing() {
            self.scene.integrator = self.lanes[0].sim.world.integrator();
        }
    }

    /// Changes the timestep (s) and restarts at tick 0 with it.
    pub fn set_dt(&mut self, dt: f64) -> Result<(), String> {
        self.scene.set_dt(dt)?;
        self.restart(None);
        Ok(())
    }

    /// Switches compare mode (an empty list turns it off) and restarts at tick 0.
    pub fn set_compare(&mut self, integrators: Vec<Integrator>) {
        self.keep_integrator_choice();
        self.compare = integrators;
        self.build_lanes();
    }

    /// Pauses or resumes every lane.
    pub fn set_paused(&mut self, paused: bool) {
        self.clock.paused = paused;
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

    /// Sets the time scale of every lane (0 to 100).
    pub fn set_time_scale(&mut self, scale: f64) {
        for lane in &mut self.lanes {
            if let Err(e) = lane.sim.clock.set_time_scale(scale) {
                self.last_error = Some(e.to_string());
                return;
            }
        }
        self.clock.time_scale = scale;
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

    /// The scene file.
    pub fn path(&self) -> &Path {
        &self.path
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
    pub fn compare(&self) -> &[Integrator] {
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
            .map(|l| draw::Lane {
                world: &l.sim.world,
                history: &l.history,
                alpha: l.sim.clock.alpha(),
                colour: l.colour(),
            })
            .collect()
    }
}
