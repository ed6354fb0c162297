//! Scene hot reload: saving the scene file reloads it.
//!
//! The folder holding the file is watched (editors often save by writing a new file and renaming
//! it over the old one, which a watch on the file itself would lose). Events naming the file mark
//! it changed; the window reloads once the file has been quiet for [`SETTLE`], so an editor's
//! several writes per save load once. A file that does not parse leaves the running scene alone
//! and puts the error, with its line and column, in the panel.
//!
//! A browser page cannot watch files: there [`SceneWatch::new`] refuses, and the panel says so.

use std::path::Path;
use std::time::Duration;

use crate::platform::{FolderWatch, Instant};

/// Quiet time after the last change before the file is read.
pub const SETTLE: Duration = Duration::from_millis(150);

/// A watch on one scene file.
pub struct SceneWatch {
    /// The watch on the file's folder ([`crate::platform::FolderWatch`]).
    folder: FolderWatch,
    changed_at: Option<Instant>,
}

impl SceneWatch {
    /// Watches `path`'s folder for changes to `path`; a page refuses, saying why.
    pub fn new(path: &Path) -> Result<SceneWatch, String> {
        Ok(SceneWatch {
            folder: FolderWatch::new(path)?,
            changed_at: None,
        })
    }

    /// The watched file.
    pub fn path(&self) -> &Path {
        self.folder.path()
    }

    /// Whether the file changed and has been quiet since for [`SETTLE`] (then it should be
    /// reloaded now). Never blocks.
    pub fn poll(&mut self, now: Instant) -> bool {
        if self.folder.touched() {
            self.changed_at = Some(now);
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
