//! The sandbox window: a winit [`ApplicationHandler`] that owns the window, turns input into
//! [`Action`]s (and those into commands), paces frames, and draws each one with the same
//! [`crate::render::Renderer`] the offscreen capture uses, plus the egui panel.
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
mod host;
pub mod input;
pub mod panel;
mod pick;
pub mod script;
pub mod session;
pub mod setup_drag;
pub mod surface;
mod timing;
mod ui;
mod view;
pub mod watch;
#[cfg(target_arch = "wasm32")]
pub mod web;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use web_time::Instant;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use crate::clock::LoopPolicy;
use crate::integrate::Integrator;
use crate::pacing::DrawMode;
use crate::pacing::SweepDisplay;
use crate::render::GpuError;
use crate::scene::Scene;
use display::Frames;
use drill::SurfaceDrill;
use frame::FrameUi;
use host::Host;
pub use input::Action;
use panel::PanelState;
pub use session::Session;
#[cfg(not(target_arch = "wasm32"))]
use surface::WindowGpu;
use timing::FrameTiming;
use ui::UiState;
use view::{SceneView, viewport_of};
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
        }
    }
}

impl std::error::Error for AppError {}

/// What a window run drew, for a closing summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Frames presented.
    pub frames: u64,
    /// The adapter, as [`crate::render::Gpu::describe`] gives it.
    pub adapter: String,
    /// Median time between frames (ms), over the frames of a run with a frame limit (empty
    /// otherwise, to keep a long session's memory flat).
    pub interval_ms: Option<f64>,
    /// Median time spent on a frame (ms): stepping, the panel, drawing, presenting.
    pub work_ms: Option<f64>,
    /// Median CPU time of the UI in a frame (ms): the panel and plots laid out and tessellated.
    pub ui_ms: Option<f64>,
    /// Median number of triangles egui's meshes had in a frame: what a software rasteriser
    /// pays for the panel and plots (besides their area), counted, so it does not vary with the
    /// machine's load.
    pub ui_triangles: Option<usize>,
    /// The recordings made in the window, oldest first (the last one ended when it closed).
    pub recordings: Vec<session::recording::FinishedRecording>,
    /// Where the last replay stood when it ended or the window closed.
    pub replay: Option<session::replaying::ReplayVerdict>,
    /// Each lane as the window closed: for tests and scripted demos.
    pub lanes: Vec<LaneReport>,
    /// What the probe read when the window closed, if it was on something.
    pub probe: Option<Vec<String>>,
    /// The loop as the window closed: policy, draw mode, frames, cadence, swings and the
    /// measured body's display error ([`session::pacing`]).
    pub pacing: String,
    /// The panel's "Forces" lines as the window closed, an inactive term marked `(off)`.
    pub forces: Vec<String>,
}

/// A lane as the window closed.
#[derive(Clone, Debug, PartialEq)]
pub struct LaneReport {
    /// The lane's integrator.
    pub integrator: Integrator,
    /// Its tick.
    pub tick: u64,
    /// Its bodies.
    pub bodies: usize,
    /// Each body's closest pass by each target.
    pub passes: Vec<crate::render::history::Pass>,
    /// Its last aim.
    pub aim: Option<session::AimNote>,
    /// Its launcher.
    pub launcher: crate::scene::Launcher,
    /// Its dt (s) and substeps.
    pub dt: f64,
    /// Its integrator steps per tick.
    pub substeps: u32,
    /// Its force evaluations per simulated second so far.
    pub evals_per_second: f64,
    /// The targets' centres now.
    pub targets: Vec<glam::DVec3>,
}

impl std::fmt::Display for LaneReport {
    /// `lane NAME: tick N, B bodies`, then a line per pass and the aim.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "lane {}: tick {}, {} bodies, dt {} s x{}, {:.1} force evaluations per sim second",
            self.integrator.name(),
            self.tick,
            self.bodies,
            self.dt,
            self.substeps,
            self.evals_per_second
        )?;
        let l = &self.launcher;
        write!(
            f,
            "\n  launcher at ({:.4}, {:.4}, {:.4}), speed {:.4} m/s, elevation {:.4} deg, azimuth \
             {:.4} deg",
            l.position.x, l.position.y, l.position.z, l.speed, l.elevation_deg, l.azimuth_deg
        )?;
        for (i, c) in self.targets.iter().enumerate() {
            write!(f, "\n  target {i} at ({:.4}, {:.4}, {:.4})", c.x, c.y, c.z)?;
        }
        if let Some(note) = &self.aim {
            match &note.outcome {
                Ok(s) => write!(
                    f,
                    "\n  aim at target {} from tick {}: {} elevation {:.4} deg azimuth {:.4} deg \
                     speed {:.4} m/s{}",
                    note.target,
                    note.tick,
                    s.kind.label(),
                    s.elevation_deg,
                    s.azimuth_deg,
                    s.speed,
                    s.textbook.map_or(String::new(), |t| format!(
                        ", textbook misses by {:.4} m",
                        t.miss
                    ))
                )?,
                Err(why) => write!(f, "\n  aim at target {}: {why}", note.target)?,
            }
        }
        for p in &self.passes {
            write!(
                f,
                "\n  body {} passed target {} at {:e} m (t = {:.4} s){}",
                p.body,
                p.target,
                p.distance,
                p.time,
                if p.hit { ", hit" } else { "" }
            )?;
        }
        Ok(())
    }
}

/// Opens the window on `scene` (read from `path`) and runs until it is closed.
pub fn run(scene: Scene, path: &Path, options: WindowOptions) -> Result<RunSummary, AppError> {
    let session = Session::with_lanes(scene, path, options.compare.clone(), options.equal_cost);
    run_session(session, options)
}

/// Opens the window on a prepared session (a replay: [`Session::for_replay`]) and runs until it
/// is closed. A recording still running when it closes is ended with its footer.
pub fn run_session(session: Session, options: WindowOptions) -> Result<RunSummary, AppError> {
    surface::keep_freed_heap();
    let event_loop = EventLoop::new().map_err(|e| AppError::NoDisplay(os_reason(&e)))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App::new(session, options);
    let ran = event_loop.run_app(&mut app);
    app.session.stop_recording("the window closed");
    ran.map_err(|e| AppError::NoDisplay(e.to_string()))?;
    app.ending.clone().unwrap_or(Ok(()))?;
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied()
    };
    let timings = &app.timing.timings;
    Ok(RunSummary {
        frames: app.timing.stats.frames,
        adapter: app.timing.stats.adapter.clone(),
        // The first interval includes opening the window and the device.
        interval_ms: median(&mut timings.iter().skip(1).map(|t| t.0).collect()),
        work_ms: median(&mut timings.iter().map(|t| t.1).collect()),
        ui_ms: median(&mut timings.iter().map(|t| t.2).collect()),
        ui_triangles: median(&mut timings.iter().map(|t| t.3 as f64).collect()).map(|t| t as usize),
        recordings: app.session.recordings().to_vec(),
        replay: app.session.replay_verdict(),
        probe: app.ui.probe.as_ref().map(|p| p.lines()),
        pacing: app.pacing_line(),
        forces: {
            let world = app.session.world();
            panel::forces::lines(&world.params().declared, world.forces(), world.launcher())
                .into_iter()
                .map(|(line, on)| if on { line } else { format!("{line} (off)") })
                .collect()
        },
        lanes: app
            .session
            .lanes()
            .iter()
            .map(|l| LaneReport {
                integrator: l.sim.world.integrator(),
                tick: l.sim.world.tick(),
                bodies: l.sim.world.bodies().len(),
                passes: l.history.passes.all().to_vec(),
                aim: l.aim.clone(),
                launcher: *l.sim.world.launcher(),
                dt: l.sim.world.dt(),
                substeps: l.sim.world.substeps(),
                evals_per_second: l.evals_per_second().unwrap_or(0.0),
                targets: {
                    let w = &l.sim.world;
                    let since = w.tick() as f64 * w.dt();
                    w.contacts()
                        .targets
                        .iter()
                        .map(|t| t.center_at(since))
                        .collect()
                },
            })
            .collect(),
    })
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

    /// Watches the session's scene file (if watching is on and the scene has a file of its
    /// own); failure is a note, not an error.
    fn rewatch(&mut self) {
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

    /// In a browser: opens what was picked in the page's file input, a recording (`.vrec`,
    /// replayed and verified) or a scene or saved setup (anything else, read as a scene file).
    #[cfg(target_arch = "wasm32")]
    fn open_picked(&mut self) {
        for (name, bytes) in web::take_picked() {
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

    /// Loads `path` and restarts on it; a bad file leaves the running scene and shows why.
    fn load_scene(&mut self, path: &Path, reload: bool) {
        #[cfg(not(target_arch = "wasm32"))]
        let loaded = crate::scene::load(path);
        #[cfg(target_arch = "wasm32")]
        let loaded = web::load(path);
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

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<(), AppError> {
        let window = match &self.host.window {
            Some(w) => w.clone(),
            None => {
                let (w, h) = self.options.size;
                let attributes = Window::default_attributes()
                    .with_title(self.title())
                    .with_inner_size(winit::dpi::LogicalSize::new(w, h));
                // In a browser the window is a canvas, added to the page's body.
                #[cfg(target_arch = "wasm32")]
                let attributes = {
                    use winit::platform::web::WindowAttributesExtWebSys;
                    attributes.with_append(true)
                };
                let window = event_loop
                    .create_window(attributes)
                    .map_err(|e| AppError::NoDisplay(e.to_string()))?;
                Arc::new(window)
            }
        };
        // On the real clock the game believes in the monitor's refresh, where it reports one.
        let monitor_hz = window
            .current_monitor()
            .and_then(|m| m.refresh_rate_millihertz())
            .map(|mhz| f64::from(mhz) / 1e3);
        if let (Frames::Clock(_), None, Some(hz)) =
            (&self.timing.frames, self.options.frame_rate, monitor_hz)
        {
            self.session.set_refresh(display::believed_refresh(hz));
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let gfx = WindowGpu::new(event_loop, window.clone()).map_err(AppError::Gpu)?;
            self.timing.stats.adapter = gfx.gpu.describe();
            self.host.attach(window, gfx);
        }
        #[cfg(target_arch = "wasm32")]
        self.host.open_in_browser(event_loop, window);
        Ok(())
    }

    /// In a browser: takes the device once the browser has opened it, or ends on why it
    /// could not.
    #[cfg(target_arch = "wasm32")]
    fn adopt_browser_gpu(&mut self, event_loop: &ActiveEventLoop) {
        let Some(opened) = self.host.take_opened() else {
            return;
        };
        match (opened, self.host.window.clone()) {
            (Ok(gfx), Some(window)) => {
                // A GPU error the page did not expect is shown in it, not a silent stop.
                gfx.gpu
                    .device
                    .on_uncaptured_error(std::sync::Arc::new(|e: wgpu::Error| {
                        web::show_error(&format!("GPU error: {e}"));
                    }));
                self.timing.stats.adapter = match gfx.renderer.trails_missing() {
                    Some(why) => format!("{}; {why}", gfx.gpu.describe()),
                    None => gfx.gpu.describe(),
                };
                self.host.attach(window, gfx);
                web::show_adapter(&self.timing.stats.adapter);
            }
            (Err(e), _) => {
                web::show_error(&AppError::Gpu(e).to_string());
                self.ending = Some(Err(AppError::Gpu(GpuError::Surface("see the page".into()))));
                event_loop.exit();
            }
            (Ok(_), None) => {}
        }
    }

    /// Reloads the scene if its file was saved and has settled.
    fn check_reload(&mut self, now: Instant) {
        let changed = self.watch.as_mut().is_some_and(|w| w.poll(now));
        if changed {
            let path = self.session.path().to_path_buf();
            self.load_scene(&path, true);
        }
    }

    /// One frame, stage by stage.
    fn redraw(&mut self) {
        let start = Instant::now();
        self.advance(start);
        let Some(window) = self.host.window.clone() else {
            return;
        };
        let Some(mut ui) = self.build_ui(&window) else {
            return;
        };
        self.upload_ui_textures(&mut ui.textures);
        self.place_view(ui.rest, ui.ppp);
        if let Some(screen) = self.present(&ui.primitives, ui.ppp) {
            let drawn = FrameUi {
                primitives: &ui.primitives,
                screen: &screen,
            };
            self.after_present(&drawn);
            self.drill();
        }
        self.free_ui_textures(ui.textures);
        let keep = self.options.exit_after_frames.is_some();
        self.timing.end_frame(start, &window, keep);
    }

    /// Advances the loop: the script's actions due now, the frame's delta, a saved scene
    /// reloaded, the lanes run for the delta; the panel's values follow the session unless
    /// commands still wait for a tick.
    fn advance(&mut self, start: Instant) {
        for action in self.script.due() {
            self.apply(action);
        }
        let frame = self.timing.frames.next_frame();
        self.check_reload(start);
        if let Some(why) = self.session.frame_shown(frame.delta, frame.shown) {
            self.refuse(why);
        }
        if self.session.lanes().iter().all(|l| l.pending() == 0) {
            let panel = &mut self.ui.panel;
            let (dt_ms, substeps) = (panel.dt_ms, panel.substeps);
            let pick = panel.compare_pick.clone();
            panel.sync(&self.session);
            // The step fields keep what is being typed until it is applied.
            (panel.dt_ms, panel.substeps) = (dt_ms, substeps);
            panel.compare_pick = pick;
        }
    }

    /// Builds the UI: the probe, the panels laid out with the script's queued input, what they
    /// asked for applied, and their shapes tessellated; the UI's time and triangles are
    /// measured. Nothing without egui's state (before the window opened).
    fn build_ui(&mut self, window: &Window) -> Option<BuiltUi> {
        self.host.egui_state.as_ref()?;
        let ui_start = Instant::now();
        let scale = self.timing.stats.scale;
        self.ui.update_probe(&self.session, &self.view, scale);
        let egui_state = self.host.egui_state.as_mut()?;
        let mut raw = egui_state.take_egui_input(window);
        if let Some(events) = self.script.next_input() {
            raw.events.extend(events);
        }
        let mut actions = Vec::new();
        let mut rest = egui::Rect::NOTHING;
        self.ui.panel.pacing_view = self.ui.toggles.pacing;
        self.ui.panel.judder_ghosts = self.ui.toggles.judder;
        let output = self.host.egui.run_ui(raw, |ui| {
            rest = self
                .ui
                .lay_out(ui, &self.session, &self.timing.stats, &mut actions);
        });
        egui_state.handle_platform_output(window, output.platform_output);
        self.ui.controls = panel::take_controls(&self.host.egui);
        // The UI's time leaves out what its actions do (a seek, an aim): that is simulation.
        let laid_out = ui_start.elapsed();
        for action in actions {
            self.apply(action);
        }
        let tessellating = Instant::now();
        let ppp = output.pixels_per_point;
        let primitives = self.host.egui.tessellate(output.shapes, ppp);
        self.timing.ui_ms = (laid_out + tessellating.elapsed()).as_secs_f64() * 1e3;
        self.timing.ui_triangles = primitives
            .iter()
            .map(|p| match &p.primitive {
                egui::epaint::Primitive::Mesh(m) => m.indices.len() / 3,
                egui::epaint::Primitive::Callback(_) => 0,
            })
            .sum();
        Some(BuiltUi {
            primitives,
            textures: output.textures_delta,
            ppp,
            rest,
        })
    }

    /// Sends egui's new and changed textures to its renderer.
    fn upload_ui_textures(&mut self, textures: &mut egui::TexturesDelta) {
        if let Some(gfx) = self.host.gfx.as_mut() {
            for (id, deltas) in textures.set.drain() {
                for delta in &deltas {
                    gfx.egui
                        .update_texture(&gfx.gpu.device, &gfx.gpu.queue, id, delta);
                }
            }
        }
    }

    /// Fits the 3D view into what the panels left (`rest`, points at `ppp` pixels per point),
    /// framing the scene if asked to.
    fn place_view(&mut self, rest: egui::Rect, ppp: f32) {
        if let Some(gfx) = self.host.gfx.as_ref() {
            self.view.viewport = viewport_of(rest, ppp, gfx.size());
        }
        self.view.frame_if_asked(self.session.bounds());
    }

    /// Frees the textures egui no longer uses, once the frame that may use them was drawn.
    fn free_ui_textures(&mut self, mut textures: egui::TexturesDelta) {
        if let Some(gfx) = self.host.gfx.as_mut() {
            for id in textures.free.drain() {
                gfx.egui.free_texture(&id);
            }
        }
        // Without a device (suspended) the deltas have nowhere to go; the context is replaced
        // when the device comes back.
        textures.clear();
    }

    /// `--surface-drill`'s next step, after a presented frame.
    fn drill(&mut self) {
        let (Some(drill), Some(window), Some(gfx)) = (
            self.drill.as_mut(),
            self.host.window.as_deref(),
            self.host.gfx.as_mut(),
        ) else {
            return;
        };
        drill.after_frame(self.timing.stats.frames, self.options.size, window, gfx);
    }

    /// The closing summary's pacing line.
    fn pacing_line(&self) -> String {
        let s = &self.session;
        let log = s.pacing();
        let mode = s.draw_mode();
        let when = if log.display_times {
            "at display time"
        } else {
            "at the frames' samples"
        };
        let error = match (log.median_error(mode, f64::INFINITY), &log.note) {
            (Some(e), _) => format!("median display error {:.4} mm {when}", e * 1e3),
            (None, Some(why)) => format!("no display error: {why}"),
            (None, None) => "no display error".into(),
        };
        format!(
            "pacing: {} + {} on {}, body {}, ticks/frame {}, 0-2 swings {}, {error}",
            s.policy().name(),
            mode.name(),
            self.ui.panel.frames_note,
            log.body,
            log.cadence(),
            log.swings(),
        )
    }
}

/// A frame's UI, built and tessellated, waiting to be drawn.
struct BuiltUi {
    /// egui's meshes.
    primitives: Vec<egui::ClippedPrimitive>,
    /// The textures egui sets and frees this frame.
    textures: egui::TexturesDelta,
    /// Pixels per point.
    ppp: f32,
    /// What the panels left for the 3D view (points).
    rest: egui::Rect,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.host.gfx.is_some() {
            return;
        }
        if let Err(e) = self.open(event_loop) {
            self.ending = Some(Err(e));
            event_loop.exit();
            return;
        }
        // `--record FILE`: from tick 0, once there is a window to run in.
        if let Some(path) = self.options.record.take()
            && let Err(e) = self.session.start_recording(Some(path))
        {
            self.ending = Some(Err(AppError::Io(e)));
            event_loop.exit();
        }
    }

    fn suspended(&mut self, _event_loop: &ActiveEventLoop) {
        // The surface may not outlive a suspension (Android); it is rebuilt on `resumed`.
        self.host.gfx = None;
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        #[cfg(target_arch = "wasm32")]
        self.adopt_browser_gpu(event_loop);
        let (Some(window), Some(egui_state)) =
            (self.host.window.clone(), self.host.egui_state.as_mut())
        else {
            return;
        };
        let consumed = egui_state.on_window_event(&window, &event).consumed;
        match &event {
            WindowEvent::CloseRequested => self.quit(),
            WindowEvent::Resized(size) => {
                if let Some(gfx) = self.host.gfx.as_mut() {
                    gfx.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested => self.redraw(),
            WindowEvent::KeyboardInput { event, .. }
                if event.state.is_pressed()
                    && !consumed
                    && !self.host.egui.egui_wants_keyboard_input() =>
            {
                if let Some(action) = input::action_for_key(&event.logical_key) {
                    self.apply(action);
                }
            }
            _ => self.on_pointer(&event, consumed || self.host.egui.is_pointer_over_egui()),
        }
        if self.ending.is_some() {
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        #[cfg(target_arch = "wasm32")]
        {
            self.adopt_browser_gpu(event_loop);
            self.open_picked();
        }
        if self.ending.is_some() {
            event_loop.exit();
            return;
        }
        let Some(window) = &self.host.window else {
            return;
        };
        if !self.host.visible() {
            // Minimised: nothing to draw; the next resize event wakes the loop.
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        let due = self.timing.last_frame + Duration::from_secs_f64(1.0 / MAX_FPS);
        if Instant::now() >= due {
            event_loop.set_control_flow(ControlFlow::Poll);
            window.request_redraw();
        } else {
            event_loop.set_control_flow(ControlFlow::WaitUntil(due));
        }
    }
}
