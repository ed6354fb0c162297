//! `volley pacing`: the loop lab's sweep, every loop policy x draw mode x display x tick rate,
//! against the exact motion at each frame's display time; writes the CSV of every run and the
//! generated page, and prints the default's ranking.

use std::path::{Path, PathBuf};

use clap::Args;

use volley::Integrator;
use volley::clock::LoopPolicy;
use volley::pacing::shard::{self, PacingShard};
use volley::pacing::sweep::{self, Row, Sweep, SweepDisplay};
use volley::pacing::{DisplayModel, Subject, read_capture, report};

use super::args::parse_integrator;
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail};

/// The capture the sweep reads unless told otherwise (PresentMon's own test capture, MIT).
const SHIPPED_CAPTURE: &str = "assets/captures/presentmon_test_case_4.csv";

/// Arguments of `volley pacing`.
#[derive(Args, Clone)]
pub struct PacingArgs {
    /// Display models, comma-separated: bundled names (60, 59.94, 120, 144, 165, 240,
    /// 60-misses, vrr-144, 60-hitch) or any rate in Hz (default: every bundled one).
    #[arg(long, value_delimiter = ',')]
    pub displays: Option<Vec<String>>,
    /// PresentMon, OCAT or CapFrameX capture files to run beside the models (default: the
    /// shipped PresentMon capture), comma-separated or the flag repeated.
    #[arg(long = "capture", value_name = "FILE.csv", value_delimiter = ',')]
    pub captures: Vec<PathBuf>,
    /// The application whose rows a capture keeps (default: the one with the most rows).
    #[arg(long)]
    pub application: Option<String>,
    /// Run no capture, not even the shipped one.
    #[arg(long, conflicts_with = "captures")]
    pub no_capture: bool,
    /// Tick rates (Hz), comma-separated (default: 30, 60, 64, 120).
    #[arg(long, value_delimiter = ',')]
    pub rates: Option<Vec<f64>>,
    /// Loop policies, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub policies: Option<Vec<String>>,
    /// Integrators, comma-separated (default: velocity-verlet,exact).
    #[arg(long, value_delimiter = ',')]
    pub integrators: Option<Vec<String>>,
    /// Subjects, comma-separated: orbit, shot (default: both).
    #[arg(long, value_delimiter = ',')]
    pub subjects: Option<Vec<String>>,
    /// Seconds of display timing per model (default 60).
    #[arg(long, default_value_t = sweep::SECONDS)]
    pub seconds: f64,
    /// The tick rate the ranking and the page summarise (default 60).
    #[arg(long, default_value_t = 60.0)]
    pub rate: f64,
    /// Output folder for pacing.csv, report.md and the plot (default: pacing).
    #[arg(long, default_value = "pacing")]
    pub out: PathBuf,
    /// Run only shard I of N (numbered from 0: jobs k with k mod N = I of the sweep's order)
    /// and write its rows, pacing.shard-I-of-N.json, to the output folder.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Merge the shard files of one sweep into its CSV, page and plot (space- or
    /// comma-separated).
    #[arg(long, value_name = "FILE", num_args = 1.., value_delimiter = ',', conflicts_with_all = [
        "displays", "captures", "application", "no_capture", "rates", "policies",
        "integrators", "subjects", "seconds", "shard",
    ])]
    pub merge: Option<Vec<PathBuf>>,
}

fn displays(args: &PacingArgs) -> Result<Vec<SweepDisplay>, Failure> {
    if !(args.seconds.is_finite() && (1.0..=3600.0).contains(&args.seconds)) {
        return Err(fail(
            EXIT_INPUT,
            format!(
                "--seconds: expected a number from 1 to 3600, got {}",
                args.seconds
            ),
        ));
    }
    let mut out = match &args.displays {
        None => Sweep::bundled_displays(args.seconds),
        Some(names) => names
            .iter()
            .map(|n| {
                DisplayModel::named(n.trim())
                    .map(|m| SweepDisplay::model(n.trim(), &m, args.seconds))
                    .ok_or_else(|| {
                        let known: Vec<_> = DisplayModel::bundled().iter().map(|d| d.0).collect();
                        fail(
                            EXIT_INPUT,
                            format!(
                                "--displays: unknown `{n}`, expected a rate in Hz or one of {}",
                                known.join(", ")
                            ),
                        )
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    let mut files = args.captures.clone();
    if files.is_empty() && !args.no_capture {
        let shipped = [
            PathBuf::from(SHIPPED_CAPTURE),
            Path::new(env!("CARGO_MANIFEST_DIR")).join(SHIPPED_CAPTURE),
        ];
        files.extend(shipped.into_iter().find(|p| p.is_file()));
    }
    for file in files {
        let text = super::read_input(&file)?;
        let timing = read_capture(
            &text,
            &file.display().to_string(),
            args.application.as_deref(),
        )
        .map_err(|e| fail(EXIT_INPUT, e))?;
        let name = timing.name.clone();
        out.push(SweepDisplay::capture(&name, timing));
    }
    Ok(out)
}

fn names<T>(
    flag: &str,
    given: &Option<Vec<String>>,
    default: Vec<T>,
    parse: impl Fn(&str) -> Result<T, Failure>,
) -> Result<Vec<T>, Failure> {
    let Some(given) = given else {
        return Ok(default);
    };
    let out: Vec<T> = given
        .iter()
        .map(|n| parse(n.trim()))
        .collect::<Result<_, _>>()?;
    if out.is_empty() {
        return Err(fail(EXIT_INPUT, format!("{flag}: expected at least one")));
    }
    Ok(out)
}

/// Runs `volley pacing`.
pub fn run(args: &PacingArgs) -> Result<(), Failure> {
    if let Some(files) = &args.merge {
        return write(args, &merge(files)?);
    }
    let sweep = sweep(args)?;
    if let Some(text) = &args.shard {
        let part = super::study::shard(text)?;
        let result = PacingShard::run(&sweep, part)
            .map_err(|e| fail(super::EXIT_DIVERGED, format!("pacing: {e}")))?;
        create(&args.out)?;
        let path = args.out.join(format!(
            "pacing.shard-{}-of-{}.json",
            part.index, part.count
        ));
        std::fs::write(&path, result.to_json())
            .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", path.display())))?;
        println!(
            "wrote {} ({} of {} runs)",
            path.display(),
            result.rows.len(),
            result.sweep.jobs()
        );
        return Ok(());
    }
    let rows = sweep
        .run()
        .map_err(|e| fail(super::EXIT_DIVERGED, format!("pacing: {e}")))?;
    write(args, &rows)
}

/// `--merge`: every shard file read, merged into the sweep's rows.
fn merge(files: &[PathBuf]) -> Result<Vec<Row>, Failure> {
    let mut parts = Vec::with_capacity(files.len());
    for path in files {
        let label = path.display().to_string();
        let text = super::read_input(path)?;
        let part = PacingShard::from_json(&text, &label).map_err(|e| fail(EXIT_INPUT, e))?;
        parts.push((label, part));
    }
    shard::merge(&parts).map_err(|e| fail(EXIT_INPUT, e))
}

fn create(dir: &Path) -> Result<(), Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", dir.display())))
}

/// The sweep the flags ask for.
fn sweep(args: &PacingArgs) -> Result<Sweep, Failure> {
    let mut sweep = Sweep::bundled(displays(args)?);
    if let Some(rates) = &args.rates {
        if rates.is_empty()
            || !rates
                .iter()
                .all(|r| r.is_finite() && (1.0..=1000.0).contains(r))
        {
            return Err(fail(
                EXIT_INPUT,
                "--rates: expected tick rates from 1 to 1000 Hz",
            ));
        }
        sweep.rates = rates.clone();
    }
    sweep.policies = names("--policies", &args.policies, sweep.policies, |n| {
        LoopPolicy::NAMES
            .into_iter()
            .find(|p| *p == n)
            .ok_or_else(|| {
                fail(
                    EXIT_INPUT,
                    format!(
                        "--policies: unknown `{n}`, expected one of {}",
                        LoopPolicy::NAMES.join(", ")
                    ),
                )
            })
    })?;
    sweep.integrators = names("--integrators", &args.integrators, sweep.integrators, |n| {
        parse_integrator("--integrators", n)
    })?;
    sweep.subjects = names("--subjects", &args.subjects, sweep.subjects, |n| {
        Subject::parse(n).ok_or_else(|| {
            fail(
                EXIT_INPUT,
                format!(
                    "--subjects: unknown `{n}`, expected one of {}",
                    Subject::ALL.map(Subject::name).join(", ")
                ),
            )
        })
    })?;
    Ok(sweep)
}

/// The CSV, the page and the plot of `rows`, and the ranking on stdout.
fn write(args: &PacingArgs, rows: &[Row]) -> Result<(), Failure> {
    let integrator = rows
        .iter()
        .map(|r| r.integrator)
        .find(|i| *i != Integrator::Exact)
        .unwrap_or(Integrator::Exact);
    let subject = rows.first().map_or(Subject::Orbit, |r| r.subject);
    let command = "volley pacing --out docs/pacing";
    let page = report::page(
        rows,
        args.rate,
        subject,
        integrator,
        command,
        Some("report.svg"),
    );
    create(&args.out)?;
    let write = |name: &str, text: &str| {
        let path = args.out.join(name);
        std::fs::write(&path, text)
            .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", path.display())))
    };
    write("pacing.csv", &report::csv(rows))?;
    write("report.md", &page)?;
    let plot = |e: volley::plot::PlotError| fail(EXIT_ENVIRONMENT, e);
    let svg = volley::plot::pacing::svg(rows, args.rate, subject, integrator).map_err(plot)?;
    write("report.svg", &svg)?;
    let png = volley::plot::pacing::png(rows, args.rate, subject, integrator).map_err(plot)?;
    let path = args.out.join("report.png");
    std::fs::write(&path, png)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", path.display())))?;
    // The ranking, the page's first section, on stdout.
    let ranking: String = page
        .split("\n## ")
        .nth(1)
        .map(|s| format!("## {s}"))
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with("!["))
        .map(|l| format!("{l}\n"))
        .collect();
    print!("{ranking}");
    println!(
        "wrote {}/{{pacing.csv,report.md,report.svg,report.png}} ({} runs)",
        args.out.display(),
        rows.len()
    );
    Ok(())
}
