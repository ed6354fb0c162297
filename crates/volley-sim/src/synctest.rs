//! The sync test: every tick, restore the state of K ticks back, re-run those ticks with the
//! commands the first run applied, and compare; on a mismatch, say where the runs part.
//!
//! GGRS's `SyncTestSession` (gschup/ggrs, `src/sessions/sync_test_session.rs`) does the same
//! rollback every frame and reports the frame numbers whose checksums differ; GGPO's synctest
//! writes two state dumps to compare by hand. [`SyncTest`] goes on to the field: the tick, the
//! body, the field, both values with their bit patterns (the replay's keyframe diff,
//! [`crate::FieldDiff`]), and the stage of the tick where the runs first part (Photon Quantum's
//! per-system partial checksums, here a hash after each stage of the step, [`TickStage`]).
//!
//! Cost: the first run steps once and each check re-runs K ticks, so a tick costs K + 1 steps
//! and one compare of what a step changes. Saving the new state and restoring the oldest is one
//! exchange of buffers, with no copy and no allocation (`synctest/ring.rs`); a frame keeps 48
//! bytes a body (positions and momenta), 8 more while a motor burns, 24 more for velocity
//! Verlet's carried force. Stage hashes cost a hash per stage, so they are computed only when
//! a check fails (by running the failing tick again, stage by stage) or when asked for every
//! run ([`SyncTest::with_stage_hashes`]).

mod locate;
mod report;
mod ring;

use std::collections::VecDeque;

use crate::command::{Command, CommandError, Stamped};
use crate::step::{Stage, StageBuffers};
use crate::world::{Divergence, RestoreError, State, World};

pub use crate::step::Stage as TickStage;
pub use report::{FoundBy, StageHashes, SyncMismatch};
use ring::{Epochs, Frame};

/// The most ticks a check may reach back ([`SyncTest::new`]).
pub const MAX_CHECK_DISTANCE: u32 = 256;

/// A game's own restore, when it puts a state back through code of its own (a network
/// snapshot's decoder, a rollback library's cell): the sync test restores through it.
type RestoreFn = Box<dyn FnMut(&mut World, &State) -> Result<(), RestoreError> + Send>;
/// A look at (and a change of) the world after each stage of every run, for tests.
type StageHook = Box<dyn FnMut(Stage, &mut World) + Send>;

/// Where the re-runs run: their own rayon pool and thread count.
struct RerunThreads {
    pool: rayon::ThreadPool,
    threads: usize,
}

/// A world run under a sync test: each [`SyncTest::advance`] runs one tick (the first run),
/// then restores the state of `check_distance` ticks back, re-runs those ticks with the
/// commands the first run applied, and compares the result with the first run's, field by
/// field. The world goes on from the re-run's state, which is the first run's bit for bit.
///
/// ```
/// use volley_sim::{Command, SyncTest, World, bundled_scene};
///
/// let scene = bundled_scene("seed")?;
/// let mut sync = SyncTest::new(World::new(&scene), 7)?;
/// for tick in 0..27 {
///     let commands: &[Command] = if tick == 10 { &[Command::Fire] } else { &[] };
///     sync.advance(commands)?; // Err(SyncError::Mismatch(..)) names the tick, body, field and stage
/// }
/// assert_eq!((sync.world().tick(), sync.checks()), (27, 27));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct SyncTest {
    world: World,
    distance: usize,
    /// The first run's states, oldest first, one per tick (at most `distance`). Boxed, so the
    /// ring moves a pointer where a frame changes place, not the frame (a few hundred bytes:
    /// two copies a tick were a fifth of the one-body seed's overhead under callgrind).
    frames: VecDeque<Box<Frame>>,
    /// A frame's buffers kept for reuse.
    spare: Option<Box<Frame>>,
    epochs: Epochs,
    /// The epoch of the first run's fixed part now, and the next epoch's id.
    epoch: u64,
    next_epoch: u64,
    /// The window's first tick: its commands, stage hashes and state hash, moved or copied out
    /// of its frame (a full ring hands that frame over to the newest state).
    first_commands: Vec<Command>,
    first_stages: Vec<(Stage, u64)>,
    first_hash: u64,
    restore: Option<RestoreFn>,
    /// A full state, for a game's own restore.
    scratch: State,
    rerun: Option<RerunThreads>,
    stage_hashes: bool,
    hook: Option<StageHook>,
    buffers: StageBuffers,
    /// The stage hashes of the run in progress.
    log: Vec<(Stage, u64)>,
    /// Commands of the tick being run by [`SyncTest::run_script`].
    pending: Vec<Command>,
    checks: u64,
    resimulated: u64,
    stopped: Option<SyncError>,
    /// The last tick at which the first run applied commands: a window from a later tick
    /// re-runs steps only.
    last_commands: Option<u64>,
}

/// Why a [`SyncTest`] could not be set up.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SyncTestError {
    /// The check distance is 0 or above [`MAX_CHECK_DISTANCE`].
    CheckDistance(u32),
    /// The re-runs' thread pool could not be started.
    Threads(String),
    /// The scene declares an event that stops a body or the run ([`crate::EventStop`]). Its
    /// tallies, the bodies it removes inside a step and the run's stop are not yet part of
    /// what the sync test saves and compares, so it refuses the world rather than report a
    /// false mismatch or miss a true one. Events that stop nothing change no state, and are
    /// taken.
    DeclaredEvents,
}

impl std::fmt::Display for SyncTestError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SyncTestError::CheckDistance(k) => write!(
                f,
                "check distance must be 1 to {MAX_CHECK_DISTANCE} ticks, got {k}"
            ),
            SyncTestError::Threads(e) => write!(f, "cannot start the re-runs' threads: {e}"),
            SyncTestError::DeclaredEvents => f.write_str(
                "the scene declares an event that stops a body or the run, which the sync \
                     test does not roll back yet (events that stop nothing are taken)",
            ),
        }
    }
}

impl std::error::Error for SyncTestError {}

/// Why [`SyncTest::advance`] stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum SyncError {
    /// A re-run parted from the first run: where, and how it was found. The sync test stops.
    Mismatch(Box<SyncMismatch>),
    /// The run diverged (the guard stopped it) and the re-run reproduced the divergence at the
    /// same tick, body and cause: the world is stopped, deterministically.
    Diverged(Divergence),
    /// A command could not be applied in the first run (it changed nothing; the tick did not
    /// step, and the commands before it in the call stay applied).
    Command {
        /// The tick it was for.
        tick: u64,
        /// The command.
        command: Command,
        /// Why it failed (boxed: rare, and it keeps every `Result` of the sync test small).
        error: Box<CommandError>,
    },
    /// The game's restore ([`SyncTest::with_restore`]) refused a state the sync test saved.
    Restore {
        /// The saved state's tick.
        tick: u64,
        /// What the restore said.
        error: RestoreError,
    },
}

impl std::fmt::Display for SyncError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SyncError::Mismatch(m) => write!(f, "{}", m.headline()),
            SyncError::Diverged(d) => write!(f, "{d} (the re-run reproduced it)"),
            SyncError::Command {
                tick,
                command,
                error,
            } => write!(f, "command `{tick}: {command}` failed: {error}"),
            SyncError::Restore { tick, error } => {
                write!(f, "the restore refused the state of tick {tick}: {error}")
            }
        }
    }
}

impl std::error::Error for SyncError {}

impl SyncTest {
    /// A sync test of `world` from its current tick, re-running `check_distance` ticks (1 to
    /// [`MAX_CHECK_DISTANCE`]) after each tick. Until that many ticks have run, each check
    /// re-runs every tick since the start.
    pub fn new(world: World, check_distance: u32) -> Result<SyncTest, SyncTestError> {
        if !(1..=MAX_CHECK_DISTANCE).contains(&check_distance) {
            return Err(SyncTestError::CheckDistance(check_distance));
        }
        if world.params.contacts.events.stops() {
            return Err(SyncTestError::DeclaredEvents);
        }
        let distance = check_distance as usize;
        // A frame's epoch is at most `distance + 1` ticks that applied commands old.
        let epochs = Epochs::new(distance + 3, &world);
        let scratch = world.snapshot();
        Ok(SyncTest {
            world,
            distance,
            frames: VecDeque::with_capacity(distance + 1),
            spare: None,
            epochs,
            epoch: 0,
            next_epoch: 1,
            first_commands: Vec::new(),
            first_stages: Vec::new(),
            first_hash: 0,
            restore: None,
            scratch,
            rerun: None,
            stage_hashes: false,
            hook: None,
            buffers: StageBuffers::default(),
            log: Vec::new(),
            pending: Vec::new(),
            checks: 0,
            resimulated: 0,
            stopped: None,
            last_commands: None,
        })
    }

    /// Restores through the game's own `restore` instead of the sync test's frames: each
    /// check hands it the full [`State`] of the window's first tick. For a game whose rollback
    /// puts state back through code of its own; slower (a full state is built and copied per
    /// check), and everything a state holds is compared, not only what a step changes.
    pub fn with_restore(
        mut self,
        restore: impl FnMut(&mut World, &State) -> Result<(), RestoreError> + Send + 'static,
    ) -> SyncTest {
        self.restore = Some(Box::new(restore));
        self
    }

    /// Runs the re-runs on `threads` threads (`World::set_threads`) in a rayon pool of that
    /// size, while the first run keeps the world's and the caller's: a result that depends on
    /// the thread count (a parallel sum split by `rayon::current_num_threads`) then differs.
    pub fn with_rerun_threads(mut self, threads: usize) -> Result<SyncTest, SyncTestError> {
        let threads = threads.max(1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| SyncTestError::Threads(e.to_string()))?;
        self.rerun = Some(RerunThreads { pool, threads });
        Ok(self)
    }

    /// Hashes the world after every stage of every run (the first run's and each re-run's),
    /// so a mismatch names the stage where the two runs that disagree first parted, even when
    /// running the tick again does not reproduce it (a one-off input, state outside the world
    /// that changed since). Off by default: a hash per stage costs more than a cheap step.
    pub fn with_stage_hashes(mut self, on: bool) -> SyncTest {
        self.stage_hashes = on;
        self
    }

    /// Calls `hook` after every stage of every run, before the stage is hashed (and turns
    /// stage hashes on): a seam for tests that inject faults between stages.
    #[doc(hidden)]
    pub fn with_stage_hook(
        mut self,
        hook: impl FnMut(TickStage, &mut World) + Send + 'static,
    ) -> SyncTest {
        self.hook = Some(Box::new(hook));
        self.stage_hashes = true;
        self
    }

    /// The world (the first run's state, which every check found the re-run to reproduce).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world, giving the sync test up.
    pub fn into_world(self) -> World {
        self.world
    }

    /// Ticks each check re-runs once enough ticks have run.
    pub fn check_distance(&self) -> u32 {
        self.distance as u32
    }

    /// Checks passed so far (one per tick run).
    pub fn checks(&self) -> u64 {
        self.checks
    }

    /// Ticks re-run so far by the checks.
    pub fn resimulated_ticks(&self) -> u64 {
        self.resimulated
    }

    /// Bytes a tick's saved state holds per body now (8 per value kept): 48 for positions and
    /// momenta, 8 more while a motor burns, 24 more for a valid carried force. What only
    /// commands change is kept once per tick that applied commands, not per tick.
    pub fn frame_bytes_per_body(&self) -> usize {
        self.frames.back().map_or(0, |f| f.bytes_per_body())
    }

    /// Runs one tick: applies `commands` at the world's tick boundary, steps, then checks the
    /// tick by re-running the last `check_distance` ticks from the state saved then.
    ///
    /// `Err(SyncError::Diverged)` when the run diverged and the re-run reproduced it;
    /// `Err(SyncError::Mismatch)` names where a re-run parted from the first run, after which
    /// the sync test stops (every later call returns the same error).
    pub fn advance(&mut self, commands: &[Command]) -> Result<(), SyncError> {
        if let Some(e) = &self.stopped {
            return Err(e.clone());
        }
        if let Some(d) = self.world.divergence() {
            return Err(SyncError::Diverged(d));
        }
        self.first_run(commands)?;
        self.check()
    }

    /// Runs ticks until the world's tick is `until`, applying each command of `script` (in
    /// tick order, as [`crate::parse_script`] returns them) at its tick; commands stamped
    /// before the world's tick apply at once, as [`crate::SimLoop`] applies them.
    pub fn run_script(&mut self, script: &[Stamped], until: u64) -> Result<(), SyncError> {
        let mut next = 0;
        let mut pending = std::mem::take(&mut self.pending);
        let mut outcome = Ok(());
        while self.world.tick() < until {
            pending.clear();
            while let Some(s) = script.get(next).filter(|s| s.tick <= self.world.tick()) {
                pending.push(s.command);
                next += 1;
            }
            outcome = self.advance(&pending);
            if outcome.is_err() {
                break;
            }
        }
        self.pending = pending;
        outcome
    }

    /// Whether runs are stepped stage by stage and hashed.
    fn staged(&self) -> bool {
        self.stage_hashes || self.hook.is_some()
    }

    /// The first run's tick: the commands (kept in the newest frame, with a new epoch when any
    /// applied), then the step. Its divergence, if any, is kept by the world for the check.
    fn first_run(&mut self, commands: &[Command]) -> Result<(), SyncError> {
        if self.frames.is_empty() {
            let mut f = Box::<Frame>::default();
            ring::save_copy(&self.world, &mut f, self.epoch);
            f.hash = if self.staged() {
                locate::stage_hash(&self.world)
            } else {
                0
            };
            self.frames.push_back(f);
        }
        let tick = self.world.tick();
        let mut applied = false;
        let mut failed = None;
        for &command in commands {
            if let Err(error) = self.world.apply(&command) {
                failed = Some(SyncError::Command {
                    tick,
                    command,
                    error: Box::new(error),
                });
                break;
            }
            self.newest().commands.push(command);
            self.last_commands = Some(tick);
            applied = true;
        }
        if applied {
            self.epochs.store(self.next_epoch, &self.world);
            self.epoch = self.next_epoch;
            self.next_epoch += 1;
        }
        if let Some(e) = failed {
            return Err(e);
        }
        if self.staged() {
            let mut log = std::mem::take(&mut self.log);
            log.clear();
            let _ = locate::run_staged(
                &mut self.world,
                &[],
                &mut self.buffers,
                self.hook.as_mut(),
                &mut log,
            );
            let newest = self.newest();
            newest.stages.clear();
            newest.stages.extend_from_slice(&log);
            self.log = log;
            // A stage hook may change what only commands change: keep the first run's own
            // fixed part, so a report compares against what the first run really had.
            if !ring::same_static(&self.world, self.epochs.get(self.epoch)) {
                self.epochs.store(self.next_epoch, &self.world);
                self.epoch = self.next_epoch;
                self.next_epoch += 1;
            }
        } else {
            // A divergence stays in the world (`World::divergence`); the check compares it.
            let _ = self.world.step();
        }
        Ok(())
    }

    fn newest(&mut self) -> &mut Frame {
        self.frames
            .back_mut()
            .expect("the first run keeps the start state before its first tick")
    }

    /// Saves the world's new state as the newest frame, puts the window's first state back,
    /// re-runs the window and compares.
    fn check(&mut self) -> Result<(), SyncError> {
        let end = self.world.tick();
        let new_hash = if self.staged() {
            locate::stage_hash(&self.world)
        } else {
            0
        };
        let consume = self.restore.is_none() && self.frames.len() == self.distance;
        let world_epoch = if consume {
            // The oldest frame becomes the newest: one exchange of buffers saves and restores.
            let mut f = self.frames.pop_front().expect("a full ring");
            std::mem::swap(&mut self.first_commands, &mut f.commands);
            std::mem::swap(&mut self.first_stages, &mut f.stages);
            self.first_hash = f.hash;
            let e = ring::swap(&mut self.world, &mut f, &self.epochs, self.epoch);
            f.hash = new_hash;
            self.frames.push_back(f);
            e
        } else {
            let mut f = self.spare.take().unwrap_or_default();
            ring::save_copy(&self.world, &mut f, self.epoch);
            f.hash = new_hash;
            self.frames.push_back(f);
            let first = &self.frames[0];
            self.first_commands.clone_from(&first.commands);
            self.first_stages.clone_from(&first.stages);
            self.first_hash = first.hash;
            match self.restore.as_mut() {
                Some(restore) => {
                    ring::full_state(first, &self.epochs, &mut self.scratch);
                    restore(&mut self.world, &self.scratch).map_err(|error| {
                        SyncError::Restore {
                            tick: self.scratch.tick,
                            error,
                        }
                    })?;
                }
                None => ring::load_copy(&mut self.world, first, &self.epochs, self.epoch),
            }
            first.epoch
        };
        let from = self.world.tick();
        // Commands at a tick of the window `from..end` (each frame's, and the first's moved
        // out of its frame).
        let commands = self.last_commands.is_some_and(|t| t >= from);
        let outcome = self.rerun(from, end, commands);
        let newest = self.frames.back().expect("the newest frame was just saved");
        let cross_command = world_epoch != self.epoch || commands;
        let same = outcome.is_none()
            && ring::same_dynamic(&self.world, newest)
            && (!(cross_command || self.restore.is_some())
                || ring::same_static(&self.world, self.epochs.get(self.epoch)));
        if !same {
            let m = locate::locate(self, from, end, outcome);
            let e = SyncError::Mismatch(Box::new(m));
            self.stopped = Some(e.clone());
            return Err(e);
        }
        if self.frames.len() > self.distance {
            self.spare = self.frames.pop_front();
        }
        self.checks += 1;
        self.resimulated += end - from;
        match self.world.divergence() {
            Some(d) => Err(SyncError::Diverged(d)),
            None => Ok(()),
        }
    }

    /// Re-runs ticks `from..end` from the restored world with the first run's commands, in the
    /// re-runs' threads. `None` when it ran through; otherwise what stopped it early.
    fn rerun(&mut self, from: u64, end: u64, commands: bool) -> Option<locate::Early> {
        let first_threads = self.world.threads();
        let staged = self.staged();
        let mut run = locate::Rerun {
            world: &mut self.world,
            frames: &self.frames,
            first_commands: &self.first_commands,
            first_stages: &self.first_stages,
            first_hash: self.first_hash,
            staged,
            commands,
            hook: self.hook.as_mut(),
            buffers: &mut self.buffers,
            log: &mut self.log,
        };
        let outcome = match &self.rerun {
            Some(r) => {
                run.world.set_threads(r.threads);
                r.pool.install(|| run.run(from, end))
            }
            None => run.run(from, end),
        };
        self.world.set_threads(first_threads);
        outcome
    }
}
