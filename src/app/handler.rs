//! winit's calls into the window: opened (the window, its device and egui) on `resumed`,
//! dropped on `suspended`, events turned into actions, and frames paced in `about_to_wait`.

use std::sync::Arc;
use std::time::Duration;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::display::{self, Frames};
use super::{App, AppError, MAX_FPS, input};
use crate::platform::{self, Instant};

impl App {
    /// Opens the window (once) and starts opening its device ([`App::adopt_gpu`] takes it).
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<(), AppError> {
        let window = match &self.host.window {
            Some(w) => w.clone(),
            None => {
                let (w, h) = self.options.size;
                let attributes = Window::default_attributes()
                    .with_title(self.title())
                    .with_inner_size(winit::dpi::LogicalSize::new(w, h));
                let window = event_loop
                    .create_window(platform::on_page(attributes))
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
        self.host.open(event_loop, window);
        Ok(())
    }

    /// Takes the device once the GPU has opened it (at once on the desktop, later in a
    /// browser), or ends on why it could not.
    fn adopt_gpu(&mut self, event_loop: &ActiveEventLoop) {
        let Some(opened) = self.host.take_opened() else {
            return;
        };
        match (opened, self.host.window.clone()) {
            (Ok(gfx), Some(window)) => {
                platform::report_gpu_errors(&gfx.gpu.device);
                self.timing.stats.adapter = match gfx.renderer.trails_missing() {
                    Some(why) => format!("{}; {why}", gfx.gpu.describe()),
                    None => gfx.gpu.describe(),
                };
                self.host.attach(window, gfx);
                let adapter = self.timing.stats.adapter.clone();
                platform::show_on_page(|| vec![("adapter", adapter)]);
            }
            (Err(e), _) => {
                let e = AppError::Gpu(e);
                platform::show_error(&e.to_string());
                self.ending = Some(Err(e));
                event_loop.exit();
            }
            (Ok(_), None) => {}
        }
    }
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
        // The desktop's device is open already; a page's comes later.
        self.adopt_gpu(event_loop);
        if self.ending.is_some() {
            return;
        }
        // `--record FILE`: from tick 0, once there is a window to run in.
        if let Some(path) = self.options.record.take()
            && let Err(e) = self.session.start_recording(Some(path))
        {
            self.ending = Some(Err(AppError::Recording(e)));
            event_loop.exit();
        }
    }

    fn suspended(&mut self, _event_loop: &ActiveEventLoop) {
        // The surface may not outlive a suspension (Android); it is rebuilt on `resumed`.
        self.host.gfx = None;
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        self.adopt_gpu(event_loop);
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
        self.adopt_gpu(event_loop);
        self.open_picked();
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
