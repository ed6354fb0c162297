//! The [`FrameWriter`] that `volley headless --frames` runs as a tick observer: the world drawn
//! offscreen every few ticks and written as PNG files (a desktop feature: a page writes no
//! files, and reading a frame back blocks on the GPU).

use std::path::{Path, PathBuf};

use crate::render::bounds::SceneBounds;
use crate::render::camera::{OrbitCamera, Viewport};
use crate::render::capture::{CaptureError, OFFSCREEN_FORMAT, OffscreenTarget};
use crate::render::draw::{DrawOptions, Lane, integrator_colour};
use crate::render::gpu::Gpu;
use crate::render::history::TickHistory;
use crate::render::renderer::{Renderer, View};
use crate::sim_loop::{ObserverError, TickObserver};
use crate::world::World;

/// Writes a PNG of the world every `every` ticks while a headless run steps it: a tick
/// observer around the same renderer the window uses, at alpha 1 (each file shows its tick).
pub struct FrameWriter {
    gpu: Gpu,
    renderer: Renderer,
    target: OffscreenTarget,
    history: TickHistory,
    camera: OrbitCamera,
    options: DrawOptions,
    dir: PathBuf,
    every: u64,
    written: u64,
}

impl FrameWriter {
    /// A writer for `world` (at its current tick) into folder `dir` (created if missing), with
    /// frames of `size` pixels every `every` ticks (at least 1).
    pub fn new(
        gpu: Gpu,
        world: &World,
        dir: &Path,
        size: (u32, u32),
        every: u64,
    ) -> Result<FrameWriter, CaptureError> {
        std::fs::create_dir_all(dir)
            .map_err(|e| CaptureError(format!("{}: cannot create: {e}", dir.display())))?;
        let bounds = SceneBounds::of_scene(world.scene());
        let renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT);
        let target = OffscreenTarget::new(&gpu, size, OFFSCREEN_FORMAT);
        Ok(FrameWriter {
            history: TickHistory::new(world, bounds.center()),
            camera: OrbitCamera::framing(&bounds, f64::from(size.0) / f64::from(size.1.max(1))),
            options: DrawOptions::picture(bounds.center(), bounds.radius()),
            renderer,
            target,
            gpu,
            dir: dir.to_path_buf(),
            every: every.max(1),
            written: 0,
        })
    }

    /// PNG files written so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    /// Renders the world as it is now and writes `tick_NNNNNN.png`.
    pub fn write(&mut self, world: &World) -> Result<(), CaptureError> {
        let size = self.target.size();
        let view = View {
            camera: self.camera,
            viewport: Viewport::full(size.0, size.1),
            target_size: size,
        };
        let lane = Lane {
            world,
            history: &self.history,
            at: crate::render::history::DrawAt::interpolated(1.0),
            colour: integrator_colour(world.integrator()),
            judder: &[],
        };
        self.renderer
            .render(&self.gpu, self.target.view(), &[lane], &view, &self.options);
        let image = self.target.read(&self.gpu)?;
        image.save_png(&self.dir.join(format!("tick_{:06}.png", world.tick())))?;
        self.written += 1;
        Ok(())
    }
}

impl TickObserver for FrameWriter {
    fn on_command(
        &mut self,
        world: &World,
        stamped: &crate::command::Stamped,
    ) -> Result<(), ObserverError> {
        self.history.on_command(world, stamped)
    }

    fn before_last_tick(&mut self, world: &World) {
        self.history.before_last_tick(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.history.after_tick(world)?;
        if world.tick().is_multiple_of(self.every) {
            self.write(world)
                .map_err(|e| ObserverError(e.to_string()))?;
        }
        Ok(())
    }
}

/// Steps each of `worlds` by `ticks` and writes one PNG of `size` pixels to `path`: every world
/// as a lane of the window's compare mode, with its trail and the closed form's dashed ghost,
/// framed as the window frames the first world's scene (what `volley` without a display writes).
pub fn write_picture(
    gpu: Gpu,
    worlds: Vec<World>,
    ticks: u64,
    size: (u32, u32),
    path: &Path,
) -> Result<(), CaptureError> {
    use crate::sim_loop::SimLoop;
    let Some(first) = worlds.first() else {
        return Err(CaptureError("no world to draw".into()));
    };
    let bounds = SceneBounds::of_scene(first.scene());
    let mut lanes = Vec::with_capacity(worlds.len());
    for world in worlds {
        let mut history = TickHistory::new(&world, bounds.center());
        let step = world.scene().timestep();
        let mut sim = SimLoop::new(world);
        sim.run_until(
            ticks,
            &mut crate::clock::VirtualClock::Steady(step),
            &mut history,
        )
        .map_err(|e| CaptureError(e.to_string()))?;
        lanes.push((sim.world, history));
    }
    let mut renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT);
    let target = OffscreenTarget::new(&gpu, size, OFFSCREEN_FORMAT);
    let view = View {
        camera: OrbitCamera::framing(&bounds, f64::from(size.0) / f64::from(size.1.max(1))),
        viewport: Viewport::full(size.0, size.1),
        target_size: size,
    };
    let drawn: Vec<Lane> = lanes
        .iter()
        .map(|(world, history)| Lane {
            world,
            history,
            at: crate::render::history::DrawAt::interpolated(1.0),
            colour: integrator_colour(world.integrator()),
            judder: &[],
        })
        .collect();
    let options = DrawOptions::picture(bounds.center(), bounds.radius());
    renderer.render(&gpu, target.view(), &drawn, &view, &options);
    target.read(&gpu)?.save_png(path)
}
