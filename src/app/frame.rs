//! Drawing a frame: the scene and the panel into the surface, or into an offscreen texture for a
//! screenshot, through the same code.

use std::path::Path;

use super::session::Session;
use super::{App, AppError};
use crate::platform;
use crate::render::{DrawOptions, Image, OffscreenTarget, View};

impl App {
    /// Draws the frame into the next surface texture and presents it, returning the screen it
    /// was drawn for (nothing while the surface has nothing to give: minimised, occluded,
    /// rebuilt).
    pub(super) fn present(
        &mut self,
        primitives: &[egui::ClippedPrimitive],
        ppp: f32,
    ) -> Option<egui_wgpu::ScreenDescriptor> {
        let gfx = self.host.gfx.as_mut()?;
        let size = gfx.size();
        let frame = gfx.acquire()?;
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: ppp,
        };
        let ui = FrameUi {
            primitives,
            screen: &screen,
        };
        let target = frame.texture.create_view(&Default::default());
        let scene = crate::render::capture::view_in(&frame.texture, gfx.scene_format());
        let targets = Targets {
            scene: scene.as_ref().unwrap_or(&target),
            ui: &target,
        };
        self.draw(&targets, &ui);
        if let Some(gfx) = self.host.gfx.as_mut() {
            gfx.gpu.queue.present(frame);
            gfx.refresh();
        }
        self.timing.stats.frames += 1;
        let frames = self.timing.stats.frames;
        platform::show_on_page(|| page_facts(&self.session, frames));
        Some(screen)
    }

    /// Draws the scene and the panel into `target` (the surface, or a capture of it).
    fn draw(&mut self, target: &Targets<'_>, ui: &FrameUi<'_>) {
        let (dragged, ring) = (self.dragged_launcher(), self.dragged_target());
        let Some(gfx) = self.host.gfx.as_mut() else {
            return;
        };
        let lanes = self.session.draw_lanes();
        let bounds = self.session.bounds();
        // While commands wait for the next tick (paused), the launcher shows the panel's aim.
        let waiting = self.session.lanes().iter().any(|l| l.pending() > 0);
        let queued = waiting.then(|| crate::scene::Launcher {
            speed: self.ui.panel.speed,
            elevation_deg: self.ui.panel.elevation_deg,
            azimuth_deg: self.ui.panel.azimuth_deg,
            ..*self.session.world().launcher()
        });
        // A drag under way shows its launcher first.
        let aim = dragged.or(queued);
        let options = DrawOptions {
            origin: bounds.center(),
            scale: bounds.radius(),
            trails: self.ui.toggles.trails,
            ghosts: self.ui.toggles.ghosts,
            aim,
            markers: self.ui.toggles.markers,
            vectors: self.ui.toggles.vectors.then(|| {
                crate::render::draw::ArrowScale::of(self.session.world(), bounds.radius())
            }),
            highlight: ring.or(self.ui.probe.as_ref().map(|p| p.at.p)),
            judder: self.ui.toggles.judder,
        };
        let view = View {
            camera: self.view.camera,
            viewport: self.view.viewport,
            target_size: gfx.size(),
        };
        gfx.renderer.prepare(&gfx.gpu, &lanes, &view, &options);
        let device = &gfx.gpu.device;
        let mut encoder = device.create_command_encoder(&Default::default());
        gfx.renderer.encode(&mut encoder, target.scene);
        let extra = gfx.egui.update_buffers(
            device,
            &gfx.gpu.queue,
            &mut encoder,
            ui.primitives,
            ui.screen,
        );
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("panel"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target.ui,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui
                .render(&mut pass.forget_lifetime(), ui.primitives, ui.screen);
        }
        gfx.gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
    }

    /// Screenshots and the frame limit, after a frame was presented.
    pub(super) fn after_present(&mut self, ui: &FrameUi<'_>) {
        let done = self
            .options
            .exit_after_frames
            .is_some_and(|n| self.timing.stats.frames >= n);
        let path = match (self.screenshot.take(), done) {
            (Some(p), _) => Some(p),
            (None, true) => self.options.screenshot.clone(),
            (None, false) => None,
        };
        if let Some(path) = path
            && let Err(e) = self.capture(&path, ui)
        {
            self.ending = Some(Err(AppError::Io(e)));
        }
        if done {
            self.quit();
        }
    }

    /// Saves a screenshot of the frame as `path` (a PNG file on the desktop, a download in a
    /// page: [`platform::save_screenshot`]).
    fn capture(&mut self, path: &Path, ui: &FrameUi<'_>) -> Result<(), String> {
        platform::save_screenshot(path, |path| self.write_png(path, ui))
    }

    /// Draws the frame again into an offscreen texture of the surface's size and format, through
    /// the same [`App::draw`], and writes it as a PNG.
    fn write_png(&mut self, path: &Path, ui: &FrameUi<'_>) -> Result<(), String> {
        let Some(gfx) = self.host.gfx.as_ref() else {
            return Ok(());
        };
        let target =
            OffscreenTarget::with_views(&gfx.gpu, gfx.size(), gfx.format(), gfx.scene_format());
        let targets = Targets {
            scene: target.scene_view(),
            ui: target.view(),
        };
        self.draw(&targets, ui);
        let Some(gfx) = self.host.gfx.as_ref() else {
            return Ok(());
        };
        let image: Image = target.read(&gfx.gpu).map_err(|e| e.to_string())?;
        image.save_png(path).map_err(|e| e.to_string())
    }
}

/// What a page shows on its canvas after a frame (`data-KEY`, for tests and curious users): the
/// frame count, the first lane's tick, the scene's name, the lanes' integrators and how many of
/// them fired their last aim, and while replaying, the replay's verdict line (the one
/// `volley replay --verify` prints). Asked for only in a browser ([`platform::show_on_page`]).
fn page_facts(session: &Session, frames: u64) -> Vec<(&'static str, String)> {
    let lanes = session.lanes();
    let integrators: Vec<&str> = lanes
        .iter()
        .map(|lane| lane.sim.world.integrator().name())
        .collect();
    let fired = lanes
        .iter()
        .filter(|lane| lane.aim.as_ref().is_some_and(|aim| aim.outcome.is_ok()))
        .count();
    let mut facts = vec![
        ("frames", frames.to_string()),
        ("tick", session.world().tick().to_string()),
        ("scene", session.scene().name().to_string()),
        ("lanes", integrators.join(",")),
        ("aims", fired.to_string()),
    ];
    if let Some(verdict) = session.replay_verdict() {
        facts.push(("replay", verdict.line()));
    }
    facts
}

/// Two views of the texture a frame draws into (the same view twice where the adapter cannot
/// view a surface in another format).
struct Targets<'a> {
    /// The 3D view's: sRGB, since its shaders output linear colour.
    scene: &'a wgpu::TextureView,
    /// egui's: the texture's own format, blended in gamma space as egui expects.
    ui: &'a wgpu::TextureView,
}

/// The panel's share of a frame, for drawing it (again, for a capture).
pub(super) struct FrameUi<'a> {
    /// egui's meshes.
    pub(super) primitives: &'a [egui::ClippedPrimitive],
    /// The surface's size and scale they are drawn for.
    pub(super) screen: &'a egui_wgpu::ScreenDescriptor,
}
