//! `volley headless`: step a scene through the same loop the window uses, print the table.

use std::path::PathBuf;

use clap::Args;

use volley::clock::VirtualClock;
use volley::hash::hex;
use volley::table::{Format, Summary, TableWriter};
use volley::{SimLoop, World};

use super::args::{
    RunArgs, TickCountParser, format_parser, load_commands, load_scene, loop_failure,
    print_stability_warnings, run_length,
};
use super::{EXIT_ENVIRONMENT, EXIT_MISMATCH, Failure, fail};

/// Arguments of `volley headless`.
#[derive(Args, Clone)]
pub struct HeadlessArgs {
    /// The scene and the run.
    #[command(flatten)]
    pub run: RunArgs,
    /// Print a row every K ticks (at least 1).
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = TickCountParser)]
    pub every: u64,
    /// Output format.
    #[arg(long, value_parser = format_parser(), default_value_t = Format::Table)]
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
    /// Ticks between frames for `--frames` (at least 1).
    #[arg(long, value_name = "K", default_value_t = 1, requires = "frames", value_parser = TickCountParser)]
    pub frame_every: u64,
    /// The final state hash this run must end with (as the summary prints it): a different one
    /// exits 1 after the summary, for CI that pins a scene's result.
    #[arg(long, value_name = "HASH", value_parser = volley::hash::parse_hex)]
    pub expect_hash: Option<u64>,
}

/// Runs the scene and prints rows, events and the summary; a divergence keeps what was printed.
pub fn run(args: &HeadlessArgs) -> Result<(), Failure> {
    let (_, scene) = load_scene(&args.run.scene, &args.run.overrides)?;
    let ticks = run_length(&args.run, &scene)?;
    let commands = load_commands(args.run.commands.as_ref())?;
    print_stability_warnings(&volley::stability::check(&scene));
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
            let mut source = VirtualClock::Steady(scene.timestep());
            let size = args.size.as_deref();
            let mut frames = super::frames::writer(&sim.world, dir, size, args.frame_every)?;
            sim.run_until(ticks, &mut source, &mut (&mut table, &mut frames))
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
