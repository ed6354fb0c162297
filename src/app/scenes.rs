//! Scenes in the window: the scene file watched for hot reload, a scene picked or reloaded
//! (restarting the session on it), and in a browser the files picked in the page's file input.

use std::path::{Path, PathBuf};

use super::watch::SceneWatch;
use super::{App, session};
use crate::platform::{self, Instant};
use crate::scene::Scene;

impl App {
    /// Watches the session's scene file (if watching is on and the scene has a file of its
    /// own); failure is a note, not an error.
    pub(super) fn rewatch(&mut self) {
        let note = &mut self.ui.panel.file_note;
        if self.session.is_embedded() {
            *note = Some(("the recording's scene: no hot reload".into(), true));
            self.watch = None;
            return;
        }
        if !self.options.watch {
            return;
        }
        match SceneWatch::new(self.session.path()) {
            Ok(w) => {
                *note = Some(("watching for changes".into(), true));
                self.watch = Some(w);
            }
            Err(e) => {
                *note = Some((format!("hot reload off: {e}"), false));
                self.watch = None;
            }
        }
    }

    /// Opens what was picked in a page's file input (nothing on the desktop: files come from
    /// its command line), a recording (`.vrec`, replayed and verified) or a scene or saved
    /// setup (anything else, read as a scene file).
    pub(super) fn open_picked(&mut self) {
        for (name, bytes) in platform::take_picked() {
            if name.ends_with(".vrec") {
                let source = session::replaying::ReplaySource::Bytes {
                    name: PathBuf::from(&name),
                    bytes: bytes.into(),
                };
                if let Err(why) = self.replay_from(source) {
                    self.refuse(why);
                }
                continue;
            }
            let stem = name.strip_suffix(".ron").unwrap_or(&name).to_string();
            let loaded = String::from_utf8(bytes)
                .map_err(|_| crate::SceneError {
                    file: name.clone(),
                    position: None,
                    field: None,
                    message: "not UTF-8 text".into(),
                })
                .and_then(|text| crate::scene::parse(&text, &name, &stem));
            self.use_scene(loaded, Path::new(&name), false);
        }
    }

    /// Loads `path` (in a page, the bundled scene of that path) and restarts on it; a bad file
    /// leaves the running scene and shows why.
    pub(super) fn load_scene(&mut self, path: &Path, reload: bool) {
        let loaded = platform::load_scene(path);
        self.use_scene(loaded, path, reload);
    }

    /// Restarts on `loaded` (from `path`); an error leaves the running scene and shows why.
    fn use_scene(&mut self, loaded: Result<Scene, crate::SceneError>, path: &Path, reload: bool) {
        match loaded {
            Ok(scene) => {
                let why = if reload {
                    "the scene file was saved"
                } else {
                    "another scene was picked"
                };
                let restarted = self.session.restart(Some((scene, path.to_path_buf())), why);
                if let Err(why) = restarted {
                    self.refuse(why);
                }
                self.ui.panel.sync(&self.session);
                if reload {
                    let at = self.session.world().tick();
                    self.ui.panel.file_note = Some((format!("reloaded (tick {at})"), true));
                } else {
                    self.rewatch();
                    self.view.needs_framing = true;
                }
                self.retitle();
            }
            Err(e) => self.ui.panel.file_note = Some((e.to_string(), false)),
        }
    }

    /// Reloads the scene if its file was saved and has settled.
    pub(super) fn check_reload(&mut self, now: Instant) {
        let changed = self.watch.as_mut().is_some_and(|w| w.poll(now));
        if changed {
            let path = self.session.path().to_path_buf();
            self.load_scene(&path, true);
        }
    }
}
