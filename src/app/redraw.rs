//! One frame, stage by stage: the loop advanced by the frame's delta, the UI built and
//! tessellated, the 3D view placed in what the panels left, the frame drawn and presented
//! ([`super::frame`]), then screenshots, the frame limit and the surface drill.

use crate::platform::Instant;

use winit::window::Window;

use super::App;
use super::frame::FrameUi;
use super::panel;
use super::view::viewport_of;

impl App {
    /// One frame, stage by stage.
    pub(super) fn redraw(&mut self) {
        let start = Instant::now();
        self.advance(start);
        let Some(window) = self.host.window.clone() else {
            return;
        };
        let Some(mut ui) = self.build_ui(&window) else {
            return;
        };
        self.upload_ui_textures(&mut ui.textures);
        self.place_view(ui.rest, ui.ppp);
        if let Some(screen) = self.present(&ui.primitives, ui.ppp) {
            let drawn = FrameUi {
                primitives: &ui.primitives,
                screen: &screen,
            };
            self.after_present(&drawn);
            self.drill();
        }
        self.free_ui_textures(ui.textures);
        let keep = self.options.exit_after_frames.is_some();
        self.timing.end_frame(start, &window, keep);
    }

    /// Advances the loop: the script's actions due now, the frame's delta, a saved scene
    /// reloaded, the lanes run for the delta; the panel's values follow the session unless
    /// commands still wait for a tick.
    fn advance(&mut self, start: Instant) {
        for action in self.script.due() {
            self.apply(action);
        }
        let frame = self.timing.frames.next_frame();
        self.check_reload(start);
        if let Some(why) = self.session.frame_shown(frame.delta, frame.shown) {
            self.refuse(why);
        }
        if self.session.lanes().iter().all(|l| l.pending() == 0) {
            let panel = &mut self.ui.panel;
            let (dt_ms, substeps) = (panel.dt_ms, panel.substeps);
            let pick = panel.compare_pick.clone();
            panel.sync(&self.session);
            // The step fields keep what is being typed until it is applied.
            (panel.dt_ms, panel.substeps) = (dt_ms, substeps);
            panel.compare_pick = pick;
        }
    }

    /// Builds the UI: the probe, the panels laid out with the script's queued input, what they
    /// asked for applied, and their shapes tessellated; the UI's time and triangles are
    /// measured. Nothing without egui's state (before the window opened).
    fn build_ui(&mut self, window: &Window) -> Option<BuiltUi> {
        self.host.egui_state.as_ref()?;
        let ui_start = Instant::now();
        let scale = self.timing.stats.scale;
        self.ui.update_probe(&self.session, &self.view, scale);
        let egui_state = self.host.egui_state.as_mut()?;
        let mut raw = egui_state.take_egui_input(window);
        if let Some(events) = self.script.next_input() {
            raw.events.extend(events);
        }
        let mut actions = Vec::new();
        let mut rest = egui::Rect::NOTHING;
        self.ui.panel.pacing_view = self.ui.toggles.pacing;
        self.ui.panel.judder_ghosts = self.ui.toggles.judder;
        let output = self.host.egui.run_ui(raw, |ui| {
            rest = self
                .ui
                .lay_out(ui, &self.session, &self.timing.stats, &mut actions);
        });
        egui_state.handle_platform_output(window, output.platform_output);
        self.ui.controls = panel::take_controls(&self.host.egui);
        // The UI's time leaves out what its actions do (a seek, an aim): that is simulation.
        let laid_out = ui_start.elapsed();
        for action in actions {
            self.apply(action);
        }
        let tessellating = Instant::now();
        let ppp = output.pixels_per_point;
        let primitives = self.host.egui.tessellate(output.shapes, ppp);
        self.timing.ui_ms = (laid_out + tessellating.elapsed()).as_secs_f64() * 1e3;
        self.timing.ui_triangles = primitives
            .iter()
            .map(|p| match &p.primitive {
                egui::epaint::Primitive::Mesh(m) => m.indices.len() / 3,
                egui::epaint::Primitive::Callback(_) => 0,
            })
            .sum();
        Some(BuiltUi {
            primitives,
            textures: output.textures_delta,
            ppp,
            rest,
        })
    }

    /// Sends egui's new and changed textures to its renderer.
    fn upload_ui_textures(&mut self, textures: &mut egui::TexturesDelta) {
        if let Some(gfx) = self.host.gfx.as_mut() {
            for (id, deltas) in textures.set.drain() {
                for delta in &deltas {
                    gfx.egui
                        .update_texture(&gfx.gpu.device, &gfx.gpu.queue, id, delta);
                }
            }
        }
    }

    /// Fits the 3D view into what the panels left (`rest`, points at `ppp` pixels per point),
    /// framing the scene if asked to.
    fn place_view(&mut self, rest: egui::Rect, ppp: f32) {
        if let Some(gfx) = self.host.gfx.as_ref() {
            self.view.viewport = viewport_of(rest, ppp, gfx.size());
        }
        self.view.frame_if_asked(self.session.bounds());
    }

    /// Frees the textures egui no longer uses, once the frame that may use them was drawn.
    fn free_ui_textures(&mut self, mut textures: egui::TexturesDelta) {
        if let Some(gfx) = self.host.gfx.as_mut() {
            for id in textures.free.drain() {
                gfx.egui.free_texture(&id);
            }
        }
        // Without a device (suspended) the deltas have nowhere to go; the context is replaced
        // when the device comes back.
        textures.clear();
    }

    /// `--surface-drill`'s next step, after a presented frame.
    fn drill(&mut self) {
        let (Some(drill), Some(window), Some(gfx)) = (
            self.drill.as_mut(),
            self.host.window.as_deref(),
            self.host.gfx.as_mut(),
        ) else {
            return;
        };
        drill.after_frame(self.timing.stats.frames, self.options.size, window, gfx);
    }
}

/// A frame's UI, built and tessellated, waiting to be drawn.
struct BuiltUi {
    /// egui's meshes.
    primitives: Vec<egui::ClippedPrimitive>,
    /// The textures egui sets and frees this frame.
    textures: egui::TexturesDelta,
    /// Pixels per point.
    ppp: f32,
    /// What the panels left for the 3D view (points).
    rest: egui::Rect,
}
