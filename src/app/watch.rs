//! Scene hot reload: saving the scene file reloads it.
//!
//! The folder holding the file is watched (editors often save by writing a new file and renaming
//! it over the old one, which a watch on the file itself would lose). Events naming the file mark
//! it changed; the window reloads once the file has been quiet for [`SETTLE`], so an editor's
//! several writes per save load once. A file that does not parse leaves the running scene alone
//! and puts the error, with its line and column, in the panel.
//!
//! A browser page cannot watch files: there [`SceneWatch::new`] refuses, and the panel says so.

use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;
use std::time::Duration;

use web_time::Instant;

#[cfg(not(target_arch = "wasm32"))]
use notify::{RecommendedWatcher, RecursiveMode, Watcher};

/// What the watcher sends: something happened to a file in the folder.
#[cfg(not(target_arch = "wasm32"))]
type FileEvent = notify::Result<notify::Event>;
/// In a browser nothing is ever sent.
#[cfg(target_arch = "wasm32")]
type FileEvent = Result<BrowserEvent, ()>;

/// The event a browser never sends (the watch is refused before it starts).
#[cfg(target_arch = "wasm32")]
pub struct BrowserEvent {
    kind: BrowserKind,
    paths: Vec<PathBuf>,
}

#[cfg(target_arch = "wasm32")]
struct BrowserKind;

#[cfg(target_arch = "wasm32")]
impl BrowserKind {
    fn is_access(&self) -> bool {
        true
    }
}

/// Quiet time after the last change before the file is read.
pub const SETTLE: Duration = Duration::from_millis(150);

/// A watch on one scene file.
pub struct SceneWatch {
    path: PathBuf,
    #[cfg(not(target_arch = "wasm32"))]
    _watcher: RecommendedWatcher,
    events: Receiver<FileEvent>,
    changed_at: Option<Instant>,
}

impl SceneWatch {
    /// Watches `path`'s folder for changes to `path`.
    #[cfg(target_arch = "wasm32")]
    pub fn new(_path: &Path) -> Result<SceneWatch, String> {
        Err("a browser page cannot watch files; load the scene again to see a change".into())
    }

    /// Watches `path`'s folder for changes to `path`.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new(path: &Path) -> Result<SceneWatch, String> {
        let path = path
            .canonicalize()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let dir = path.parent().unwrap_or(Path::new("/")).to_path_buf();
        let (tx, events) = std::sync::mpsc::channel();
        let mut watcher = notify::recommended_watcher(move |event| {
            let _ = tx.send(event);
        })
        .map_err(|e| format!("cannot watch {}: {e}", dir.display()))?;
        watcher
            .watch(&dir, RecursiveMode::NonRecursive)
            .map_err(|e| format!("cannot watch {}: {e}", dir.display()))?;
        Ok(SceneWatch {
            path,
            _watcher: watcher,
            events,
            changed_at: None,
        })
    }

    /// The watched file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the file changed and has been quiet since for [`SETTLE`] (then it should be
    /// reloaded now). Never blocks.
    pub fn poll(&mut self, now: Instant) -> bool {
        while let Ok(event) = self.events.try_recv() {
            let touches = event.is_ok_and(|e| {
                !e.kind.is_access() && e.paths.iter().any(|p| same_file(p, &self.path))
            });
            if touches {
                self.changed_at = Some(now);
            }
        }
        match self.changed_at {
            Some(t) if now.duration_since(t) >= SETTLE => {
                self.changed_at = None;
                true
            }
            _ => false,
        }
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    a == b || a.canonicalize().is_ok_and(|a| a == b)
}
