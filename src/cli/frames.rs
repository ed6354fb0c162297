//! `volley headless --frames DIR`: PNG frames of a headless run, drawn offscreen by the same
//! renderer as the window, on whatever adapter wgpu finds.

use std::path::Path;

use volley::World;
use volley::render::{FrameWriter, Gpu};

use super::{EXIT_ENVIRONMENT, Failure, fail};

/// Default frame size (px).
pub const DEFAULT_SIZE: (u32, u32) = (1280, 720);

/// A frame writer for `world`, with tick 0's frame (or the current tick's) already written.
pub fn writer(
    world: &World,
    dir: &Path,
    size: Option<&str>,
    every: u64,
) -> Result<FrameWriter, Failure> {
    let size = size.map_or(Ok(DEFAULT_SIZE), |s| {
        super::display::parse_size("--size", s)
    })?;
    let gpu = Gpu::headless().map_err(|e| {
        fail(
            EXIT_ENVIRONMENT,
            format!("--frames: {e}; run without --frames to step the scene without a GPU"),
        )
    })?;
    let mut frames = FrameWriter::new(gpu, world, dir, size, every)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("--frames: {e}")))?;
    frames
        .write(world)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("--frames: {e}")))?;
    Ok(frames)
}
