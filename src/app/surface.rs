//! The window's GPU side: device, surface and its configuration, the scene renderer and egui's.
//!
//! The surface is configured at the window's physical size (HiDPI included) and not at all while
//! the window is minimised to 0 x 0.
//!
//! Two views of one surface texture where the adapter allows it: the 3D view draws into an sRGB
//! view (its shaders work in linear colour), egui into the plain 8-bit one, because egui blends
//! in gamma space (egui-wgpu warns on an sRGB target and prefers `Bgra8Unorm`). On the software
//! adapter that also spares every panel pixel the sRGB conversions (docs/performance.md, "The
//! window on a software adapter"). An adapter without surface view formats gets one sRGB
//! surface for both, as before.
//!
//! A lost surface is recreated, an outdated one reconfigured, a timed-out or occluded frame
//! skipped: none of them ends the program.

use std::sync::Arc;

use winit::event_loop::OwnedDisplayHandle;
use winit::window::Window;

use crate::platform;
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
    /// The format the 3D view draws in: the sRGB twin of the surface's format, or that format.
    scene_format: wgpu::TextureFormat,
    configured: bool,
    window: Arc<Window>,
}

impl WindowGpu {
    /// Opens a device that can present to `window` and configures its surface. The GPU's
    /// answers are futures: the desktop blocks on this one, a page spawns it
    /// ([`platform::complete`]); in a browser the instance is WebGPU where the browser has it,
    /// WebGL2 otherwise ([`platform::gpu_instance`]).
    pub async fn open(
        display: OwnedDisplayHandle,
        window: Arc<Window>,
    ) -> Result<WindowGpu, GpuError> {
        let descriptor =
            wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(display));
        let instance = platform::gpu_instance(descriptor).await;
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| GpuError::Surface(e.to_string()))?;
        let gpu = Gpu::open_async(instance, Some(&surface)).await?;
        WindowGpu::on(gpu, surface, window)
    }

    /// The surface configured and the renderers made, on an open device.
    fn on(
        gpu: Gpu,
        surface: wgpu::Surface<'static>,
        window: Arc<Window>,
    ) -> Result<WindowGpu, GpuError> {
        let caps = surface.get_capabilities(&gpu.adapter);
        let (format, scene_format) = pick_formats(&caps.formats, gpu.surface_view_formats())
            .ok_or_else(|| GpuError::Surface("the surface supports no format".into()))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            // Opaque where offered: the frame's alpha is not coverage (a browser composites a
            // premultiplied canvas over the page, and its colours with alpha 0 add up to white).
            alpha_mode: if caps.alpha_modes.contains(&wgpu::CompositeAlphaMode::Opaque) {
                wgpu::CompositeAlphaMode::Opaque
            } else {
                caps.alpha_modes
                    .first()
                    .copied()
                    .unwrap_or(wgpu::CompositeAlphaMode::Auto)
            },
            view_formats: crate::render::capture::view_formats(format, scene_format),
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        let renderer = Renderer::new(&gpu, scene_format);
        let egui = egui_wgpu::Renderer::new(&gpu.device, format, ui_options());
        let mut this = WindowGpu {
            gpu,
            renderer,
            egui,
            surface,
            config,
            scene_format,
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

    /// The surface's colour format, which egui draws in.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// The format the 3D view draws in: an sRGB view of the surface's texture, or its own format.
    pub fn scene_format(&self) -> wgpu::TextureFormat {
        self.scene_format
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

/// egui's renderer options: no dithering. Dithering hides banding in smooth gradients, which
/// Volley's panel does not draw (flat fills, text, lines), and costs the software adapter a
/// per-pixel noise function on every panel pixel.
pub fn ui_options() -> egui_wgpu::RendererOptions {
    egui_wgpu::RendererOptions {
        dithering: false,
        ..Default::default()
    }
}

/// The surface's format and the 3D view's: an 8-bit format without sRGB encoding for the
/// surface (egui's) and its sRGB twin for the scene, when the adapter can view a surface in
/// another format and the surface offers such a pair; otherwise an sRGB format (or the first)
/// for both. `None` when the surface offers no format.
pub fn pick_formats(
    formats: &[wgpu::TextureFormat],
    view_formats: bool,
) -> Option<(wgpu::TextureFormat, wgpu::TextureFormat)> {
    let pair = formats
        .iter()
        .copied()
        .find(|f| !f.is_srgb() && f.add_srgb_suffix() != *f);
    match pair {
        Some(f) if view_formats => Some((f, f.add_srgb_suffix())),
        _ => {
            let f = formats
                .iter()
                .copied()
                .find(wgpu::TextureFormat::is_srgb)
                .or(formats.first().copied())?;
            Some((f, f))
        }
    }
}
