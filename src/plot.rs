//! The work-precision diagram: error against cost, log-log, one line per integrator.
//!
//! Drawn with `plotters`: its SVG backend for the `.svg`, its bitmap backend into an RGB buffer
//! encoded with the `png` crate for the `.png`. Text in the PNG is rasterised with `ab_glyph`
//! from a font compiled into the binary (`assets/fonts/DejaVuSans-subset.ttf`, DejaVu Sans cut
//! to printable ASCII and a few symbols, 11 kB; licence beside it), so the plot renders the same
//! on a machine with no fonts installed. The SVG names the `sans-serif` family and leaves the
//! glyphs to the viewer.
//!
//! Left panel: largest position error against force evaluations per simulated second. Right
//! panel, when the study was timed: the same errors against wall time per simulated second.
//! Diverged runs have no error and are left out; runs at the rounding floor (an integrator exact
//! for the scene) are drawn at the floor, marked in the legend.

pub mod pacing;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::integrate::Integrator;

use crate::study::{Outcome, StudyReport};

/// Size of the diagram in pixels (SVG user units).
pub const SIZE: (u32, u32) = (1200, 560);

/// Errors below this (m) are drawn at it: a log axis has no zero.
const ERROR_FLOOR: f64 = 1e-16;

/// Why the diagram could not be made.
#[derive(Debug)]
pub enum PlotError {
    /// The font compiled into the binary does not load.
    Font,
    /// `plotters` failed to draw (its message).
    Draw(String),
    /// The PNG encoder failed.
    Png(png::EncodingError),
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlotError::Font => f.write_str("the embedded plot font does not load"),
            PlotError::Draw(m) => write!(f, "plot: {m}"),
            PlotError::Png(e) => write!(f, "png: {e}"),
        }
    }
}

impl std::error::Error for PlotError {}

/// Registers the embedded plot font as plotters' `sans-serif`. The browser build's plotters
/// measures text with the page's fonts, not the embedded one, and draws no PNG with it: a plot
/// written as an image is a desktop feature.
fn register_font() -> Result<(), PlotError> {
    if crate::platform::IN_BROWSER {
        return Err(PlotError::Draw(
            "PNG plots need the desktop build (the browser build has no font rasteriser for them)"
                .into(),
        ));
    }
    crate::platform::register_plot_font()
        .then_some(())
        .ok_or(PlotError::Font)
}

/// Every plot's legend: the series' labels in a translucent white box with a black border.
fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()
        .map_err(|err| err.to_string())
}

/// The integrator's colour in the one palette the window uses too ([`crate::palette`]).
fn color(i: Integrator) -> RGBColor {
    let [r, g, b, _] = crate::palette::integrator(i);
    RGBColor(r, g, b)
}

/// (cost, error) per integrator for one cost axis.
type Series = Vec<(Integrator, Vec<(f64, f64)>)>;

fn series(r: &StudyReport, cost: impl Fn(&crate::study::StudyPoint) -> Option<f64>) -> Series {
    let mut out: Series = Vec::new();
    for p in &r.points {
        let (Some(e), Some(c), Outcome::Completed) = (p.errors, cost(p), p.outcome) else {
            continue;
        };
        if c.is_nan() || c <= 0.0 {
            continue;
        }
        let point = (c, e.max_position.max(ERROR_FLOOR));
        match out.iter_mut().find(|(i, _)| *i == p.integrator) {
            Some((_, v)) => v.push(point),
            None => out.push((p.integrator, vec![point])),
        }
    }
    for (_, v) in &mut out {
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

fn range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
    if !lo.is_finite() {
        return 1.0..10.0;
    }
    (lo / 2.0)..(hi * 2.0).max(lo * 4.0)
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_desc: &str,
    data: &Series,
) -> Result<(), String> {
    let e = |err: DrawingAreaErrorKind<DB::ErrorType>| err.to_string();
    let xs = range(data.iter().flat_map(|(_, v)| v.iter().map(|p| p.0)));
    let ys = range(data.iter().flat_map(|(_, v)| v.iter().map(|p| p.1)));
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(70)
        .build_cartesian_2d(xs.log_scale(), ys.log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("largest position error (m)")
        .x_labels(6)
        .y_labels(10)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(e)?;
    for (integrator, points) in data {
        let c = color(*integrator);
        let at_floor = points.iter().all(|p| p.1 <= ERROR_FLOOR);
        let name = if at_floor {
            format!("{integrator} (at rounding floor)")
        } else {
            integrator.to_string()
        };
        chart
            .draw_series(LineSeries::new(points.iter().copied(), c.stroke_width(2)))
            .map_err(e)?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart
            .draw_series(points.iter().map(|p| Circle::new(*p, 4, c.filled())))
            .map_err(e)?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, r: &StudyReport) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let evals = series(r, |p| Some(p.evals_per_second));
    let walls = series(r, |p| p.wall_per_sim_second());
    let title = format!("{}: error against force evaluations", r.scene);
    if walls.is_empty() {
        panel(
            &root,
            &title,
            "force evaluations per simulated second",
            &evals,
        )?;
    } else {
        let halves = root.split_evenly((1, 2));
        panel(
            &halves[0],
            &title,
            "force evaluations per simulated second",
            &evals,
        )?;
        let build = if r.release { "release" } else { "DEBUG build" };
        let title = format!("{}: error against wall time ({build})", r.scene);
        panel(
            &halves[1],
            &title,
            "wall time per simulated second (s)",
            &walls,
        )?;
    }
    root.present().map_err(|e| e.to_string())
}

/// The diagram as SVG text.
pub fn svg(r: &StudyReport) -> Result<String, PlotError> {
    register_font()?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        draw(root, r).map_err(PlotError::Draw)?;
    }
    Ok(text)
}

/// The diagram as PNG bytes.
pub fn png(r: &StudyReport) -> Result<Vec<u8>, PlotError> {
    register_font()?;
    let (w, h) = SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(root, r).map_err(PlotError::Draw)?;
    }
    encode_png(&rgb, (w, h))
}

/// RGB bytes as a PNG.
fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let encode = PlotError::Png;
    let mut writer = encoder.write_header().map_err(encode)?;
    writer.write_image_data(rgb).map_err(encode)?;
    writer.finish().map_err(encode)?;
    Ok(out)
}

/// One lane of the window's live plots, for [`live_png`].
#[derive(Clone, Debug)]
pub struct LiveLane {
    /// The lane's integrator (its colour).
    pub integrator: Integrator,
    /// Its series.
    pub series: crate::render::series::LaneSeries,
    /// Its work-precision point: (force evaluations per simulated second, largest error).
    pub work_precision: Option<(f64, f64)>,
}

/// Size of the live plots' PNG.
pub const LIVE_SIZE: (u32, u32) = (1500, 460);

/// A series panel against sim time; with `log` the values are drawn as log10 and labelled
/// as powers of ten.
fn live_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (title, y_desc): (&str, &str),
    log: bool,
    lanes: &[LiveLane],
    pick: impl Fn(&crate::render::series::LaneSeries) -> &crate::render::series::Decimated,
) -> Result<(), String> {
    let e = |err: DrawingAreaErrorKind<DB::ErrorType>| err.to_string();
    let f = |v: f64| {
        if log {
            libm::log10(v.max(ERROR_FLOOR))
        } else {
            v
        }
    };
    let buckets = || lanes.iter().flat_map(|l| pick(&l.series).buckets().iter());
    let t_max = buckets().map(|b| b.t).fold(0.0f64, f64::max).max(1e-3);
    let (lo, hi) = buckets()
        .flat_map(|b| [f(b.min), f(b.max)])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    let pad = 0.05 * (hi - lo).max(1e-12);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_max, (lo - pad)..(hi + pad))
        .map_err(e)?;
    let power = |y: &f64| format!("1e{:.1}", y);
    let plain = |y: &f64| format!("{y:.1e}");
    chart
        .configure_mesh()
        .x_desc("sim time (s)")
        .y_desc(y_desc)
        .y_label_formatter(if log { &power } else { &plain })
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(e)?;
    for lane in lanes {
        let colour = color(lane.integrator);
        let points = pick(&lane.series)
            .buckets()
            .iter()
            .flat_map(|b| [(b.t, f(b.min)), (b.t, f(b.max))]);
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(e)?
            .label(lane.integrator.to_string())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    Ok(())
}

fn draw_live<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scene: &str,
    lanes: &[LiveLane],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let parts = root.split_evenly((1, 3));
    let error_title = format!("{scene}: position error");
    live_panel(
        &parts[0],
        (&error_title, "largest position error (m)"),
        true,
        lanes,
        |s| &s.error_max,
    )?;
    live_panel(
        &parts[1],
        ("relative energy error", "(E - E0) / scale"),
        false,
        lanes,
        |s| &s.energy,
    )?;
    let series: Series = lanes
        .iter()
        .filter_map(|l| {
            l.work_precision
                .map(|(x, y)| (l.integrator, vec![(x, y.max(ERROR_FLOOR))]))
        })
        .collect();
    panel(
        &parts[2],
        "work-precision so far",
        "force evaluations per simulated second",
        &series,
    )?;
    root.present().map_err(|e| e.to_string())
}

/// The window's three live plots as PNG bytes.
pub fn live_png(scene: &str, lanes: &[LiveLane]) -> Result<Vec<u8>, PlotError> {
    register_font()?;
    let (w, h) = LIVE_SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, LIVE_SIZE).into_drawing_area();
        draw_live(root, scene, lanes).map_err(PlotError::Draw)?;
    }
    encode_png(&rgb, (w, h))
}
