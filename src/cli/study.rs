//! `volley study`: sweep integrators and timesteps over a scene; write the markdown report, the
//! CSV and the work-precision plot.

use std::path::PathBuf;

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use volley::Integrator;
use volley::scene;
use volley::study::{self, StudyConfig};

use super::args::parse_integrator;
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, resolve_scene};

/// Arguments of `volley study`.
#[derive(Args, Clone)]
pub struct StudyArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    pub scene: String,
    /// Integrators, comma-separated, or `all` (default: every one the scene allows but exact).
    #[arg(long, value_delimiter = ',')]
    pub integrators: Option<Vec<String>>,
    /// Timesteps (s), comma-separated (default: the scene's dt halved five times).
    #[arg(long, value_delimiter = ',', conflicts_with = "dt_range")]
    pub dt: Option<Vec<f64>>,
    /// Timesteps from A to B (s), log-spaced, with `--points N`.
    #[arg(long, value_name = "A..B", requires = "points")]
    pub dt_range: Option<String>,
    /// How many timesteps `--dt-range` spans (at least 2).
    #[arg(long, requires = "dt_range")]
    pub points: Option<u32>,
    /// Run until this sim time (s) (default: the end of the scene's duration).
    #[arg(long)]
    pub until: Option<f64>,
    /// Largest acceptable position error (m): name the cheapest setting that meets it.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Integrator steps per tick (default: the scene's).
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Output folder (default: study/SCENE-NAME).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Energy-drift windows per run.
    #[arg(long, default_value_t = 10)]
    pub windows: usize,
    /// Skip the wall-time measurement (errors and evaluation counts only).
    #[arg(long)]
    pub no_timing: bool,
}

/// Parses `A..B` with N points into log-spaced steps from A to B.
fn dt_range(text: &str, points: u32) -> Result<Vec<f64>, Failure> {
    let bad = || {
        fail(
            EXIT_INPUT,
            format!("--dt-range: expected A..B with positive numbers, got `{text}`"),
        )
    };
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (f64, f64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0) {
        return Err(bad());
    }
    if points < 2 {
        return Err(fail(
            EXIT_INPUT,
            format!("--points: expected at least 2, got {points}"),
        ));
    }
    let ratio = (b / a).ln() / f64::from(points - 1);
    Ok((0..points)
        .map(|k| a * (ratio * f64::from(k)).exp())
        .collect())
}

fn config(args: &StudyArgs, scene: &scene::Scene) -> Result<StudyConfig, Failure> {
    let mut config = StudyConfig::for_scene(scene);
    if let Some(names) = &args.integrators {
        config.integrators = if names.len() == 1 && names[0].eq_ignore_ascii_case("all") {
            Integrator::ALL
                .into_iter()
                .filter(|i| scene::check_integrator(*i, &scene.forces).is_ok())
                .collect()
        } else {
            names
                .iter()
                .map(|n| parse_integrator("--integrators", n.trim()))
                .collect::<Result<_, _>>()?
        };
    } else {
        config
            .integrators
            .retain(|i| scene::check_integrator(*i, &scene.forces).is_ok());
    }
    if let Some(dts) = &args.dt {
        config.dts = dts.clone();
    }
    if let (Some(range), Some(points)) = (&args.dt_range, args.points) {
        config.dts = dt_range(range, points)?;
    }
    if let Some(t) = args.until {
        config.until = t;
    }
    config.tolerance = args.tolerance;
    config.energy_windows = args.windows;
    config.timing = !args.no_timing;
    study::validate(scene, &config).map_err(|e| fail(EXIT_INPUT, e))?;
    Ok(config)
}

/// Runs the study: pre-check warnings to stderr, a progress bar on stderr (hidden when stderr
/// is not a terminal), the markdown report to stdout, the files to the output folder.
pub fn run(args: &StudyArgs) -> Result<(), Failure> {
    let path = resolve_scene(&args.scene)?;
    let mut scene = scene::load(&path).map_err(|e| fail(EXIT_INPUT, e))?;
    if let Some(n) = args.substeps {
        scene
            .set_substeps(n)
            .map_err(|e| fail(EXIT_INPUT, format!("--substeps: {e}")))?;
    }
    let config = config(args, &scene)?;
    for line in study::precheck_lines(&scene, &config) {
        eprintln!("warning: {line}");
    }
    if cfg!(debug_assertions) && config.timing {
        eprintln!("warning: debug build: wall times are not representative (use --release)");
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} runs  {msg}  [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let report = study::run(&scene, &config, &mut |p| {
        bar.set_length(p.total);
        bar.set_position(p.done);
        bar.set_message(p.message);
    });
    bar.finish_and_clear();
    let report = report.map_err(|e| fail(EXIT_INPUT, e))?;
    let markdown = study::output::markdown(&report);
    print!("{markdown}");
    // The report goes out before the stderr line naming the files.
    let _ = std::io::Write::flush(&mut std::io::stdout());
    let stem = scene.name.replace(['/', '\\'], "_");
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("study").join(&stem));
    let io = |what: &PathBuf, e: std::io::Error| {
        fail(
            EXIT_ENVIRONMENT,
            format!("{}: cannot write: {e}", what.display()),
        )
    };
    std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
    let svg = volley::plot::svg(&report).map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    let png = volley::plot::png(&report).map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    let files: [(&str, Vec<u8>); 4] = [
        ("md", markdown.into_bytes()),
        ("csv", study::output::csv(&report).into_bytes()),
        ("svg", svg.into_bytes()),
        ("png", png),
    ];
    for (ext, bytes) in files {
        let file = dir.join(format!("{stem}.{ext}"));
        std::fs::write(&file, bytes).map_err(|e| io(&file, e))?;
    }
    eprintln!("wrote {}/{stem}.{{md,csv,svg,png}}", dir.display());
    Ok(())
}
