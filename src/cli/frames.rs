//! `volley headless --frames DIR`: PNG frames of a headless run, drawn offscreen by the same
//! renderer as the window, on whatever adapter wgpu finds.

use std::path::Path;

use volley::render::{FrameWriter, Gpu};
use volley::sim_loop::{ObserverError, TickObserver};
use volley::{Stamped, World};

use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail};

/// Default frame size (px).
pub const DEFAULT_SIZE: (u32, u32) = (1280, 720);

/// Parses `WxH` (each side 1 to 16384).
pub fn parse_size(flag: &str, text: &str) -> Result<(u32, u32), Failure> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Ok((w, h)),
        _ => Err(fail(
            EXIT_INPUT,
            format!("{flag}: expected WIDTHxHEIGHT, each 1 to 16384, got `{text}`"),
        )),
    }
}

/// A frame writer for `world`, with tick 0's frame (or the current tick's) already written.
pub fn writer(
    world: &World,
    dir: &Path,
    size: Option<&str>,
    every: u64,
) -> Result<FrameWriter, Failure> {
    let size = size.map_or(Ok(DEFAULT_SIZE), |s| parse_size("--size", s))?;
    if every == 0 {
        return Err(fail(EXIT_INPUT, "--frame-every: expected at least 1"));
    }
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

/// Another observer (the table writer) with the frame writer beside it.
pub struct WithFrames<'a, O> {
    /// The observer the run had anyway.
    pub inner: &'a mut O,
    /// The frame writer.
    pub frames: &'a mut FrameWriter,
}

impl<O: TickObserver> TickObserver for WithFrames<'_, O> {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        self.inner.on_command(world, stamped)?;
        self.frames.on_command(world, stamped)
    }

    fn before_last_tick(&mut self, world: &World) {
        self.inner.before_last_tick(world);
        self.frames.before_last_tick(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.inner.after_tick(world)?;
        self.frames.after_tick(world)
    }

    fn on_divergence(&mut self, world: &World, divergence: &volley::Divergence) {
        self.inner.on_divergence(world, divergence);
        self.frames.on_divergence(world, divergence);
    }
}
