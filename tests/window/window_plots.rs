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
    s.run_ticks(60 * 3600).unwrap();
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
    s.run_ticks(20).unwrap();
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
    s.run_ticks(60).unwrap();
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

#[test]
fn body_0_is_drawn_only_where_it_is_not_the_largest_error() {
    use volley::app::panel::plots::body_zero_differs;
    // One body: its error is the largest at every tick, so its line would lie on that one.
    let mut one = session("drag", vec![Integrator::ExplicitEuler, Integrator::Rk4]);
    one.run_ticks(120).unwrap();
    for lane in one.lanes() {
        assert!(!lane.history.series.error_first.buckets().is_empty());
        assert!(!body_zero_differs(&lane.history.series));
    }
    // Three masses on one launch: the lightest (not body 0) drifts furthest from its closed
    // form under explicit Euler, so body 0's series parts from the largest.
    let mut three = session("drag_masses", vec![Integrator::ExplicitEuler]);
    three.run_ticks(120).unwrap();
    assert!(body_zero_differs(&three.lanes()[0].history.series));
}

#[test]
fn each_lanes_line_is_wider_than_the_next_so_coinciding_lines_stay_visible() {
    use volley::app::panel::plots::line_width;
    assert_eq!(line_width(0, 1), 1.5);
    let widths: Vec<f32> = (0..4).map(|k| line_width(k, 4)).collect();
    assert_eq!(widths, [5.25, 4.0, 2.75, 1.5]);
    // Past four lanes the first ones stay at the widest.
    assert_eq!(line_width(0, 16), 5.25);
    assert_eq!(line_width(15, 16), 1.5);
}

#[test]
fn the_work_precision_legend_takes_the_corner_with_the_fewest_points() {
    use egui_plot::Corner;
    use volley::app::panel::plots::legend_corner;
    // (log10 evaluations per second, log10 error): Euler and semi-implicit Euler cheap and
    // coarse, RK4 dear and accurate, Verlet between them.
    let euler = [1.8, 0.0];
    let rk4 = [2.4, -10.0];
    // Verlet cheap and middling (the orbit): the top right is empty.
    let orbit = [euler, [1.8, -0.2], [1.8, -3.0], rk4];
    assert_eq!(legend_corner(&orbit), Corner::RightTop);
    // Verlet dearer than the middle (the drag scene): the bottom left is the empty one.
    let drag = [euler, [1.9, -0.1], [2.3, -4.0], [2.2, 1.0], rk4];
    assert_eq!(legend_corner(&drag), Corner::LeftBottom);
    // Every quarter taken: the first of the fewest, in the stated order.
    let all = [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0], [0.9, 0.9]];
    assert_eq!(legend_corner(&all), Corner::LeftBottom);
    assert_eq!(legend_corner(&[]), Corner::RightTop);
}

#[test]
fn the_plots_markers_and_probe_stay_within_their_triangle_budget() {
    let test = "the_plots_markers_and_probe_stay_within_their_triangle_budget";
    let dir = support::scratch_dir(test);
    let (on, off) = (dir.join("on.script"), dir.join("off.script"));
    std::fs::write(&on, "hover body 0\n").unwrap();
    std::fs::write(&off, "key k\nkey m\n").unwrap();
    // scripts/bench-window's two runs (the drag scene, four lanes, long history), shorter.
    let triangles = |script: &std::path::Path| {
        let args = [
            "window",
            "drag",
            "--compare",
            "default",
            "--warm-up-ticks",
            "3000",
            "--exit-after-frames",
            "8",
            "--no-watch",
            "--script",
            script.to_str().unwrap(),
        ];
        let out = crate::window_smoke::window_stdout(test, &args, "1280x800")?;
        // window: N frames, median frame F ms, of which work W ms (UI U ms, T triangles), ...
        let count = out
            .split(" triangles)")
            .next()
            .and_then(|head| head.rsplit(' ').next())
            .and_then(|n| n.parse::<usize>().ok());
        Some(count.unwrap_or_else(|| panic!("no triangle count in:\n{out}")))
    };
    let (Some(on), Some(off)) = (triangles(&on), triangles(&off)) else {
        return;
    };
    // On a software adapter a frame costs about what its triangles do (docs/performance.md,
    // "The window on a software adapter"). The plots draw a point per three points of their
    // width, two triangles of band and four to six of line each: 4 lanes x 2 series x about 90
    // points x 8 is about 5 800, plus axes, grid, labels and the probe's box. 10 000 leaves
    // room for fonts and sizes, not for drawing 400 points a line again (over 15 000 added).
    assert!(on > off, "on {on}, off {off}");
    assert!(on - off <= 10_000, "the plots add {} triangles", on - off);
}

/// The rifle under RK4 at 60 Hz: the bullet stays within a few hundredths of a millimetre of its
/// converged reference all the way to the ground, where it comes to rest (restitution 0).
/// Coming to rest is a contact, so it ends the reference: the plot shows the error up to the
/// landing and no sample after it, and the work-precision point is the largest error plotted.
/// (It once went on measuring against a reference falling through the ground: about a metre.)
///
/// The bound, 3e-5 m: an independent reference, the study's RK4 at 32 substeps a tick (its own
/// error about 1.3e-9 m), puts RK4 at 60 Hz at most 2.3e-5 m off over this flight (`volley study
/// rifle --integrators rk4 --dt 0.016666667`); the window's extrapolation reference gives
/// 1.9e-5 m. Most of it comes where the bullet crosses the G7 curve's transonic kink, a
/// corner of the interpolated table that costs RK4 its fourth order (observed 1.8 between 60
/// and 120 Hz).
#[test]
fn on_the_rifle_the_plotted_error_ends_at_the_landing_and_the_work_precision_point_is_its_largest()
{
    let mut s = session("rifle", vec![Integrator::Rk4]);
    // 2.4 s of flight at 60 Hz: the landing is at about 2.17 s.
    s.run_ticks(150).unwrap();
    let lane = &s.lanes()[0];
    let id = lane.sim.world.bodies().ids()[0];
    let reference = lane.history.references.get(id).unwrap();
    let Some(volley::render::reference::ReferenceEnd::Contact { tick, time }) = reference.end
    else {
        panic!("the landing ends the reference: {:?}", reference.end);
    };
    assert!((2.1..2.25).contains(&time), "landing at {time} s");
    let series = &lane.history.series;
    let buckets = series.error_max.buckets();
    assert!(!buckets.is_empty());
    // Up to the landing: every sample below 3e-5 m (above).
    assert!(buckets.iter().all(|b| b.max < 3e-5), "{buckets:?}");
    // Nothing against the ended reference: the last sample is the tick before the landing.
    assert_eq!(
        buckets.last().unwrap().tick,
        tick - 1,
        "landing tick {tick}"
    );
    let largest = series.error_max.max().unwrap();
    let (_, error) = volley::app::panel::plots::work_precision(lane).unwrap();
    assert_eq!(error, largest);
}

/// The same in the real window under Xvfb: run past the landing, press the panel's "Save
/// plots", and read the CSV it writes: every plotted error is below 3e-5 m (the bound above),
/// none is at or after the landing tick, and the work-precision row's error is the largest
/// plotted.
#[test]
fn the_real_window_saves_the_rifles_plots_ending_at_the_landing() {
    let test = "the_real_window_saves_the_rifles_plots_ending_at_the_landing";
    let dir = support::scratch_dir(test);
    let script = dir.join("save.txt");
    std::fs::write(&script, "wait 3\nclick Save plots\nwait 3\n").unwrap();
    let args = [
        "window",
        "rifle",
        "--warm-up-ticks",
        "150",
        "--paused",
        "--exit-after-frames",
        "8",
        "--no-watch",
        "--script",
        script.to_str().unwrap(),
    ];
    let Some(out) = crate::window_smoke::under_xvfb_in(test, &dir, &args, "1280x800") else {
        return;
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The window's working folder: it writes plots-SCENE-tickN.csv there.
    let csv = dir.join("plots-rifle-tick150.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let errors: Vec<(u64, f64)> = rows
        .iter()
        .filter(|r| r[0] == "rk4" && r[1] == "error_max")
        .map(|r| (r[2].parse().unwrap(), r[5].parse().unwrap()))
        .collect();
    assert!(errors.len() > 100, "{text}");
    assert!(errors.iter().all(|&(_, e)| e < 3e-5), "{errors:?}");
    // The landing is at about 2.17 s, tick 130 or 131 at 60 Hz: no sample from then on.
    let last = errors.iter().map(|&(t, _)| t).max().unwrap();
    assert!((125..131).contains(&last), "last plotted tick {last}");
    let largest = errors.iter().map(|&(_, e)| e).fold(0.0, f64::max);
    let wp = rows
        .iter()
        .find(|r| r[0] == "rk4" && r[1] == "work-precision")
        .expect("a work-precision row");
    assert_eq!(wp[5].parse::<f64>().unwrap(), largest, "{wp:?}");
}
