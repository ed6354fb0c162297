//! `volley study`: what it measures is what the math says, and what it writes is complete.

use std::path::{Path, PathBuf};
use std::process::Command;

use volley::Integrator::{self, *};
use volley::scene::{self, Scene};
use volley::study::{self, OrderFit, Outcome, ReferenceKind, StudyConfig, StudyReport};

fn load(name: &str) -> Scene {
    scene::load(Path::new(&format!("assets/scenes/{name}.ron"))).unwrap()
}

fn study(scene: &Scene, integrators: &[Integrator], dts: &[f64]) -> StudyReport {
    let config = StudyConfig {
        integrators: integrators.to_vec(),
        dts: dts.to_vec(),
        timing: false,
        ..StudyConfig::for_scene(scene)
    };
    study::run(scene, &config, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn point(r: &StudyReport, i: Integrator, dt: f64) -> &study::StudyPoint {
    r.points
        .iter()
        .find(|p| p.integrator == i && (p.dt - dt).abs() < 1e-9)
        .unwrap()
}

#[test]
fn euler_errors_on_the_seed_are_g_t_h_over_2_and_of_order_one() {
    let scene = load("seed");
    let dts = [0.2, 0.1, 0.05];
    let r = study(
        &scene,
        &[
            ExplicitEuler,
            SemiImplicitEuler,
            VelocityVerlet,
            Midpoint,
            Rk4,
        ],
        &dts,
    );
    assert_eq!(
        r.references[0].kind,
        ReferenceKind::ExactFlow,
        "the seed has a ground and a target"
    );
    let span = scene.duration(); // 5.4 s: 27, 54 and 108 ticks exactly
    for dt in dts {
        for i in [ExplicitEuler, SemiImplicitEuler] {
            let e = point(&r, i, dt).errors.unwrap();
            let expected = 9.81 * span * dt / 2.0;
            // The only error is in z: g T h / 2 (high for explicit, low for semi-implicit).
            assert!(
                (e.final_position - expected).abs() < 1e-9 * expected,
                "{i} at {dt}: {e:?}"
            );
        }
    }
    for (i, fit) in &r.orders {
        match i {
            ExplicitEuler | SemiImplicitEuler => match fit {
                OrderFit::Fitted { order, points: 3 } => {
                    assert!((order - 1.0).abs() < 1e-6, "{i}: {order}")
                }
                other => panic!("{i}: {other:?}"),
            },
            _ => assert_eq!(
                *fit,
                OrderFit::AtRoundingFloor,
                "{i} is exact under gravity"
            ),
        }
    }
}

#[test]
fn force_evaluations_are_counted_per_stage() {
    // The drag scene touches nothing in 5.2 s, so every evaluation is an integrator stage.
    let scene = load("drag");
    let integrators = [
        ExplicitEuler,
        SemiImplicitEuler,
        VelocityVerlet,
        Midpoint,
        Rk4,
        ImplicitEuler,
    ];
    let r = study(&scene, &integrators, &[1.0 / 60.0, 1.0 / 120.0]);
    for p in &r.points {
        let per_step = p.integrator.evals_per_step(scene.forces());
        assert_eq!(p.force_evals, p.ticks * per_step, "{}", p.integrator);
        let expected = per_step as f64 / p.dt;
        assert!(
            (p.evals_per_second - expected).abs() < 1e-9 * expected,
            "{}",
            p.integrator
        );
    }
}

#[test]
fn the_reference_is_the_best_one_available() {
    let spring = load("hard/stiff_spring");
    let r = study(&spring, &[VelocityVerlet], &[0.001]);
    assert_eq!(
        r.references[0].kind,
        ReferenceKind::ClosedForm,
        "no contacts, linear spring"
    );
}

/// A shot under quadratic drag (no closed form), with no ground.
const AIR: &str = "Scene(dt: 0.05, duration: 3.0, integrator: Rk4,
    forces: [Gravity((0, 0, -9.81)), QuadraticDrag(0.02)],
    bodies: [(mass: 1.0, position: (0, 0, 1), launch: Velocity((20.0, 0, 20.0)))])";

#[test]
fn quadratic_drag_is_measured_against_the_extrapolation_reference() {
    let air = scene::parse(AIR, "air.ron", "air").unwrap();
    let r = study(&air, &[Rk4, VelocityVerlet], &[0.1, 0.05, 0.025]);
    let smallest = r
        .points
        .iter()
        .map(|p| p.errors.unwrap().final_position)
        .fold(f64::INFINITY, f64::min);
    for reference in &r.references {
        let ReferenceKind::Extrapolation {
            tolerance,
            error_estimate,
        } = reference.kind
        else {
            panic!("no contacts, no closed form: {:?}", reference.kind)
        };
        assert_eq!(tolerance, study::reference::EXTRAPOLATION_TOLERANCE);
        // Far below every measured error: a thousandth of the smallest (RK4 at the finest dt).
        assert!(
            error_estimate > 0.0 && error_estimate < smallest / 1000.0,
            "{error_estimate} vs {smallest}"
        );
    }
    // A reference good to its estimate leaves RK4 its fourth order (and Verlet its second);
    // a poor one would flatten the slopes at its own error.
    for (i, fit) in &r.orders {
        let OrderFit::Fitted { order, points: 3 } = fit else {
            panic!("{i}: {fit:?}")
        };
        let documented = f64::from(i.info().order);
        assert!((order - documented).abs() < 0.2, "{i}: {order}");
    }
    let md = study::output::markdown(&r);
    assert!(
        md.contains("- dt = 0.100: extrapolation (adaptive Gragg-Bulirsch-Stoer"),
        "{md}"
    );
    assert!(md.contains("its own error estimate: about "), "{md}");
    let estimate = format!("{:?}", r.references[0].error_estimate());
    let first_row = study::output::csv(&r).lines().nth(1).unwrap().to_string();
    assert!(first_row.ends_with(&format!(",{estimate}")), "{first_row}");
}

#[test]
fn with_contacts_and_no_closed_form_the_reference_is_rk4_at_a_sixteenth_of_the_finest_dt() {
    // The same shot over a ground: the extrapolation would step over the impact.
    let text = AIR
        .replace(
            "bodies:",
            "ground: (height: 0.0, restitution: 0.5), bodies:",
        )
        .replace("duration: 3.0", "duration: 5.0");
    let grounded = scene::parse(&text, "air.ron", "air").unwrap();
    let r = study(&grounded, &[Rk4, VelocityVerlet], &[0.05, 0.025]);
    let reference = &r.references[0];
    let ReferenceKind::Rk4 {
        substeps,
        error_estimate,
        ..
    } = reference.kind
    else {
        panic!("contacts and quadratic drag: {:?}", reference.kind)
    };
    assert_eq!(substeps, 32, "at most 1/16 of the finest dt studied");
    let rk4 = point(&r, Rk4, 0.05);
    assert!(rk4.events.reference > 0, "the shot lands within 5 s");
    let rk4 = rk4.errors.unwrap().max_position;
    assert!(
        error_estimate > 0.0 && error_estimate < rk4 / 100.0,
        "{error_estimate} vs {rk4}"
    );
    assert!(
        reference.describe().contains("the scene has contacts"),
        "{}",
        reference.describe()
    );
}

#[test]
fn event_times_are_measured_against_the_reference() {
    let r = study(&load("seed"), &[VelocityVerlet, ExplicitEuler], &[0.1]);
    let verlet = point(&r, VelocityVerlet, 0.1).events;
    // The closest approach over the target on the way up, the hit on the way down, and the
    // closest approach after it.
    assert_eq!(
        (verlet.matched, verlet.reference, verlet.hit_mismatches),
        (3, 3, 0)
    );
    assert!(verlet.max_time_error.unwrap() < 1e-9, "{verlet:?}");
    // Explicit Euler is g t h / 2 = 2.6 m high when the exact path enters the 0.5 m target.
    let euler = point(&r, ExplicitEuler, 0.1).events;
    assert_eq!(euler.hit_mismatches, 1, "{euler:?}");
}

#[test]
fn energy_drift_is_reported_for_conservative_scenes_only() {
    let spring = load("hard/stiff_spring");
    let r = study(&spring, &[VelocityVerlet], &[0.001]);
    let drift = r.points[0]
        .energy
        .clone()
        .expect("an undamped spring conserves energy");
    assert_eq!(drift.windows.len(), 10);
    // Verlet from rest keeps E/E0 in [1 - (w h)^2 / 4, 1]: drift at most (w h)^2 / 4.
    let y = 100.0 * 0.001;
    assert!(
        drift.windows.iter().all(|d| *d <= y * y / 4.0 + 1e-12),
        "{drift:?}"
    );
    assert!(drift.windows.iter().any(|d| *d > 0.0));
    let r = study(&load("drag"), &[VelocityVerlet], &[0.1]);
    assert_eq!(r.points[0].energy, None, "drag dissipates");
}

#[test]
fn a_diverged_point_is_a_result_not_a_failure() {
    let scene = load("hard/stiff_spring");
    let r = study(&scene, &[ExplicitEuler, SemiImplicitEuler], &[scene.dt()]);
    let euler = point(&r, ExplicitEuler, scene.dt());
    match euler.outcome {
        Outcome::Diverged(d) => assert_eq!((d.tick, d.body.0), (2, 0)),
        other => panic!("{other:?}"),
    }
    assert!(euler.errors.is_none() && !euler.precheck.stable);
    assert_eq!(
        point(&r, SemiImplicitEuler, scene.dt()).outcome,
        Outcome::Completed
    );
    assert!(
        r.warnings.iter().any(|w| w.contains("explicit-euler")),
        "{:?}",
        r.warnings
    );
}

#[test]
fn the_tolerance_names_the_cheapest_setting_that_meets_it() {
    let scene = load("seed");
    let mut config = StudyConfig {
        integrators: vec![ExplicitEuler, VelocityVerlet, Rk4],
        dts: vec![0.2, 0.1, 0.05, 0.025],
        timing: false,
        tolerance: Some(1.0),
        ..StudyConfig::for_scene(&scene)
    };
    let r = study::run(&scene, &config, &mut |_| {}).unwrap();
    let (_, best) = r.cheapest.unwrap();
    let best = &r.points[best.unwrap()];
    // Verlet is exact under gravity, so its largest step is the cheapest that meets any tolerance.
    assert_eq!((best.integrator, best.dt), (VelocityVerlet, 0.2));
    for p in r
        .points
        .iter()
        .filter(|p| p.errors.unwrap().max_position <= 1.0)
    {
        assert!(p.evals_per_second >= best.evals_per_second);
    }
    config.tolerance = Some(1e-20);
    let r = study::run(&scene, &config, &mut |_| {}).unwrap();
    assert_eq!(r.cheapest, Some((1e-20, None)));
}

/// Fields of a CSV line, honouring quotes.
fn fields(line: &str) -> usize {
    let mut quoted = false;
    1 + line
        .chars()
        .filter(|c| {
            if *c == '"' {
                quoted = !quoted;
            }
            *c == ',' && !quoted
        })
        .count()
}

#[test]
fn the_report_table_csv_and_plots_cover_every_point() {
    let r = study(&load("seed"), &[ExplicitEuler, Rk4], &[0.2, 0.1]);
    let md = study::output::markdown(&r);
    let rows = md
        .lines()
        .filter(|l| l.starts_with("| explicit-euler |") || l.starts_with("| rk4 |"));
    assert_eq!(
        rows.count(),
        r.points.len() + 2,
        "4 table rows and 2 order rows"
    );
    let csv = study::output::csv(&r);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), r.points.len() + 1);
    assert!(lines.iter().all(|l| fields(l) == fields(lines[0])), "{csv}");
    let svg = volley::plot::svg(&r).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("explicit-euler") && svg.contains("rk4"));
    let png = volley::plot::png(&r).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!((info.width, info.height), volley::plot::SIZE);
    assert!(pixels.iter().any(|b| *b < 128), "something is drawn");
}

fn volley(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .output()
        .unwrap()
}

fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("volley-study-{}-{name}", std::process::id()))
}

#[test]
fn the_command_writes_the_four_files() {
    let out = scratch("cli");
    let run = volley(&[
        "study",
        "seed",
        "--dt-range",
        "0.2..0.05",
        "--points",
        "3",
        "--integrators",
        "explicit-euler,rk4",
        "--no-timing",
        "--tolerance",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("| rk4 | 0.100 |") && stdout.contains("Cheapest setting"),
        "{stdout}"
    );
    for ext in ["md", "csv", "svg", "png"] {
        assert!(out.join(format!("seed.{ext}")).is_file(), "seed.{ext}");
    }
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn bad_study_arguments_exit_2_with_one_line() {
    let cases: [&[&str]; 3] = [
        &["study", "seed", "--dt-range", "0.1", "--points", "3"],
        // Quadratic drag has no closed form, so `exact` is refused (a zero-rest-length spring,
        // as in hard/stiff_spring, now has one).
        &["study", "wind", "--integrators", "exact", "--no-timing"],
        &["study", "seed", "--integrators", "leapfrog"],
    ];
    for args in cases {
        let run = volley(args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
    }
}

/// `volley study` on the air scene (written to `dir`) with `extra` arguments: its output.
fn air_study(dir: &Path, extra: &[&str]) -> std::process::Output {
    let scene = dir.join("air.ron");
    std::fs::write(&scene, AIR).unwrap();
    let mut args = vec![
        "study",
        scene.to_str().unwrap(),
        "--dt",
        "0.1,0.05,0.025",
        "--integrators",
        "explicit-euler,verlet,rk4",
        "--tolerance",
        "0.001",
        "--no-timing",
    ];
    args.extend_from_slice(extra);
    volley(&args)
}

fn ok(run: &std::process::Output) -> String {
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    String::from_utf8(run.stdout.clone()).unwrap()
}

#[test]
fn three_shards_and_a_merge_write_what_one_run_writes() {
    let dir = scratch("shards");
    std::fs::create_dir_all(&dir).unwrap();
    let (one, parts, merged) = (dir.join("one"), dir.join("parts"), dir.join("merged"));
    let whole = ok(&air_study(&dir, &["--out", one.to_str().unwrap()]));
    for i in 0..3 {
        let shard = format!("{i}/3");
        let run = air_study(&dir, &["--shard", &shard, "--out", parts.to_str().unwrap()]);
        assert_eq!(ok(&run), "", "a shard writes its file, not a report");
    }
    let files: Vec<String> = (0..3)
        .map(|i| {
            parts
                .join(format!("air.shard-{i}-of-3.json"))
                .display()
                .to_string()
        })
        .collect();
    let mut args = vec!["study", "--merge"];
    args.extend(files.iter().map(String::as_str));
    args.extend(["--out", merged.to_str().unwrap()]);
    let report = ok(&volley(&args));
    // Timing is off in both, so there are no wall times to mask: every byte must agree,
    // the observed orders and the cheapest setting included (fitted over all nine points).
    assert_eq!(report, whole);
    assert!(
        report.contains("Cheapest setting that meets it"),
        "{report}"
    );
    for ext in ["md", "csv", "svg", "png"] {
        let file = format!("air.{ext}");
        assert!(
            std::fs::read(one.join(&file)).unwrap() == std::fs::read(merged.join(&file)).unwrap(),
            "{file} differs"
        );
    }
    // Bad merges: one line naming the problem (and the file), exit 2.
    let bad = |args: &[&str], expected: &str| {
        let run = volley(args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with(expected), "{stderr}");
    };
    bad(
        &["study", "--merge", &files[0], &files[2]],
        "error: missing shard 1/3: the files given hold shards 0, 2 of 3",
    );
    bad(
        &[
            "study", "--merge", &files[0], &files[1], &files[1], &files[2],
        ],
        &format!(
            "error: {}: shard 1/3 given twice (also {})",
            files[1], files[1]
        ),
    );
    let other = dir.join("other");
    ok(&air_study(
        &dir,
        &[
            "--until",
            "2.0",
            "--shard",
            "1/3",
            "--out",
            other.to_str().unwrap(),
        ],
    ));
    let other_file = other.join("air.shard-1-of-3.json").display().to_string();
    bad(
        &["study", "--merge", &files[0], &other_file, &files[2]],
        &format!("error: {other_file}: the study configuration"),
    );
    let broken = dir.join("broken.json");
    std::fs::write(&broken, "{\"format\": \"volley-study-shard\"").unwrap();
    let broken = broken.display().to_string();
    bad(
        &["study", "--merge", &files[0], &broken],
        &format!("error: {broken}: expected a study shard file"),
    );
    bad(
        &["study", "seed", "--shard", "3/3"],
        "error: --shard: expected I/N with 0 <= I < N",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_report_on_one_thread_is_the_report_on_every_core() {
    let dir = scratch("threads");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("air.ron");
    std::fs::write(&scene, AIR).unwrap();
    let args = [
        "study",
        scene.to_str().unwrap(),
        "--dt-range",
        "0.1..0.0125",
        "--points",
        "4",
        "--integrators",
        "all",
        "--tolerance",
        "1e-4",
        "--no-timing",
        "--out",
        dir.to_str().unwrap(),
    ];
    let envs = |threads: &str| [("RAYON_NUM_THREADS", threads.to_string())];
    let run = |threads: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_volley"))
            .args(args)
            .envs(envs(threads))
            .output()
            .unwrap();
        ok(&out)
    };
    // Four threads even on a smaller machine, so the points of a dt do run interleaved.
    assert_eq!(run("1"), run("4"));
    std::fs::remove_dir_all(dir).unwrap();
}
