//! The live plots (egui_plot), in a panel under the 3D view that `K` or the panel's checkbox
//! shows and hides and its top edge resizes: one line per lane in its integrator's colour (the
//! study plots' palette).
//!
//! - position error against sim time, log y: the largest over the first bodies as a min-max
//!   band per time bucket (so spikes survive decimation), body 0 dashed (where it is not the
//!   largest);
//! - relative energy error `(E - E0) / scale` against sim time;
//! - live work-precision: force evaluations per simulated second against the largest position
//!   error so far, one point per lane, both log: the study's diagram as the run goes.
//!
//! Hovering reads sim time and value. "Save plots" writes the series as CSV and the diagram as
//! PNG ([`write()`]).

use super::{PanelState, named_button};
use std::path::{Path, PathBuf};

use egui::{Color32, Ui};
use egui_plot::{FilledArea, GridMark, Legend, Line, LineStyle, Plot, PlotPoints, Points};

use crate::app::input::Action;
use crate::app::session::{Lane, Session};
use crate::render::series::{Decimated, LaneSeries};

/// Values below this are drawn at it on the log axes (a log axis has no zero).
const FLOOR: f64 = 1e-16;

/// The work-precision point of a lane: (force evaluations per simulated second, the largest
/// position error so far), if it has run and has an error.
pub fn work_precision(lane: &Lane) -> Option<(f64, f64)> {
    Some((
        lane.evals_per_second()?,
        lane.history.series.error_max.max()?,
    ))
}

fn log10(x: f64) -> f64 {
    libm::log10(x.max(FLOOR))
}

/// `1e-3` style labels for an axis that holds log10 values.
fn power_label(mark: GridMark, _range: &std::ops::RangeInclusive<f64>) -> String {
    let v = mark.value;
    if (v - v.round()).abs() < 1e-9 {
        format!("1e{}", v.round() as i64)
    } else {
        String::new()
    }
}

/// Most points a line draws (a plot wider than twice this still draws this many).
const DISPLAY_POINTS: usize = 400;

/// Points a line draws in a plot `width` points wide: one per three points of width. The
/// software rasteriser pays per triangle, and a feathered line costs four to six a point, so
/// a line costs what its plot's width asks for, not what the history holds; each point is the
/// min and max of the buckets it merges, so no spike is lost by drawing fewer.
fn display_points(width: f32) -> usize {
    ((width / 3.0) as usize).clamp(16, DISPLAY_POINTS)
}

/// A series as drawn: each point's time, the band's edges (min and max of the buckets it
/// merges) and the edge farther from zero (the larger error, the larger energy excursion), on
/// the plot's axis (log10 on a log axis).
struct Shown {
    t: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    far: Vec<[f64; 2]>,
}

fn shown(series: &Decimated, points: usize, log: bool) -> Shown {
    let f = |v: f64| if log { log10(v) } else { v };
    let buckets = series.for_display(points);
    let mut s = Shown {
        t: Vec::with_capacity(buckets.len()),
        lo: Vec::with_capacity(buckets.len()),
        hi: Vec::with_capacity(buckets.len()),
        far: Vec::with_capacity(buckets.len()),
    };
    for (t, lo, hi) in buckets {
        s.t.push(t);
        s.lo.push(f(lo));
        s.hi.push(f(hi));
        s.far
            .push([t, f(if hi.abs() >= lo.abs() { hi } else { lo })]);
    }
    s
}

/// A series as a band from each point's min to its max, filled translucent in the lane's
/// colour (an unfeathered mesh: two triangles a point), and a line along its edge farther
/// from zero, which carries the hover. Where min and max agree the band is empty and the line
/// is the series.
fn band_and_line(
    plot: &mut egui_plot::PlotUi<'_>,
    name: &str,
    colour: Color32,
    width: f32,
    s: Shown,
) {
    if s.t.len() > 1 {
        plot.add(
            FilledArea::new(name, &s.t, &s.lo, &s.hi)
                .fill_color(colour.gamma_multiply(BAND_ALPHA))
                .allow_hover(false),
        );
    }
    plot.line(
        Line::new(name, PlotPoints::from(s.far))
            .color(colour)
            .width(width),
    );
}

/// The width of lane `k`'s line of `n`: the last lane 1.5 points, each earlier one 1.25 wider
/// (at most 5.25). Lanes often coincide (both Eulers' errors are equal and opposite, Verlet's
/// and RK4's are the same rounding under constant force), and drawn in lane order each line
/// then shows as an outline around the next instead of vanishing under it.
pub fn line_width(k: usize, n: usize) -> f32 {
    1.5 + 1.25 * n.saturating_sub(k + 1).min(3) as f32
}

/// The band's opacity.
const BAND_ALPHA: f32 = 0.3;

fn colour(lane: &Lane) -> Color32 {
    let [r, g, b, _] = lane.colour();
    Color32::from_rgb(r, g, b)
}

/// Narrower than this the plots take turns (tabs) instead of sitting side by side.
const SIDE_BY_SIDE: f32 = 720.0;

/// What the bottom panel holds: the live plots, the pacing view, or both side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BottomPanel {
    /// The three live plots.
    pub plots: bool,
    /// The pacing view ([`super::pacing::view`]).
    pub pacing: bool,
}

/// Draws the bottom panel: the plots, the pacing view, or the plots in the left half (taking
/// turns there when narrow) and the pacing view in the right half.
pub fn show(
    ui: &mut Ui,
    session: &Session,
    state: &mut PanelState,
    shown: BottomPanel,
    out: &mut Vec<Action>,
) {
    let lane = colour(&session.lanes()[0]);
    match (shown.plots, shown.pacing) {
        (true, true) => {
            let size = ui.available_size();
            let half = egui::vec2((size.x / 2.0 - 8.0).max(0.0), size.y);
            let top_down = egui::Layout::top_down(egui::Align::Min);
            ui.horizontal_top(|ui| {
                ui.allocate_ui_with_layout(half, top_down, |ui| {
                    ui.set_min_size(half);
                    ui.set_max_width(half.x);
                    plots(ui, session, state, out)
                });
                ui.separator();
                let rest = ui.available_size();
                ui.allocate_ui_with_layout(rest, top_down, |ui| {
                    ui.set_max_width(rest.x);
                    super::pacing::view(ui, session, lane, out)
                });
            });
        }
        (false, true) => super::pacing::view(ui, session, lane, out),
        _ => plots(ui, session, state, out),
    }
}

/// The three plots side by side (or one at a time, picked by the panel's `plot_tab`, when narrow), with the save
/// button above them.
fn plots(ui: &mut Ui, session: &Session, state: &mut PanelState, out: &mut Vec<Action>) {
    let narrow = ui.available_width() < SIDE_BY_SIDE;
    ui.horizontal(|ui| {
        ui.strong("Plots");
        if named_button(ui, "Save plots")
            .on_hover_text("CSV of the series and a PNG of the plots")
            .clicked()
        {
            out.push(Action::SavePlots);
        }
        if narrow {
            for (k, name) in ["error", "energy", "work-precision"]
                .into_iter()
                .enumerate()
            {
                ui.selectable_value(&mut state.plot_tab, k, name);
            }
        }
        match &state.saved_note {
            Some(note) => {
                ui.weak(note);
            }
            None if !narrow => {
                ui.weak(
                    "lane colours as above; bands span min to max, body 0 dashed; hover reads t and the value",
                );
            }
            None => {}
        }
    });
    // The panel's height less the row above: the panel is as tall as what it holds, so the
    // plots follow its resize handle, never below a readable 150 px.
    let height = (ui.max_rect().height() - 30.0).max(150.0);
    let lanes = session.lanes();
    if narrow {
        match state.plot_tab {
            0 => error_plot(ui, lanes, height),
            1 => energy_plot(ui, lanes, height),
            _ => work_precision_plot(ui, lanes, height),
        }
    } else {
        ui.columns(3, |cols| {
            error_plot(&mut cols[0], lanes, height);
            energy_plot(&mut cols[1], lanes, height);
            work_precision_plot(&mut cols[2], lanes, height);
        });
    }
}

fn error_plot(ui: &mut Ui, lanes: &[Lane], height: f32) {
    let points = display_points(ui.available_width());
    Plot::new("error")
        // The panel is the background: a second one only costs the software rasteriser.
        .show_background(false)
        .height(height)
        .x_axis_label("sim time (s)")
        .y_axis_label("position error (m)")
        .y_axis_formatter(power_label)
        .y_grid_spacer(egui_plot::log_grid_spacer(10))
        .label_formatter(|pos| hover(pos, "m", true))
        .show(ui, |plot| {
            for (k, lane) in lanes.iter().enumerate() {
                let name = lane.sim.world.integrator().name();
                let s: &LaneSeries = &lane.history.series;
                let width = line_width(k, lanes.len());
                band_and_line(
                    plot,
                    name,
                    colour(lane),
                    width,
                    shown(&s.error_max, points, true),
                );
                // Body 0 is drawn where it is not the largest error: with one body measured
                // (or body 0 always the worst) its line would lie on the largest one.
                if body_zero_differs(s) {
                    let first = shown(&s.error_first, points, true).far;
                    plot.line(
                        Line::new(format!("{name}, body 0"), PlotPoints::from(first))
                            .color(colour(lane))
                            .style(LineStyle::dashed_loose())
                            .width(1.0),
                    );
                }
            }
        });
}

/// Whether the error plot draws body 0's line: not while its series equals the largest error's
/// bucket for bucket (one body measured, or body 0 always the worst), where it would lie on it.
pub fn body_zero_differs(series: &LaneSeries) -> bool {
    series.error_first.buckets() != series.error_max.buckets()
}

fn energy_plot(ui: &mut Ui, lanes: &[Lane], height: f32) {
    let points = display_points(ui.available_width());
    Plot::new("energy")
        // The panel is the background: a second one only costs the software rasteriser.
        .show_background(false)
        .height(height)
        .x_axis_label("sim time (s)")
        .y_axis_label("(E - E0) / scale")
        .label_formatter(|pos| hover(pos, "", false))
        .show(ui, |plot| {
            for (k, lane) in lanes.iter().enumerate() {
                let name = lane.sim.world.integrator().name();
                let s = shown(&lane.history.series.energy, points, false);
                band_and_line(plot, name, colour(lane), line_width(k, lanes.len()), s);
            }
        });
}

/// Share of the work-precision diagram's width and height (measured from a corner) its legend
/// covers: four names take about two thirds of a third-of-the-window plot's width.
const LEGEND_SHARE: (f64, f64) = (0.7, 0.6);

/// The corner of the work-precision plot for its legend: the one whose legend-sized share of
/// the points' bounding box (`LEGEND_SHARE`, log axes) holds the fewest points, so the legend
/// hides none where it can. The points run from cheap and coarse (top left) to dear and
/// accurate (bottom right), and where a lane sits between them depends on the scene; ties go to
/// the first of top right, bottom left, bottom right, top left.
pub fn legend_corner(points: &[[f64; 2]]) -> egui_plot::Corner {
    use egui_plot::Corner;
    // Each point's place in the bounding box, 0 to 1 on both axes (0.5 where the box is flat).
    let range = |k: usize| {
        let lo = points.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
        let hi = points
            .iter()
            .map(|p| p[k])
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi - lo)
    };
    let ((x0, w), (y0, h)) = (range(0), range(1));
    let unit = |v: f64, lo: f64, span: f64| if span > 0.0 { (v - lo) / span } else { 0.5 };
    let (sx, sy) = LEGEND_SHARE;
    let under = |right: bool, top: bool| {
        points
            .iter()
            .filter(|p| {
                let (x, y) = (unit(p[0], x0, w), unit(p[1], y0, h));
                let in_x = if right { x >= 1.0 - sx } else { x <= sx };
                let in_y = if top { y >= 1.0 - sy } else { y <= sy };
                in_x && in_y
            })
            .count()
    };
    [
        (Corner::RightTop, under(true, true)),
        (Corner::LeftBottom, under(false, false)),
        (Corner::RightBottom, under(true, false)),
        (Corner::LeftTop, under(false, true)),
    ]
    .into_iter()
    .min_by_key(|&(_, n)| n)
    .map_or(Corner::RightTop, |(c, _)| c)
}

fn work_precision_plot(ui: &mut Ui, lanes: &[Lane], height: f32) {
    let points: Vec<(&Lane, [f64; 2])> = lanes
        .iter()
        .filter_map(|lane| {
            let (x, y) = work_precision(lane)?;
            Some((lane, [log10(x), log10(y)]))
        })
        .collect();
    let corner = legend_corner(&points.iter().map(|&(_, p)| p).collect::<Vec<_>>());
    Plot::new("work-precision")
        // The panel is the background: a second one only costs the software rasteriser.
        .show_background(false)
        .height(height)
        // Half see-through: where every corner holds a point, the one under it still shows.
        .legend(Legend::default().position(corner).background_alpha(0.5))
        .x_axis_label("force evaluations per sim second")
        .y_axis_label("max error so far (m)")
        .x_axis_formatter(power_label)
        .y_axis_formatter(power_label)
        .x_grid_spacer(egui_plot::log_grid_spacer(10))
        .y_grid_spacer(egui_plot::log_grid_spacer(10))
        .label_formatter(|pos| match pos {
            egui_plot::HoverPosition::NearDataPoint {
                plot_name,
                position,
                ..
            } => Some(format!(
                "{plot_name}\n{:.3e} evaluations/s\n{:.3e} m",
                10f64.powf(position.x),
                10f64.powf(position.y)
            )),
            _ => None,
        })
        .show(ui, |plot| {
            for (lane, point) in points {
                let name = lane.sim.world.integrator().name();
                plot.points(
                    Points::new(name, PlotPoints::from(vec![point]))
                        .color(colour(lane))
                        .radius(5.0)
                        .filled(true),
                );
            }
        });
}

/// The hover text: sim time and the value (a log10 value shown as its power).
fn hover(pos: &egui_plot::HoverPosition<'_>, unit: &str, log: bool) -> Option<String> {
    let egui_plot::HoverPosition::NearDataPoint {
        plot_name,
        position,
        ..
    } = pos
    else {
        return None;
    };
    let v = if log {
        10f64.powf(position.y)
    } else {
        position.y
    };
    Some(format!(
        "{plot_name}\nt = {:.4} s\n{v:.4e} {unit}",
        position.x
    ))
}

/// Writes every lane's series as CSV (`lane,series,tick,t,min,max`, a row per bucket, and a
/// `work-precision` row per lane) and the three plots as a PNG, as `DIR/plots-SCENE-tickN`.
/// Returns the two paths.
pub fn write(dir: &Path, session: &Session) -> Result<(PathBuf, PathBuf), String> {
    let world = session.world();
    let stem = format!(
        "plots-{}-tick{}",
        session.scene().name().replace(' ', "_"),
        world.tick()
    );
    let (csv, png) = (
        dir.join(format!("{stem}.csv")),
        dir.join(format!("{stem}.png")),
    );
    let mut text = String::from("lane,series,tick,t,min,max\n");
    let mut lanes = Vec::new();
    for lane in session.lanes() {
        let name = lane.sim.world.integrator().name();
        let s = &lane.history.series;
        for (series, data) in [
            ("error_max", &s.error_max),
            ("error_body0", &s.error_first),
            ("energy", &s.energy),
        ] {
            for b in data.buckets() {
                text += &format!(
                    "{name},{series},{},{:e},{:e},{:e}\n",
                    b.tick, b.t, b.min, b.max
                );
            }
        }
        if let Some((x, y)) = work_precision(lane) {
            text += &format!("{name},work-precision,{},{x:e},{y:e},{y:e}\n", world.tick());
        }
        lanes.push(crate::plot::LiveLane {
            integrator: lane.sim.world.integrator(),
            series: s.clone(),
            work_precision: work_precision(lane),
        });
    }
    if let Some(parent) = csv.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::write(&csv, text).map_err(|e| format!("{}: {e}", csv.display()))?;
    let bytes = crate::plot::live_png(session.scene().name(), &lanes).map_err(|e| e.to_string())?;
    std::fs::write(&png, bytes).map_err(|e| format!("{}: {e}", png.display()))?;
    Ok((csv, png))
}
