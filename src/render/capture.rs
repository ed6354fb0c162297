//! Offscreen capture: a texture to draw into, its pixels read back, PNG files in and out, and
//! the [`FrameWriter`] that `volley headless --frames` runs as a tick observer.

use std::path::{Path, PathBuf};

use crate::render::bounds::SceneBounds;
use crate::render::camera::{OrbitCamera, Viewport};
use crate::render::draw::{DrawOptions, Lane, integrator_colour};
use crate::render::gpu::Gpu;
use crate::render::history::TickHistory;
use crate::render::renderer::{Renderer, View};
use crate::sim_loop::{ObserverError, TickObserver};
use crate::world::World;

/// Colour format of offscreen targets: sRGB, so the bytes read back are what a PNG stores.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Why a capture failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaptureError(pub String);

impl std::fmt::Display for CaptureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CaptureError {}

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    /// `width * height * 4` bytes, sRGB-encoded.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Writes the image as an RGBA PNG.
    pub fn save_png(&self, path: &Path) -> Result<(), CaptureError> {
        let fail = |e: &dyn std::fmt::Display| CaptureError(format!("{}: {e}", path.display()));
        let file = std::fs::File::create(path).map_err(|e| fail(&e))?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().map_err(|e| fail(&e))?;
        writer.write_image_data(&self.rgba).map_err(|e| fail(&e))?;
        writer.finish().map_err(|e| fail(&e))
    }

    /// Reads an 8-bit RGBA or RGB PNG.
    pub fn load_png(path: &Path) -> Result<Image, CaptureError> {
        let fail = |e: &dyn std::fmt::Display| CaptureError(format!("{}: {e}", path.display()));
        let file = std::fs::File::open(path).map_err(|e| fail(&e))?;
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .map_err(|e| fail(&e))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| fail(&"image too large"))?;
        let mut buf = vec![0; size];
        let info = reader.next_frame(&mut buf).map_err(|e| fail(&e))?;
        let rgba = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgba, png::BitDepth::Eight) => buf[..info.buffer_size()].to_vec(),
            (png::ColorType::Rgb, png::BitDepth::Eight) => buf[..info.buffer_size()]
                .chunks_exact(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect(),
            other => return Err(fail(&format!("expected 8-bit RGB(A), got {other:?}"))),
        };
        Ok(Image {
            width: info.width,
            height: info.height,
            rgba,
        })
    }
}

/// The view formats a texture of `format` is made with so the 3D view can draw into it in
/// `scene_format` (its sRGB twin): none when the two are the same.
pub fn view_formats(
    format: wgpu::TextureFormat,
    scene_format: wgpu::TextureFormat,
) -> Vec<wgpu::TextureFormat> {
    if scene_format == format {
        Vec::new()
    } else {
        vec![scene_format]
    }
}

/// A view of `texture` in `format` where that differs from the texture's own (its sRGB twin,
/// which the texture must list among its [`view_formats`]); `None` where the texture's own
/// view serves. The window's surface and the offscreen capture make the 3D view's target so.
pub fn view_in(texture: &wgpu::Texture, format: wgpu::TextureFormat) -> Option<wgpu::TextureView> {
    (format != texture.format()).then(|| {
        texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(format),
            ..Default::default()
        })
    })
}

/// A texture to render into and read back.
#[derive(Debug)]
pub struct OffscreenTarget {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// A view in the scene's format when it differs from the texture's (see [`Self::with_views`]).
    scene_view: Option<wgpu::TextureView>,
    size: (u32, u32),
}

impl OffscreenTarget {
    /// A `width` x `height` target of `format` (each side at least 1).
    pub fn new(gpu: &Gpu, size: (u32, u32), format: wgpu::TextureFormat) -> OffscreenTarget {
        OffscreenTarget::with_views(gpu, size, format, format)
    }

    /// A target laid out as the window's surface is: a texture of `format` that the panel draws
    /// into, and a view of it in `scene_format` (its sRGB twin, or the same format) for the 3D
    /// view.
    pub fn with_views(
        gpu: &Gpu,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        scene_format: wgpu::TextureFormat,
    ) -> OffscreenTarget {
        let size = (size.0.max(1), size.1.max(1));
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &view_formats(format, scene_format),
        });
        let view = texture.create_view(&Default::default());
        let scene_view = view_in(&texture, scene_format);
        OffscreenTarget {
            texture,
            view,
            scene_view,
            size,
        }
    }

    /// The view to draw into.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// The view the 3D view draws into: the scene-format view, or [`Self::view`].
    pub fn scene_view(&self) -> &wgpu::TextureView {
        self.scene_view.as_ref().unwrap_or(&self.view)
    }

    /// Width and height (px).
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Copies the pixels back to the CPU (blocking until the GPU is done), as RGBA.
    pub fn read(&self, gpu: &Gpu) -> Result<Image, CaptureError> {
        let (w, h) = self.size;
        let row = (w * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(row) * u64::from(h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            self.texture.size(),
        );
        gpu.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        gpu.wait();
        rx.recv()
            .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?
            .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?;
        let mapped = buffer
            .get_mapped_range(..)
            .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?;
        let bgra = matches!(
            self.texture.format(),
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let mut rgba = Vec::with_capacity((w * h * 4) as usize);
        for y in 0..h as usize {
            let line = &mapped[y * row as usize..y * row as usize + (w * 4) as usize];
            for px in line.chunks_exact(4) {
                if bgra {
                    rgba.extend_from_slice(&[px[2], px[1], px[0], px[3]]);
                } else {
                    rgba.extend_from_slice(px);
                }
            }
        }
        Ok(Image {
            width: w,
            height: h,
            rgba,
        })
    }
}

/// Writes a PNG of the world every `every` ticks while a headless run steps it: a tick
/// observer around the same renderer the window uses, at alpha 1 (each file shows its tick).
pub struct FrameWriter {
    gpu: Gpu,
    renderer: Renderer,
    target: OffscreenTarget,
    history: TickHistory,
    camera: OrbitCamera,
    options: DrawOptions,
    dir: PathBuf,
    every: u64,
    written: u64,
}

impl FrameWriter {
    /// A writer for `world` (at its current tick) into folder `dir` (created if missing), with
    /// frames of `size` pixels every `every` ticks (at least 1).
    pub fn new(
        gpu: Gpu,
        world: &World,
        dir: &Path,
        size: (u32, u32),
        every: u64,
    ) -> Result<FrameWriter, CaptureError> {
        std::fs::create_dir_all(dir)
            .map_err(|e| CaptureError(format!("{}: cannot create: {e}", dir.display())))?;
        let bounds = SceneBounds::of_scene(world.scene());
        let renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT);
        let target = OffscreenTarget::new(&gpu, size, OFFSCREEN_FORMAT);
        Ok(FrameWriter {
            history: TickHistory::new(world, bounds.center()),
            camera: OrbitCamera::framing(&bounds, f64::from(size.0) / f64::from(size.1.max(1))),
            options: DrawOptions::picture(bounds.center(), bounds.radius()),
            renderer,
            target,
            gpu,
            dir: dir.to_path_buf(),
            every: every.max(1),
            written: 0,
        })
    }

    /// PNG files written so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    /// Renders the world as it is now and writes `tick_NNNNNN.png`.
    pub fn write(&mut self, world: &World) -> Result<(), CaptureError> {
        let size = self.target.size();
        let view = View {
            camera: self.camera,
            viewport: Viewport::full(size.0, size.1),
            target_size: size,
        };
        let lane = Lane {
            world,
            history: &self.history,
            at: crate::render::history::DrawAt::interpolated(1.0),
            colour: integrator_colour(world.integrator()),
            judder: &[],
        };
        self.renderer
            .render(&self.gpu, self.target.view(), &[lane], &view, &self.options);
        let image = self.target.read(&self.gpu)?;
        image.save_png(&self.dir.join(format!("tick_{:06}.png", world.tick())))?;
        self.written += 1;
        Ok(())
    }
}

impl TickObserver for FrameWriter {
    fn on_command(
        &mut self,
        world: &World,
        stamped: &crate::command::Stamped,
    ) -> Result<(), ObserverError> {
        self.history.on_command(world, stamped)
    }

    fn before_last_tick(&mut self, world: &World) {
        self.history.before_last_tick(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.history.after_tick(world)?;
        if world.tick().is_multiple_of(self.every) {
            self.write(world)
                .map_err(|e| ObserverError(e.to_string()))?;
        }
        Ok(())
    }
}
