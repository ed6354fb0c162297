//! `volley study`: sweep integrators and timesteps over a scene; write the markdown report, the
//! CSV and the work-precision plot. `--shard I/N` measures one share of the points and writes a
//! partial result instead; `--merge FILES...` turns the shards' files into the report.

use std::path::PathBuf;

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use volley::Integrator;
use volley::scene;
use volley::study::{self, Shard, ShardResult, StudyConfig, StudyReport};

use super::args::parse_integrator;
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, resolve_scene};

/// Arguments of `volley study`.
#[derive(Args, Clone)]
pub struct StudyArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    #[arg(required_unless_present = "merge")]
    pub scene: Option<String>,
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
    /// Measure only shard I of N (numbered from 0: points k with k mod N = I of the dt-major
    /// list) and write its partial result, NAME.shard-I-of-N.json, to the output folder.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Merge the partial results of every shard of one study into its report and files
    /// (space- or comma-separated).
    #[arg(long, value_name = "FILE", num_args = 1.., value_delimiter = ',', conflicts_with_all = [
        "scene", "integrators", "dt", "dt_range", "points", "until", "tolerance", "substeps",
        "windows", "no_timing", "shard",
    ])]
    pub merge: Option<Vec<PathBuf>>,
}

/// Parses `I/N` with `0 <= I < N` (`--shard` of `volley study` and `volley pacing`).
pub fn shard(text: &str) -> Result<Shard, Failure> {
    let bad = || {
        fail(
            EXIT_INPUT,
            format!("--shard: expected I/N with 0 <= I < N (shards numbered from 0), got `{text}`"),
        )
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let shard = Shard {
        index: i.trim().parse().map_err(|_| bad())?,
        count: n.trim().parse().map_err(|_| bad())?,
    };
    if !shard.is_valid() {
        return Err(bad());
    }
    Ok(shard)
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
                .filter(|i| scene::check_integrator(*i, scene.forces()).is_ok())
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
            .retain(|i| scene::check_integrator(*i, scene.forces()).is_ok());
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
/// is not a terminal), the markdown report to stdout, the files to the output folder. With
/// `--shard`, the partial result file instead; with `--merge`, the report of the shards' files.
pub fn run(args: &StudyArgs) -> Result<(), Failure> {
    if let Some(files) = &args.merge {
        return merge(files, args.out.as_ref());
    }
    let name = args
        .scene
        .as_deref()
        .ok_or_else(|| fail(EXIT_INPUT, "study: expected a scene or --merge FILES"))?;
    let path = resolve_scene(name)?;
    let mut scene = scene::load(&path).map_err(|e| fail(EXIT_INPUT, e))?;
    if let Some(n) = args.substeps {
        scene
            .set_substeps(n)
            .map_err(|e| fail(EXIT_INPUT, format!("--substeps: {e}")))?;
    }
    let config = config(args, &scene)?;
    let part = args.shard.as_deref().map(shard).transpose()?;
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
    let mut progress = |p: study::Progress| {
        bar.set_length(p.total);
        bar.set_position(p.done);
        bar.set_message(p.message);
    };
    let stem = stem_of(scene.name());
    let dir = out_dir(args.out.as_ref(), &stem);
    if let Some(part) = part {
        let result = study::run_shard(&scene, &config, part, &mut progress);
        bar.finish_and_clear();
        let result = result.map_err(|e| fail(EXIT_INPUT, e))?;
        std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
        let file = dir.join(format!(
            "{stem}.shard-{}-of-{}.json",
            part.index, part.count
        ));
        std::fs::write(&file, result.to_json()).map_err(|e| io(&file, e))?;
        eprintln!(
            "wrote {} ({} of the study's points)",
            file.display(),
            result.points.len()
        );
        return Ok(());
    }
    let report = study::run(&scene, &config, &mut progress);
    bar.finish_and_clear();
    let report = report.map_err(|e| fail(EXIT_INPUT, e))?;
    write_report(&report, &dir, &stem)
}

/// `--merge`: reads every shard file, merges them into the report, writes it as a study does.
fn merge(files: &[PathBuf], out: Option<&PathBuf>) -> Result<(), Failure> {
    let mut parts = Vec::with_capacity(files.len());
    for path in files {
        let label = path.display().to_string();
        let text = super::read_input(path)?;
        let part = ShardResult::from_json(&text, &label).map_err(|e| fail(EXIT_INPUT, e))?;
        parts.push((label, part));
    }
    let report = study::shard::merge(&parts).map_err(|e| fail(EXIT_INPUT, e))?;
    let stem = stem_of(&report.scene);
    write_report(&report, &out_dir(out, &stem), &stem)
}

fn stem_of(scene: &str) -> String {
    scene.replace(['/', '\\'], "_")
}

fn out_dir(out: Option<&PathBuf>, stem: &str) -> PathBuf {
    out.cloned()
        .unwrap_or_else(|| PathBuf::from("study").join(stem))
}

fn io(what: &std::path::Path, e: std::io::Error) -> Failure {
    fail(
        EXIT_ENVIRONMENT,
        format!("{}: cannot write: {e}", what.display()),
    )
}

/// The markdown report to stdout, then `STEM.{md,csv,svg,png}` in `dir`.
fn write_report(report: &StudyReport, dir: &std::path::Path, stem: &str) -> Result<(), Failure> {
    let markdown = study::output::markdown(report);
    print!("{markdown}");
    // The report goes out before the stderr line naming the files.
    let _ = std::io::Write::flush(&mut std::io::stdout());
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let svg = volley::plot::svg(report).map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    let png = volley::plot::png(report).map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    let files: [(&str, Vec<u8>); 4] = [
        ("md", markdown.into_bytes()),
        ("csv", study::output::csv(report).into_bytes()),
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
