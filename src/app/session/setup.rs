//! The setup a run starts from: the scene, its file, and the lanes it becomes (compare mode's
//! integrators with their own steps, at equal cost or not); running ahead before the window
//! opens, moving a target, and the setup as a scene file ("Save setup").

use std::path::{Path, PathBuf};

use crate::render::SceneBounds;
use crate::scene::{CompareLane, Scene};

use super::{Change, FileStep, Session, SessionError};

/// What a session's lanes are built from. A restart builds them anew from it.
#[derive(Debug)]
pub(super) struct Setup {
    /// The scene, with the step and integrator chosen in the window.
    pub(super) scene: Scene,
    /// The scene file, or the recording the scene came from.
    pub(super) path: PathBuf,
    /// The scene file as a recording's header names it.
    pub(super) scene_file: String,
    /// The scene came from a recording (no file of its own to watch).
    pub(super) embedded: bool,
    /// The region the scene plays in.
    pub(super) bounds: SceneBounds,
    /// Compare mode's lanes (empty: one lane of the scene's integrator).
    pub(super) compare: Vec<CompareLane>,
    /// Compare lanes after the first run at its force evaluations per simulated second.
    pub(super) equal_cost: bool,
    /// Threads each lane's world may step its bodies on.
    pub(super) threads: usize,
}

impl Setup {
    /// `scene` read from `path`, with these compare lanes, on every thread the machine has.
    pub(super) fn new(
        scene: Scene,
        path: &Path,
        compare: Vec<CompareLane>,
        equal_cost: bool,
    ) -> Setup {
        Setup {
            bounds: SceneBounds::of_scene(&scene),
            scene,
            path: path.to_path_buf(),
            scene_file: path.display().to_string(),
            embedded: false,
            compare,
            equal_cost,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        }
    }

    /// Takes `scene` read from `path` (a reload or a pick): its file is its own.
    pub(super) fn use_scene(&mut self, scene: Scene, path: PathBuf) {
        self.bounds = SceneBounds::of_scene(&scene);
        self.scene_file = path.display().to_string();
        self.scene = scene;
        self.path = path;
        self.embedded = false;
    }

    /// The scene each lane runs: its integrator, and its own dt and substeps where given; with
    /// equal cost on, every lane after the first gets the dt at which it spends the first
    /// lane's force evaluations per simulated second (`dt_i = dt_0 e_i s_i / (e_0 s_0)` for
    /// `e` evaluations a step and `s` substeps; a lane of the closed form, which spends none,
    /// keeps its own). Lanes the scene refuses are left out.
    pub(super) fn lane_scenes(&self) -> Vec<Scene> {
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
    /// Runs every lane `ticks` ticks ahead at once, through its observers (the timeline, the
    /// plots, the passes), without drawing: `--warm-up-ticks`, so a window opens with history.
    /// The clocks are left as they were, at the new tick. Refused while replaying; returns the
    /// last lane's error (a command refused as it was applied), if any.
    pub fn run_ticks(&mut self, ticks: u64) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::WarmUp)?;
        let mut refused = Ok(());
        for lane in &mut self.lanes {
            let saved = lane.sim.clock.clone();
            let to = lane.sim.world.tick() + ticks;
            let mut source = lane.sim.unpaced_source(64);
            if let Err(e) = lane.sim.run_until(to, &mut source, &mut lane.history) {
                refused = Err(SessionError::Loop(e));
            }
            lane.stopped = lane.sim.world.divergence();
            lane.sim.clock = saved;
            lane.sim.clock.set_tick(lane.sim.world.tick());
        }
        refused
    }

    /// Moves the scene's target `index` to `center` (a drag in the 3D view): the setup
    /// changes, so the scene restarts at tick 0 with it, like a dt change, keeping the
    /// launcher and integrator as they are now. Refused while replaying, and for a target the
    /// scene does not have.
    pub fn move_target(&mut self, index: usize, center: glam::DVec3) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::MoveTarget)?;
        let mut targets = self.setup.scene.targets().to_vec();
        let Some(target) = targets.get_mut(index) else {
            return Err(SessionError::NoTarget(index));
        };
        target.center = center;
        self.setup.scene = self
            .setup
            .scene
            .edit()
            .targets(targets)
            .launcher(*self.lanes[0].sim.world.launcher())
            .build()
            .map_err(SessionError::Scene)?;
        self.restart(None, &format!("target {index} moved"))
    }

    /// The setup as a scene: the scene with the first lane's launcher, integrator and force
    /// terms as they are now, the current dt and substeps, and the compare lanes. Its bodies
    /// and volley are the scene's own (a setup is where a run starts, not where it got to).
    pub fn setup(&self) -> Result<Scene, SessionError> {
        let world = self.world();
        let mut scene = self
            .setup
            .scene
            .edit()
            .launcher(*world.launcher())
            .compare(self.setup.compare.clone())
            .build()
            .map_err(SessionError::Scene)?;
        scene
            .set_integrator(world.integrator())
            .map_err(SessionError::Integrator)?;
        Ok(scene)
    }

    /// Writes [`Session::setup`] as `DIR/setups/SCENE-tickN.ron` and returns the path. A
    /// browser page, which writes no files, offers it as a download of that name instead
    /// ([`crate::platform::save_file`]).
    pub fn save_setup(&self, dir: &Path) -> Result<PathBuf, SessionError> {
        let setup = self.setup()?;
        let name = setup.name().replace([' ', '/'], "_");
        let file = format!("{name}-tick{}.ron", self.world().tick());
        let bytes = setup.to_ron();
        crate::platform::save_file(&dir.join("setups"), &file, bytes.as_bytes(), "text/plain")
            .map_err(|(path, e)| SessionError::io(path, FileStep::Save, e))
    }
}
