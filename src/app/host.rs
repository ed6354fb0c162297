//! What the window runs on: the winit window, its GPU surface and renderer, and egui.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::surface::WindowGpu;
use crate::platform;
use crate::render::GpuError;

/// The window and what draws into it. The window is made on the first `resumed` and kept; the
/// GPU side is dropped on a suspension and made again on the next `resumed`.
pub(super) struct Host {
    /// The window, once opened.
    pub(super) window: Option<Arc<Window>>,
    /// Device, surface and renderers, while the window has a surface.
    pub(super) gfx: Option<WindowGpu>,
    /// egui's context (a new one for each new device).
    pub(super) egui: egui::Context,
    /// egui's link to the window's events, once opened.
    pub(super) egui_state: Option<egui_winit::State>,
    /// The device opened for the window (or why not), until the App takes it
    /// ([`Host::take_opened`]): at once on the desktop, later in a browser.
    opened: Rc<RefCell<Option<Result<WindowGpu, GpuError>>>>,
}

impl Host {
    /// Nothing opened yet.
    pub(super) fn new() -> Host {
        Host {
            window: None,
            gfx: None,
            egui: egui::Context::default(),
            egui_state: None,
            opened: Default::default(),
        }
    }

    /// Opens a device for `window`; [`Host::take_opened`] has it (or why not) once the GPU has
    /// answered: before this returns on the desktop, which blocks on it; later in a browser
    /// (WebGPU, or WebGL2 where it has none), which then asks the window to redraw so the loop
    /// wakes for it.
    pub(super) fn open(&mut self, event_loop: &ActiveEventLoop, window: Arc<Window>) {
        let slot = self.opened.clone();
        let display = event_loop.owned_display_handle();
        self.window = Some(window.clone());
        let opening = WindowGpu::open(display, window.clone());
        platform::complete(opening, move |gfx| {
            *slot.borrow_mut() = Some(gfx);
            window.request_redraw();
        });
    }

    /// The device opened (or why it could not), once, when the GPU has answered.
    pub(super) fn take_opened(&mut self) -> Option<Result<WindowGpu, GpuError>> {
        self.opened.borrow_mut().take()
    }

    /// Takes `window` and the GPU made for it, with egui's state for them.
    pub(super) fn attach(&mut self, window: Arc<Window>, gfx: WindowGpu) {
        if self.egui_state.is_some() {
            // A new device after a suspension: a new context, so egui sends its font atlas to
            // the new renderer (it never sends a texture twice).
            self.egui = egui::Context::default();
        }
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
    }

    /// Sets the window's title, if it is open.
    pub(super) fn retitle(&self, title: &str) {
        if let Some(w) = &self.window {
            w.set_title(title);
        }
    }

    /// Whether there is a surface to draw on (not minimised, not suspended).
    pub(super) fn visible(&self) -> bool {
        self.gfx.as_ref().is_some_and(WindowGpu::is_drawable)
    }
}
