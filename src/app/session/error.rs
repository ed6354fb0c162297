//! Why the session refused a call, one variant per kind of refusal. Its `Display` is the line
//! the panel shows; the variants keep the simulation's own typed errors (a scene's, a value's,
//! the clock's, the loop's, a seek's, the firing solver's) where one is the reason.

use std::path::PathBuf;
use std::sync::Arc;

use crate::clock::ClockError;
use crate::command::Command;
use crate::firing::{Blocked, FiringError, ShotKind, blocked_text};
use crate::integrate::Integrator;
use crate::replay::ReplayError;
use crate::scene::{IntegratorError, InvalidValue, SceneError};
use crate::sim_loop::LoopError;
use crate::timeline::SeekError;
use crate::world::Divergence;

/// Why the session refused a call, or why a lane's aim fired nothing.
#[derive(Clone, Debug, PartialEq)]
pub enum SessionError {
    /// A replay is playing: the change would part the run from its recording.
    Replaying(Change),
    /// An integrator switch in compare mode, where each lane is its integrator.
    IntegratorPerLane,
    /// The lanes' forces refuse the integrator asked for.
    Integrator(IntegratorError),
    /// The scene refuses every compared integrator: one lane of its own runs instead.
    NoComparedLane {
        /// The integrator the lane runs.
        showing: Integrator,
    },
    /// The scene refuses some compared integrators; the others run. The reasons, as
    /// [`crate::app::session::compare_refusals`] words them.
    LanesLeftOut(String),
    /// A scene (a compare lane's, an edited setup's) that fails its checks.
    Scene(SceneError),
    /// A value (dt, substeps) that fails its check.
    Value(InvalidValue),
    /// A time scale out of range.
    Clock(ClockError),
    /// A loop policy name that is not one ([`crate::clock::LoopPolicy::NAMES`]).
    UnknownPolicy(String),
    /// The loop stopped a lane's run: a command refused as it was applied, an observer failed.
    Loop(LoopError),
    /// An aim at a target the scene does not have.
    NoTargetToAim(usize),
    /// A move of a target the scene does not have.
    NoTarget(usize),
    /// The firing solver found no shot.
    Firing(FiringError),
    /// The solver's shots have none of this kind at the launcher's speed.
    NoShot(ShotKind),
    /// The shot of this kind hits something before the target.
    Blocked(ShotKind, Blocked),
    /// No lane keeps a timeline: a keyframe of its world is over an eighth of the budget.
    NoHistory {
        /// Each lane's timeline budget (bytes).
        budget: usize,
    },
    /// A seek in a lane's timeline failed.
    Seek(SeekError),
    /// A seek in the replay failed: the recording did not open again at the tick.
    ReplaySeek(ReplayError),
    /// A recording is running already, to this file.
    AlreadyRecording(PathBuf),
    /// The first lane is stopped by this divergence: there is nothing to record from.
    Diverged(Divergence),
    /// A file or folder could not be made or written.
    Io {
        /// The file (or the folder, when making it failed while saving).
        path: PathBuf,
        /// What the session was doing with it.
        doing: FileStep,
        /// The system's reason.
        error: IoError,
    },
    /// Every default recording name of this second is taken, from the first to the last tried.
    NamesTaken {
        /// The first name tried.
        first: PathBuf,
        /// The last name tried.
        last: PathBuf,
    },
}

/// A change refused while replaying.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// A command.
    Command(Command),
    /// Reset.
    Reset,
    /// Aiming and firing.
    Aim,
    /// Switching compare mode or its lanes.
    CompareMode,
    /// Switching equal cost.
    EqualCost,
    /// Running ahead (`--warm-up-ticks`).
    WarmUp,
    /// Moving a target.
    MoveTarget,
    /// A new step: the recording's is the one it replays with.
    Step,
    /// Recording: the replay is a recording already.
    Record,
    /// A restart for this reason.
    Restart(String),
}

/// What the session was doing with a file when the system refused.
#[derive(Clone, Debug, PartialEq)]
pub enum FileStep {
    /// Making the folder (this one) a recording goes in.
    MakeFolder(PathBuf),
    /// Creating or writing a recording.
    Record,
    /// Saving a setup (making its folder, or writing the file).
    Save,
}

/// An I/O error, shared so a [`SessionError`] can be cloned, and equal to another of the same
/// kind and text.
#[derive(Clone, Debug)]
pub struct IoError(pub Arc<std::io::Error>);

impl From<std::io::Error> for IoError {
    fn from(e: std::io::Error) -> IoError {
        IoError(Arc::new(e))
    }
}

impl PartialEq for IoError {
    fn eq(&self, other: &IoError) -> bool {
        self.0.kind() == other.0.kind() && self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for IoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl SessionError {
    /// `error` while `doing` something with `path`.
    pub fn io(path: impl Into<PathBuf>, doing: FileStep, error: std::io::Error) -> SessionError {
        SessionError::Io {
            path: path.into(),
            doing,
            error: error.into(),
        }
    }
}

impl std::fmt::Display for Change {
    /// The change as the refusal names it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Change::Command(c) => write!(f, "`{c}`"),
            Change::Reset => f.write_str("reset"),
            Change::Aim => f.write_str("aim"),
            Change::CompareMode => f.write_str("compare mode"),
            Change::EqualCost => f.write_str("equal cost"),
            Change::WarmUp => f.write_str("warming up"),
            Change::MoveTarget => f.write_str("moving a target"),
            Change::Step => f.write_str("the step"),
            Change::Record => f.write_str("recording"),
            Change::Restart(why) => f.write_str(why),
        }
    }
}

impl std::fmt::Display for SessionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use SessionError as E;
        match self {
            E::Replaying(Change::Step) => f.write_str("replaying: the step is the recording's"),
            E::Replaying(Change::Record) => f.write_str(
                "replaying: the replay is a recording already (Go live first to record from here)",
            ),
            E::Replaying(what) => write!(
                f,
                "replaying: {what} is off (Go live, or L, takes over from this tick)"
            ),
            E::IntegratorPerLane => f.write_str("compare mode runs every integrator at once"),
            E::Integrator(e) => write!(f, "{e}"),
            E::NoComparedLane { showing } => write!(
                f,
                "none of the compared integrators can run this scene; showing {showing}"
            ),
            E::LanesLeftOut(reasons) => write!(f, "compare mode leaves out {reasons}"),
            E::Scene(e) => write!(f, "{e}"),
            E::Value(e) => write!(f, "{e}"),
            E::Clock(e) => write!(f, "{e}"),
            E::UnknownPolicy(name) => write!(
                f,
                "loop policy: unknown `{name}`, expected one of {}",
                crate::clock::LoopPolicy::NAMES.join(", ")
            ),
            E::Loop(e) => write!(f, "{e}"),
            E::NoTargetToAim(i) => write!(f, "aim: the scene has no target {i}"),
            E::NoTarget(i) => write!(f, "no target {i}"),
            E::Firing(e) => write!(f, "{e}"),
            E::NoShot(kind) => write!(f, "no {} at this speed", kind.label()),
            E::Blocked(kind, b) => write!(f, "the {} {}", kind.label(), blocked_text(b)),
            E::NoHistory { budget } => write!(
                f,
                "no history to seek in: a keyframe of this world is over an eighth of the {} MiB \
                 budget (--history-budget)",
                budget >> 20
            ),
            E::Seek(e) => write!(f, "seek: {e}"),
            E::ReplaySeek(e) => write!(f, "seek: {e}"),
            E::AlreadyRecording(path) => write!(f, "already recording to {}", path.display()),
            E::Diverged(d) => write!(f, "the lane {d}: reset before recording"),
            E::Io { path, doing, error } => {
                let path = path.display();
                match doing {
                    FileStep::MakeFolder(dir) => write!(
                        f,
                        "{path}: cannot create its folder {}: {error}",
                        dir.display()
                    ),
                    FileStep::Record => write!(f, "{path}: cannot write: {error}"),
                    FileStep::Save => write!(f, "{path}: {error}"),
                }
            }
            E::NamesTaken { first, last } => write!(
                f,
                "{} to {}: every name is taken; name a file to record to",
                first.display(),
                last.display()
            ),
        }
    }
}

impl std::error::Error for SessionError {}
