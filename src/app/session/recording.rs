//! The window's record toggle: a [`Recorder`] on the session's first lane, composed with the
//! lane's [`TickHistory`], started and ended between frames.
//!
//! A recording made in the window is the same file `volley record` writes: it starts at the tick
//! the toggle was pressed (its first keyframe is that state), holds every command the window
//! pushed from then on (they reach the recorder through [`SimLoop::push`](crate::SimLoop::push)
//! and [`TickObserver::on_command`]), a hash every tick and a keyframe every
//! [`RecordOptions::default`] interval, and is flushed at least every 50 ms, so a crash leaves
//! a readable file truncated after its last flushed tick. Ending it (the toggle, a restart that
//! rebuilds the world, a divergence of the lane, closing the window) writes the final keyframe
//! and the footer.

use std::fs::File;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

use super::{Change, FileStep, Session, SessionError};

use crate::command::Stamped;
use crate::platform::{self, SystemTime, UNIX_EPOCH};
use crate::render::TickHistory;
use crate::replay::{RecordOptions, RecordStats, Recorder};
use crate::sim_loop::{ObserverError, TickObserver};
use crate::world::{Divergence, World};

/// Folder (relative to the working directory) that recordings go to when no file is named.
pub const DEFAULT_DIR: &str = "recordings";

/// Most numbered names [`create_default`] tries in one second's name (`-2` up to this) before
/// it gives up: enough for any person pressing a key, and a bound on the file-system calls the
/// UI thread makes when something else is wrong.
pub const DEFAULT_NAME_TRIES: u32 = 100;

/// A recording in progress.
pub struct LiveRecording {
    recorder: Recorder<Sink>,
    path: PathBuf,
    /// The first write error; the recording stops taking ticks after it.
    error: Option<String>,
}

impl std::fmt::Debug for LiveRecording {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveRecording")
            .field("path", &self.path)
            .field("stats", &self.recorder.stats())
            .field("error", &self.error)
            .finish()
    }
}

/// Where a recording's bytes go: its file, or (in a browser, which writes no files) memory,
/// offered as a download when the recording ends.
#[derive(Debug)]
pub enum Sink {
    /// A file.
    File(File),
    /// Bytes kept for a download.
    Download(Vec<u8>),
}

impl std::io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::File(f) => f.write(buf),
            Sink::Download(v) => v.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::File(f) => f.flush(),
            Sink::Download(_) => Ok(()),
        }
    }
}

impl Sink {
    /// Hands the finished recording over: a file is complete already; bytes are offered as a
    /// download named as the file would be.
    fn deliver(self, path: &Path) {
        match self {
            Sink::File(_) => {}
            Sink::Download(bytes) => {
                let name = path.to_string_lossy();
                let name = name.strip_suffix(" (a download)").unwrap_or(&name);
                platform::offer_download(name, &bytes, "application/octet-stream");
            }
        }
    }
}

impl LiveRecording {
    /// Creates `path` (and its folder) and starts recording `world` as it is now; `scene_file`
    /// names the scene in the header.
    pub fn start(
        path: &Path,
        world: &World,
        scene_file: &str,
    ) -> Result<LiveRecording, SessionError> {
        let fail = |e| SessionError::io(path, FileStep::Record, e);
        create_folder_of(path)?;
        let file = File::create(path).map_err(fail)?;
        LiveRecording::start_in(Sink::File(file), path, world, scene_file)
    }

    /// Starts recording `world` into `file`, already created at `path`.
    fn start_in(
        sink: Sink,
        path: &Path,
        world: &World,
        scene_file: &str,
    ) -> Result<LiveRecording, SessionError> {
        let fail = |e| SessionError::io(path, FileStep::Record, e);
        let options = RecordOptions {
            scene_file: scene_file.to_string(),
            ..RecordOptions::default()
        };
        let recorder = Recorder::start(sink, world, options).map_err(fail)?;
        Ok(LiveRecording {
            recorder,
            path: path.to_path_buf(),
            error: None,
        })
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What was written so far.
    pub fn stats(&self) -> RecordStats {
        self.recorder.stats()
    }

    /// The write error that stopped the recording, if one did.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Ends the recording at `world`'s tick (final keyframe, footer), noting why it ended.
    pub fn finish(self, world: &World, ended: &str) -> FinishedRecording {
        let (stats, error) = match (self.error, self.recorder.finish(world)) {
            (Some(e), _) => (None, Some(e)),
            (None, Ok((sink, stats))) => {
                sink.deliver(&self.path);
                (Some(stats), None)
            }
            (None, Err(e)) => (None, Some(format!("cannot write: {e}"))),
        };
        FinishedRecording {
            path: self.path,
            scene: world.scene().name().to_string(),
            stats,
            ended: ended.to_string(),
            error,
        }
    }

    /// Forwards one observer call unless an earlier one failed; a failure is kept, not
    /// returned, so the simulation goes on without the recording.
    fn forward(&mut self, call: impl FnOnce(&mut Recorder<Sink>) -> Result<(), ObserverError>) {
        if self.error.is_none()
            && let Err(e) = call(&mut self.recorder)
        {
            self.error = Some(e.0);
        }
    }
}

/// A recording that ended.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishedRecording {
    /// The file.
    pub path: PathBuf,
    /// The scene's name.
    pub scene: String,
    /// The final counts, when the footer was written.
    pub stats: Option<RecordStats>,
    /// Why it ended: stopped, a restart, a divergence, the window closing.
    pub ended: String,
    /// The write error that cut it short, if any (the file then holds what was flushed, and
    /// opens as truncated).
    pub error: Option<String>,
}

impl std::fmt::Display for FinishedRecording {
    /// One line, as `volley record` prints it, with why the recording ended.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let path = self.path.display();
        match (&self.stats, &self.error) {
            (Some(s), None) => write!(
                f,
                "recorded ticks {}..={} of `{}` to {path}: {} bytes, {} hashes, {} keyframes, \
                 {} commands ({})",
                s.start_tick,
                s.last_tick,
                self.scene,
                s.bytes,
                s.hashes,
                s.keyframes,
                s.commands,
                self.ended
            ),
            (_, Some(e)) => write!(
                f,
                "recording to {path} failed ({e}); what was flushed opens as truncated"
            ),
            (None, None) => write!(f, "recording to {path} ended ({})", self.ended),
        }
    }
}

/// The session's recordings of its first lane.
#[derive(Debug, Default)]
pub(super) struct Recordings {
    /// The recording in progress.
    pub(super) current: Option<LiveRecording>,
    /// The recordings finished, oldest first.
    pub(super) finished: Vec<FinishedRecording>,
    /// Where recordings without a named file go ([`DEFAULT_DIR`] under it); empty, the
    /// default, is the working directory.
    pub(super) dir: PathBuf,
}

impl Session {
    /// Starts recording the first lane (in compare mode: the first integrator's world) from its
    /// current tick, to `path` or to a new file named by [`default_path`] under the session's
    /// recordings folder (the working directory unless set), made by [`create_default`]. Refused while
    /// replaying, while recording, and while the lane is stopped by a divergence.
    pub fn start_recording(&mut self, path: Option<PathBuf>) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::Record)?;
        if let Some(r) = &self.recording.current {
            return Err(SessionError::AlreadyRecording(r.path().to_path_buf()));
        }
        let lane = &self.lanes[0];
        if let Some(d) = lane.stopped {
            return Err(SessionError::Diverged(d));
        }
        let world = &lane.sim.world;
        let (scene, scene_file) = (self.setup.scene.name(), &self.setup.scene_file);
        let recording = match path {
            Some(path) => LiveRecording::start(&path, world, scene_file)?,
            None => {
                let now = SystemTime::now().duration_since(UNIX_EPOCH);
                let seconds = now.map_or(0, |d| d.as_secs());
                if !platform::WRITES_FILES {
                    // A page writes no files: the recording is kept and downloaded at its end.
                    let path = default_path(Path::new(""), scene, seconds, 1);
                    let path = PathBuf::from(format!(
                        "{} (a download)",
                        path.file_name().unwrap_or_default().to_string_lossy()
                    ));
                    LiveRecording::start_in(Sink::Download(Vec::new()), &path, world, scene_file)?
                } else {
                    let (path, file) = create_default(&self.recording.dir, scene, seconds)?;
                    LiveRecording::start_in(Sink::File(file), &path, world, scene_file)?
                }
            }
        };
        self.recording.current = Some(recording);
        Ok(())
    }

    /// Ends the recording, if one is running, at the first lane's tick (final keyframe and
    /// footer), noting why; returns it.
    pub fn stop_recording(&mut self, ended: &str) -> Option<&FinishedRecording> {
        let recording = self.recording.current.take()?;
        let finished = recording.finish(&self.lanes[0].sim.world, ended);
        self.recording.finished.push(finished);
        self.recording.finished.last()
    }

    /// Starts or stops recording (the panel's button and its key); returns why a recording
    /// could not start.
    pub fn toggle_recording(&mut self) -> Result<(), SessionError> {
        if self.recording.current.is_some() {
            self.stop_recording("stopped");
            Ok(())
        } else {
            self.start_recording(None)
        }
    }

    /// The recording in progress.
    pub fn recording(&self) -> Option<&LiveRecording> {
        self.recording.current.as_ref()
    }

    /// The recordings this session finished, oldest first.
    pub fn recordings(&self) -> &[FinishedRecording] {
        &self.recording.finished
    }

    /// Where recordings without a named file go ([`DEFAULT_DIR`] under it) and setups are
    /// saved; empty, the default, is the working directory.
    pub fn recordings_dir(&self) -> &Path {
        &self.recording.dir
    }

    /// Sends recordings without a named file, and saved setups, to `dir`.
    pub fn set_recordings_dir(&mut self, dir: PathBuf) {
        self.recording.dir = dir;
    }
}

/// `recordings/<scene>-<unix time>.vrec` under `dir`, or with `-n` added for `n >= 2` (two
/// recordings in one second); characters other than letters, digits, `-`, `_` and `.` in the
/// scene name become `_`.
pub fn default_path(dir: &Path, scene: &str, unix_seconds: u64, n: u32) -> PathBuf {
    let name: String = scene
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let base = dir.join(DEFAULT_DIR);
    match n {
        0 | 1 => base.join(format!("{name}-{unix_seconds}.vrec")),
        n => base.join(format!("{name}-{unix_seconds}-{n}.vrec")),
    }
}

/// Creates the first free [`default_path`] (its folder too) and opens it, never overwriting a
/// file: each name is created with `create_new`, so a file that appears between two calls is
/// not clobbered either. Tries at most [`DEFAULT_NAME_TRIES`] names and stops at the first error
/// other than "exists" (the folder is a file, no permission), naming the path and the cause.
pub fn create_default(
    dir: &Path,
    scene: &str,
    unix_seconds: u64,
) -> Result<(PathBuf, File), SessionError> {
    let first = default_path(dir, scene, unix_seconds, 1);
    create_folder_of(&first)?;
    for n in 1..=DEFAULT_NAME_TRIES {
        let path = default_path(dir, scene, unix_seconds, n);
        match File::options().write(true).create_new(true).open(&path) {
            Ok(file) => return Ok((path, file)),
            Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(SessionError::io(path, FileStep::Record, e)),
        }
    }
    let last = default_path(dir, scene, unix_seconds, DEFAULT_NAME_TRIES);
    Err(SessionError::NamesTaken { first, last })
}

/// Creates the folder `path` goes in, if it has one and it is missing.
fn create_folder_of(path: &Path) -> Result<(), SessionError> {
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => std::fs::create_dir_all(dir)
            .map_err(|e| SessionError::io(path, FileStep::MakeFolder(dir.to_path_buf()), e)),
        None => Ok(()),
    }
}

/// The first lane's observer while it records: the recorder first, then the history, for every
/// call (the recorder has written a tick before anything draws it).
pub(crate) struct Recorded<'a> {
    /// The recording.
    pub recording: &'a mut LiveRecording,
    /// The lane's history.
    pub history: &'a mut TickHistory,
}

impl TickObserver for Recorded<'_> {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        self.recording.forward(|r| r.on_command(world, stamped));
        self.history.on_command(world, stamped)
    }

    fn before_last_tick(&mut self, world: &World) {
        self.recording.forward(|r| {
            r.before_last_tick(world);
            Ok(())
        });
        self.history.before_last_tick(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.recording.forward(|r| r.after_tick(world));
        self.history.after_tick(world)
    }

    fn on_divergence(&mut self, world: &World, divergence: &Divergence) {
        self.recording.forward(|r| {
            r.on_divergence(world, divergence);
            Ok(())
        });
        self.history.on_divergence(world, divergence);
    }
}
