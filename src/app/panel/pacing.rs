//! The loop lab in the panel: the loop policy and draw mode controls in the side panel, and the
//! pacing view beside the plots (ticks per frame, the display error, the cadence).
//!
//! The view reads the session's [`crate::app::session::pacing::PacingLog`]: the first lane's
//! last frames, its measured body's display error under every draw mode (the selected one
//! plotted), and why there is none where there is none.

use egui::{Color32, Ui};
use egui_plot::{Line, Plot, PlotPoints, Points};

use super::{PanelState, named_button};
use crate::app::input::Action;
use crate::app::session::Session;
use crate::app::session::pacing::{CADENCE_FRAMES, PacingFrame};
use crate::clock::LoopPolicy;
use crate::pacing::DrawMode;

/// Wall time the view's plots cover (s).
pub const VIEW_SECONDS: f64 = 4.0;

/// What a loop policy does, for its hover text.
pub fn policy_note(name: &str) -> &'static str {
    match name {
        "accumulator" => "the delta as measured (Fiedler's accumulator)",
        "snap" => "deltas within 0.2 ms of 1 to 4 refresh intervals taken as exactly that (Glaiel)",
        "snap-avg" => "snapped, then averaged over 4 frames with the remainder carried (Glaiel)",
        "quantise" => {
            "deltas rounded to whole refresh intervals, the remainder carried (Godot's delta \
             smoother)"
        }
        "hysteresis" => {
            "ticks per frame kept steady, game time within half a tick of wall time (Godot's \
             physics jitter fix)"
        }
        _ => "",
    }
}

/// What a draw mode shows and what it costs.
pub fn draw_note(mode: DrawMode) -> &'static str {
    match mode {
        DrawMode::Current => {
            "the current tick: on average half a tick behind the sample, moving in whole ticks"
        }
        DrawMode::Interpolate => {
            "between the last two ticks: smooth, but always exactly one tick behind"
        }
        DrawMode::Extrapolate => {
            "past the current tick by the velocity, to the sample: no lag; overshoots through a \
             bounce or a sharp turn"
        }
        DrawMode::Predict => {
            "extrapolated to the expected present (sample + median frame delta): the least \
             display error on smooth motion; overshoots through a bounce by up to a tick and a \
             refresh"
        }
        DrawMode::Swept => {
            "predict's path stopped and reflected at the ground, walls and level surfaces: \
             never inside a surface; where none is in reach, predict exactly"
        }
    }
}

/// The loop section of the side panel: the frames, the policy and draw mode pickers, the
/// pacing view's and the judder ghosts' toggles.
pub fn controls(ui: &mut Ui, state: &PanelState, session: &Session, out: &mut Vec<Action>) {
    ui.strong("Loop");
    let refresh_hz = 1.0 / session.refresh().as_secs_f64();
    ui.weak(format!(
        "{}; policies snap to {refresh_hz:.0} Hz",
        state.frames_note
    ));
    let policy = session.policy();
    egui::ComboBox::from_label("loop policy")
        .selected_text(policy.name())
        .show_ui(ui, |ui| {
            for name in LoopPolicy::NAMES {
                let picked = ui
                    .selectable_label(policy.name() == name, name)
                    .on_hover_text(policy_note(name));
                if picked.clicked() {
                    out.push(Action::SetPolicy(name.to_string()));
                }
            }
        })
        .response
        .on_hover_text(policy_note(policy.name()));
    let mode = session.draw_mode();
    egui::ComboBox::from_label("draw mode")
        .selected_text(mode.name())
        .show_ui(ui, |ui| {
            for m in DrawMode::ALL {
                let picked = ui
                    .selectable_label(m == mode, m.name())
                    .on_hover_text(draw_note(m));
                if picked.clicked() {
                    out.push(Action::SetDrawMode(m));
                }
            }
        });
    ui.weak(draw_note(mode));
    ui.horizontal(|ui| {
        if named_button(ui, "Pacing view")
            .on_hover_text("ticks per frame, the display error, the cadence (beside the plots)")
            .clicked()
        {
            out.push(Action::TogglePacing);
        }
        if named_button(ui, "Judder ghosts")
            .on_hover_text(
                "the measured body's last drawn positions (spheres) beside the exact ones at \
                 each display time (crosses)",
            )
            .clicked()
        {
            out.push(Action::ToggleJudder);
        }
        let on = |b: bool| if b { "on" } else { "off" };
        ui.weak(format!(
            "{} / {}",
            on(state.pacing_view),
            on(state.judder_ghosts)
        ));
    });
}

/// The frames of the last [`VIEW_SECONDS`].
fn recent(frames: &[PacingFrame]) -> &[PacingFrame] {
    let now = frames.last().map_or(0.0, |f| f.wall);
    let from = frames.partition_point(|f| f.wall < now - VIEW_SECONDS);
    &frames[from..]
}

/// The pacing view: a header (policy, draw mode, the measured body, swings and drift; the
/// cadence; every draw mode's median error) and two plots side by side, ticks per frame and the
/// selected draw mode's display error over the last [`VIEW_SECONDS`].
pub fn view(ui: &mut Ui, session: &Session, lane_colour: Color32, out: &mut Vec<Action>) {
    let log = session.pacing();
    let frames: Vec<PacingFrame> = log.frames().copied().collect();
    let mode = session.draw_mode();
    let cadence = log.cadence();
    let drift = frames.last().map_or(0.0, |f| f.drift);
    ui.horizontal_wrapped(|ui| {
        ui.strong("Pacing");
        ui.label(format!("{} + {}", session.policy().name(), mode.name()));
        let mut body = log.body;
        let last = session.world().bodies().len().saturating_sub(1);
        let drag = egui::DragValue::new(&mut body)
            .range(0..=last)
            .prefix("body ");
        if ui
            .add(drag)
            .on_hover_text("the first lane's body measured (storage order)")
            .changed()
        {
            out.push(Action::SetPacingBody(body));
        }
        ui.label(format!("0-2 swings {}", log.swings()))
            .on_hover_text(format!(
                "a frame of no tick next to one of two or more, in the last {CADENCE_FRAMES} \
                 frames"
            ));
        ui.label(format!("drift {:+.2} ms", drift * 1e3))
            .on_hover_text(
                "game time minus wall time: the game time the frame was drawn from, against \
                 the wall clock's since the last restart, seek or pause",
            );
        let inside = log.inside();
        ui.label(format!(
            "inside a surface {} of {} frames{}",
            inside.frames,
            inside.of,
            if inside.frames > 0 {
                format!(", deepest {} mm", significant(inside.deepest * 1e3))
            } else {
                String::new()
            }
        ))
        .on_hover_text(
            "frames that drew some body inside the ground, a wall or a level surface, in the \
             draw mode of that frame, since the window opened (predict draws a bounce past \
             the surface; swept never does)",
        );
    });
    ui.add(egui::Label::new(egui::RichText::new(cadence).monospace().size(9.5)).truncate())
        .on_hover_text(format!(
            "the ticks each of the last {CADENCE_FRAMES} frames ran, oldest first"
        ));
    let shown = recent(&frames);
    let k = DrawMode::ALL.iter().position(|&m| m == mode).unwrap_or(0);
    let medians: Vec<String> = DrawMode::ALL
        .iter()
        .map(|&m| match log.median_error(m, VIEW_SECONDS) {
            Some(v) => format!("{} {}", m.name(), significant(v * 1e3)),
            None => format!("{} -", m.name()),
        })
        .collect();
    let when = if log.display_times {
        "at display time"
    } else {
        "at the frame's sample (no display times: --display gives them)"
    };
    ui.add(
        egui::Label::new(
            egui::RichText::new(format!("median error (mm) {when}: {}", medians.join(", ")))
                .small()
                .weak(),
        )
        .wrap(),
    );
    let height = (ui.available_height() - 4.0).max(80.0);
    ui.columns(2, |cols| {
        ticks_plot(&mut cols[0], shown, height);
        match &log.note {
            Some(why) if shown.iter().all(|f| f.errors[k].is_none()) => {
                cols[1].add_space(height / 3.0);
                cols[1].colored_label(Color32::LIGHT_YELLOW, format!("no display error: {why}"));
            }
            _ => error_plot(&mut cols[1], shown, k, lane_colour, height),
        }
    });
}

/// `v` to three significant digits (two below 1e-2, in exponent form).
fn significant(v: f64) -> String {
    match v.abs() {
        a if a >= 100.0 => format!("{v:.0}"),
        a if a >= 10.0 => format!("{v:.1}"),
        a if a >= 1.0 => format!("{v:.2}"),
        a if a >= 0.01 => format!("{v:.3}"),
        _ => format!("{v:.1e}"),
    }
}

/// Seconds-before-now axis ticks: a label every second.
fn seconds_grid() -> impl Fn(egui_plot::GridInput) -> Vec<egui_plot::GridMark> {
    egui_plot::uniform_grid_spacer(|_| [0.25, 1.0, 2.0])
}

/// Grid steps of 1, 2 and 5 times a power of ten from the smallest egui allows: a short axis
/// of a few units still gets labels (powers of ten alone leave 0 to 6 with none but 0).
fn nice_grid() -> impl Fn(egui_plot::GridInput) -> Vec<egui_plot::GridMark> {
    egui_plot::uniform_grid_spacer(|input| {
        let nice = |at_least: f64| {
            let p = 10f64.powf(at_least.max(1e-12).log10().floor());
            [1.0, 2.0, 5.0, 10.0]
                .into_iter()
                .map(|m| m * p)
                .find(|s| *s >= at_least)
                .unwrap_or(10.0 * p)
        };
        let s0 = nice(input.base_step_size);
        let s1 = nice(s0 * 1.5);
        [s0, s1, nice(s1 * 1.5)]
    })
}

/// A plot of the last [`VIEW_SECONDS`] against wall time before the newest frame, fixed in
/// place (no drag, zoom or scroll): what both of the view's plots share.
fn over_last_seconds(id: &str, height: f32) -> Plot<'static> {
    Plot::new(id)
        .show_background(false)
        .height(height)
        .include_x(-VIEW_SECONDS)
        .include_x(0.0)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .x_grid_spacer(seconds_grid())
        .x_axis_label("s before now")
}

/// Ticks per frame against wall time (s before the newest frame): a dot a frame, so a steady
/// cadence is one row and 0-to-2 swings are dots above and below it.
fn ticks_plot(ui: &mut Ui, frames: &[PacingFrame], height: f32) {
    let now = frames.last().map_or(0.0, |f| f.wall);
    let points: Vec<[f64; 2]> = frames
        .iter()
        .map(|f| [f.wall - now, f64::from(f.steps)])
        .collect();
    let top = frames.iter().map(|f| f.steps).max().unwrap_or(1).max(2);
    over_last_seconds("pacing ticks", height)
        .include_y(-0.25)
        .include_y(f64::from(top) + 0.25)
        .y_axis_label("ticks per frame")
        .show(ui, |plot| {
            plot.points(
                Points::new("ticks", PlotPoints::from(points))
                    .color(Color32::from_gray(220))
                    .radius(1.5)
                    .filled(true),
            );
        });
}

/// The display error of draw mode `k` against wall time (mm, or m past a metre, so the axis
/// labels stay short): how far from the exact motion at each frame's display time the frame
/// drew the body.
fn error_plot(ui: &mut Ui, frames: &[PacingFrame], k: usize, colour: Color32, height: f32) {
    let now = frames.last().map_or(0.0, |f| f.wall);
    let largest = frames
        .iter()
        .filter_map(|f| f.errors[k])
        .fold(0.0, f64::max);
    let (scale, unit) = if largest >= 1.0 {
        (1.0, "m")
    } else {
        (1e3, "mm")
    };
    let mut runs: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
    for f in frames {
        match f.errors[k] {
            Some(e) => runs
                .last_mut()
                .expect("runs starts with one")
                .push([f.wall - now, e * scale]),
            // A frame without an error (dropped, ended) breaks the line.
            None if runs.last().is_some_and(|r| !r.is_empty()) => runs.push(Vec::new()),
            None => {}
        }
    }
    over_last_seconds("pacing error", height)
        .include_y(0.0)
        .y_grid_spacer(nice_grid())
        .y_axis_label(format!("display error ({unit})"))
        .label_formatter(|pos| match pos {
            egui_plot::HoverPosition::NearDataPoint { position, .. } => Some(format!(
                "{:.3} s before now\n{:.4} {unit}",
                position.x, position.y
            )),
            _ => None,
        })
        .show(ui, |plot| {
            for run in runs.into_iter().filter(|r| !r.is_empty()) {
                plot.line(
                    Line::new("display error", PlotPoints::from(run))
                        .color(colour)
                        .width(1.5),
                );
            }
        });
}
