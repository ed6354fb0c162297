//! The loop lab's plot: p99 display error per display, one line per loop policy and draw mode
//! (the four draw modes under the plain accumulator, and the predicting draw under every other
//! policy), for one tick rate, subject and integrator. Log scale: the draw modes differ by an
//! order of magnitude.

use plotters::prelude::*;

use crate::clock::LoopPolicy;
use crate::integrate::Integrator;
use crate::pacing::sweep::{Cell, Row, cells};
use crate::pacing::{DrawMode, Subject};

use super::{PlotError, register_font};

/// Size of the plot (SVG user units).
pub const SIZE: (u32, u32) = (1200, 600);

/// The lines drawn: (policy, draw mode).
fn lines() -> Vec<(&'static str, DrawMode)> {
    let mut out: Vec<_> = DrawMode::ALL.map(|m| ("accumulator", m)).to_vec();
    out.extend(
        LoopPolicy::NAMES
            .into_iter()
            .filter(|p| *p != "accumulator")
            .map(|p| (p, DrawMode::Predict)),
    );
    out
}

const COLOURS: [RGBColor; 10] = [
    RGBColor(90, 90, 90),
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(188, 189, 34),
];

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
    rate: f64,
    subject: Subject,
    integrator: Integrator,
) -> Result<(), String> {
    let e = |err: DrawingAreaErrorKind<DB::ErrorType>| err.to_string();
    root.fill(&WHITE).map_err(e)?;
    let all: Vec<Cell<'_>> = cells(rows, subject, integrator)
        .into_iter()
        .filter(|c| c.row.rate == rate)
        .collect();
    let mut displays: Vec<&str> = Vec::new();
    for c in &all {
        if !displays.contains(&c.row.display.as_str()) {
            displays.push(&c.row.display);
        }
    }
    let errors = |policy: &str, mode: DrawMode| -> Vec<(f64, f64)> {
        displays
            .iter()
            .enumerate()
            .filter_map(|(i, d)| {
                all.iter()
                    .find(|c| c.row.display == *d && c.row.policy == policy && c.mode == mode)
                    .map(|c| (i as f64, (c.metrics().error.p99 * 1e3).max(1e-3)))
            })
            .collect()
    };
    let values: Vec<f64> = lines()
        .iter()
        .flat_map(|(p, m)| errors(p, *m))
        .map(|p| p.1)
        .collect();
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(0.0f64, f64::max);
    let (lo, hi) = if lo.is_finite() {
        (lo / 1.5, hi * 1.5)
    } else {
        (1.0, 10.0)
    };
    let n = displays.len().max(1) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{} at {rate} Hz ({}): p99 display error by display",
                subject.name(),
                integrator.name()
            ),
            ("sans-serif", 18),
        )
        .margin(12)
        .margin_right(70)
        .x_label_area_size(60)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5..n - 0.5, (lo..hi).log_scale())
        .map_err(e)?;
    let names = displays.clone();
    let label = move |x: &f64| {
        let i = x.round();
        if (x - i).abs() > 1e-6 || i < 0.0 {
            return String::new();
        }
        names
            .get(i as usize)
            .map(|s| {
                // A capture's name is its file and application: keep the file's stem.
                match s.split_once(".csv") {
                    Some((stem, _)) => stem.to_string(),
                    None => s.to_string(),
                }
            })
            .unwrap_or_default()
    };
    chart
        .configure_mesh()
        .x_desc("display")
        .y_desc("p99 display error (mm)")
        .x_labels(displays.len().max(2))
        .x_label_formatter(&label)
        .y_labels(12)
        .y_label_formatter(&|y| format!("{y:.0}"))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(e)?;
    for (k, (policy, mode)) in lines().into_iter().enumerate() {
        let points = errors(policy, mode);
        if points.is_empty() {
            continue;
        }
        let c = COLOURS[k % COLOURS.len()];
        let width = if (policy, mode) == ("accumulator", DrawMode::Interpolate) {
            3
        } else {
            2
        };
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                c.stroke_width(width),
            ))
            .map_err(e)?
            .label(format!("{policy} + {}", mode.name()))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart
            .draw_series(points.iter().map(|p| Circle::new(*p, 4, c.filled())))
            .map_err(e)?;
    }
    super::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(e)
}

/// The plot as SVG text.
pub fn svg(
    rows: &[Row],
    rate: f64,
    subject: Subject,
    integrator: Integrator,
) -> Result<String, PlotError> {
    register_font()?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        draw(root, rows, rate, subject, integrator).map_err(PlotError::Draw)?;
    }
    Ok(text)
}

/// The plot as PNG bytes.
pub fn png(
    rows: &[Row],
    rate: f64,
    subject: Subject,
    integrator: Integrator,
) -> Result<Vec<u8>, PlotError> {
    register_font()?;
    let (w, h) = SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(root, rows, rate, subject, integrator).map_err(PlotError::Draw)?;
    }
    super::encode_png(&rgb, (w, h))
}
