//! The render pipelines, one shader file each under `shaders/` (with `shaders/globals.wgsl`
//! prepended): spheres (solid and translucent variants), lines (line and triangle variants),
//! trails, the ground grid, and the level's lit triangles.
//!
//! Depth is reversed (cleared to 0, nearer is greater), so every depth test is `Greater`.
//! Solid spheres write depth; everything translucent tests against it without writing.

use crate::render::draw::{ColouredVertex, SphereInstance};
use crate::render::level::LitVertex;

/// Depth buffer format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

const GLOBALS: &str = include_str!("../../shaders/globals.wgsl");

/// Every pipeline and the layouts their bind groups need.
#[derive(Debug)]
pub struct Pipelines {
    /// Group 0 of every pipeline: the globals uniform.
    pub globals_layout: wgpu::BindGroupLayout,
    /// The trails' pipeline and the layout of its group 1 (uniform, samples, counts), where
    /// the device can read storage buffers in a vertex shader; WebGL2 cannot, and draws no
    /// trails ([`Pipelines::trails_missing`] says why).
    pub trails: Option<TrailPipeline>,
    /// Lit spheres.
    pub solid_spheres: wgpu::RenderPipeline,
    /// Translucent spheres (ghosts, targets).
    pub translucent_spheres: wgpu::RenderPipeline,
    /// Line lists.
    pub lines: wgpu::RenderPipeline,
    /// Translucent triangles.
    pub surfaces: wgpu::RenderPipeline,
    /// The ground grid.
    pub grid: wgpu::RenderPipeline,
    /// Level surfaces: opaque lit triangles.
    pub level: wgpu::RenderPipeline,
}

/// The trails' pipeline and its group 1 layout.
#[derive(Debug)]
pub struct TrailPipeline {
    /// Group 1: the trail's uniform, samples and counts.
    pub layout: wgpu::BindGroupLayout,
    /// The pipeline.
    pub pipeline: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Why trails are not drawn on this device, if they are not.
    pub fn trails_missing(&self) -> Option<&'static str> {
        self.trails.is_none().then_some(
            "no trails on this adapter: they are read from storage buffers in a vertex shader, \
             which it cannot do (WebGL2)",
        )
    }
}

fn shader(device: &wgpu::Device, label: &str, body: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(format!("{GLOBALS}\n{body}").into()),
    })
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// How a pipeline blends and uses depth.
#[derive(Clone, Copy)]
struct Mode {
    topology: wgpu::PrimitiveTopology,
    translucent: bool,
}

struct Stage<'a> {
    module: &'a wgpu::ShaderModule,
    fragment: &'a str,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
}

const SPHERE_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Unorm8x4];
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
const LIT_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Unorm8x4];

impl Pipelines {
    /// Builds every pipeline for colour targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Pipelines {
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[uniform_entry(0)],
        });
        let trail_layout = (device.limits().max_storage_buffers_per_shader_stage >= 2).then(|| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("trail"),
                entries: &[uniform_entry(0), storage_entry(1), storage_entry(2)],
            })
        });
        let layout_of = |label: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let common = layout_of("common", &[Some(&globals_layout)]);
        let trail = trail_layout
            .as_ref()
            .map(|l| layout_of("trail", &[Some(&globals_layout), Some(l)]));
        let sphere = shader(device, "sphere", include_str!("../../shaders/sphere.wgsl"));
        let line = shader(device, "line", include_str!("../../shaders/line.wgsl"));
        let grid_shader = shader(device, "grid", include_str!("../../shaders/grid.wgsl"));
        let level_shader = shader(device, "level", include_str!("../../shaders/level.wgsl"));
        let spheres = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SphereInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &SPHERE_ATTRIBUTES,
        })];
        let vertices = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<ColouredVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX_ATTRIBUTES,
        })];
        let lit = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LitVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &LIT_ATTRIBUTES,
        })];
        use wgpu::PrimitiveTopology as T;
        let build = |label, layout, stage: Stage<'_>, topology, translucent| {
            pipeline(
                device,
                format,
                label,
                layout,
                stage,
                Mode {
                    topology,
                    translucent,
                },
            )
        };
        let sphere_stage = |fragment| Stage {
            module: &sphere,
            fragment,
            buffers: &spheres,
        };
        let line_stage = || Stage {
            module: &line,
            fragment: "fs_main",
            buffers: &vertices,
        };
        Pipelines {
            solid_spheres: build(
                "solid spheres",
                &common,
                sphere_stage("fs_solid"),
                T::TriangleStrip,
                false,
            ),
            translucent_spheres: build(
                "translucent spheres",
                &common,
                sphere_stage("fs_ghost"),
                T::TriangleStrip,
                true,
            ),
            lines: build("lines", &common, line_stage(), T::LineList, true),
            surfaces: build("surfaces", &common, line_stage(), T::TriangleList, true),
            grid: build(
                "grid",
                &common,
                Stage {
                    module: &grid_shader,
                    fragment: "fs_main",
                    buffers: &[],
                },
                T::TriangleStrip,
                true,
            ),
            level: build(
                "level",
                &common,
                Stage {
                    module: &level_shader,
                    fragment: "fs_main",
                    buffers: &lit,
                },
                T::TriangleList,
                false,
            ),
            trails: trail_layout.zip(trail.as_ref()).map(|(layout, trail)| {
                let shader = shader(device, "trail", include_str!("../../shaders/trail.wgsl"));
                let stage = Stage {
                    module: &shader,
                    fragment: "fs_main",
                    buffers: &[],
                };
                let pipeline = build("trails", trail, stage, T::LineList, true);
                TrailPipeline { layout, pipeline }
            }),
            globals_layout,
        }
    }
}

fn pipeline(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    label: &str,
    layout: &wgpu::PipelineLayout,
    stage: Stage<'_>,
    mode: Mode,
) -> wgpu::RenderPipeline {
    let blend = mode.translucent.then_some(wgpu::BlendState::ALPHA_BLENDING);
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: stage.module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: stage.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: mode.topology,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(!mode.translucent),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: stage.module,
            entry_point: Some(stage.fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
