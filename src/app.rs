//! The sandbox window: a winit [`ApplicationHandler`](winit::application::ApplicationHandler)
//! that owns the window, turns input into [`Action`]s (and those into commands), paces frames,
//! and draws each one with the same [`crate::render::Renderer`] the offscreen capture uses, plus
//! the egui panel.
//!
//! A frame: the frame delta (the real clock, or a steady virtual one with `--frame-rate`) goes
//! to every lane of the [`Session`]; the panel is laid out; the 3D view fills what the panel
//! leaves; the scene and the panel are encoded into the surface texture and presented. Device and
//! surface are created on `resumed`, as winit requires. Without vsync, frames are capped at
//! [`MAX_FPS`] so a software adapter does not spin a core drawing frames nobody sees.
//!
//! The session records its first lane on request ([`session::recording`]) and plays recordings
//! back ([`session::replaying`], [`run_session`] with [`Session::for_replay`]); the panel shows
//! divergences, a replay's mismatch and the stability pre-check at its top
//! ([`panel`]).

mod control;
pub mod display;
mod drill;
mod frame;
mod handler;
mod host;
pub mod input;
pub mod panel;
mod pick;
mod redraw;
mod scenes;
pub mod script;
pub mod session;
pub mod setup_drag;
mod summary;
pub mod surface;
mod timing;
mod ui;
mod view;
pub mod watch;
#[cfg(target_arch = "wasm32")]
pub mod web;

use std::path::{Path, PathBuf};

use winit::event_loop::{ControlFlow, EventLoop};

use crate::clock::LoopPolicy;
use crate::pacing::DrawMode;
use crate::pacing::SweepDisplay;
use crate::render::GpuError;
use crate::scene::Scene;
use display::Frames;
use drill::SurfaceDrill;
use host::Host;
pub use input::Action;
use panel::PanelState;
pub use session::{Session, SessionError};
pub use summary::{LaneReport, RunSummary};
use timing::FrameTiming;
use ui::UiState;
use view::SceneView;
use watch::SceneWatch;

/// Highest frame rate drawn when the display does not pace frames itself.
pub const MAX_FPS: f64 = 250.0;

/// How the window runs.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowOptions {
    /// Lanes to compare side by side, each an integrator with its own dt and substeps if
    /// given (empty: one world).
    pub compare: Vec<crate::scene::CompareLane>,
    /// Compare lanes at the first one's force evaluations per simulated second.
    pub equal_cost: bool,
    /// Close after this many frames (smoke tests, screenshots).
    pub exit_after_frames: Option<u64>,
    /// Save the last frame (scene and panel) to this PNG before closing.
    pub screenshot: Option<PathBuf>,
    /// Initial inner size (logical px).
    pub size: (u32, u32),
    /// Drive the loop with steady frames of this rate instead of the real clock.
    pub frame_rate: Option<f64>,
    /// Start paused.
    pub paused: bool,
    /// Initial time scale.
    pub time_scale: f64,
    /// Watch the scene file and reload it when it is saved.
    pub watch: bool,
    /// Bundled scenes for the picker, (name, path).
    pub scenes: Vec<(String, PathBuf)>,
    /// Record the first lane from tick 0 to this file (`volley window --record FILE`).
    pub record: Option<PathBuf>,
    /// Put the window through a resize, a minimise and restore, and a lost surface, a few
    /// frames apart (`--surface-drill`, for the smoke tests).
    pub surface_drill: bool,
    /// An input script played from the first frame (`--script FILE`, [`script`]).
    pub script: Vec<script::Step>,
    /// Each lane's timeline budget (bytes), [`crate::timeline::DEFAULT_BUDGET`] by default.
    pub history_budget: usize,
    /// Ticks every lane runs before the window opens (`--warm-up-ticks`).
    pub warm_up_ticks: u64,
    /// Emulate this display (`--display`): its frame deltas drive the loop, its display times
    /// are measured against (instead of `frame_rate` or the real clock).
    pub display: Option<SweepDisplay>,
    /// The loop policy every lane starts with (`--policy`); [`crate::pacing::DEFAULT_POLICY`]
    /// by default. A snapping or quantising policy is given the display's refresh.
    pub policy: LoopPolicy,
    /// How every lane is drawn at start (`--draw`); [`crate::pacing::DEFAULT_DRAW`] by default.
    pub draw: DrawMode,
}

/// Why the window could not run.
#[derive(Clone, Debug, PartialEq)]
pub enum AppError {
    /// No display server to open a window on.
    NoDisplay(String),
    /// No adapter, device or surface.
    Gpu(GpuError),
    /// A file could not be written (a screenshot).
    Io(String),
    /// The recording asked for from the start (`--record FILE`) could not start.
    Recording(SessionError),
}

impl std::fmt::Display for AppError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AppError::NoDisplay(why) => write!(
                f,
                "no display to open a window on ({why}); `volley headless SCENE` runs without \
                 one (add --frames DIR for pictures)"
            ),
            AppError::Gpu(e) => write!(
                f,
                "{e}; `volley headless SCENE` runs without a GPU (its --frames option needs \
                 only a software adapter)"
            ),
            AppError::Io(why) => f.write_str(why),
            AppError::Recording(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for AppError {}

/// Opens the window on `scene` (read from `path`) and runs until it is closed.
pub fn run(scene: Scene, path: &Path, options: WindowOptions) -> Result<RunSummary, AppError> {
    let session = Session::with_lanes(scene, path, options.compare.clone(), options.equal_cost);
    run_session(session, options)
}

/// Opens the window on a prepared session (a replay: [`Session::for_replay`]) and runs until it
/// is closed. A recording still running when it closes is ended with its footer.
pub fn run_session(session: Session, options: WindowOptions) -> Result<RunSummary, AppError> {
    crate::platform::keep_freed_heap();
    let event_loop = EventLoop::new().map_err(|e| AppError::NoDisplay(os_reason(&e)))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App::new(session, options);
    let ran = event_loop.run_app(&mut app);
    app.session.stop_recording("the window closed");
    ran.map_err(|e| AppError::NoDisplay(e.to_string()))?;
    app.ending.clone().unwrap_or(Ok(()))?;
    Ok(app.summary())
}

/// The reason in a winit error without the source location winit prefixes to it.
fn os_reason(e: &dyn std::fmt::Display) -> String {
    let text = e.to_string();
    match text.split_once("os error at ") {
        Some((_, rest)) => rest.rsplit_once(": ").map_or(rest.to_string(), |(_, why)| {
            why.trim_end_matches('.').to_string()
        }),
        None => text,
    }
}

/// The window: one field per concern, each its own type.
struct App {
    /// How the window was asked to run.
    options: WindowOptions,
    /// The simulations shown.
    session: Session,
    /// The panel, the view's toggles, the pointer, the probe and a setup drag.
    ui: UiState,
    /// The 3D view's camera and where it is drawn.
    view: SceneView,
    /// Where frames come from and how long they take.
    timing: FrameTiming,
    /// The scene file's watcher, while hot reload is on.
    watch: Option<SceneWatch>,
    /// The window, its GPU side and egui.
    host: Host,
    /// The input script being played, with the egui input its clicks queued.
    script: script::Player,
    /// `--surface-drill`'s progress, if asked for.
    drill: Option<SurfaceDrill>,
    /// A screenshot asked for by its key, written after the next frame.
    screenshot: Option<PathBuf>,
    /// How the window ends, once it is asked to: closed (`Ok`) or failed; `None` while it runs.
    ending: Option<Result<(), AppError>>,
}

impl App {
    /// Asks the window to close after this event, keeping a failure already recorded.
    fn quit(&mut self) {
        self.ending.get_or_insert(Ok(()));
    }

    fn new(mut session: Session, options: WindowOptions) -> App {
        if options.history_budget != session.history_budget() {
            session.set_history_budget(options.history_budget);
        }
        let warmed = match options.warm_up_ticks {
            0 => Ok(()),
            ticks => session.run_ticks(ticks),
        };
        session.set_paused(options.paused);
        let scaled = session.set_time_scale(options.time_scale);
        session.set_policy(options.policy);
        session.set_refresh(match (&options.display, options.frame_rate) {
            (Some(d), _) => d.refresh,
            (None, Some(hz)) => display::believed_refresh(hz),
            (None, None) => display::DEFAULT_REFRESH,
        });
        session.set_draw_mode(options.draw);
        let mut panel = PanelState::new(&session, options.scenes.clone());
        // The panel shows the later refusal, as it would have replaced the earlier one.
        if let Err(why) = scaled.and(warmed) {
            panel.refuse(&session, why);
        }
        panel.frames_note = match (&options.display, options.frame_rate) {
            (Some(d), _) => format!("display {} (virtual frames)", d.name),
            (None, Some(hz)) => format!("steady {hz} Hz frames"),
            (None, None) => "the real clock".into(),
        };
        let script = script::Player::new(options.script.clone());
        let frames = Frames::of(options.display.as_ref(), options.frame_rate);
        let mut app = App {
            view: SceneView::new(session.bounds()),
            session,
            ui: UiState::new(panel),
            timing: FrameTiming::new(frames),
            watch: None,
            host: Host::new(),
            screenshot: None,
            script,
            drill: options.surface_drill.then(SurfaceDrill::default),
            ending: None,
            options,
        };
        app.rewatch();
        app
    }

    /// The window title: the scene, and the recording when replaying.
    fn title(&self) -> String {
        match self.session.replay() {
            Some(r) => format!(
                "Volley: {} (replaying {})",
                self.session.scene().name(),
                r.file().display()
            ),
            None => format!("Volley: {}", self.session.scene().name()),
        }
    }

    fn retitle(&self) {
        self.host.retitle(&self.title());
    }
}
