//! winit's calls into the window: opened (the window, its device and egui) on `resumed`,
//! dropped on `suspended`, events turned into actions, and frames paced in `about_to_wait`.

use std::sync::Arc;
use std::time::Duration;

use web_time::Instant;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::display::{self, Frames};
#[cfg(not(target_arch = "wasm32"))]
use super::surface::WindowGpu;
#[cfg(target_arch = "wasm32")]
use super::web;
use super::{App, AppError, MAX_FPS, input};
#[cfg(target_arch = "wasm32")]
use crate::render::GpuError;

impl App {
    /// Opens the window (once) and its device.
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
            self.ending = Some(Err(AppError::Recording(e)));
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
