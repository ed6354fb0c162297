//! Frame timing: where a frame's delta comes from, how long frames take, and what the panel and
//! the closing summary say about it.

use crate::platform::Instant;

use winit::window::Window;

use super::display::Frames;
use super::panel::FrameStats;

/// Weight of the newest frame in the smoothed frame times.
const SMOOTHING: f64 = 0.1;

/// The frames' source and their measured times.
pub(super) struct FrameTiming {
    /// Where each frame's delta comes from: the real clock, steady frames or an emulated
    /// display.
    pub(super) frames: Frames,
    /// The smoothed times, frames drawn, adapter and window size, for the panel.
    pub(super) stats: FrameStats,
    /// When the last frame started.
    pub(super) last_frame: Instant,
    /// (interval, work, UI) of each frame (ms) and its UI triangles, kept only when the run
    /// has a frame limit.
    pub(super) timings: Vec<(f64, f64, f64, usize)>,
    /// The UI's CPU time of the frame being drawn (ms).
    pub(super) ui_ms: f64,
    /// The triangles of egui's meshes in the frame being drawn.
    pub(super) ui_triangles: usize,
}

impl FrameTiming {
    /// Timing of the frames `frames` gives, from now.
    pub(super) fn new(frames: Frames) -> FrameTiming {
        FrameTiming {
            frames,
            stats: FrameStats::default(),
            last_frame: Instant::now(),
            timings: Vec::new(),
            ui_ms: 0.0,
            ui_triangles: 0,
        }
    }

    /// Ends the frame that started at `start`: blends its interval, work and UI time into the
    /// stats (keeping them too if `keep`), and takes the window's size and scale.
    pub(super) fn end_frame(&mut self, start: Instant, window: &Window, keep: bool) {
        let blend = |old: f64, new: f64| {
            if old == 0.0 {
                new
            } else {
                old + SMOOTHING * (new - old)
            }
        };
        let interval = start.duration_since(self.last_frame).as_secs_f64() * 1e3;
        let work = start.elapsed().as_secs_f64() * 1e3;
        self.stats.interval_ms = blend(self.stats.interval_ms, interval);
        self.stats.work_ms = blend(self.stats.work_ms, work);
        self.stats.ui_ms = blend(self.stats.ui_ms, self.ui_ms);
        if keep {
            self.timings
                .push((interval, work, self.ui_ms, self.ui_triangles));
        }
        let size = window.inner_size();
        self.stats.size = (size.width, size.height);
        self.stats.scale = window.scale_factor();
        self.last_frame = start;
    }
}
