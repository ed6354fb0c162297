//! The setup a run starts from: running ahead before the window opens, moving a target,
//! and the setup as a scene file ("Save setup").

use super::Session;

impl Session {
    /// Runs every lane `ticks` ticks ahead at once, through its observers (the timeline, the
    /// plots, the passes), without drawing: `--warm-up-ticks`, so a window opens with history.
    /// The clocks are left as they were, at the new tick. Refused while replaying; returns the
    /// last lane's error (a command refused as it was applied), if any.
    pub fn run_ticks(&mut self, ticks: u64) -> Result<(), String> {
        self.refuse_while_replaying("warming up")?;
        let mut refused = Ok(());
        for lane in &mut self.lanes {
            let saved = lane.sim.clock.clone();
            let to = lane.sim.world.tick() + ticks;
            let mut source = lane.sim.unpaced_source(64);
            if let Err(e) = lane.sim.run_until(to, &mut source, &mut lane.history) {
                refused = Err(e.to_string());
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
    pub fn move_target(&mut self, index: usize, center: glam::DVec3) -> Result<(), String> {
        self.refuse_while_replaying("moving a target")?;
        let mut targets = self.scene.targets().to_vec();
        let Some(target) = targets.get_mut(index) else {
            return Err(format!("no target {index}"));
        };
        target.center = center;
        self.scene = self
            .scene
            .edit()
            .targets(targets)
            .launcher(*self.lanes[0].sim.world.launcher())
            .build()
            .map_err(|e| e.to_string())?;
        self.restart(None, &format!("target {index} moved"))
    }

    /// The setup as a scene: the scene with the first lane's launcher, integrator and force
    /// terms as they are now, the current dt and substeps, and the compare lanes. Its bodies
    /// and volley are the scene's own (a setup is where a run starts, not where it got to).
    pub fn setup(&self) -> Result<crate::scene::Scene, String> {
        let world = self.world();
        let mut scene = self
            .scene
            .edit()
            .launcher(*world.launcher())
            .compare(self.compare.clone())
            .build()
            .map_err(|e| e.to_string())?;
        scene
            .set_integrator(world.integrator())
            .map_err(|e| e.to_string())?;
        Ok(scene)
    }

    /// Writes [`Session::setup`] as `DIR/setups/SCENE-tickN.ron` and returns the path. A
    /// browser page, which writes no files, offers it as a download of that name instead.
    pub fn save_setup(&self, dir: &std::path::Path) -> Result<std::path::PathBuf, String> {
        let setup = self.setup()?;
        #[cfg(target_arch = "wasm32")]
        {
            let _ = dir;
            let name = setup.name.replace([' ', '/'], "_");
            let file = format!("{name}-tick{}.ron", self.world().tick());
            crate::app::web::download(&file, setup.to_ron().as_bytes(), "text/plain");
            Ok(std::path::PathBuf::from(format!("{file} (downloaded)")))
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let folder = dir.join("setups");
            std::fs::create_dir_all(&folder).map_err(|e| format!("{}: {e}", folder.display()))?;
            let name = setup.name().replace([' ', '/'], "_");
            let path = folder.join(format!("{name}-tick{}.ron", self.world().tick()));
            std::fs::write(&path, setup.to_ron())
                .map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(path)
        }
    }
}
