//! The side panel (egui): the loop's state, the numerical error, and every control.
//!
//! The panel only reads the session; what the user asks for comes back as [`Action`]s. While a
//! replay runs, the controls that would change the simulation are greyed out.

mod alerts;
pub mod forces;
pub mod pacing;
pub mod plots;
mod record;

use std::path::PathBuf;

use egui::{Color32, RichText, Ui};

use crate::app::input::{Action, DEFAULT_COMPARE, MOUSE, SHORTCUTS};
use crate::app::session::Session;
use crate::integrate::Integrator;
use crate::render::BodyError;
use crate::render::reference::ReferenceEnd;

pub use alerts::{cause, overlay};

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

/// Bodies listed in the error table.
const ERROR_ROWS: usize = 8;
/// Bodies the "largest error" line looks at (the first ones, so the cost stays bounded).
const ERROR_SCAN: usize = 4096;

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

    /// Shows `why` as the session's last refusal.
    pub fn refuse(&mut self, session: &Session, why: String) {
        self.refused = Some((why, session.replays_opened()));
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
        clock(ui, state, session, out);
        timeline(ui, session, out);
        ui.separator();
        pacing::controls(ui, state, session, out);
        ui.separator();
        ui.add_enabled_ui(live, |ui| simulation(ui, state, session, out));
        forces::show(ui, session);
        ui.separator();
        ui.add_enabled_ui(live, |ui| compare(ui, state, session, out));
        ui.separator();
        errors(ui, session);
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

fn clock(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let world = session.world();
    let last = session.last_frame();
    let lane = &session.lanes()[0];
    egui::Grid::new("clock").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.monospace(v);
            ui.end_row();
        };
        row("tick", world.tick().to_string());
        row("sim time", format!("{:.6} s", world.time()));
        row("dt", format!("{:.6} ms", world.dt() * 1e3));
        row("steps this frame", last.steps.to_string());
        row("alpha", format!("{:.3}", last.alpha));
        row(
            "dropped",
            format!(
                "{:.1} ms this frame, {:.3} s in all",
                last.dropped.as_secs_f64() * 1e3,
                lane.sim.clock.dropped().as_secs_f64()
            ),
        );
        let integrator = if session.is_comparing() {
            format!("{} compared (legend below)", session.lanes().len())
        } else {
            world.integrator().to_string()
        };
        row("integrator", integrator);
        row("bodies", world.bodies().len().to_string());
    });
    ui.horizontal(|ui| {
        let label = if session.is_paused() {
            "Resume"
        } else {
            "Pause"
        };
        if named_button(ui, label).clicked() {
            out.push(Action::TogglePause);
        }
        if named_button(ui, "Step").clicked() {
            out.push(Action::Step);
        }
        let pending = lane.pending();
        if pending > 0 {
            ui.weak(format!("{pending} command(s) wait for the next tick"));
        }
    });
    let mut scale = session.time_scale();
    let slider = egui::Slider::new(&mut scale, 0.01..=100.0)
        .logarithmic(true)
        .text("time scale");
    if ui.add(slider).changed() {
        out.push(Action::SetTimeScale(scale));
    }
    ui.add_enabled_ui(session.replay().is_none(), |ui| {
        ui.horizontal(|ui| {
            ui.add(
                egui::DragValue::new(&mut state.dt_ms)
                    .speed(0.1)
                    .range(0.001..=10_000.0)
                    .suffix(" ms"),
            );
            ui.add(
                egui::DragValue::new(&mut state.substeps)
                    .speed(0.1)
                    .range(1..=crate::scene::MAX_SUBSTEPS)
                    .suffix(" substeps"),
            );
            if named_button(ui, "Apply").clicked() {
                out.push(Action::SetStep {
                    dt: state.dt_ms * 1e-3,
                    substeps: state.substeps,
                });
            }
        });
    });
    ui.weak(
        "Changing dt or substeps restarts the scene at tick 0 with the new step, so sim time \
         stays tick x dt.",
    );
}

/// The scrub bar over the ticks held and Box2D's `|< < play > >|`, with playing backwards.
fn timeline(ui: &mut Ui, session: &Session, out: &mut Vec<Action>) {
    let Some((start, end)) = session.history_range() else {
        ui.weak(format!(
            "timeline off: a keyframe of this world is over an eighth of the {} MiB budget",
            session.history_budget() >> 20
        ));
        return;
    };
    let now = session.world().tick();
    let mut tick = now;
    ui.spacing_mut().slider_width = 200.0;
    let slider = egui::Slider::new(&mut tick, start..=end.max(start + 1))
        .text("timeline")
        .integer();
    if ui.add_enabled(end > start, slider).changed() && tick != now {
        out.push(Action::Seek(tick));
    }
    ui.horizontal(|ui| {
        let button =
            |ui: &mut Ui, text: &str, hover: &str| named_button(ui, text).on_hover_text(hover);
        if button(ui, "|<", "jump to the first tick held (Backspace)").clicked() {
            out.push(Action::JumpStart);
        }
        if button(ui, "<", "step back one tick (,)").clicked() {
            out.push(Action::StepBack);
        }
        let back = if session.is_reversing() { "stop" } else { "<<" };
        if button(ui, back, "play backwards (B)").clicked() {
            out.push(Action::ToggleReverse);
        }
        let play = if session.is_paused() && !session.is_reversing() {
            ">>"
        } else {
            "||"
        };
        if button(ui, play, "play / pause (Space)").clicked() {
            out.push(if session.is_reversing() {
                Action::ToggleReverse
            } else {
                Action::TogglePause
            });
        }
        if button(ui, ">", "step forward one tick (N)").clicked() {
            out.push(Action::Step);
        }
        if button(ui, ">|", "jump to the last tick run (End)").clicked() {
            out.push(Action::JumpEnd);
        }
    });
    if session.replay().is_none()
        && let Some(t) = session.lanes()[0].history.timeline.as_ref()
    {
        ui.weak(format!(
            "ticks {start} to {end}: {} keyframes every {} ticks, {:.1} of {} MiB a lane",
            t.keyframes(),
            t.every(),
            t.bytes() as f64 / f64::from(1 << 20),
            t.budget() >> 20
        ));
    }
    if let Some(tick) = session.future_dropped_at() {
        ui.weak(future_dropped_note(tick));
    }
}

fn simulation(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let world = session.world();
    let current = world.integrator();
    ui.add_enabled_ui(!session.is_comparing(), |ui| {
        egui::ComboBox::from_label("integrator")
            .selected_text(current.name())
            .show_ui(ui, |ui| {
                for i in Integrator::ALL {
                    let allowed = crate::scene::check_integrator(i, world.forces()).is_ok();
                    let clicked = ui
                        .add_enabled(allowed, egui::Button::selectable(i == current, i.name()))
                        .clicked();
                    if clicked {
                        out.push(Action::SetIntegrator(i));
                    }
                }
            });
    });
    let info = current.info();
    ui.weak(format!(
        "order {}, {}",
        if info.order == u32::MAX {
            "exact".to_string()
        } else {
            info.order.to_string()
        },
        if info.symplectic {
            "symplectic"
        } else {
            "not symplectic"
        }
    ));
    let launch = |ui: &mut Ui, value: &mut f64, range, text: &str, suffix: &str| {
        let slider = egui::Slider::new(value, range).text(text).suffix(suffix);
        ui.add(slider).changed()
    };
    // Up to 200 m/s for a thrown or kicked ball; a bullet's scene (the rifle's 838 m/s) gets a
    // range to 1200 m/s, so the slider shows its speed instead of clamping it.
    let top = if state.speed > 200.0 { 1200.0 } else { 200.0 };
    let s = launch(ui, &mut state.speed, 0.0..=top, "speed", " m/s");
    let e = launch(
        ui,
        &mut state.elevation_deg,
        -90.0..=90.0,
        "elevation",
        " deg",
    );
    let a = launch(
        ui,
        &mut state.azimuth_deg,
        -180.0..=180.0,
        "azimuth",
        " deg",
    );
    if s || e || a {
        out.push(Action::Launch {
            speed: s.then_some(state.speed),
            elevation_deg: e.then_some(state.elevation_deg),
            azimuth_deg: a.then_some(state.azimuth_deg),
        });
    }
    ui.horizontal(|ui| {
        if named_button(ui, "Fire").clicked() {
            out.push(Action::Fire);
        }
        if named_button(ui, "Reset").clicked() {
            out.push(Action::Reset);
        }
        if named_button(ui, "Save setup")
            .on_hover_text("the scene with this launcher, integrator, step and compare lanes")
            .clicked()
        {
            out.push(Action::SaveSetup);
        }
    });
    ui.horizontal(|ui| {
        if let Some(note) = &state.saved_note {
            ui.weak(note);
        }
    });
    aim(ui, state, session, out);
}

/// The aim buttons and, per lane, what its own solve fired and how the textbook would miss.
fn aim(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let targets = session.world().contacts().targets.len();
    if targets == 0 {
        return;
    }
    state.aim_target = state.aim_target.min(targets - 1);
    ui.horizontal(|ui| {
        if targets > 1 {
            egui::ComboBox::from_id_salt("aim target")
                .selected_text(format!("target {}", state.aim_target))
                .show_ui(ui, |ui| {
                    for k in 0..targets {
                        ui.selectable_value(&mut state.aim_target, k, format!("target {k}"));
                    }
                });
        }
        if named_button(ui, "Aim: high arc").clicked() {
            out.push(Action::Aim(crate::exact::Arc::High));
        }
        if named_button(ui, "Aim: low arc").clicked() {
            out.push(Action::Aim(crate::exact::Arc::Low));
        }
    });
    for lane in session.lanes() {
        let Some(note) = &lane.aim else {
            continue;
        };
        let name = lane.sim.world.integrator().name();
        let (first, second) = match &note.outcome {
            Ok(shot) => {
                let mut first = format!(
                    "{name}: {} {:.2} deg, {:.2} m/s, {:.3} s",
                    shot.kind.label(),
                    shot.elevation_deg,
                    shot.speed,
                    shot.flight_time
                );
                if let Some(tb) = shot.textbook {
                    let (e, _) = crate::firing::angles_of(tb.velocity);
                    first += &format!("; textbook {e:.2} deg misses by {:.3} m", tb.miss);
                }
                let second = match aimed_pass(lane, note, shot) {
                    Some(p) => format!("  passed at {:.1e} m, t = {:.3} s", p.distance, p.time),
                    None => "  in flight".to_string(),
                };
                (first, second)
            }
            Err(why) => (format!("{name}: no shot: {why}"), String::new()),
        };
        ui.colored_label(colour(lane.colour()), first);
        if !second.is_empty() {
            ui.monospace(second);
        }
    }
}

/// The aimed shot's pass by the aimed target, once it has come (within half a tick of when it
/// was due).
pub fn aimed_pass<'a>(
    lane: &'a crate::app::session::Lane,
    note: &crate::app::session::AimNote,
    shot: &crate::firing::Shot,
) -> Option<&'a crate::render::history::Pass> {
    let world = &lane.sim.world;
    let due = world.time_of(note.tick) + shot.flight_time;
    lane.history
        .passes
        .all()
        .iter()
        .filter(|p| p.body == note.body && p.target as usize == note.target)
        .find(|p| (p.time - due).abs() < 0.5 * world.dt())
}

fn compare(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let mut on = session.is_comparing();
    if ui.checkbox(&mut on, "Compare integrators").changed() {
        out.push(Action::SetCompare(if on {
            state.compare_pick.clone()
        } else {
            Vec::new()
        }));
    }
    ui.horizontal_wrapped(|ui| {
        for i in Integrator::ALL {
            let mut picked = state.compare_pick.contains(&i);
            let text = RichText::new(i.name()).color(colour(crate::render::integrator_colour(i)));
            if ui.checkbox(&mut picked, text).changed() {
                state.compare_pick.retain(|&j| j != i);
                if picked {
                    state.compare_pick.push(i);
                    state.compare_pick.sort();
                }
                if on {
                    out.push(Action::SetCompare(state.compare_pick.clone()));
                }
            }
        }
    });
    if !on {
        return;
    }
    let mut equal = session.is_equal_cost();
    if ui
        .checkbox(&mut equal, "Equal cost")
        .on_hover_text(
            "every lane spends the first lane's force evaluations per simulated second: its dt \
             scaled by its evaluations a tick (RK4 at 4 h beside Euler at h)",
        )
        .changed()
    {
        out.push(Action::SetEqualCost(equal));
    }
    egui::Grid::new("legend").striped(true).show(ui, |ui| {
        ui.strong("integrator");
        ui.strong("dt (ms)");
        ui.strong("substeps");
        ui.strong("evals/s");
        ui.strong("max |dp|");
        ui.end_row();
        let specs = session.compare_lanes();
        for (i, lane) in session.lanes().iter().enumerate() {
            let world = &lane.sim.world;
            ui.colored_label(colour(lane.colour()), world.integrator().name());
            let (mut dt_ms, mut substeps) = (world.dt() * 1e3, world.substeps());
            let derived = session.is_equal_cost() && i > 0;
            let dt_edit = ui.add_enabled(
                !derived,
                egui::DragValue::new(&mut dt_ms)
                    .speed(0.1)
                    .range(0.001..=10_000.0),
            );
            let n_edit = ui.add(
                egui::DragValue::new(&mut substeps)
                    .speed(0.1)
                    .range(1..=1000),
            );
            if (dt_edit.lost_focus()
                || dt_edit.drag_stopped()
                || n_edit.lost_focus()
                || n_edit.drag_stopped())
                && (dt_ms != world.dt() * 1e3 || substeps != world.substeps())
                && specs.get(i).is_some()
            {
                out.push(Action::SetLaneStep {
                    lane: i,
                    dt: Some(dt_ms * 1e-3),
                    substeps: Some(substeps),
                });
            }
            ui.monospace(
                lane.evals_per_second()
                    .map_or("-".into(), |e| format!("{e:.0}")),
            );
            match &lane.stopped {
                Some(d) => {
                    ui.colored_label(Color32::LIGHT_RED, format!("diverged at tick {}", d.tick))
                        .on_hover_text(format!("body {}: {}", d.body, cause(d)));
                }
                None => {
                    let first = (!lane.sim.world.bodies().is_empty())
                        .then(|| lane.history.references.error(&lane.sim.world, 0));
                    // The largest error, or why body 0 has none (its reference ended).
                    ui.monospace(match (max_error(lane), first) {
                        (Some(m), _) => format!("{m:.2e} m"),
                        (None, Some(e)) => short(&e),
                        (None, None) => "-".into(),
                    });
                }
            }
            ui.end_row();
        }
    });
}

/// Largest position error over the first bodies of a lane, if any body has one.
fn max_error(lane: &crate::app::session::Lane) -> Option<f64> {
    let world = &lane.sim.world;
    (0..world.bodies().len().min(ERROR_SCAN))
        .filter_map(|i| match lane.history.references.error(world, i) {
            BodyError::Measured { position, .. } => Some(position),
            _ => None,
        })
        .reduce(f64::max)
}

fn short(e: &BodyError) -> String {
    match e {
        BodyError::Measured { position, .. } => format!("{position:.3e} m"),
        BodyError::NoClosedForm => "no closed form".into(),
        BodyError::Ended(ReferenceEnd::Contact { time, .. }) => format!("contact at {time:.3} s"),
        BodyError::Ended(ReferenceEnd::ForcesChanged { tick }) => {
            format!("forces changed at tick {tick}")
        }
        BodyError::Unknown => "-".into(),
    }
}

fn errors(ui: &mut Ui, session: &Session) {
    let lane = &session.lanes()[0];
    let world = &lane.sim.world;
    ui.strong("Error against the reference");
    if let Some(r) = world
        .bodies()
        .ids()
        .first()
        .and_then(|id| lane.history.references.get(*id))
    {
        let (kind, estimate) = r.kind();
        ui.weak(match estimate {
            Some(e) => format!("body 0 against: {kind}, its own error about {e:.1e}"),
            None => format!("body 0 against: {kind}"),
        });
    }
    egui::Grid::new("errors").striped(true).show(ui, |ui| {
        ui.strong("body");
        ui.strong("|p - p_exact|");
        ui.strong("|v - v_exact|");
        ui.end_row();
        for i in 0..world.bodies().len().min(ERROR_ROWS) {
            ui.monospace(world.bodies().ids()[i].to_string());
            match lane.history.references.error(world, i) {
                BodyError::Measured { position, velocity } => {
                    ui.monospace(format!("{position:.4e} m"));
                    ui.monospace(format!("{velocity:.4e} m/s"));
                }
                other => {
                    ui.weak(short(&other));
                    ui.label("");
                }
            }
            ui.end_row();
        }
    });
    let n = world.bodies().len();
    if n > ERROR_ROWS {
        let scanned = n.min(ERROR_SCAN);
        let max = max_error(lane).map_or("-".into(), |m| format!("{m:.4e} m"));
        ui.weak(format!(
            "largest |p - p_exact| over the first {scanned} of {n} bodies: {max}"
        ));
    }
    ui.weak("References have no contacts: a body's reference ends at its first impact.");
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
