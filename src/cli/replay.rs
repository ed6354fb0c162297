//! `volley replay`: play a recording back in the window, as a state table, or verify it bit for
//! bit.
//!
//! Which one: `--verify` prints the verdict; `--headless`, or any table option (`--format`,
//! `--every`, `--precision`, `--no-table`, `--threads`), prints the table; otherwise the
//! recording plays in the window, and where no window can open (no display, no adapter) the
//! table is printed instead, after a one-line warning. Every form checks every stored hash;
//! one that parts from the recording exits 1 with the report.

use std::path::PathBuf;

use clap::Args;

use volley::app::session::replaying::ReplayVerdict;
use volley::app::{self, AppError, Session};
use volley::hash::{hex, state_hash};
use volley::replay::{ErrorKind, Recording, Replay, ReplayError};
use volley::table::{Format, Summary, TableWriter};

use super::args::{TickCountParser, format_parser};
use super::display::{DisplayArgs, report, window_failure};
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
    /// Print the state table instead of opening the window.
    #[arg(long)]
    pub headless: bool,
    /// Print a row every K ticks (default 1, at least 1; implies the table).
    #[arg(long, value_name = "K", value_parser = TickCountParser)]
    pub every: Option<u64>,
    /// Output format of the table (default table; implies the table).
    #[arg(long, value_parser = format_parser())]
    pub format: Option<Format>,
    /// Decimals in the aligned table (default 4; implies the table).
    #[arg(long)]
    pub precision: Option<usize>,
    /// Print events and the summary only, no rows (implies the table).
    #[arg(long)]
    pub no_table: bool,
    /// Worker threads for stepping, headless (results are identical for any count; default 1;
    /// implies the table).
    #[arg(long)]
    pub threads: Option<usize>,
    /// List at most this many differing fields in a divergence report (default: all).
    #[arg(long)]
    pub diff_limit: Option<usize>,
    /// The window's options (when the recording plays in the window).
    #[command(flatten)]
    pub display: DisplayArgs,
}

impl ReplayArgs {
    /// Whether the table is asked for, by `--headless` or by one of its options.
    fn wants_table(&self) -> bool {
        self.headless
            || self.no_table
            || self.every.is_some()
            || self.format.is_some()
            || self.precision.is_some()
            || self.threads.is_some()
    }
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
    replay.set_threads(args.threads.unwrap_or(1));
    Ok(replay)
}

/// Plays back in the window (or as a table) or verifies; a replay that parts from its
/// recording exits 1 with the report.
pub fn run(args: &ReplayArgs) -> Result<(), Failure> {
    if args.verify || args.wants_table() {
        return headless(args);
    }
    let session = Session::for_replay(&args.file, args.seek).map_err(failure)?;
    let warnings = session
        .replay()
        .map_or(Vec::new(), |r| r.warnings().to_vec());
    let options = args.display.options()?;
    match app::run_session(session, options) {
        Ok(summary) => {
            // The panel showed them; the terminal gets them too, once the window is gone.
            for w in warnings {
                eprintln!("warning: {}: {w}", args.file.display());
            }
            report(&args.display, &summary);
            match summary.replay {
                Some(verdict) => verdict_of_window(args, &verdict),
                None => Ok(()),
            }
        }
        Err(e @ (AppError::NoDisplay(_) | AppError::Gpu(_))) => {
            eprintln!("warning: no window ({e}); printing the replay's table instead");
            headless(args)
        }
        Err(e) => Err(window_failure(e)),
    }
}

/// The window's replay on the command line: the verdict line, or the report and exit 1.
fn verdict_of_window(args: &ReplayArgs, verdict: &ReplayVerdict) -> Result<(), Failure> {
    if let Some(d) = &verdict.parted {
        print!("{}", d.report(args.diff_limit));
        return Err(fail(EXIT_MISMATCH, verdict.line()));
    }
    if let Some(e) = &verdict.error {
        return Err(fail(EXIT_INPUT, e));
    }
    println!("{}", verdict.line());
    Ok(())
}

/// The verdict (`--verify`) or the table, without a window.
fn headless(args: &ReplayArgs) -> Result<(), Failure> {
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
        args.format.unwrap_or(Format::Table),
        args.every.unwrap_or(1),
        args.precision.unwrap_or(4),
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
