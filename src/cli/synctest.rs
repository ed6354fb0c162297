//! `volley synctest`: run a scene (with a command script) or a recording under the sync test:
//! every tick re-run from K ticks back and compared; a mismatch prints where and exits 1.

use std::io::Read;
use std::path::{Path, PathBuf};

use clap::Args;

use volley::body::COLUMNS;
use volley::hash::{hex, state_hash};
use volley::replay::format::MAGIC;
use volley::replay::{ErrorKind, Recording, ReplayError};
use volley::world::{RestoreError, State};
use volley::{Stamped, SyncError, SyncTest, World};

use super::args::{Overrides, load_commands, load_scene};
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, EXIT_MISMATCH, Failure, fail};

/// Arguments of `volley synctest`.
#[derive(Args, Clone)]
pub struct SyncTestArgs {
    /// Scene file, the name of a bundled scene (see `volley scenes`), or a recording (`volley
    /// record -o FILE`): its scene, its first keyframe and its commands.
    pub input: String,
    /// Ticks each check restores back and re-runs (1 to 256).
    #[arg(long, value_name = "K", default_value_t = 7,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(volley::MAX_CHECK_DISTANCE)))]
    pub check_distance: u32,
    /// The scene's settings replaced for this run (not with a recording, which fixes them).
    #[command(flatten)]
    pub overrides: Overrides,
    /// Ticks to run (default: the scene's duration, or a recording's length).
    #[arg(long, conflicts_with = "until")]
    pub ticks: Option<u64>,
    /// Run until this sim time (s).
    #[arg(long)]
    pub until: Option<f64>,
    /// Command script (`TICK: COMMAND` lines) applied during the run (a recording brings its
    /// own).
    #[arg(long)]
    pub commands: Option<PathBuf>,
    /// Worker threads of the first run (results are identical for any count).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Run the re-runs on N threads in a pool of their own, so a result that depends on the
    /// thread count differs between the runs and is caught.
    #[arg(long, value_name = "N")]
    pub rerun_threads: Option<usize>,
    /// Hash every stage of every run (first run and re-runs) as it runs: slower, and names the
    /// stage of a fault that running the tick again does not reproduce.
    #[arg(long)]
    pub stage_hashes: bool,
    /// List at most this many differing fields in a mismatch report (default: all).
    #[arg(long, value_name = "N")]
    pub diff_limit: Option<usize>,
    /// A test seam, not in `--help`: restore through a faulty restore that keeps the world's
    /// COLUMN (`p.x` to `mV.z`) instead of the saved one, so the mismatch path (the report, the
    /// exit code) can be run end to end; the scenes alone have no fault to find.
    #[arg(long, value_name = "COLUMN", hide = true)]
    pub inject_restore_fault: Option<String>,
}

/// What a run starts from: a label, the world, the commands and the tick to stop at.
struct Start {
    label: String,
    world: World,
    commands: Vec<Stamped>,
    until: u64,
}

/// Whether `path` is a file that starts with a recording's magic bytes.
fn is_recording(path: &Path) -> bool {
    let mut head = [0u8; 8];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|()| head == MAGIC)
}

fn replay_failure(e: ReplayError) -> Failure {
    match e.kind {
        ErrorKind::Input => fail(EXIT_INPUT, e),
        ErrorKind::Output => fail(EXIT_ENVIRONMENT, e),
    }
}

/// A recording's scene, first keyframe and commands; its settings cannot be overridden.
fn from_recording(args: &SyncTestArgs, path: &Path) -> Result<Start, Failure> {
    let o = &args.overrides;
    let given = [
        (o.integrator.is_some(), "--integrator"),
        (o.dt.is_some(), "--dt"),
        (o.substeps.is_some(), "--substeps"),
        (o.tolerance.is_some(), "--tolerance"),
        (args.commands.is_some(), "--commands"),
    ];
    if let Some((_, flag)) = given.iter().find(|(g, _)| *g) {
        return Err(fail(
            EXIT_INPUT,
            format!(
                "{flag}: {} is a recording, which fixes its scene's settings and commands",
                path.display()
            ),
        ));
    }
    let mut recording = Recording::open(path).map_err(replay_failure)?;
    let label = recording.label().to_string();
    for w in recording.build_warnings() {
        eprintln!("warning: {label}: {w}");
    }
    let scene = recording.scene().map_err(replay_failure)?;
    let world = recording.world_at(0, &scene).map_err(replay_failure)?;
    let start = world.tick();
    let until = match (args.ticks, args.until) {
        (Some(n), _) => start.saturating_add(n),
        (None, Some(t)) if t.is_finite() => scene.ticks_until(t),
        (None, Some(t)) => {
            return Err(fail(
                EXIT_INPUT,
                format!("--until: expected a finite time, got {t}"),
            ));
        }
        (None, None) => recording.end_tick(),
    };
    Ok(Start {
        label,
        world,
        commands: recording.commands().to_vec(),
        until,
    })
}

/// A scene with its overrides and command script.
fn from_scene(args: &SyncTestArgs) -> Result<Start, Failure> {
    let (_, scene) = load_scene(&args.input, &args.overrides)?;
    let until = match (args.ticks, args.until) {
        (Some(n), _) => n,
        (None, Some(t)) if t.is_finite() => scene.ticks_until(t),
        (None, Some(t)) => {
            return Err(fail(
                EXIT_INPUT,
                format!("--until: expected a finite time, got {t}"),
            ));
        }
        (None, None) => scene.ticks_until(scene.start_time() + scene.duration()),
    };
    Ok(Start {
        label: format!("`{}`", scene.name()),
        world: World::new(&scene),
        commands: load_commands(args.commands.as_ref())?,
        until,
    })
}

/// The injected fault of `--inject-restore-fault`: a restore that keeps the world's column
/// `name` (one of the first six, positions and momenta) instead of the saved one.
fn dropping(
    name: &str,
) -> Result<impl FnMut(&mut World, &State) -> Result<(), RestoreError> + Send + 'static, Failure> {
    let column = COLUMNS[..6]
        .iter()
        .find(|c| c.name == name)
        .copied()
        .ok_or_else(|| {
            let names: Vec<_> = COLUMNS[..6].iter().map(|c| c.name).collect();
            fail(
                EXIT_INPUT,
                format!(
                    "--inject-restore-fault: unknown column `{name}`, expected one of {}",
                    names.join(", ")
                ),
            )
        })?;
    Ok(move |world: &mut World, saved: &State| {
        let mut kept = saved.clone();
        let now = column.get(&world.state().bodies);
        if now.len() == kept.bodies.len() {
            column.get_mut(&mut kept.bodies).clone_from(now);
        }
        world.restore(&kept)
    })
}

/// Runs the sync test; a mismatch prints its report and exits 1. A divergence the re-run
/// reproduced passes, as `volley replay --verify` passes a reproduced one: what is tested is
/// that the runs agree.
pub fn run(args: &SyncTestArgs) -> Result<(), Failure> {
    let path = Path::new(&args.input);
    let Start {
        label,
        mut world,
        commands,
        until,
    } = if is_recording(path) {
        from_recording(args, path)?
    } else {
        from_scene(args)?
    };
    world.set_threads(args.threads);
    let start = world.tick();
    let k = args.check_distance;
    let mut sync = SyncTest::new(world, k)
        .map_err(|e| fail(EXIT_INPUT, format!("--check-distance: {e}")))?
        .with_stage_hashes(args.stage_hashes);
    if let Some(name) = &args.inject_restore_fault {
        sync = sync.with_restore(dropping(name)?);
    }
    if let Some(n) = args.rerun_threads {
        sync = sync
            .with_rerun_threads(n)
            .map_err(|e| fail(EXIT_ENVIRONMENT, format!("--rerun-threads: {e}")))?;
    }
    let outcome = sync.run_script(&commands, until);
    let end = sync.world().tick();
    let summary = format!(
        "{label}: ticks {start}..={end}, each re-run from up to {k} ticks back ({} checks, {} \
         ticks re-run), frames of {} bytes a body; final hash {}",
        sync.checks(),
        sync.resimulated_ticks(),
        sync.frame_bytes_per_body(),
        hex(state_hash(sync.world()))
    );
    match outcome {
        Ok(()) => {
            println!("sync test passed: {summary}");
            Ok(())
        }
        Err(SyncError::Diverged(d)) => {
            println!("sync test passed: {summary}; the run {d}, and the re-run reproduced it");
            Ok(())
        }
        Err(SyncError::Mismatch(m)) => {
            print!("{}", m.report(args.diff_limit));
            Err(fail(EXIT_MISMATCH, format!("{label}: {}", m.headline())))
        }
        Err(e @ SyncError::Command { .. }) => Err(fail(EXIT_INPUT, e)),
        Err(e @ SyncError::Restore { .. }) => Err(fail(EXIT_MISMATCH, e)),
    }
}
