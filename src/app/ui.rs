//! The window's UI state: what the panel holds, what the view shows besides the bodies, the
//! pointer, the probe and a setup drag under way; and how the panels are laid out in a frame.

use winit::event::MouseButton;

use super::panel::{self, FrameStats, PanelState};
use super::pick;
use super::setup_drag::SetupDrag;
use super::view::SceneView;
use super::{Action, Session};
use crate::render::probe::Probe;

/// Mouse state between events.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Pointer {
    pub(super) position: Option<(f64, f64)>,
    pub(super) dragging: Option<MouseButton>,
    /// The button held has moved the pointer (a drag, not a click).
    pub(super) moved: bool,
    pub(super) shift: bool,
}

/// What the view shows besides the bodies.
#[derive(Clone, Copy, Debug)]
pub(super) struct Toggles {
    pub(super) trails: bool,
    /// The closed-form ghosts: dashed trajectories and the sphere where the exact solution is.
    pub(super) ghosts: bool,
    pub(super) panel: bool,
    pub(super) plots: bool,
    pub(super) markers: bool,
    pub(super) vectors: bool,
    /// The pacing view beside the plots.
    pub(super) pacing: bool,
    /// The judder ghosts: the measured body's last drawn positions beside the exact ones.
    pub(super) judder: bool,
}

/// Everything the window's user handles besides the simulation: the panel's widgets and notes,
/// the view's toggles, the pointer, the probe, a setup drag, and the panel's named controls.
pub(super) struct UiState {
    /// The panel's widget values and notes.
    pub(super) panel: PanelState,
    /// What the view shows besides the bodies.
    pub(super) toggles: Toggles,
    /// The mouse between events.
    pub(super) pointer: Pointer,
    /// What the probe reads: under the pointer, or pinned by a click.
    pub(super) probe: Option<Probe>,
    /// The probe stays where it was clicked until the next click.
    pub(super) probe_pinned: bool,
    /// A drag of the launcher, its handle or a target under way.
    pub(super) setup_drag: Option<SetupDrag>,
    /// The panel's named controls as the last frame laid them out.
    pub(super) controls: panel::Controls,
}

impl UiState {
    /// The panel as `panel` holds it, the default toggles, no probe and no drag.
    pub(super) fn new(panel: PanelState) -> UiState {
        UiState {
            panel,
            toggles: Toggles {
                trails: true,
                ghosts: true,
                panel: true,
                plots: true,
                markers: true,
                vectors: false,
                pacing: false,
                judder: false,
            },
            pointer: Pointer::default(),
            probe: None,
            probe_pinned: false,
            setup_drag: None,
            controls: panel::Controls::default(),
        }
    }

    /// Points the probe at what is under the pointer on the 3D view (nothing off it or while a
    /// button drags), unless it is pinned. `scale` is the window's scale factor.
    pub(super) fn update_probe(&mut self, session: &Session, view: &SceneView, scale: f64) {
        if self.probe_pinned {
            return;
        }
        let over_view = self.pointer.position.is_some_and(|(x, y)| {
            let v = &view.viewport;
            let (x, y) = (x as f32, y as f32);
            x >= v.x && x < v.x + v.width && y >= v.y && y < v.y + v.height
        });
        self.probe = match self.pointer.position {
            Some((x, y)) if over_view && self.pointer.dragging.is_none() => pick::pick(
                session,
                &view.camera,
                &view.viewport,
                (x as f32, y as f32),
                pick::PICK_RADIUS * scale.max(1.0) as f32,
            ),
            _ => None,
        };
    }

    /// Lays out the frame's UI: the side panel and the bottom panel as toggled, the overlay
    /// and the probe's box on what they leave, which it returns (points): the 3D view's
    /// rectangle. What the user asked for goes to `actions`.
    pub(super) fn lay_out(
        &mut self,
        ui: &mut egui::Ui,
        session: &Session,
        stats: &FrameStats,
        actions: &mut Vec<Action>,
    ) -> egui::Rect {
        let show_panel = self.toggles.panel;
        let show_plots = self.toggles.plots;
        let show_pacing = self.toggles.pacing;
        if show_panel {
            egui::Panel::left("panel")
                .default_size(340.0)
                .show(ui, |ui| {
                    panel::show(ui, &mut self.panel, session, stats, actions)
                });
        }
        if show_plots || show_pacing {
            egui::Panel::bottom("plots")
                .resizable(true)
                .default_size(240.0)
                .min_size(190.0)
                .show(ui, |ui| {
                    let shown = panel::plots::BottomPanel {
                        plots: show_plots,
                        pacing: show_pacing,
                    };
                    panel::plots::show(ui, session, &mut self.panel, shown, actions)
                });
        }
        let rest = ui.available_rect_before_wrap();
        panel::overlay(ui.ctx(), rest, session);
        if let (Some(probe), Some((x, y))) = (&self.probe, self.pointer.position) {
            let ppp = ui.ctx().pixels_per_point();
            let at = egui::pos2(x as f32 / ppp + 16.0, y as f32 / ppp + 16.0);
            panel::probe_box(ui.ctx(), at, probe, self.probe_pinned);
        }
        rest
    }
}
