//! `volley replay`: play a recording back as a state table, or verify it bit for bit.

use std::path::PathBuf;

use clap::Args;

use volley::hash::{hex, state_hash};
use volley::replay::{ErrorKind, Recording, Replay, ReplayError};
use volley::table::{Format, Summary, TableWriter};

use super::{EXIT_ENVIRONMENT, EXIT_INPUT, EXIT_MISMATCH, Failure, fail};

/// Arguments of `volley replay`.
#[derive(Args, Clone)]
pub struct ReplayArgs {
    /// The recording (`volley record -o FILE`).
    pub file: PathBuf,
    /// Re-simulate and compare every stored hash and keyframe; print the verdict, not a table.
    #[arg(long)]
    pub verify: bool,
    /// Start at this tick, from the nearest keyframe at or before it.
    #[arg(long)]
    pub seek: Option<u64>,
    /// Print a row every K ticks.
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Output format of the table.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Decimals in the aligned table.
    #[arg(long, default_value_t = 4)]
    pub precision: usize,
    /// Print events and the summary only, no rows.
    #[arg(long)]
    pub no_table: bool,
    /// Worker threads for stepping (results are identical for any count).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// List at most this many differing fields in a divergence report (default: all).
    #[arg(long)]
    pub diff_limit: Option<usize>,
}

/// Maps a replay error to the CLI's exit codes: the file's fault 2, the output's 4.
fn failure(e: ReplayError) -> Failure {
    match e.kind {
        ErrorKind::Input => fail(EXIT_INPUT, e),
        ErrorKind::Output => fail(EXIT_ENVIRONMENT, e),
    }
}

/// Opens the recording and prints its warnings: another Volley version or target, truncation.
fn open(args: &ReplayArgs) -> Result<Replay<std::io::BufReader<std::fs::File>>, Failure> {
    let recording = Recording::open(&args.file).map_err(failure)?;
    let file = recording.label().to_string();
    for w in recording.build_warnings() {
        eprintln!("warning: {file}: {w}; replaying anyway and verifying honestly");
    }
    let end = recording.end_tick();
    if let Some(at) = recording.truncated_at() {
        eprintln!(
            "warning: {file}: truncated after tick {end} (no footer; the complete records end at \
             byte {at}): replaying the ticks it holds"
        );
    }
    if let Some(seek) = args.seek.filter(|&s| s > end) {
        return Err(fail(
            EXIT_INPUT,
            format!("--seek {seek}: {file} ends at tick {end}"),
        ));
    }
    let mut replay = Replay::start(recording, args.seek).map_err(failure)?;
    replay.set_threads(args.threads);
    Ok(replay)
}

/// Plays back or verifies; a replay that parts from its recording exits 1 with the report.
pub fn run(args: &ReplayArgs) -> Result<(), Failure> {
    let mut replay = open(args)?;
    let file = replay.recording().label().to_string();
    if args.verify {
        replay.run_to(u64::MAX, &mut ()).map_err(failure)?;
    } else {
        play(args, &mut replay)?;
    }
    if let Some((tick, f)) = replay.force_evals_differ() {
        eprintln!(
            "warning: {file}: {f} at the keyframe of tick {tick} (a cost counter, not state: \
             the evaluation bookkeeping changed)"
        );
    }
    if let Some(d) = replay.first_divergence() {
        let report = d.report(args.diff_limit);
        if args.verify {
            print!("{report}");
        } else {
            eprint!("{report}");
        }
        return Err(fail(
            EXIT_MISMATCH,
            format!(
                "{file}: the replay parts from the recording at tick {}",
                d.tick
            ),
        ));
    }
    if args.verify {
        let (from, to) = (replay.started_at(), replay.world().tick());
        let mut line = format!(
            "verified {} ticks, final hash {} (ticks {from}..={to}: {} hashes and {} keyframes \
             compared",
            to - from,
            hex(state_hash(replay.world())),
            replay.hashes_checked(),
            replay.keyframes_checked(),
        );
        if let Some(d) = replay.world().divergence() {
            line += &format!("; the recorded divergence reproduced: {d}");
        }
        println!("{line})");
    }
    Ok(())
}

/// The table: silent from the keyframe to the seek tick, then rows to the end.
fn play<R: std::io::Read + std::io::Seek>(
    args: &ReplayArgs,
    replay: &mut Replay<R>,
) -> Result<(), Failure> {
    let from = args.seek.unwrap_or(0).max(replay.started_at());
    if args.seek.is_some() {
        eprintln!(
            "seeking to tick {from} from the keyframe at tick {} ({} ticks re-simulated)",
            replay.started_at(),
            from - replay.started_at()
        );
    }
    replay.run_to(from, &mut ()).map_err(failure)?;
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
    if !args.no_table && replay.first_divergence().is_none() {
        table.rows(replay.world()).map_err(io)?;
    }
    let outcome = replay.run_to(u64::MAX, &mut table);
    table.flush().map_err(io)?;
    outcome.map_err(failure)?;
    table.summary(&Summary::of(replay.world())).map_err(io)?;
    if let (Some(d), None) = (replay.world().divergence(), replay.first_divergence()) {
        eprintln!("the recorded run {d}; the replay reproduced it");
    }
    Ok(())
}
