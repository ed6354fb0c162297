//! The sandbox window: a winit [`ApplicationHandler`] that owns the window, turns input into
//! [`Action`]s (and those into commands), paces frames, and draws each one with the same
//! [`Renderer`] the offscreen capture uses, plus the egui panel.
//!
//! A frame: the frame delta (the real clock, or a steady virtual one with `--frame-rate`) goes
//! to every lane of the [`Session`]; the panel is laid out; the 3D view fills what the panel
//! leaves; the scene and the panel are encoded into the surface texture and presented. Device and
//! surface are created on `resumed`, as winit requires. Without vsync, frames are capped at
//! [`MAX_FPS`] so a software adapter does not spin a core drawing frames nobody sees.

pub mod input;
pub mod panel;
pub mod session;
pub mod surface;
pub mod watch;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use crate::clock::{FrameSource, RealClock, VirtualClock};
use crate::command::Command;
use crate::integrate::Integrator;
use crate::render::{DrawOptions, GpuError, Image, OffscreenTarget, OrbitCamera, View, Viewport};
use crate::scene::Scene;
pub use input::Action;
use panel::{FrameStats, PanelState};
pub use session::Session;
use surface::WindowGpu;
use watch::SceneWatch;

/// Highest frame rate drawn when the display does not pace frames itself.
pub const MAX_FPS: f64 = 250.0;
/// Weight of the newest frame in the smoothed frame times.
const SMOOTHING: f64 = 0.1;

/// How the window runs.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowOptions {
    /// Integrators to compare side by side (empty: one world).
    pub compare: Vec<Integrator>,
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

/// Opens the window on `scene` (read from `path`) and runs until it is closed.
pub fn run(scene: Scene, path: &Path, options: WindowOptions) -> Result<(), AppError> {
    let event_loop = EventLoop::new().map_err(|e| AppError::NoDisplay(os_reason(&e)))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App::new(scene, path, options);
    event_loop
        .run_app(&mut app)
        .map_err(|e| AppError::NoDisplay(e.to_string()))?;
    app.outcome
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

/// Mouse state between events.
#[derive(Clone, Copy, Debug, Default)]
struct Pointer {
    position: Option<(f64, f64)>,
    dragging: Option<MouseButton>,
    shift: bool,
}

/// What the view shows besides the bodies.
#[derive(Clone, Copy, Debug)]
struct Toggles {
    trails: bool,
    ghosts: bool,
    panel: bool,
}

struct App {
    options: WindowOptions,
    session: Session,
    panel: PanelState,
    stats: FrameStats,
    camera: OrbitCamera,
    needs_framing: bool,
    toggles: Toggles,
    pointer: Pointer,
    source: Box<dyn FrameSource>,
    watch: Option<SceneWatch>,
    window: Option<Arc<Window>>,
    gfx: Option<WindowGpu>,
    egui: egui::Context,
    egui_state: Option<egui_winit::State>,
    viewport: Viewport,
    screenshot: Option<PathBuf>,
    last_frame: Instant,
    quit: bool,
    outcome: Result<(), AppError>,
}

impl App {
    fn new(scene: Scene, path: &Path, options: WindowOptions) -> App {
        let mut session = Session::new(scene, path, options.compare.clone());
        session.set_paused(options.paused);
        session.set_time_scale(options.time_scale);
        let panel = PanelState::new(&session, options.scenes.clone());
        let source: Box<dyn FrameSource> = match options.frame_rate {
            Some(hz) => Box::new(VirtualClock::display(hz)),
            None => Box::new(RealClock::new()),
        };
        let mut app = App {
            camera: OrbitCamera::framing(session.bounds(), 16.0 / 9.0),
            session,
            panel,
            stats: FrameStats::default(),
            needs_framing: true,
            toggles: Toggles {
                trails: true,
                ghosts: true,
                panel: true,
            },
            pointer: Pointer::default(),
            source,
            watch: None,
            window: None,
            gfx: None,
            egui: egui::Context::default(),
            egui_state: None,
            viewport: Viewport::full(1, 1),
            screenshot: None,
            last_frame: Instant::now(),
            quit: false,
            outcome: Ok(()),
            options,
        };
        app.rewatch();
        app
    }

    /// Watches the session's scene file (if watching is on); failure is a note, not an error.
    fn rewatch(&mut self) {
        if !self.options.watch {
            return;
        }
        match SceneWatch::new(self.session.path()) {
            Ok(w) => {
                self.panel.file_note = Some(("watching for changes".into(), true));
                self.watch = Some(w);
            }
            Err(e) => {
                self.panel.file_note = Some((format!("hot reload off: {e}"), false));
                self.watch = None;
            }
        }
    }

    /// Loads `path` and restarts on it; a bad file leaves the running scene and shows why.
    fn load_scene(&mut self, path: &Path, reload: bool) {
        match crate::scene::load(path) {
            Ok(scene) => {
                self.session.restart(Some((scene, path.to_path_buf())));
                self.panel.sync(&self.session);
                if reload {
                    let at = self.session.world().tick();
                    self.panel.file_note = Some((format!("reloaded (tick {at})"), true));
                } else {
                    self.rewatch();
                    self.needs_framing = true;
                }
                if let Some(w) = &self.window {
                    w.set_title(&format!("Volley: {}", self.session.scene().name));
                }
            }
            Err(e) => self.panel.file_note = Some((e.to_string(), false)),
        }
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<(), AppError> {
        let window = match &self.window {
            Some(w) => w.clone(),
            None => {
                let (w, h) = self.options.size;
                let attributes = Window::default_attributes()
                    .with_title(format!("Volley: {}", self.session.scene().name))
                    .with_inner_size(winit::dpi::LogicalSize::new(w, h));
                let window = event_loop
                    .create_window(attributes)
                    .map_err(|e| AppError::NoDisplay(e.to_string()))?;
                Arc::new(window)
            }
        };
        let gfx = WindowGpu::new(event_loop, window.clone()).map_err(AppError::Gpu)?;
        self.stats.adapter = gfx.gpu.describe();
        let max_texture = gfx.gpu.device.limits().max_texture_dimension_2d as usize;
        self.egui_state = Some(egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_texture),
        ));
        self.gfx = Some(gfx);
        self.window = Some(window);
        Ok(())
    }

    fn apply(&mut self, action: Action) {
        let s = &mut self.session;
        match action {
            Action::TogglePause => s.set_paused(!s.is_paused()),
            Action::Step => s.single_step(),
            Action::SetTimeScale(x) => s.set_time_scale(x),
            Action::ScaleTime(f) => s.set_time_scale((s.time_scale() * f).clamp(1e-3, 100.0)),
            Action::SetDt(dt) => self.set_dt(dt),
            Action::ScaleDt(f) => {
                let dt = s.scene().dt() * f;
                self.set_dt(dt);
            }
            Action::SetIntegrator(i) => s.push(Command::SetIntegrator(i)),
            Action::Launch {
                speed,
                elevation_deg,
                azimuth_deg,
            } => s.push(Command::SetLaunch {
                speed,
                elevation_deg,
                azimuth_deg,
                position: None,
            }),
            Action::NudgeLaunch(ds, de, da) => {
                let p = &mut self.panel;
                p.speed = (p.speed + ds).max(0.0);
                p.elevation_deg = (p.elevation_deg + de).clamp(-90.0, 90.0);
                p.azimuth_deg += da;
                s.push(Command::SetLaunch {
                    speed: Some(p.speed),
                    elevation_deg: Some(p.elevation_deg),
                    azimuth_deg: Some(p.azimuth_deg),
                    position: None,
                });
            }
            Action::Fire => s.push(Command::Fire),
            Action::Reset => s.reset(),
            Action::PickScene(path) => self.load_scene(&path, false),
            Action::SetCompare(list) => s.set_compare(list),
            Action::ToggleCompare => {
                let list = if s.is_comparing() {
                    Vec::new()
                } else {
                    self.panel.compare_pick.clone()
                };
                s.set_compare(list);
            }
            Action::ToggleTrails => self.toggles.trails = !self.toggles.trails,
            Action::ToggleGhosts => self.toggles.ghosts = !self.toggles.ghosts,
            Action::TogglePanel => self.toggles.panel = !self.toggles.panel,
            Action::FrameScene => self.needs_framing = true,
            Action::Screenshot => {
                let tick = s.world().tick();
                self.screenshot = Some(PathBuf::from(format!("volley-tick{tick}.png")));
            }
            Action::Quit => self.quit = true,
        }
    }

    fn set_dt(&mut self, dt: f64) {
        match self.session.set_dt(dt) {
            Ok(()) => self.panel.sync(&self.session),
            Err(e) => self.session.last_error = Some(format!("dt: {e}")),
        }
    }

    fn on_pointer(&mut self, event: &WindowEvent, over_ui: bool) {
        match *event {
            WindowEvent::ModifiersChanged(m) => self.pointer.shift = m.state().shift_key(),
            WindowEvent::MouseInput { state, button, .. } => {
                self.pointer.dragging = match state {
                    ElementState::Pressed if !over_ui => Some(button),
                    _ => None,
                };
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (Some(button), Some(last)) = (self.pointer.dragging, self.pointer.position) {
                    let (dx, dy) = (now.0 - last.0, now.1 - last.1);
                    let orbit = button == MouseButton::Left && !self.pointer.shift;
                    if orbit {
                        self.camera.orbit(dx, dy);
                    } else {
                        let h = f64::from(self.viewport.height.max(1.0));
                        self.camera.pan(dx, dy, h);
                    }
                }
                self.pointer.position = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } if !over_ui => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.camera.zoom(steps);
            }
            _ => {}
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

    fn redraw(&mut self) {
        let start = Instant::now();
        let delta = self.source.next_delta();
        self.check_reload(start);
        self.session.frame(delta);
        if self.session.lanes().iter().all(|l| l.pending() == 0) {
            let (dt_ms, pick) = (self.panel.dt_ms, self.panel.compare_pick.clone());
            self.panel.sync(&self.session);
            // The dt field keeps what is being typed until it is applied.
            self.panel.dt_ms = dt_ms;
            self.panel.compare_pick = pick;
        }
        let (Some(window), Some(egui_state)) = (self.window.clone(), self.egui_state.as_mut())
        else {
            return;
        };
        let raw = egui_state.take_egui_input(&window);
        let mut actions = Vec::new();
        let mut rest = egui::Rect::NOTHING;
        let show_panel = self.toggles.panel;
        let output = self.egui.run_ui(raw, |ui| {
            if show_panel {
                egui::Panel::left("panel")
                    .default_size(340.0)
                    .show(ui, |ui| {
                        panel::show(
                            ui,
                            &mut self.panel,
                            &self.session,
                            &self.stats,
                            &mut actions,
                        )
                    });
            }
            rest = ui.available_rect_before_wrap();
        });
        egui_state.handle_platform_output(&window, output.platform_output);
        for action in actions {
            self.apply(action);
        }
        let ppp = output.pixels_per_point;
        let primitives = self.egui.tessellate(output.shapes, ppp);
        let mut textures = output.textures_delta;
        if let Some(gfx) = self.gfx.as_mut() {
            for (id, deltas) in textures.set.drain() {
                for delta in &deltas {
                    gfx.egui
                        .update_texture(&gfx.gpu.device, &gfx.gpu.queue, id, delta);
                }
            }
            self.viewport = viewport_of(rest, ppp, gfx.size());
        }
        if self.needs_framing && self.viewport.is_visible() {
            let aspect = f64::from(self.viewport.aspect());
            self.camera = OrbitCamera::framing(self.session.bounds(), aspect);
            self.needs_framing = false;
        }
        self.present(&primitives, ppp);
        if let Some(gfx) = self.gfx.as_mut() {
            for id in textures.free.drain() {
                gfx.egui.free_texture(&id);
            }
        }
        // Without a device the deltas have nowhere to go; egui rebuilds them on demand.
        textures.clear();
        self.update_stats(start, &window);
    }

    /// Draws the frame into the next surface texture and presents it (skipped while the
    /// surface has nothing to give: minimised, occluded, rebuilt).
    fn present(&mut self, primitives: &[egui::ClippedPrimitive], ppp: f32) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let size = gfx.size();
        let Some(frame) = gfx.acquire() else {
            return;
        };
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: ppp,
        };
        let ui = FrameUi {
            primitives,
            screen: &screen,
        };
        let target = frame.texture.create_view(&Default::default());
        self.draw(&target, &ui);
        if let Some(gfx) = self.gfx.as_mut() {
            gfx.gpu.queue.present(frame);
            gfx.refresh();
        }
        self.stats.frames += 1;
        self.after_present(&ui);
    }

    /// Draws the scene and the panel into `target` (the surface, or a capture of it).
    fn draw(&mut self, target: &wgpu::TextureView, ui: &FrameUi<'_>) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let lanes = self.session.draw_lanes();
        let bounds = self.session.bounds();
        let options = DrawOptions {
            origin: bounds.center(),
            scale: bounds.radius(),
            trails: self.toggles.trails,
            ghosts: self.toggles.ghosts,
        };
        let view = View {
            camera: self.camera,
            viewport: self.viewport,
            target_size: gfx.size(),
        };
        gfx.renderer.prepare(&gfx.gpu, &lanes, &view, &options);
        let device = &gfx.gpu.device;
        let mut encoder = device.create_command_encoder(&Default::default());
        gfx.renderer.encode(&mut encoder, target);
        let extra = gfx.egui.update_buffers(
            device,
            &gfx.gpu.queue,
            &mut encoder,
            ui.primitives,
            ui.screen,
        );
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("panel"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui
                .render(&mut pass.forget_lifetime(), ui.primitives, ui.screen);
        }
        gfx.gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
    }

    /// Screenshots and the frame limit, after a frame was presented.
    fn after_present(&mut self, ui: &FrameUi<'_>) {
        let done = self
            .options
            .exit_after_frames
            .is_some_and(|n| self.stats.frames >= n);
        let path = match (self.screenshot.take(), done) {
            (Some(p), _) => Some(p),
            (None, true) => self.options.screenshot.clone(),
            (None, false) => None,
        };
        if let Some(path) = path
            && let Err(e) = self.capture(&path, ui)
        {
            self.outcome = Err(AppError::Io(e));
            self.quit = true;
        }
        if done {
            self.quit = true;
        }
    }

    /// Draws the frame again into an offscreen texture of the surface's size and format, through
    /// the same [`App::draw`], and writes it as a PNG.
    fn capture(&mut self, path: &Path, ui: &FrameUi<'_>) -> Result<(), String> {
        let Some(gfx) = self.gfx.as_ref() else {
            return Ok(());
        };
        let target = OffscreenTarget::new(&gfx.gpu, gfx.size(), gfx.format());
        self.draw(target.view(), ui);
        let Some(gfx) = self.gfx.as_ref() else {
            return Ok(());
        };
        let image: Image = target.read(&gfx.gpu).map_err(|e| e.to_string())?;
        image.save_png(path).map_err(|e| e.to_string())
    }

    fn update_stats(&mut self, start: Instant, window: &Window) {
        let blend = |old: f64, new: f64| {
            if old == 0.0 {
                new
            } else {
                old + SMOOTHING * (new - old)
            }
        };
        let interval = start.duration_since(self.last_frame).as_secs_f64() * 1e3;
        self.stats.interval_ms = blend(self.stats.interval_ms, interval);
        self.stats.work_ms = blend(self.stats.work_ms, start.elapsed().as_secs_f64() * 1e3);
        let size = window.inner_size();
        self.stats.size = (size.width, size.height);
        self.stats.scale = window.scale_factor();
        self.last_frame = start;
    }

    fn visible(&self) -> bool {
        self.gfx.as_ref().is_some_and(WindowGpu::is_drawable)
    }
}

/// The panel's share of a frame, for drawing it (again, for a capture).
struct FrameUi<'a> {
    primitives: &'a [egui::ClippedPrimitive],
    screen: &'a egui_wgpu::ScreenDescriptor,
}

/// The 3D viewport in physical pixels: egui's remaining rectangle (points) times the scale,
/// clamped to the surface.
fn viewport_of(rest: egui::Rect, ppp: f32, size: (u32, u32)) -> Viewport {
    let (w, h) = (size.0 as f32, size.1 as f32);
    if !rest.is_positive() {
        return Viewport::full(size.0, size.1);
    }
    let x = (rest.min.x * ppp).clamp(0.0, w).round();
    let y = (rest.min.y * ppp).clamp(0.0, h).round();
    Viewport {
        x,
        y,
        width: ((rest.max.x * ppp).clamp(0.0, w).round() - x).max(0.0),
        height: ((rest.max.y * ppp).clamp(0.0, h).round() - y).max(0.0),
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        if let Err(e) = self.open(event_loop) {
            self.outcome = Err(e);
            event_loop.exit();
        }
    }

    fn suspended(&mut self, _event_loop: &ActiveEventLoop) {
        // The surface may not outlive a suspension (Android); it is rebuilt on `resumed`.
        self.gfx = None;
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let (Some(window), Some(egui_state)) = (self.window.clone(), self.egui_state.as_mut())
        else {
            return;
        };
        let consumed = egui_state.on_window_event(&window, &event).consumed;
        match &event {
            WindowEvent::CloseRequested => self.quit = true,
            WindowEvent::Resized(size) => {
                if let Some(gfx) = self.gfx.as_mut() {
                    gfx.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested => self.redraw(),
            WindowEvent::KeyboardInput { event, .. }
                if event.state.is_pressed()
                    && !consumed
                    && !self.egui.egui_wants_keyboard_input() =>
            {
                if let Some(action) = input::action_for_key(&event.logical_key) {
                    self.apply(action);
                }
            }
            _ => self.on_pointer(&event, consumed || self.egui.is_pointer_over_egui()),
        }
        if self.quit {
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.quit {
            event_loop.exit();
            return;
        }
        let Some(window) = &self.window else {
            return;
        };
        if !self.visible() {
            // Minimised: nothing to draw; the next resize event wakes the loop.
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        let due = self.last_frame + Duration::from_secs_f64(1.0 / MAX_FPS);
        if Instant::now() >= due {
            event_loop.set_control_flow(ControlFlow::Poll);
            window.request_redraw();
        } else {
            event_loop.set_control_flow(ControlFlow::WaitUntil(due));
        }
    }
}
