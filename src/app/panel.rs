//! The side panel (egui): the loop's state, the numerical error, and every control.
//!
//! The panel only reads the session; what the user asks for comes back as [`Action`]s. While a
//! replay runs, the controls that would change the simulation are greyed out.

mod alerts;
mod clock;
mod compare;
mod errors;
pub mod forces;
pub mod pacing;
pub mod plots;
mod record;
mod simulation;
mod timeline;

use std::path::PathBuf;

use egui::{Color32, Ui};

use crate::app::input::{Action, DEFAULT_COMPARE, MOUSE, SHORTCUTS};
use crate::app::session::Session;
use crate::integrate::Integrator;

pub use alerts::{cause, overlay};
pub use simulation::aimed_pass;

/// The panel's named controls of the last frame: each button's label and its rectangle
/// (points), so an input script can `click` a control by its label.
#[derive(Clone, Debug, Default)]
pub struct Controls(pub Vec<(String, egui::Rect)>);

fn controls_id() -> egui::Id {
    egui::Id::unique("volley named controls")
}

/// A button that input scripts can click by its label.
pub fn named_button(ui: &mut Ui, text: &str) -> egui::Response {
    let response = ui.button(text);
    let rect = response.rect;
    ui.ctx().data_mut(|d| {
        d.get_temp_mut_or_default::<Controls>(controls_id())
            .0
            .push((text.to_string(), rect));
    });
    response
}

/// Takes the controls registered since the last call (once a frame).
pub fn take_controls(ctx: &egui::Context) -> Controls {
    ctx.data_mut(|d| d.remove_temp::<Controls>(controls_id()))
        .unwrap_or_default()
}

/// What the panel remembers between frames: its widgets' values and the window's notes.
#[derive(Clone, Debug)]
pub struct PanelState {
    /// Launch speed (m/s) as the slider shows it.
    pub speed: f64,
    /// Elevation (degrees).
    pub elevation_deg: f64,
    /// Azimuth (degrees).
    pub azimuth_deg: f64,
    /// The timestep being edited (ms).
    pub dt_ms: f64,
    /// The substeps being edited.
    pub substeps: u32,
    /// The integrators ticked for compare mode.
    pub compare_pick: Vec<Integrator>,
    /// The target the aim buttons aim at (index in the scene).
    pub aim_target: usize,
    /// The plot shown when the window is too narrow for all three.
    pub plot_tab: usize,
    /// A note on the scene file: watched, reloaded, or why a reload failed.
    pub file_note: Option<(String, bool)>,
    /// Where the last "Save plots" or "Save setup" wrote, or why it could not.
    pub saved_note: Option<String>,
    /// The last command or setting the session refused, and [`Session::replays_opened`] when it
    /// was refused: shown until another refusal replaces it, a replay opens (a seek in one
    /// too) or the session goes live ([`PanelState::refusal`]).
    pub refused: Option<(String, u64)>,
    /// Bundled scenes, (name, path).
    pub scenes: Vec<(String, PathBuf)>,
    /// Where the frames come from (an emulated display, steady frames, the real clock).
    pub frames_note: String,
    /// Whether the pacing view is shown (the window's toggle, for the panel to say).
    pub pacing_view: bool,
    /// Whether the judder ghosts are shown.
    pub judder_ghosts: bool,
}

impl PanelState {
    /// Widget values taken from the session.
    pub fn new(session: &Session, scenes: Vec<(String, PathBuf)>) -> PanelState {
        let mut state = PanelState {
            speed: 0.0,
            elevation_deg: 0.0,
            azimuth_deg: 0.0,
            dt_ms: 0.0,
            substeps: 1,
            // The lanes running (`--compare`), else the default set to start compare mode with.
            compare_pick: if session.is_comparing() {
                session.compare().to_vec()
            } else {
                DEFAULT_COMPARE.to_vec()
            },
            aim_target: 0,
            plot_tab: 0,
            file_note: None,
            saved_note: None,
            refused: None,
            scenes,
            frames_note: "the real clock".into(),
            pacing_view: false,
            judder_ghosts: false,
        };
        state.sync(session);
        state
    }

    /// Takes the launcher and dt from the session (after a restart or a keyboard change).
    pub fn sync(&mut self, session: &Session) {
        let l = session.world().launcher();
        self.speed = l.speed;
        self.elevation_deg = l.elevation_deg;
        self.azimuth_deg = l.azimuth_deg;
        self.dt_ms = session.scene().dt() * 1e3;
        self.substeps = session.scene().substeps();
    }

    /// Shows `why` (in the words its `Display` gives) as the session's last refusal.
    pub fn refuse(&mut self, session: &Session, why: impl std::fmt::Display) {
        self.refused = Some((why.to_string(), session.replays_opened()));
    }

    /// The refusal to show: the last one, unless a replay opened since.
    pub fn refusal(&self, session: &Session) -> Option<&str> {
        match &self.refused {
            Some((why, opened)) if *opened == session.replays_opened() => Some(why),
            _ => None,
        }
    }
}

/// The timeline's note after a new command at `tick` dropped the recorded future.
pub fn future_dropped_note(tick: u64) -> String {
    format!("a new command at tick {tick}: the recorded future after it was dropped")
}

/// Frame timing and display facts for the panel.
#[derive(Clone, Debug, Default)]
pub struct FrameStats {
    /// Time between frames (ms), smoothed.
    pub interval_ms: f64,
    /// Time spent on a frame: stepping, building, encoding, presenting (ms), smoothed.
    pub work_ms: f64,
    /// Of that, the UI's CPU work: laying out the panel and the plots (egui, egui_plot) and
    /// tessellating them (ms), smoothed.
    pub ui_ms: f64,
    /// Frames drawn.
    pub frames: u64,
    /// The adapter.
    pub adapter: String,
    /// Window size (physical px) and scale factor.
    pub size: (u32, u32),
    /// Pixels per point.
    pub scale: f64,
}

/// An egui colour from a renderer colour.
fn colour(c: [u8; 4]) -> Color32 {
    Color32::from_rgb(c[0], c[1], c[2])
}

/// The probe's readout in a small window at `at` (points), pinned or following the pointer.
pub fn probe_box(
    ctx: &egui::Context,
    at: egui::Pos2,
    probe: &crate::render::probe::Probe,
    pinned: bool,
) {
    egui::Area::new(egui::Id::unique("volley probe"))
        .fixed_pos(at)
        .order(egui::Order::Tooltip)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                for line in probe.lines() {
                    ui.monospace(line);
                }
                ui.weak(if pinned {
                    "pinned: click the view to release"
                } else {
                    "click to pin"
                });
            });
        });
}

/// Draws the panel's contents.
pub fn show(
    ui: &mut Ui,
    state: &mut PanelState,
    session: &Session,
    stats: &FrameStats,
    out: &mut Vec<Action>,
) {
    egui::ScrollArea::vertical().show(ui, |ui| {
        header(ui, state, session, out);
        alerts::show(ui, session, out);
        ui.separator();
        record::show(ui, session, out);
        ui.separator();
        let live = session.replay().is_none();
        clock::show(ui, state, session, out);
        timeline::show(ui, session, out);
        ui.separator();
        pacing::controls(ui, state, session, out);
        ui.separator();
        ui.add_enabled_ui(live, |ui| simulation::show(ui, state, session, out));
        forces::show(ui, session);
        ui.separator();
        ui.add_enabled_ui(live, |ui| compare::show(ui, state, session, out));
        ui.separator();
        errors::show(ui, session);
        ui.separator();
        frame(ui, stats, out);
        egui::CollapsingHeader::new("Keyboard and mouse")
            .default_open(false)
            .show(ui, |ui| {
                egui::Grid::new("keys").striped(true).show(ui, |ui| {
                    for (keys, what) in SHORTCUTS.iter().chain(MOUSE.iter()) {
                        ui.monospace(*keys);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            });
    });
}

fn header(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let scene = session.scene();
    ui.heading(format!("Volley: {}", scene.name()));
    if !scene.description().is_empty() {
        ui.label(scene.description());
    }
    ui.small(session.path().display().to_string());
    if let Some((note, ok)) = &state.file_note {
        let c = if *ok {
            Color32::LIGHT_GREEN
        } else {
            Color32::LIGHT_RED
        };
        ui.colored_label(c, note);
    }
    let current = session.path().to_path_buf();
    egui::ComboBox::from_label("scene")
        .selected_text(scene.name())
        .show_ui(ui, |ui| {
            for (name, path) in &state.scenes {
                if ui.selectable_label(*path == current, name).clicked() {
                    out.push(Action::PickScene(path.clone()));
                }
            }
        });
    if let Some(e) = state.refusal(session) {
        ui.colored_label(Color32::LIGHT_RED, e);
    }
}

fn frame(ui: &mut Ui, stats: &FrameStats, out: &mut Vec<Action>) {
    let fps = if stats.interval_ms > 0.0 {
        1e3 / stats.interval_ms
    } else {
        0.0
    };
    ui.monospace(format!(
        "frame {:.2} ms ({fps:.0} fps), work {:.2} ms",
        stats.interval_ms, stats.work_ms
    ));
    ui.small(format!(
        "{} x {} px at {:.2} px/pt, {}",
        stats.size.0, stats.size.1, stats.scale, stats.adapter
    ));
    ui.horizontal(|ui| {
        if named_button(ui, "Trails").clicked() {
            out.push(Action::ToggleTrails);
        }
        if named_button(ui, "Ghosts").clicked() {
            out.push(Action::ToggleGhosts);
        }
        if named_button(ui, "Plots").clicked() {
            out.push(Action::TogglePlots);
        }
        if named_button(ui, "Frame scene").clicked() {
            out.push(Action::FrameScene);
        }
        if named_button(ui, "Screenshot").clicked() {
            out.push(Action::Screenshot);
        }
    });
}
