//! What a loop-lab run measured: display error, animation error, judder, latency, cadence and
//! drift, per draw mode.
//!
//! Definitions (all over the frames that reached the screen, unless said otherwise):
//! - **display error**: the distance (m) between the drawn position and the exact position at
//!   the frame's display time.
//! - **animation error**: PresentMon's `MsAnimationError`, the frame-to-frame step of the game
//!   time drawn minus the frame-to-frame step of display time (ms), as its absolute value
//!   (GameTechDev/PresentMon, README-ConsoleApplication.md). A constant latency cancels out of
//!   it; what is left is what the eye sees as uneven motion.
//! - **judder**: the drawn displacement from one shown frame to the next against the true one
//!   over the same display interval, `|(drawn_j - drawn_i) - (exact_j - exact_i)|` (m).
//! - **latency**: from an input sampled at a frame (a command pushed before the frame runs, so
//!   applied before the next tick) to the display time of the first shown frame whose drawn
//!   state includes that tick (ms), over every frame.
//! - **lag**: display time minus the game time drawn (ms): how old what is shown is.
//! - **inside**: the frames shown with the drawn body inside a surface (the ground, a wall, a
//!   level surface; on the `target` subject, whose game removes a shot that hits, the target
//!   too), and the deepest it was drawn there (m): a frame a player sees a ball in the floor,
//!   or a shot through its target.
//! - **near and far**: the display error of the frames shown within a tick and a refresh of a
//!   discontinuity (an impact or a command's turn), and of the rest, apart: a bounce is a few
//!   frames a second, too few to move a p99 over all frames. After a command, the error near
//!   is the misprediction: no draw can foresee an input.
//! - **cadence**: ticks per frame, as a histogram (0, 1, 2, 3 or more), the first frames as a
//!   string, and 0-to-2 swings (a 0-tick frame next to one of 2 or more) per second.
//! - **drift**: game time (ticks plus the accumulator) minus wall time at each frame's sample
//!   (ms): its largest magnitude, its value at the end, and its growth over the second half of
//!   the run (bounded drift does not grow), and the largest magnitude of the drift plus the
//!   time dropped so far (the drift the policy causes, apart from what the clamp drops).
//! - **recovery**: after the longest frame (when it is over four times the median), the wall
//!   time until 30 frames in a row run no more ticks than any frame before it did.
//!
//! Percentiles are nearest-rank: the p-th percentile of n values is the ceil(p n)-th smallest.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::lab::DrawMode;

/// One frame of a run, as the lab saw it.
#[derive(Clone, Debug)]
pub struct FrameRecord {
    /// Wall time of the frame's sample, since the first (s).
    pub wall: f64,
    /// Wall time it was shown, since the first sample (s); `None` if dropped.
    pub shown: Option<f64>,
    /// The delta the clock was given (s).
    pub delta: f64,
    /// Ticks the frame ran.
    pub steps: u32,
    /// The world's tick before and after the frame.
    pub tick_before: u64,
    /// See `tick_before`.
    pub tick_after: u64,
    /// The clock's alpha after the frame.
    pub alpha: f64,
    /// Game time minus wall time at the sample (s).
    pub drift: f64,
    /// Time the clock has dropped so far (s): the clamp and the tick cap, on purpose.
    pub dropped: f64,
    /// Drawn position per draw mode ([`DrawMode::ALL`] order).
    pub drawn: [DVec3; DrawMode::COUNT],
    /// Game time drawn per draw mode, on the wall clock: less the first frame's phase (s).
    pub drawn_time: [f64; DrawMode::COUNT],
    /// How deep the drawn body is inside a surface per draw mode (m; 0 outside).
    pub inside: [f64; DrawMode::COUNT],
    /// The exact position at the display time; `None` if not shown.
    pub exact: Option<DVec3>,
    /// Whether it is shown within a tick and a refresh of a discontinuity.
    pub near: bool,
}

/// Median, 99th percentile and largest value of a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Median.
    pub median: f64,
    /// 99th percentile (nearest rank).
    pub p99: f64,
    /// Largest.
    pub worst: f64,
}

impl Stats {
    /// The statistics of `values` (all zero when empty).
    pub fn of(mut values: Vec<f64>) -> Stats {
        if values.is_empty() {
            return Stats::default();
        }
        values.sort_unstable_by(f64::total_cmp);
        let rank =
            |p: f64| values[((p * values.len() as f64).ceil() as usize).clamp(1, values.len()) - 1];
        Stats {
            median: rank(0.5),
            p99: rank(0.99),
            worst: values[values.len() - 1],
        }
    }
}

/// One draw mode's measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ModeMetrics {
    /// Display error (m).
    pub error: Stats,
    /// Absolute animation error (ms).
    pub animation: Stats,
    /// Judder (m).
    pub judder: Stats,
    /// Input-to-display latency (ms).
    pub latency: Stats,
    /// Median lag (ms).
    pub lag: f64,
    /// Frames shown with the drawn body inside a surface.
    pub inside_frames: u64,
    /// The deepest a shown frame drew it inside a surface (m).
    pub inside_depth: f64,
    /// Display error of the frames shown near a discontinuity (m).
    pub error_near: Stats,
    /// Display error of the other frames (m).
    pub error_far: Stats,
}

/// Most frames the cadence string holds.
pub const CADENCE_CHARS: usize = 120;

/// Everything one run measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Frames presented.
    pub frames: usize,
    /// Frames shown.
    pub shown: usize,
    /// Per draw mode, in [`DrawMode::ALL`] order.
    pub modes: [ModeMetrics; DrawMode::COUNT],
    /// Frames that ran 0, 1, 2, and 3 or more ticks.
    pub histogram: [u64; 4],
    /// Ticks per frame of the first frames, one digit each (`+` for 10 or more).
    pub cadence: String,
    /// 0-to-2 swings per second of wall time.
    pub swings_per_s: f64,
    /// Largest |game time - wall time| (ms).
    pub drift_worst: f64,
    /// Game time - wall time at the last frame (ms).
    pub drift_end: f64,
    /// Growth of the drift over the second half of the run (ms).
    pub drift_growth: f64,
    /// Largest |game time + time dropped - wall time| (ms): the drift the policy itself
    /// causes, apart from the time the clock's clamp and tick cap drop on purpose.
    pub drift_kept: f64,
    /// Time the clock dropped (ms).
    pub dropped: f64,
    /// Recovery after the longest frame (ms), when there was a hitch.
    pub recovery: Option<f64>,
}

impl Metrics {
    /// The metrics of a run's frames, with `dropped` seconds dropped by the clock.
    pub fn of(records: &[FrameRecord], dropped: f64) -> Metrics {
        let shown: Vec<&FrameRecord> = records.iter().filter(|r| r.shown.is_some()).collect();
        let modes = std::array::from_fn(|m| mode_metrics(records, &shown, m));
        let mut histogram = [0u64; 4];
        for r in records {
            histogram[(r.steps as usize).min(3)] += 1;
        }
        let cadence = records
            .iter()
            .take(CADENCE_CHARS)
            .map(|r| char::from_digit(r.steps, 10).unwrap_or('+'))
            .collect();
        let swings = records
            .windows(2)
            .filter(|w| {
                (w[0].steps == 0 && w[1].steps >= 2) || (w[0].steps >= 2 && w[1].steps == 0)
            })
            .count();
        let span = records.last().map_or(0.0, |r| r.wall);
        let drift_at = |i: usize| records.get(i).map_or(0.0, |r| r.drift);
        Metrics {
            frames: records.len(),
            shown: shown.len(),
            modes,
            histogram,
            cadence,
            swings_per_s: if span > 0.0 {
                swings as f64 / span
            } else {
                0.0
            },
            drift_worst: records.iter().map(|r| r.drift.abs()).fold(0.0, f64::max) * 1e3,
            drift_end: drift_at(records.len().saturating_sub(1)) * 1e3,
            drift_growth: (drift_at(records.len().saturating_sub(1)) - drift_at(records.len() / 2))
                * 1e3,
            drift_kept: records
                .iter()
                .map(|r| (r.drift + r.dropped).abs())
                .fold(0.0, f64::max)
                * 1e3,
            dropped: dropped * 1e3,
            recovery: recovery(records),
        }
    }

    /// The metrics of draw mode `mode`.
    pub fn mode(&self, mode: DrawMode) -> &ModeMetrics {
        let i = DrawMode::ALL.iter().position(|m| *m == mode).unwrap_or(0);
        &self.modes[i]
    }

    /// The share of frames that ran exactly one tick.
    pub fn single_tick_share(&self) -> f64 {
        self.histogram[1] as f64 / self.frames.max(1) as f64
    }
}

fn mode_metrics(records: &[FrameRecord], shown: &[&FrameRecord], m: usize) -> ModeMetrics {
    let mut error = Vec::with_capacity(shown.len());
    let (mut near, mut far) = (Vec::new(), Vec::with_capacity(shown.len()));
    let mut lag = Vec::with_capacity(shown.len());
    let (mut inside_frames, mut inside_depth) = (0, 0.0f64);
    for r in shown {
        if r.inside[m] > 0.0 {
            inside_frames += 1;
            inside_depth = inside_depth.max(r.inside[m]);
        }
        if let (Some(e), Some(d)) = (r.exact, r.shown) {
            let err = (r.drawn[m] - e).length();
            error.push(err);
            if r.near { &mut near } else { &mut far }.push(err);
            lag.push((d - r.drawn_time[m]) * 1e3);
        }
    }
    let mut animation = Vec::with_capacity(shown.len());
    let mut judder = Vec::with_capacity(shown.len());
    for w in shown.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (Some(da), Some(db)) = (a.shown, b.shown) else {
            continue;
        };
        animation.push((((b.drawn_time[m] - a.drawn_time[m]) - (db - da)) * 1e3).abs());
        if let (Some(ea), Some(eb)) = (a.exact, b.exact) {
            judder.push(((b.drawn[m] - a.drawn[m]) - (eb - ea)).length());
        }
    }
    let interpolate = DrawMode::ALL[m] == DrawMode::Interpolate;
    let mut latency = Vec::with_capacity(records.len());
    for (i, r) in records.iter().enumerate() {
        let due = r.tick_before + 1;
        let seen = records[i..].iter().find(|f| {
            f.shown.is_some()
                && if interpolate {
                    f.tick_after > due || (f.tick_after == due && f.alpha > 0.0)
                } else {
                    f.tick_after >= due
                }
        });
        if let Some(f) = seen {
            latency.push((f.shown.unwrap_or(f.wall) - r.wall) * 1e3);
        }
    }
    ModeMetrics {
        error: Stats::of(error),
        animation: Stats::of(animation),
        judder: Stats::of(judder),
        latency: Stats::of(latency),
        lag: Stats::of(lag).median,
        inside_frames,
        inside_depth,
        error_near: Stats::of(near),
        error_far: Stats::of(far),
    }
}

fn recovery(records: &[FrameRecord]) -> Option<f64> {
    let mut deltas: Vec<f64> = records.iter().skip(1).map(|r| r.delta).collect();
    if deltas.len() < 3 {
        return None;
    }
    let (hitch, longest) = records
        .iter()
        .enumerate()
        .skip(1)
        .max_by(|a, b| a.1.delta.total_cmp(&b.1.delta))?;
    deltas.sort_unstable_by(f64::total_cmp);
    if longest.delta <= 4.0 * deltas[deltas.len() / 2] {
        return None;
    }
    let steady = records[..hitch].iter().map(|r| r.steps).max().unwrap_or(1);
    let calm = |k: usize| {
        records[k..(k + 30).min(records.len())]
            .iter()
            .all(|r| r.steps <= steady)
    };
    (hitch + 1..records.len())
        .find(|&k| calm(k))
        .map(|k| (records[k].wall - longest.wall) * 1e3)
}
