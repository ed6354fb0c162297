//! Drawing worlds with wgpu: device setup, pipelines, instance buffers, camera, offscreen capture.
//!
//! The path of a frame: the loop's [`TickHistory`] observer keeps the previous state, the trails
//! and each body's closed-form reference; [`DrawList::build`] turns one or more worlds (one per
//! integrator in compare mode) and the loop's alpha into flat arrays; the [`Renderer`] uploads
//! them into buffers it reuses and draws into any `&wgpu::TextureView`. The window draws into
//! its surface, `volley headless --frames` into an [`OffscreenTarget`] it reads back into PNG
//! files: one code path.
//!
//! Everything here reads the simulation; nothing writes to it. The simulation modules never
//! import wgpu or winit.

pub mod bounds;
pub mod camera;
pub mod capture;
pub mod draw;
pub mod frame_writer;
pub mod gpu;
pub mod history;
pub mod level;
pub mod pipelines;
pub mod probe;
pub mod reference;
pub mod renderer;
pub mod series;
pub mod trails;

pub use bounds::SceneBounds;
pub use camera::{OrbitCamera, Viewport};
pub use capture::{CaptureError, Image, OFFSCREEN_FORMAT, OffscreenTarget};
pub use draw::{DrawList, DrawOptions, JudderMark, Lane, integrator_colour};
pub use frame_writer::{FrameWriter, write_picture};
pub use gpu::{Gpu, GpuError};
pub use history::{DrawAt, TickHistory};
pub use reference::{BodyError, Reference, References};
pub use renderer::{Renderer, View};
