//! Starting again at tick 0: a new step (dt, substeps), compare mode switched or its lanes
//! changed, equal cost switched, a scene picked or reloaded. Sim time stays exactly
//! `tick * dt` because the lanes are built anew; a recording ends first, noting why. Refused
//! while replaying, except a new scene, which ends the replay.

use std::path::PathBuf;

use crate::integrate::Integrator;
use crate::scene::{CompareLane, Scene};
use crate::sim_loop::SimLoop;
use crate::world::World;

use super::{Change, Lane, Session, SessionError, compare_refusals};

impl Session {
    /// Builds every lane afresh at tick 0. If the scene refuses every compared integrator
    /// (`exact` without a closed form), compare mode ends and one lane of the scene's integrator
    /// runs; the refusal says so. If it refuses some, the others run and the refusal names the
    /// ones left out, with the scene's reason.
    pub(super) fn build_lanes(&mut self) -> Result<(), SessionError> {
        let mut refused = Ok(());
        let mut scenes = self.setup.lane_scenes();
        if scenes.is_empty() {
            refused = Err(SessionError::NoComparedLane {
                showing: self.setup.scene.integrator(),
            });
            self.setup.compare.clear();
            scenes = self.setup.lane_scenes();
        } else if let Some(reasons) = compare_refusals(&self.setup.compare, &self.setup.scene) {
            refused = Err(SessionError::LanesLeftOut(reasons));
        }
        let origin = self.setup.bounds.center();
        self.lanes = scenes
            .into_iter()
            .map(|scene| {
                let mut world = World::new(&scene);
                world.set_threads(self.setup.threads);
                let mut sim = SimLoop::new(world);
                self.tune(&mut sim);
                Lane::new(sim, origin, Some(self.rewind.budget))
            })
            .collect();
        self.clock.last = Default::default();
        self.pacing.log.rebase();
        refused
    }

    /// Starts again at tick 0, with `scene` if given (a reload or a pick: the file's own dt and
    /// integrator; it ends a replay), else the same scene with the integrator chosen in the
    /// running session (refused while replaying). A recording ends first, noting `why`. If the
    /// scene refuses every compared integrator, compare mode ends and the refusal says so.
    pub fn restart(
        &mut self,
        scene: Option<(Scene, PathBuf)>,
        why: &str,
    ) -> Result<(), SessionError> {
        match scene {
            Some((scene, path)) => {
                self.end_replay();
                self.setup.use_scene(scene, path);
            }
            None => {
                self.refuse_while_replaying(Change::Restart(why.to_string()))?;
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
                .setup
                .scene
                .set_integrator(self.lanes[0].sim.world.integrator());
        }
    }

    /// Changes the timestep (s) and restarts at tick 0 with it.
    pub fn set_dt(&mut self, dt: f64) -> Result<(), SessionError> {
        self.set_step(dt, self.setup.scene.substeps())
    }

    /// Changes the timestep (s) and the integrator steps per tick, and restarts at tick 0 with
    /// them (nothing changes if either is refused, or while replaying).
    pub fn set_step(&mut self, dt: f64, substeps: u32) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::Step)?;
        let mut scene = self.setup.scene.clone();
        scene.set_dt(dt).map_err(SessionError::Value)?;
        scene.set_substeps(substeps).map_err(SessionError::Value)?;
        let old = &self.setup.scene;
        let why = match (
            scene.timestep() != old.timestep(),
            scene.substeps() != old.substeps(),
        ) {
            (true, true) => "dt and substeps changed",
            (false, true) => "substeps changed",
            _ => "dt changed",
        };
        // The checked scene with the new step (and nothing else changed).
        self.setup.scene = scene;
        // The lanes were running this scene: a new step cannot make it refuse them all.
        self.restart(None, why)
    }

    /// Switches compare mode (an empty list turns it off) and restarts at tick 0; lanes of
    /// integrators already compared keep their own dt and substeps. Refused while replaying; if
    /// the scene refuses every integrator listed, one lane of its own runs and the refusal says
    /// so.
    pub fn set_compare(&mut self, integrators: Vec<Integrator>) -> Result<(), SessionError> {
        let lanes = integrators
            .into_iter()
            .map(|i| {
                self.setup
                    .compare
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
    pub fn set_compare_lanes(&mut self, lanes: Vec<CompareLane>) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::CompareMode)?;
        self.keep_integrator_choice();
        self.setup.compare = lanes;
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
    ) -> Result<(), SessionError> {
        let mut lanes = self.setup.compare.clone();
        let Some(lane) = lanes.get_mut(i) else {
            return Ok(());
        };
        let trial = CompareLane {
            dt,
            substeps,
            ..*lane
        };
        trial
            .apply(&self.setup.scene)
            .map_err(SessionError::Scene)?;
        *lane = trial;
        self.set_compare_lanes(lanes)
    }

    /// Gives every compare lane the first lane's force evaluations per simulated second (or
    /// each its own step again) and restarts at tick 0. Refused while replaying.
    pub fn set_equal_cost(&mut self, on: bool) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::EqualCost)?;
        self.setup.equal_cost = on;
        self.stop_recording("equal cost switched: the world restarted at tick 0");
        self.build_lanes()
    }

    /// Whether compare lanes run at equal cost.
    pub fn is_equal_cost(&self) -> bool {
        self.setup.equal_cost
    }
}
