//! The `volley` command line: parses arguments, calls the library, prints, picks the exit code.
//!
//! Exit codes: 0 success; 1 a replay failed verification or a sync test found a mismatch; 2 bad input (arguments, scene, command
//! script, recording); 3 the simulation diverged; 4 an environment failure (no GPU adapter, no
//! display, an I/O error).
//!
//! Each subcommand lives in its own file under `src/cli/`.

mod cli;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "volley",
    version,
    about = "A game-loop sandbox for the numerics of game physics"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Cmd>,
}

#[derive(Subcommand)]
enum Cmd {
    /// Step a scene without a window and print its state table and summary.
    Headless(cli::headless::HeadlessArgs),
    /// Solve both launch angles that hit a target at a given speed.
    Aim(cli::aim::AimArgs),
    /// A scene's range table: drop, windage, speed, Mach, energy and time at chosen ranges.
    Range(cli::range::RangeArgs),
    /// List the bundled scenes.
    Scenes,
    /// Sweep integrators and timesteps: error against cost, as a table, CSV and plot.
    Study(cli::study::StudyArgs),
    /// The loop lab: every loop policy and draw mode under every display, against the exact motion.
    Pacing(cli::pacing::PacingArgs),
    /// Run a scene headless and write a recording (commands, hashes, keyframes).
    Record(cli::record::RecordArgs),
    /// Play a recording back in the window (a table with --headless), or verify it (--verify).
    Replay(cli::replay::ReplayArgs),
    /// Run a scene or recording re-running every tick from K ticks back; name where runs part.
    Synctest(cli::synctest::SyncTestArgs),
    /// Open the sandbox window (what `volley` alone does, on the seed scene).
    Window(cli::window::WindowArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return cli::usage_error(e),
    };
    let result = match cli.command {
        Some(Cmd::Headless(args)) => cli::headless::run(&args),
        Some(Cmd::Aim(args)) => cli::aim::run(&args),
        Some(Cmd::Range(args)) => cli::range::run(&args),
        Some(Cmd::Scenes) => cli::scenes::run(),
        Some(Cmd::Study(args)) => cli::study::run(&args),
        Some(Cmd::Pacing(args)) => cli::pacing::run(&args),
        Some(Cmd::Record(args)) => cli::record::run(&args),
        Some(Cmd::Replay(args)) => cli::replay::run(&args),
        Some(Cmd::Synctest(args)) => cli::synctest::run(&args),
        Some(Cmd::Window(args)) => cli::window::run(&args),
        None => cli::window::default_run(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
