//! The live plots: a whole run in bounded memory (an hour at 60 Hz in four lanes), the series
//! they show, the CSV and PNG they save, and the real window drawing them under Xvfb.

use crate::support;

use std::time::Duration;

use volley::app::session::Session;
use volley::render::series::{BUCKETS, Bucket, Decimated};
use volley::{Integrator, scene};

fn session(name: &str, compare: Vec<Integrator>) -> Session {
    let path = support::crate_path(&format!("assets/scenes/{name}.ron"));
    Session::new(scene::load(&path).unwrap(), &path, compare)
}

/// The stated budget: three series of at most `BUCKETS` buckets a lane, plus the per-body
/// energy starts of at most 4 x 64 bodies, plus headers; four lanes.
const LANE_BUDGET: usize = 3 * BUCKETS * std::mem::size_of::<Bucket>()
    + 3 * std::mem::size_of::<Decimated>()
    + 4 * 64 * 24;

// Under 1 MiB for four lanes, as docs/window.md states.
const _: () = assert!(4 * LANE_BUDGET < 1 << 20);

#[test]
fn an_hour_at_60_hz_in_four_lanes_stays_within_the_stated_budget() {
    let lanes = vec![
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
    ];
    // The drag scene at 60 Hz (a closed form, so every lane has an error to plot).
    let mut s = session("drag", lanes);
    s.run_ticks(60 * 3600);
    assert_eq!(s.world().tick(), 216_000);
    for lane in s.lanes() {
        let series = &lane.history.series;
        assert_eq!(series.samples, 216_000);
        assert!(
            series.bytes() <= LANE_BUDGET,
            "{} > {LANE_BUDGET}",
            series.bytes()
        );
        for d in [&series.error_max, &series.error_first, &series.energy] {
            assert!(d.buckets().len() <= BUCKETS);
        }
        // The shot lands at about 5 s: the error series ends there (the closed form knows no
        // ground), the energy one runs the whole hour.
        assert!(series.energy.buckets().last().unwrap().t > 3590.0);
    }
    let total: usize = s.lanes().iter().map(|l| l.history.series.bytes()).sum();
    assert!(total <= 4 * LANE_BUDGET, "{total}");
}

#[test]
fn the_plotted_error_is_the_error_column_and_the_energy_error_is_relative() {
    let mut s = session("drag", vec![Integrator::ExplicitEuler, Integrator::Rk4]);
    for _ in 0..30 {
        s.frame(Duration::from_millis(50));
    }
    for lane in s.lanes() {
        let series = &lane.history.series;
        let last = *series.error_first.buckets().last().unwrap();
        let volley::render::BodyError::Measured { position, .. } =
            lane.history.references.error(&lane.sim.world, 0)
        else {
            panic!("the drag scene has a closed form");
        };
        // The newest bucket holds this tick's sample (it is one tick wide this early).
        assert_eq!(last.max, position);
        let e = series.energy.buckets().last().unwrap().max;
        assert!(
            e.abs() < 1.0,
            "a relative error, well inside the guard's bound: {e}"
        );
    }
    // Explicit Euler's error grows past RK4's by orders of magnitude.
    let err = |i: usize| s.lanes()[i].history.series.error_max.max().unwrap();
    assert!(err(0) > 1e4 * err(1), "{} vs {}", err(0), err(1));
    // And the work-precision points: RK4 pays four evaluations a step.
    let wp: Vec<(f64, f64)> = s
        .lanes()
        .iter()
        .map(|l| volley::app::panel::plots::work_precision(l).unwrap())
        .collect();
    assert!((wp[1].0 / wp[0].0 - 4.0).abs() < 1e-9, "{wp:?}");
}

#[test]
fn save_plots_writes_the_series_as_csv_and_the_plots_as_png() {
    let dir = support::scratch_dir("save_plots_writes_the_series");
    let mut s = session("seed", vec![Integrator::ExplicitEuler, Integrator::Rk4]);
    s.run_ticks(20);
    let (csv, png) = volley::app::panel::plots::write(&dir, &s).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("lane,series,tick,t,min,max"));
    let rows: Vec<&str> = lines.collect();
    for lane in ["explicit-euler", "rk4"] {
        for series in ["error_max", "error_body0", "energy", "work-precision"] {
            assert!(
                rows.iter()
                    .any(|r| r.starts_with(&format!("{lane},{series},"))),
                "no {lane} {series} row"
            );
        }
    }
    let image = volley::render::Image::load_png(&png).unwrap();
    assert_eq!((image.width, image.height), volley::plot::LIVE_SIZE);
    // Not blank: the lanes' colours are drawn.
    let [r, g, b, _] = volley::palette::integrator(Integrator::Rk4);
    assert!(
        image
            .rgba
            .chunks(4)
            .any(|p| p[0] == r && p[1] == g && p[2] == b)
    );
}

#[test]
fn the_real_window_draws_the_plots_in_each_lanes_colour() {
    let test = "the_real_window_draws_the_plots_in_each_lanes_colour";
    let dir = support::scratch_dir(test);
    let shot = dir.join("plots.png");
    let args = [
        "window",
        "drag",
        "--compare",
        "explicit-euler,rk4",
        "--warm-up-ticks",
        "300",
        "--exit-after-frames",
        "12",
        "--no-watch",
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    let Some(out) = crate::window_smoke::under_xvfb_sized(test, &[], &args, "1280x800") else {
        return;
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = volley::render::Image::load_png(&shot).unwrap();
    assert_eq!((image.width, image.height), (1280, 800));
    // The plots panel is at least its 190 px minimum tall at the bottom, right of the 340 px
    // side panel, so the bottom 160 px right of x = 400 are plots only: both lanes' colours
    // are there (lines are anti-aliased, so look for pixels close to the colour).
    let (w, h) = (image.width as usize, image.height as usize);
    let near = |c: [u8; 4]| {
        (h - 160..h).any(|y| {
            (400..w).any(|x| {
                let p = &image.rgba[(y * w + x) * 4..][..3];
                (0..3).all(|k| (i32::from(p[k]) - i32::from(c[k])).abs() <= 24)
            })
        })
    };
    for i in [Integrator::ExplicitEuler, Integrator::Rk4] {
        assert!(
            near(volley::palette::integrator(i)),
            "no {i:?} pixels in the plots"
        );
    }
}

#[test]
fn a_scene_without_a_closed_form_is_measured_against_the_numerical_reference() {
    // The wind scene: quadratic drag, no closed form. The first bodies get the extrapolation
    // reference, so the error column and the plots have numbers; RK4 at 60 Hz is far closer
    // to it than explicit Euler.
    let mut s = session("wind", vec![Integrator::ExplicitEuler, Integrator::Rk4]);
    s.run_ticks(60);
    let error = |lane: usize| {
        let l = &s.lanes()[lane];
        match l.history.references.error(&l.sim.world, 0) {
            volley::render::BodyError::Measured { position, .. } => position,
            other => panic!("{other:?}"),
        }
    };
    assert!(error(1) < 1e-6, "{}", error(1));
    assert!(error(0) > 1e3 * error(1), "{} vs {}", error(0), error(1));
    let r = s.lanes()[1]
        .history
        .references
        .get(s.world().bodies().ids()[0])
        .unwrap();
    let (kind, estimate) = r.kind();
    assert!(kind.starts_with("extrapolation"), "{kind}");
    // Its own error estimate is a hundredth of the error it measures, or less.
    assert!(
        estimate.unwrap() < 1e-2 * error(1),
        "{estimate:?} vs {}",
        error(1)
    );
    assert!(!s.lanes()[1].history.series.error_max.buckets().is_empty());
}
