//! `volley headless`: step a scene through the same loop the window uses, print the table.

use std::path::PathBuf;

use clap::Args;

use volley::clock::VirtualClock;
use volley::hash::hex;
use volley::scene::{self, Scene};
use volley::table::{Format, Summary, TableWriter};
use volley::{Integrator, LoopError, SimLoop, World};

use super::{
    EXIT_DIVERGED, EXIT_ENVIRONMENT, EXIT_INPUT, EXIT_MISMATCH, Failure, fail, resolve_scene,
};

/// What `volley headless` and `volley record` both take: the scene, its overrides, how long to
/// run, threads and a command script.
#[derive(Args, Clone)]
pub struct RunArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    pub scene: String,
    /// Ticks to run (default: the scene's duration).
    #[arg(long, conflicts_with = "until")]
    pub ticks: Option<u64>,
    /// Run until this sim time (s).
    #[arg(long)]
    pub until: Option<f64>,
    /// Integrator: explicit-euler, semi-implicit-euler, verlet, midpoint, rk4, implicit-euler,
    /// exact.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Timestep (s), rounded to whole nanoseconds.
    #[arg(long)]
    pub dt: Option<f64>,
    /// Integrator steps per tick.
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Worker threads for stepping (results are identical for any count).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Command script (`TICK: COMMAND` lines) applied during the run.
    #[arg(long)]
    pub commands: Option<PathBuf>,
}

impl RunArgs {
    /// Defaults for `scene`, as if only the scene were given.
    pub fn for_scene(scene: &str) -> RunArgs {
        RunArgs {
            scene: scene.to_string(),
            ticks: None,
            until: None,
            integrator: None,
            dt: None,
            substeps: None,
            threads: 1,
            commands: None,
        }
    }
}

/// Arguments of `volley headless`.
#[derive(Args, Clone)]
pub struct HeadlessArgs {
    /// The scene and the run.
    #[command(flatten)]
    pub run: RunArgs,
    /// Print a row every K ticks.
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Output format.
    #[arg(long, value_parser = super::format_parser(), default_value_t = Format::Table)]
    pub format: Format,
    /// Decimals in the aligned table.
    #[arg(long, default_value_t = 4)]
    pub precision: usize,
    /// Print events and the summary only, no rows.
    #[arg(long)]
    pub no_table: bool,
    /// Write a PNG of the scene into this folder at tick 0 and every `--frame-every` ticks
    /// (rendered offscreen; needs a GPU adapter, a software one will do).
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// Frame size for `--frames`, WIDTHxHEIGHT in pixels (default 1280x720).
    #[arg(long, value_name = "WxH", requires = "frames")]
    pub size: Option<String>,
    /// Ticks between frames for `--frames`.
    #[arg(long, value_name = "K", default_value_t = 1, requires = "frames")]
    pub frame_every: u64,
    /// The final state hash this run must end with (as the summary prints it): a different one
    /// exits 1 after the summary, for CI that pins a scene's result.
    #[arg(long, value_name = "HASH", value_parser = volley::hash::parse_hex)]
    pub expect_hash: Option<u64>,
}

/// Parses an integrator name for a flag, listing the valid names on error.
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

/// Loads the scene and applies the run's overrides (dt, substeps, integrator).
pub fn load_scene(args: &RunArgs) -> Result<Scene, Failure> {
    let path = resolve_scene(&args.scene)?;
    let mut scene = scene::load(&path).map_err(|e| fail(EXIT_INPUT, e))?;
    if let Some(dt) = args.dt {
        scene
            .set_dt(dt)
            .map_err(|e| fail(EXIT_INPUT, format!("--dt: {e}")))?;
    }
    if let Some(n) = args.substeps {
        scene
            .set_substeps(n)
            .map_err(|e| fail(EXIT_INPUT, format!("--substeps: {e}")))?;
    }
    if let Some(name) = &args.integrator {
        let integrator = parse_integrator("--integrator", name)?;
        scene
            .set_integrator(integrator)
            .map_err(|e| fail(EXIT_INPUT, format!("--integrator: {e}")))?;
    }
    Ok(scene)
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
        (None, None) => Ok(scene.ticks_until(scene.start_time + scene.duration)),
    }
}

/// Reads a command script, if one was given.
pub fn load_commands(path: Option<&PathBuf>) -> Result<Vec<volley::Stamped>, Failure> {
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| fail(EXIT_INPUT, format!("{}: cannot read: {e}", path.display())))?;
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

/// Runs the scene and prints rows, events and the summary; a divergence keeps what was printed.
pub fn run(args: &HeadlessArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.run)?;
    let ticks = run_length(&args.run, &scene)?;
    let commands = load_commands(args.run.commands.as_ref())?;
    super::study::print_stability_warnings(&volley::stability::check(&scene));
    let mut world = World::new(&scene);
    world.set_threads(args.run.threads);
    let mut sim = SimLoop::new(world);
    sim.schedule(commands);
    let stdout = std::io::stdout().lock();
    let mut table = TableWriter::new(
        std::io::BufWriter::new(stdout),
        args.format,
        args.every,
        args.precision,
        !args.no_table,
    );
    let io = |e: volley::sim_loop::ObserverError| fail(EXIT_ENVIRONMENT, e);
    table.header().map_err(io)?;
    if !args.no_table {
        table.rows(&sim.world).map_err(io)?;
    }
    let outcome = match &args.frames {
        Some(dir) => {
            let mut source = VirtualClock::Steady(scene.timestep);
            let size = args.size.as_deref();
            let mut frames = super::frames::writer(&sim.world, dir, size, args.frame_every)?;
            let mut both = super::frames::WithFrames {
                inner: &mut table,
                frames: &mut frames,
            };
            sim.run_until(ticks, &mut source, &mut both)
        }
        None => {
            // Frames of many ticks: the ticks the table does not print may run as batches.
            let mut source = sim.unpaced_source(volley::sim_loop::UNPACED_FRAME_TICKS);
            sim.run_until(ticks, &mut source, &mut table)
        }
    };
    table.flush().map_err(io)?;
    outcome.map_err(loop_failure)?;
    let summary = Summary::of(&sim.world);
    table.summary(&summary).map_err(io)?;
    let hash = volley::hash::state_hash(&sim.world);
    match args.expect_hash {
        Some(expected) if expected != hash => Err(fail(
            EXIT_MISMATCH,
            format!(
                "final hash {} at tick {}, expected {}: the run differs from the pinned one (a \
                 recording made by the build that gave it, checked by this one with `volley \
                 replay --verify`, names the first divergent tick)",
                summary.hash,
                sim.world.tick(),
                hex(expected)
            ),
        )),
        _ => Ok(()),
    }
}
