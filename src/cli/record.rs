//! `volley record`: run a scene headless through the loop and write a recording of it.

use std::path::PathBuf;

use clap::Args;

use volley::hash::hex;
use volley::replay::{RecordOptions, Recorder};
use volley::{LoopError, SimLoop, World};

use super::args::{RunArgs, TickCountParser, load_commands, load_scene, loop_failure, run_length};
use super::{EXIT_DIVERGED, EXIT_ENVIRONMENT, Failure, fail};

/// Arguments of `volley record`.
#[derive(Args, Clone)]
pub struct RecordArgs {
    /// The scene and the run, as for `volley headless` (commands are recorded).
    #[command(flatten)]
    pub run: RunArgs,
    /// The recording to write (overwritten if it exists); `.vrec` by convention.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Store the state hash every K ticks (1: every tick).
    #[arg(long, default_value_t = 1, value_parser = TickCountParser)]
    pub hash_every: u64,
    /// Store a keyframe every K ticks for seeking and field reports (0: start and end only).
    #[arg(long, default_value_t = 600)]
    pub keyframe_every: u64,
}

/// Records the run; a divergence is recorded too (the replay reproduces it) and exits 3.
pub fn run(args: &RecordArgs) -> Result<(), Failure> {
    let (_, scene) = load_scene(&args.run.scene, &args.run.overrides)?;
    let ticks = run_length(&args.run, &scene)?;
    let commands = load_commands(args.run.commands.as_ref())?;
    let mut world = World::new(&scene);
    world.set_threads(args.run.threads);
    let mut sim = SimLoop::new(world);
    sim.schedule(commands);
    let path = args.output.display().to_string();
    let io = |e: std::io::Error| fail(EXIT_ENVIRONMENT, format!("{path}: cannot write: {e}"));
    let file = std::fs::File::create(&args.output).map_err(io)?;
    let options = RecordOptions {
        hash_every: args.hash_every,
        keyframe_every: args.keyframe_every,
        scene_file: args.run.scene.clone(),
        ..RecordOptions::default()
    };
    let mut recorder = Recorder::start(file, &sim.world, options).map_err(io)?;
    let mut source = sim.unpaced_source(volley::sim_loop::UNPACED_FRAME_TICKS);
    let outcome = sim.run_until(ticks, &mut source, &mut recorder);
    if let Err(LoopError::Observer(e)) = outcome {
        return Err(fail(EXIT_ENVIRONMENT, format!("{path}: {e}")));
    }
    let (_, stats) = recorder.finish(&sim.world).map_err(io)?;
    println!(
        "recorded ticks {}..={} of `{}` to {path}: {} bytes, {} hashes, {} keyframes, {} \
         commands; final hash {}",
        stats.start_tick,
        stats.last_tick,
        scene.name(),
        stats.bytes,
        stats.hashes,
        stats.keyframes,
        stats.commands,
        hex(volley::hash::state_hash(&sim.world))
    );
    match outcome {
        Err(LoopError::Diverged(d)) => Err(fail(
            EXIT_DIVERGED,
            format!("{d} (recorded: the replay reproduces it)"),
        )),
        Err(e) => Err(loop_failure(e)),
        Ok(()) => Ok(()),
    }
}
