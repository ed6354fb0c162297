//! The window's GPU side: device, surface and its configuration, the scene renderer and egui's.
//!
//! The surface is configured at the window's physical size (HiDPI included) and not at all while
//! the window is minimised to 0 x 0. A lost surface is recreated, an outdated one reconfigured,
//! a timed-out or occluded frame skipped: none of them ends the program.

use std::sync::Arc;

use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use crate::render::{Gpu, GpuError, Renderer};

/// Everything the window draws with.
pub struct WindowGpu {
    /// The device.
    pub gpu: Gpu,
    /// The scene renderer (the same one the offscreen capture uses).
    pub renderer: Renderer,
    /// egui's renderer.
    pub egui: egui_wgpu::Renderer,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    configured: bool,
    window: Arc<Window>,
}

impl WindowGpu {
    /// Opens a device that can present to `window` and configures its surface.
    pub fn new(event_loop: &ActiveEventLoop, window: Arc<Window>) -> Result<WindowGpu, GpuError> {
        let display = Box::new(event_loop.owned_display_handle());
        let descriptor = wgpu::InstanceDescriptor::new_with_display_handle_from_env(display);
        let instance = wgpu::Instance::new(descriptor);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| GpuError::Surface(e.to_string()))?;
        let gpu = Gpu::open(instance, Some(&surface))?;
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or(caps.formats.first().copied())
            .ok_or_else(|| GpuError::Surface("the surface supports no format".into()))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        let renderer = Renderer::new(&gpu, format);
        let egui = egui_wgpu::Renderer::new(&gpu.device, format, Default::default());
        let mut this = WindowGpu {
            gpu,
            renderer,
            egui,
            surface,
            config,
            configured: false,
            window,
        };
        this.resize(size.width, size.height);
        Ok(this)
    }

    /// Follows a new window size (physical px); 0 x 0 (minimised) leaves the surface alone.
    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.configured = false;
            return;
        }
        // A window larger than the device's largest texture draws at that size, stretched.
        let max = self.gpu.device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        self.surface.configure(&self.gpu.device, &self.config);
        self.configured = true;
    }

    /// Size of the surface (physical px).
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// The surface's colour format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// Whether there is anything to draw into (not minimised).
    pub fn is_drawable(&self) -> bool {
        self.configured
    }

    /// The next surface texture, or `None` when this frame should be skipped (minimised,
    /// occluded, timed out, or the surface had to be rebuilt).
    pub fn acquire(&mut self) -> Option<wgpu::SurfaceTexture> {
        if !self.configured {
            return None;
        }
        use wgpu::CurrentSurfaceTexture as C;
        match self.surface.get_current_texture() {
            C::Success(frame) => Some(frame),
            C::Suboptimal(frame) => {
                // Draw this one; the next frame gets a surface that matches again.
                self.configured = false;
                Some(frame)
            }
            C::Outdated => {
                let s = self.window.inner_size();
                self.resize(s.width, s.height);
                None
            }
            C::Lost => {
                self.rebuild_surface();
                None
            }
            C::Timeout | C::Occluded | C::Validation => None,
        }
    }

    /// A lost surface: a new one for the same window (the old one is dropped before the new
    /// one is configured), at the window's current size.
    pub fn rebuild_surface(&mut self) {
        if let Ok(surface) = self.gpu.instance.create_surface(self.window.clone()) {
            self.surface = surface;
        }
        let s = self.window.inner_size();
        self.resize(s.width, s.height);
    }

    /// After presenting a suboptimal frame: reconfigure at the window's current size.
    pub fn refresh(&mut self) {
        if !self.configured {
            let s = self.window.inner_size();
            self.resize(s.width, s.height);
        }
    }
}
