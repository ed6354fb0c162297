//! What several subcommands take: the scene and its overrides, the length of a run, the
//! command script, the value parsers for names (`--integrator`, `--format`), and the mapping of
//! loop errors to exit codes. No subcommand imports another's helpers; they share these.
//!
//! One rule for counts of ticks (`--every`, `--frame-every`, `--hash-every`): 0 is refused at
//! parse time, with the flag's name, because "every 0 ticks" means nothing; use 1 for every
//! tick. (`--keyframe-every 0` is not a count of this kind: it means "start and end only".)

use std::ffi::OsStr;
use std::path::PathBuf;

use clap::Args;
use clap::builder::{PossibleValue, TypedValueParser};
use clap::error::ErrorKind;

use volley::scene::{self, Scene};
use volley::stability::StabilityReport;
use volley::table::Format;
use volley::{Integrator, LoopError, Stamped};

use super::{EXIT_DIVERGED, EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, resolve_scene};

/// The overrides of a scene's own settings that every subcommand loading a scene takes.
#[derive(Args, Clone, Debug, Default)]
pub struct Overrides {
    /// Integrator (replaces the scene's).
    #[arg(long, value_name = "NAME", value_parser = IntegratorParser)]
    pub integrator: Option<Integrator>,
    /// Timestep (s), rounded to whole nanoseconds.
    #[arg(long)]
    pub dt: Option<f64>,
    /// Integrator steps per tick.
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Error tolerance of the adaptive integrator, dopri5 (replaces the scene's `tolerance`;
    /// the fixed-step integrators ignore it).
    #[arg(long)]
    pub tolerance: Option<f64>,
}

/// What `volley headless` and `volley record` both take: the scene, its overrides, how long to
/// run, threads and a command script.
#[derive(Args, Clone)]
pub struct RunArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    pub scene: String,
    /// The scene's settings replaced for this run.
    #[command(flatten)]
    pub overrides: Overrides,
    /// Ticks to run (default: the scene's duration).
    #[arg(long, conflicts_with = "until")]
    pub ticks: Option<u64>,
    /// Run until this sim time (s).
    #[arg(long)]
    pub until: Option<f64>,
    /// Worker threads for stepping (results are identical for any count).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Command script (`TICK: COMMAND` lines) applied during the run.
    #[arg(long)]
    pub commands: Option<PathBuf>,
}

/// `--integrator NAME` (and the names in lists): any of [`Integrator::ALL`]'s names, which
/// `--help` lists; an unknown name is refused naming the flag and the alternatives.
#[derive(Clone, Copy, Debug)]
pub struct IntegratorParser;

impl TypedValueParser for IntegratorParser {
    type Value = Integrator;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<Integrator, clap::Error> {
        let flag = arg
            .and_then(clap::Arg::get_long)
            .map_or_else(|| "--integrator".to_string(), |l| format!("--{l}"));
        let name = value.to_string_lossy();
        parse_integrator(&flag, &name)
            .map_err(|f| clap::Error::raw(ErrorKind::InvalidValue, format!("{}\n", f.message)))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            Integrator::ALL.iter().map(|i| PossibleValue::new(i.name())),
        ))
    }
}

/// A count of ticks (`--every`, `--frame-every`, `--hash-every`): a whole number, at least 1;
/// anything else is refused naming the flag.
#[derive(Clone, Copy, Debug)]
pub struct TickCountParser;

impl TypedValueParser for TickCountParser {
    type Value = u64;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<u64, clap::Error> {
        let flag = arg
            .and_then(clap::Arg::get_long)
            .map_or_else(|| "--every".to_string(), |l| format!("--{l}"));
        let text = value.to_string_lossy();
        match text.parse::<u64>() {
            Ok(n) if n >= 1 => Ok(n),
            _ => Err(clap::Error::raw(
                ErrorKind::InvalidValue,
                format!("{flag}: expected a number of ticks, at least 1, got `{text}`\n"),
            )),
        }
    }
}

/// Parses an integrator name for `flag`, listing the valid names on error.
pub fn parse_integrator(flag: &str, name: &str) -> Result<Integrator, Failure> {
    Integrator::parse(name).ok_or_else(|| {
        let names: Vec<_> = Integrator::ALL.iter().map(|i| i.name()).collect();
        fail(
            EXIT_INPUT,
            format!(
                "{flag}: unknown `{name}`, expected one of {}",
                names.join(", ")
            ),
        )
    })
}

/// `--format`: the table formats by name, so `--help` lists them.
pub fn format_parser() -> impl TypedValueParser<Value = Format> {
    clap::builder::PossibleValuesParser::new(Format::ALL.map(|(_, name)| name))
        .map(|name| Format::from_name(&name).unwrap_or(Format::Table))
}

/// Loads the scene `arg` (a path or a bundled name) and applies the overrides; returns the
/// resolved path too.
pub fn load_scene(arg: &str, overrides: &Overrides) -> Result<(PathBuf, Scene), Failure> {
    let path = resolve_scene(arg)?;
    let mut scene = scene::load(&path).map_err(|e| fail(EXIT_INPUT, e))?;
    apply_overrides(&mut scene, overrides)?;
    Ok((path, scene))
}

/// Applies `--dt`, `--substeps`, `--integrator` and `--tolerance` to `scene`, each refusal
/// naming its flag.
pub fn apply_overrides(scene: &mut Scene, overrides: &Overrides) -> Result<(), Failure> {
    if let Some(dt) = overrides.dt {
        scene
            .set_dt(dt)
            .map_err(|e| fail(EXIT_INPUT, format!("--dt: {e}")))?;
    }
    if let Some(n) = overrides.substeps {
        scene
            .set_substeps(n)
            .map_err(|e| fail(EXIT_INPUT, format!("--substeps: {e}")))?;
    }
    if let Some(integrator) = overrides.integrator {
        scene
            .set_integrator(integrator)
            .map_err(|e| fail(EXIT_INPUT, format!("--integrator: {e}")))?;
    }
    if let Some(tolerance) = overrides.tolerance {
        scene
            .set_tolerance(tolerance)
            .map_err(|e| fail(EXIT_INPUT, format!("--tolerance: {e}")))?;
    }
    Ok(())
}

/// Ticks a run covers: `--ticks`, `--until`, or the scene's duration.
pub fn run_length(args: &RunArgs, scene: &Scene) -> Result<u64, Failure> {
    match (args.ticks, args.until) {
        (Some(n), _) => Ok(n),
        (None, Some(t)) if t.is_finite() => Ok(scene.ticks_until(t)),
        (None, Some(t)) => Err(fail(
            EXIT_INPUT,
            format!("--until: expected a finite time, got {t}"),
        )),
        (None, None) => Ok(scene.ticks_until(scene.start_time() + scene.duration())),
    }
}

/// Reads a command script, if one was given.
pub fn load_commands(path: Option<&PathBuf>) -> Result<Vec<Stamped>, Failure> {
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    let text = super::read_input(path)?;
    volley::command::parse_script(&text, &path.display().to_string())
        .map_err(|e| fail(EXIT_INPUT, e))
}

/// Maps a loop error to the CLI's exit codes.
pub fn loop_failure(e: LoopError) -> Failure {
    match e {
        LoopError::Diverged(d) => fail(EXIT_DIVERGED, d),
        LoopError::Command { .. } => fail(EXIT_INPUT, e),
        LoopError::Observer(e) => fail(EXIT_ENVIRONMENT, e),
    }
}

/// Prints the pre-check's warning lines to stderr (nothing when the chosen integrator is stable).
pub fn print_stability_warnings(report: &StabilityReport) {
    for line in report.warnings() {
        eprintln!("warning: {line}");
    }
}
