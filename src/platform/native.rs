//! The desktop's side of the seam ([`crate::platform`]): files are written and read, the scene's
//! folder is watched, and the program blocks on the GPU's futures where it needs their answer.

use std::future::Future;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;

use notify::{RecommendedWatcher, RecursiveMode, Watcher};
use winit::window::WindowAttributes;

use crate::SceneError;
use crate::scene::Scene;

/// Not the browser build.
pub const IN_BROWSER: bool = false;

/// Recordings, saved setups and screenshots are files.
pub const WRITES_FILES: bool = true;

/// The desktop may block until the GPU has answered (opening a device, reading a frame back).
pub const CAN_BLOCK: bool = true;

/// Runs `future` to its end on this thread and returns its output (always `Some` here).
pub fn block_on<F: Future>(future: F) -> Option<F::Output> {
    Some(pollster::block_on(future))
}

/// Runs `future` to its end on this thread, then `then` with its output, before returning.
pub fn complete<F: Future + 'static>(future: F, then: impl FnOnce(F::Output) + 'static) {
    then(pollster::block_on(future));
}

/// An instance on the backends `descriptor` allows (`WGPU_BACKEND` chooses among them).
pub async fn gpu_instance(descriptor: wgpu::InstanceDescriptor) -> wgpu::Instance {
    wgpu::Instance::new(descriptor)
}

/// Leaves wgpu's own handler in place: an uncaptured GPU error panics with its message.
pub fn report_gpu_errors(_device: &wgpu::Device) {}

/// The window is a window of its own.
pub fn on_page(attributes: WindowAttributes) -> WindowAttributes {
    attributes
}

/// The scene in the file `path`.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    crate::scene::load(path)
}

/// Writes `bytes` to the file `name` in `folder` (made if missing) and returns its path, or the
/// path that failed and why.
pub fn save_file(
    folder: &Path,
    name: &str,
    bytes: &[u8],
    _mime: &str,
) -> Result<PathBuf, (PathBuf, std::io::Error)> {
    std::fs::create_dir_all(folder).map_err(|e| (folder.to_path_buf(), e))?;
    let path = folder.join(name);
    std::fs::write(&path, bytes).map_err(|e| (path.clone(), e))?;
    Ok(path)
}

/// Nothing: the desktop writes files ([`WRITES_FILES`]) and never has bytes waiting for a
/// download.
pub fn offer_download(_name: &str, _bytes: &[u8], _mime: &str) {}

/// Writes the screenshot to `path` with `write_png` (the frame drawn again offscreen and read
/// back).
pub fn save_screenshot(
    path: &Path,
    write_png: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    write_png(path)
}

/// Nothing: files are opened from the command line, not picked in a page.
pub fn take_picked() -> Vec<(String, Vec<u8>)> {
    Vec::new()
}

/// Nothing: the command line prints the window's error when it closes.
pub fn show_error(_message: &str) {}

/// Nothing: there is no page to show the run's facts on (`facts` is not called).
pub fn show_on_page(_facts: impl FnOnce() -> Vec<(&'static str, String)>) {}

/// The plot font, DejaVu Sans (a subset), compiled into the binary.
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// Registers the embedded font (DejaVu Sans, a subset) as plotters' `sans-serif`, once;
/// whether it loaded.
pub fn register_plot_font() -> bool {
    static ONCE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ONCE.get_or_init(|| {
        plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, FONT)
            .is_ok()
    })
}

/// Keeps up to 64 MiB of freed memory at the top of a heap for reuse, instead of glibc's default
/// (128 KiB): the software adapter (lavapipe) allocates and frees vertex buffers on its own
/// thread every frame, and once a frame's meshes pass that size (the plots' do) glibc handed
/// the top of that thread's heap back to the kernel (`madvise`) after every frame and the next
/// frame faulted it in again: about 1 ms a frame here (strace: one `madvise` a frame; perf:
/// page faults and unmapping in the frame's thread). Memory the window held at its busiest
/// frame stays held; nothing else changes. glibc on Linux only; elsewhere nothing is done.
/// Called once, as the window starts.
pub fn keep_freed_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets a tuning parameter of the allocator; glibc serialises it
    // against allocations in other threads.
    unsafe {
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
    }
}

/// What the watcher sends: something happened to a file in the folder.
type FileEvent = notify::Result<notify::Event>;

/// A watch on the folder holding one file. The folder is watched, not the file: editors often
/// save by writing a new file and renaming it over the old one, which a watch on the file itself
/// would lose.
pub struct FolderWatch {
    path: PathBuf,
    _watcher: RecommendedWatcher,
    events: Receiver<FileEvent>,
}

impl FolderWatch {
    /// Watches `path`'s folder for changes to `path`.
    pub fn new(path: &Path) -> Result<FolderWatch, String> {
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
        Ok(FolderWatch {
            path,
            _watcher: watcher,
            events,
        })
    }

    /// The watched file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether anything but a read touched the file since the last call. Never blocks.
    pub fn touched(&mut self) -> bool {
        let mut touched = false;
        while let Ok(event) = self.events.try_recv() {
            touched |= event.is_ok_and(|e| {
                !e.kind.is_access() && e.paths.iter().any(|p| same_file(p, &self.path))
            });
        }
        touched
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    a == b || a.canonicalize().is_ok_and(|a| a == b)
}
