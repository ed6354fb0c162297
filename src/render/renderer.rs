//! The renderer: draws a frame into any `&wgpu::TextureView`, so the window's surface and an
//! offscreen capture go through the same code.
//!
//! Per frame: [`Renderer::prepare`] builds the [`DrawList`] and uploads it into buffers that are
//! kept and only grow (to the next power of two) when a frame needs more; trails upload only the
//! rows recorded since the last frame; the level's triangles upload only when the scene or the
//! render origin changes ([`crate::render::level`]). [`Renderer::encode`] records one render
//! pass: solid spheres (all bodies of all lanes in one instanced draw), the level, the grid,
//! walls, trails (one instanced draw per lane), lines, translucent spheres.

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, Vec3};

use crate::render::camera::{OrbitCamera, Viewport};
use crate::render::draw::{DrawList, DrawOptions, Lane, Rgba};
use crate::render::gpu::Gpu;
use crate::render::level::{LevelKey, LitVertex, level_vertices};
use crate::render::pipelines::{DEPTH_FORMAT, Pipelines};
use crate::render::trails::{TRAIL_SAMPLES, TrailRing, segments_per_trail};

/// Background colour (linear).
pub const CLEAR: wgpu::Color = wgpu::Color {
    r: 0.012,
    g: 0.015,
    b: 0.022,
    a: 1.0,
};
/// Smallest radius a sphere is drawn with (px).
pub const MIN_SPHERE_PX: f32 = 2.5;

/// Where and how a frame is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The camera.
    pub camera: OrbitCamera,
    /// The part of the target the 3D view fills.
    pub viewport: Viewport,
    /// Size of the whole target (px).
    pub target_size: (u32, u32),
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Globals {
    view: [[f32; 4]; 4],
    proj: [[f32; 4]; 4],
    viewport: [f32; 4],
    light: [f32; 4],
    ground: [f32; 4],
    grid: [f32; 4],
    axes: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct TrailUniform {
    colour: [f32; 4],
    head: u32,
    len: u32,
    stride: u32,
    alpha: f32,
    segments: u32,
    pad: [u32; 3],
}

/// A GPU buffer that is rewritten every frame and reallocated only to grow.
#[derive(Debug)]
struct GrowBuffer {
    buffer: wgpu::Buffer,
    usage: wgpu::BufferUsages,
    label: &'static str,
    len: u32,
}

impl GrowBuffer {
    fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowBuffer {
            buffer: create_buffer(device, label, 256, usage),
            usage,
            label,
            len: 0,
        }
    }

    /// Uploads `items`; returns whether the buffer was reallocated.
    fn write<T: Pod>(&mut self, gpu: &Gpu, items: &[T]) -> bool {
        let bytes: &[u8] = bytemuck::cast_slice(items);
        let grew = bytes.len() as u64 > self.buffer.size();
        if grew {
            let size = (bytes.len() as u64).next_power_of_two();
            self.buffer = create_buffer(&gpu.device, self.label, size, self.usage);
        }
        if !bytes.is_empty() {
            gpu.queue.write_buffer(&self.buffer, 0, bytes);
        }
        self.len = items.len() as u32;
        grew
    }
}

fn create_buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage,
        mapped_at_creation: false,
    })
}

/// The GPU copy of one lane's trail ring.
#[derive(Debug)]
struct TrailBuffers {
    uniform: wgpu::Buffer,
    samples: GrowBuffer,
    counts: GrowBuffer,
    group: wgpu::BindGroup,
    ring_id: u64,
    rows_uploaded: u64,
    stride: usize,
    slots: u32,
}

/// Pipelines, buffers and the depth target of one colour format.
#[derive(Debug)]
pub struct Renderer {
    format: wgpu::TextureFormat,
    pipelines: Pipelines,
    globals: wgpu::Buffer,
    globals_group: wgpu::BindGroup,
    solid: GrowBuffer,
    translucent: GrowBuffer,
    lines: GrowBuffer,
    surfaces: GrowBuffer,
    level: GrowBuffer,
    level_key: Option<LevelKey>,
    level_vertices: Vec<LitVertex>,
    trails: Vec<TrailBuffers>,
    depth: Option<(wgpu::TextureView, (u32, u32))>,
    viewport: Viewport,
    list: DrawList,
    counts: Vec<u32>,
    segments: u32,
    allocations: u64,
}

impl Renderer {
    /// A renderer drawing into colour targets of `format` (an sRGB format shows colours right).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Renderer {
        let device = &gpu.device;
        let pipelines = Pipelines::new(device, format);
        let globals = create_buffer(
            device,
            "globals",
            std::mem::size_of::<Globals>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &pipelines.globals_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let vertex = wgpu::BufferUsages::VERTEX;
        Renderer {
            format,
            solid: GrowBuffer::new(device, "solid spheres", vertex),
            translucent: GrowBuffer::new(device, "translucent spheres", vertex),
            lines: GrowBuffer::new(device, "lines", vertex),
            surfaces: GrowBuffer::new(device, "surfaces", vertex),
            level: GrowBuffer::new(device, "level", vertex),
            level_key: None,
            level_vertices: Vec::new(),
            pipelines,
            globals,
            globals_group,
            trails: Vec::new(),
            depth: None,
            viewport: Viewport::full(1, 1),
            list: DrawList::default(),
            counts: Vec::new(),
            segments: 0,
            allocations: 0,
        }
    }

    /// The colour format this renderer draws into.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// The draw list of the last prepared frame.
    pub fn draw_list(&self) -> &DrawList {
        &self.list
    }

    /// Why this device draws no trails, if it does not (WebGL2).
    pub fn trails_missing(&self) -> Option<&'static str> {
        self.pipelines.trails_missing()
    }

    /// How many times a frame needed a bigger GPU buffer (instances, lines, trails) since the
    /// renderer was made: buffers are kept between frames and only grow, so this stops
    /// changing once the scene stops growing.
    pub fn buffer_allocations(&self) -> u64 {
        self.allocations
    }

    /// Builds and uploads everything the next [`Renderer::encode`] draws.
    pub fn prepare(&mut self, gpu: &Gpu, lanes: &[Lane<'_>], view: &View, options: &DrawOptions) {
        self.list.build(lanes, options);
        let grew = [
            self.solid.write(gpu, &self.list.solid),
            self.translucent.write(gpu, &self.list.translucent),
            self.lines.write(gpu, &self.list.lines),
            self.surfaces.write(gpu, &self.list.surfaces),
        ];
        self.allocations += grew.iter().filter(|g| **g).count() as u64;
        self.prepare_level(gpu, lanes, options);
        let ground = lanes
            .first()
            .and_then(|l| l.world.contacts().ground.map(|g| g.height));
        let globals = globals(view, options, ground);
        gpu.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        self.trails.truncate(lanes.len());
        let slots = |lane: &Lane<'_>| {
            if options.trails {
                lane.history.trails.used() as u32
            } else {
                0
            }
        };
        let total: u32 = lanes.iter().map(slots).sum();
        if self.pipelines.trails.is_none() {
            self.trails.clear();
            self.viewport = view.viewport;
            self.ensure_depth(gpu, view.target_size);
            return;
        }
        self.segments = segments_per_trail(total as usize);
        for (k, lane) in lanes.iter().enumerate() {
            if k == self.trails.len() {
                let t = self.new_trail(gpu);
                self.trails.push(t);
            }
            let alpha = lane.at.trail_alpha(lane.world.dt());
            self.upload_trail(gpu, k, &lane.history.trails, alpha, lane.colour);
            self.trails[k].slots = slots(lane);
        }
        self.ensure_depth(gpu, view.target_size);
        self.viewport = view.viewport;
    }

    /// Uploads the level's triangles when the scene's surfaces or the render origin changed
    /// since the last upload (lane 0's: every lane steps the same scene).
    fn prepare_level(&mut self, gpu: &Gpu, lanes: &[Lane<'_>], options: &DrawOptions) {
        let key = lanes
            .first()
            .map(|l| LevelKey::of(l.world.contacts(), options.origin))
            .unwrap_or_default();
        if self.level_key.as_ref() == Some(&key) {
            return;
        }
        self.level_vertices.clear();
        if let Some(l) = lanes.first() {
            level_vertices(l.world.contacts(), options.origin, &mut self.level_vertices);
        }
        if self.level.write(gpu, &self.level_vertices) {
            self.allocations += 1;
        }
        self.level_key = Some(key);
    }

    fn new_trail(&self, gpu: &Gpu) -> TrailBuffers {
        let device = &gpu.device;
        let uniform = create_buffer(
            device,
            "trail uniform",
            std::mem::size_of::<TrailUniform>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let storage = wgpu::BufferUsages::STORAGE;
        let samples = GrowBuffer::new(device, "trail samples", storage);
        let counts = GrowBuffer::new(device, "trail counts", storage);
        let group = self.trail_group(gpu, &uniform, &samples, &counts);
        TrailBuffers {
            uniform,
            samples,
            counts,
            group,
            ring_id: 0,
            rows_uploaded: 0,
            stride: 0,
            slots: 0,
        }
    }

    fn trail_group(
        &self,
        gpu: &Gpu,
        uniform: &wgpu::Buffer,
        samples: &GrowBuffer,
        counts: &GrowBuffer,
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("trail"),
            layout: &self
                .pipelines
                .trails
                .as_ref()
                .expect("trail buffers are made only with a trail pipeline")
                .layout,
            entries: &[
                entry(0, uniform),
                entry(1, &samples.buffer),
                entry(2, &counts.buffer),
            ],
        })
    }

    /// Brings lane `k`'s GPU trail up to date: the whole table when the ring is new or wider,
    /// otherwise only the rows recorded since the last upload.
    fn upload_trail(&mut self, gpu: &Gpu, k: usize, ring: &TrailRing, alpha: f64, colour: Rgba) {
        let stride = ring.stride();
        let t = &mut self.trails[k];
        let fresh = t.ring_id != ring.id() || t.stride != stride;
        let new_rows = ring.rows_written() - if fresh { 0 } else { t.rows_uploaded };
        let mut regroup = false;
        if fresh {
            regroup |= t.samples.write(gpu, ring.samples());
        } else {
            let rows = new_rows.min(TRAIL_SAMPLES as u64) as usize;
            for age in 0..rows {
                let row = (ring.head() + TRAIL_SAMPLES - age) % TRAIL_SAMPLES;
                let range = row * stride..row * stride + ring.used();
                let offset = (row * stride * std::mem::size_of::<[f32; 4]>()) as u64;
                let bytes: &[u8] = bytemuck::cast_slice(&ring.samples()[range]);
                if !bytes.is_empty() {
                    gpu.queue.write_buffer(&t.samples.buffer, offset, bytes);
                }
            }
        }
        self.counts.clear();
        self.counts
            .extend((0..ring.used()).map(|slot| ring.count(slot)));
        regroup |= t.counts.write(gpu, &self.counts);
        t.ring_id = ring.id();
        t.rows_uploaded = ring.rows_written();
        t.stride = stride;
        let c = colour.map(|x| f32::from(x) / 255.0);
        let uniform = TrailUniform {
            colour: c,
            head: ring.head() as u32,
            len: TRAIL_SAMPLES as u32,
            stride: stride as u32,
            alpha: alpha as f32,
            segments: self.segments,
            pad: [0; 3],
        };
        gpu.queue
            .write_buffer(&t.uniform, 0, bytemuck::bytes_of(&uniform));
        if regroup {
            self.allocations += 1;
            let t = &self.trails[k];
            let group = self.trail_group(gpu, &t.uniform, &t.samples, &t.counts);
            self.trails[k].group = group;
        }
    }

    fn ensure_depth(&mut self, gpu: &Gpu, size: (u32, u32)) {
        let size = (size.0.max(1), size.1.max(1));
        if self.depth.as_ref().is_some_and(|(_, s)| *s == size) {
            return;
        }
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        self.depth = Some((texture.create_view(&Default::default()), size));
    }

    /// Records the frame's render pass into `encoder`, drawing into `target` (which must be the
    /// size given to [`Renderer::prepare`] and of this renderer's format).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        let Some((depth, _)) = &self.depth else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(CLEAR),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let v = self.viewport;
        if !v.is_visible() {
            return;
        }
        pass.set_viewport(v.x, v.y, v.width, v.height, 0.0, 1.0);
        pass.set_bind_group(0, &self.globals_group, &[]);
        let p = &self.pipelines;
        draw_instanced(&mut pass, &p.solid_spheres, &self.solid);
        draw_vertices(&mut pass, &p.level, &self.level);
        pass.set_pipeline(&p.grid);
        pass.draw(0..4, 0..1);
        draw_vertices(&mut pass, &p.surfaces, &self.surfaces);
        if let Some(trails) = &p.trails {
            pass.set_pipeline(&trails.pipeline);
            for t in self.trails.iter().filter(|t| t.slots > 0) {
                pass.set_bind_group(1, &t.group, &[]);
                pass.draw(0..2 * self.segments, 0..t.slots);
            }
        }
        draw_vertices(&mut pass, &p.lines, &self.lines);
        draw_instanced(&mut pass, &p.translucent_spheres, &self.translucent);
    }

    /// Prepares, encodes and submits one frame into `target`.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        target: &wgpu::TextureView,
        lanes: &[Lane<'_>],
        view: &View,
        options: &DrawOptions,
    ) {
        self.prepare(gpu, lanes, view, options);
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode(&mut encoder, target);
        gpu.queue.submit([encoder.finish()]);
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

fn draw_instanced(
    pass: &mut wgpu::RenderPass<'_>,
    pipeline: &wgpu::RenderPipeline,
    b: &GrowBuffer,
) {
    if b.len > 0 {
        pass.set_pipeline(pipeline);
        pass.set_vertex_buffer(0, b.buffer.slice(..));
        pass.draw(0..4, 0..b.len);
    }
}

fn draw_vertices(pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, b: &GrowBuffer) {
    if b.len > 0 {
        pass.set_pipeline(pipeline);
        pass.set_vertex_buffer(0, b.buffer.slice(..));
        pass.draw(0..b.len, 0..1);
    }
}

/// The frame constants: camera, light, ground and grid.
fn globals(view: &View, options: &DrawOptions, ground: Option<f64>) -> Globals {
    let camera = &view.camera;
    let origin = options.origin;
    let view_m = camera.view(origin);
    let proj = camera.projection(view.viewport.aspect());
    // Light from above and behind the viewer.
    let sun = (camera.back() + DVec3::new(0.0, 0.0, 1.5))
        .normalize()
        .as_vec3();
    let light = view_m.transform_vector3(sun).normalize_or(Vec3::Z);
    let v = view.viewport;
    // Grid spacing: a power of ten near a tenth of the viewing distance, lines 10x apart.
    let major = 10f64.powf(camera.distance.max(1e-3).log10().floor());
    let minor = major / 10.0;
    let wrap = DVec3::new(origin.x.rem_euclid(major), origin.y.rem_euclid(major), 0.0);
    let target = camera.target - origin;
    let extent = (camera.distance * 8.0).max(50.0);
    Globals {
        view: view_m.to_cols_array_2d(),
        proj: proj.to_cols_array_2d(),
        viewport: [v.x, v.y, v.width, v.height],
        light: light.extend(0.0).to_array(),
        ground: [
            (ground.unwrap_or(0.0) - origin.z) as f32,
            if ground.is_some() { 1.0 } else { 0.0 },
            extent as f32,
            MIN_SPHERE_PX,
        ],
        grid: [wrap.x as f32, wrap.y as f32, minor as f32, major as f32],
        axes: [
            origin.x as f32,
            origin.y as f32,
            target.x as f32,
            target.y as f32,
        ],
    }
}
