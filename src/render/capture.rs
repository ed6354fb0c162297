//! Offscreen capture: a texture to draw into, its pixels read back, PNG files in and out.

use std::path::Path;

use crate::render::gpu::Gpu;

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
        self.encode_png(std::io::BufWriter::new(file))
            .map_err(|e| fail(&e))
    }

    /// The image as an RGBA PNG file's bytes (the browser build offers them as a download).
    pub fn png_bytes(&self) -> Result<Vec<u8>, CaptureError> {
        let mut bytes = Vec::new();
        self.encode_png(&mut bytes)
            .map_err(|e| CaptureError(format!("encoding the PNG: {e}")))?;
        Ok(bytes)
    }

    fn encode_png(&self, out: impl std::io::Write) -> Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.rgba)?;
        writer.finish()
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

    /// Copies the pixels back to the CPU (blocking until the GPU is done), as RGBA; refused in
    /// a page, which cannot block ([`crate::platform::CAN_BLOCK`]).
    pub fn read(&self, gpu: &Gpu) -> Result<Image, CaptureError> {
        if !crate::platform::CAN_BLOCK {
            return Err(CaptureError(
                "reading the frame back: a page cannot block on the GPU".into(),
            ));
        }
        let (buffer, row) = self.copy_back(gpu);
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        gpu.wait();
        rx.recv()
            .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?
            .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?;
        self.image_from(&buffer, row)
    }

    /// Copies the texture into a mappable buffer; its rows are `row` bytes apart.
    fn copy_back(&self, gpu: &Gpu) -> (wgpu::Buffer, u32) {
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
        (buffer, row)
    }

    fn image_from(&self, buffer: &wgpu::Buffer, row: u32) -> Result<Image, CaptureError> {
        image_of(buffer, row, self.size, self.texture.format())
    }
}

/// The RGBA image in a mapped readback `buffer` of a texture of `size` and `format`.
fn image_of(
    buffer: &wgpu::Buffer,
    row: u32,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
) -> Result<Image, CaptureError> {
    let mapped = buffer
        .get_mapped_range(..)
        .map_err(|e| CaptureError(format!("reading the frame back: {e}")))?;
    let bgra = matches!(
        format,
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
