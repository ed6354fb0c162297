//! Display timings: when a game samples its frame clock, and when each frame reaches the screen.

use std::time::Duration;

use volley_sim::internals::rng::SplitMix64;

/// One presented frame of a display timing, in wall-clock time from the timing's start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Present {
    /// When the game reads its frame clock for this frame: the delta the loop steps by is this
    /// minus the previous present's `sampled`.
    pub sampled: Duration,
    /// When the frame's image reached the screen (photon time, as far as the source knows it);
    /// `None` when the frame was dropped and never shown.
    pub shown: Option<Duration>,
}

/// A sequence of presents from one source: a display model or a capture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisplayTiming {
    /// What produced it (`60 Hz`, a capture's file name and application).
    pub name: String,
    /// The presents in order; `sampled` never decreases.
    pub presents: Vec<Present>,
}

impl DisplayTiming {
    /// The frame deltas the game's clock reads: the first is `first`, then each present's
    /// `sampled` minus the previous one's.
    pub fn deltas(&self, first: Duration) -> impl Iterator<Item = Duration> + '_ {
        let mut last = None;
        self.presents.iter().map(move |p| {
            let d = last.map_or(first, |l| p.sampled.saturating_sub(l));
            last = Some(p.sampled);
            d
        })
    }

    /// The median interval between consecutive shown frames: the refresh interval a game
    /// would measure. `None` with fewer than two shown frames.
    pub fn median_display_interval(&self) -> Option<Duration> {
        let shown: Vec<Duration> = self.presents.iter().filter_map(|p| p.shown).collect();
        let mut steps: Vec<Duration> = shown
            .windows(2)
            .map(|w| w[1].saturating_sub(w[0]))
            .collect();
        if steps.is_empty() {
            return None;
        }
        steps.sort_unstable();
        Some(steps[steps.len() / 2])
    }

    /// Wall time covered, from the first sample to the last.
    pub fn span(&self) -> Duration {
        match (self.presents.first(), self.presents.last()) {
            (Some(a), Some(b)) => b.sampled.saturating_sub(a.sampled),
            _ => Duration::ZERO,
        }
    }
}

/// A display to emulate: how the game's frames are paced and when they are shown.
///
/// Every model is deterministic: its noise comes from a [`SplitMix64`] seeded by the model's
/// `seed`, so a run under a model repeats exactly.
#[derive(Clone, Debug, PartialEq)]
pub enum DisplayModel {
    /// A fixed-refresh display with vsync (FIFO, double buffered): the game's present blocks
    /// until the vsync that shows the previous frame, wakes a little after it and samples its
    /// clock, renders, and the frame is shown at the first vsync after rendering ends. A frame
    /// whose rendering ends after the next vsync misses it and is shown one refresh later (a
    /// dropped frame, in players' words: the display repeats the previous one).
    Fixed {
        /// Refresh rate (Hz).
        hz: f64,
        /// Largest wake-up delay after a vsync; each frame's is uniform from 0 to it. Unity
        /// measured deltas of 6.5 to 7.4 ms on a locked 144 Hz display ("Fixing
        /// Time.deltaTime in 2020.2"): about +-0.45 ms, so 0.5 ms is the default.
        wake: Duration,
        /// Render cost of a frame, from sampling the clock to the end of its rendering.
        cost: Duration,
        /// Every how many frames on average one costs a refresh and a half more (a missed
        /// vsync); 0 for never.
        miss_every: u32,
        /// Generator seed.
        seed: u64,
    },
    /// Variable refresh (G-Sync, FreeSync): a frame is shown when its rendering ends, but no
    /// sooner than `1 / max_hz` after the previous one; the next frame starts when the present
    /// returns.
    Variable {
        /// Highest refresh rate (Hz).
        max_hz: f64,
        /// Mean render cost.
        cost: Duration,
        /// Largest deviation of the render cost, uniform around the mean.
        spread: Duration,
        /// Generator seed.
        seed: u64,
    },
    /// A fixed-refresh display with one frame that takes `length` to render, at `at` seconds.
    Hitch {
        /// Refresh rate (Hz).
        hz: f64,
        /// When the hitch starts (s).
        at: f64,
        /// How long the hitch frame renders.
        length: Duration,
    },
}

/// Render cost of an ordinary frame in the fixed-refresh models: 4 ms, well inside a refresh
/// at 240 Hz.
pub const DEFAULT_COST: Duration = Duration::from_millis(4);
/// Largest wake-up delay of the fixed-refresh models (see [`DisplayModel::Fixed`]).
pub const DEFAULT_WAKE: Duration = Duration::from_micros(500);

impl DisplayModel {
    /// A fixed-refresh display at `hz` with the default wake-up noise and cost, no misses.
    pub fn fixed(hz: f64) -> DisplayModel {
        DisplayModel::Fixed {
            hz,
            wake: DEFAULT_WAKE,
            cost: DEFAULT_COST,
            miss_every: 0,
            seed: 1,
        }
    }

    /// The bundled displays the loop lab measures, with their names: fixed refresh at 60,
    /// 59.94, 120, 144, 165 and 240 Hz; 60 Hz missing a vsync every 30 frames on average;
    /// variable refresh up to 144 Hz with a 9 +- 4 ms render cost; 60 Hz with a 300 ms hitch at
    /// 5 s.
    pub fn bundled() -> Vec<(&'static str, DisplayModel)> {
        let mut out: Vec<(&'static str, DisplayModel)> = [
            ("60", 60.0),
            ("59.94", 60_000.0 / 1001.0),
            ("120", 120.0),
            ("144", 144.0),
            ("165", 165.0),
            ("240", 240.0),
        ]
        .into_iter()
        .map(|(n, hz)| (n, DisplayModel::fixed(hz)))
        .collect();
        out.push((
            "60-misses",
            DisplayModel::Fixed {
                hz: 60.0,
                wake: DEFAULT_WAKE,
                cost: DEFAULT_COST,
                miss_every: 30,
                seed: 2,
            },
        ));
        out.push((
            "vrr-144",
            DisplayModel::Variable {
                max_hz: 144.0,
                cost: Duration::from_millis(9),
                spread: Duration::from_millis(4),
                seed: 3,
            },
        ));
        out.push((
            "60-hitch",
            DisplayModel::Hitch {
                hz: 60.0,
                at: 5.0,
                length: Duration::from_millis(300),
            },
        ));
        out
    }

    /// The model a `--display` value names: a bundled name (`59.94`, `vrr-144`, ...) or any
    /// refresh rate in hertz (`75`).
    pub fn named(name: &str) -> Option<DisplayModel> {
        if let Some((_, m)) = DisplayModel::bundled()
            .into_iter()
            .find(|(n, _)| *n == name)
        {
            return Some(m);
        }
        let hz: f64 = name.parse().ok()?;
        (hz.is_finite() && (1.0..=1000.0).contains(&hz)).then(|| DisplayModel::fixed(hz))
    }

    /// The refresh rate the game believes in: the nominal rate rounded to whole hertz (59.94 Hz
    /// is taken as 60, as Godot's estimator and Glaiel's constants do); for variable refresh,
    /// its highest rate.
    pub fn believed_refresh(&self) -> Duration {
        let hz = match self {
            DisplayModel::Fixed { hz, .. } | DisplayModel::Hitch { hz, .. } => *hz,
            DisplayModel::Variable { max_hz, .. } => *max_hz,
        };
        believed_refresh(hz)
    }

    /// `seconds` of presents under this model.
    pub fn timing(&self, name: &str, seconds: f64) -> DisplayTiming {
        let end = (seconds.max(0.0) * 1e9) as u64;
        let mut presents = Vec::new();
        match self {
            DisplayModel::Fixed {
                hz,
                wake,
                cost,
                miss_every,
                seed,
            } => {
                let mut rng = SplitMix64(*seed);
                let period = 1e9 / hz;
                let miss = *miss_every;
                fixed_refresh(&mut presents, period, end, |_, _| {
                    let w = (wake.as_nanos() as f64 * rng.next_f64()) as u64;
                    let spike = miss > 0 && rng.next_u64().is_multiple_of(u64::from(miss));
                    let extra = if spike { (1.5 * period) as u64 } else { 0 };
                    (w, cost.as_nanos() as u64 + extra)
                });
            }
            DisplayModel::Hitch { hz, at, length } => {
                let period = 1e9 / hz;
                let at = (at * 1e9) as u64;
                let mut done = false;
                fixed_refresh(&mut presents, period, end, |_, sampled| {
                    let hitch = !done && sampled >= at;
                    done |= hitch;
                    let c = if hitch {
                        length.as_nanos() as u64
                    } else {
                        DEFAULT_COST.as_nanos() as u64
                    };
                    (DEFAULT_WAKE.as_nanos() as u64 / 2, c)
                });
            }
            DisplayModel::Variable {
                max_hz,
                cost,
                spread,
                seed,
            } => {
                let mut rng = SplitMix64(*seed);
                let min_gap = (1e9 / max_hz) as u64;
                let mut start = 0u64;
                let mut last_shown: Option<u64> = None;
                while start <= end {
                    let sampled = start + (DEFAULT_WAKE.as_nanos() as u64 / 2);
                    let c = (cost.as_nanos() as f64 + spread.as_nanos() as f64 * rng.next_signed())
                        .max(0.0) as u64;
                    let done = sampled + c;
                    let shown = last_shown.map_or(done, |l| done.max(l + min_gap));
                    presents.push(Present {
                        sampled: Duration::from_nanos(sampled),
                        shown: Some(Duration::from_nanos(shown)),
                    });
                    last_shown = Some(shown);
                    start = shown;
                }
            }
        }
        DisplayTiming {
            name: name.to_string(),
            presents,
        }
    }
}

/// Presents on a fixed-refresh vsync grid: `frame(i, wake-up time)` gives a frame's wake-up
/// delay after the vsync it starts at, and its render cost (ns).
fn fixed_refresh(
    presents: &mut Vec<Present>,
    period: f64,
    end: u64,
    mut frame: impl FnMut(usize, u64) -> (u64, u64),
) {
    let vsync = |k: u64| (k as f64 * period).round() as u64;
    // Frame i starts at vsync k (the one that showed frame i - 1), is shown at the first vsync
    // after its rendering ends.
    let mut k = 0u64;
    let mut i = 0;
    while vsync(k) <= end {
        let (wake, cost) = frame(i, vsync(k));
        let sampled = vsync(k) + wake;
        let done = sampled + cost;
        let mut shown = k + 1;
        while vsync(shown) < done {
            shown += 1;
        }
        presents.push(Present {
            sampled: Duration::from_nanos(sampled),
            shown: Some(Duration::from_nanos(vsync(shown))),
        });
        k = shown;
        i += 1;
    }
}

/// The refresh a game believes in when nothing says otherwise: 60 Hz (what Glaiel's constants
/// and a monitor that reports nothing give).
pub const DEFAULT_REFRESH: Duration = Duration::from_nanos(16_666_667);

/// The refresh interval a game believes in for a display of `hz`: the rate rounded to whole
/// hertz (59.94 Hz is taken as 60, as Godot's estimator and Glaiel's constants do), at least
/// 1 Hz; [`DEFAULT_REFRESH`] for a rate that is not a finite number above 0.
pub fn believed_refresh(hz: f64) -> Duration {
    if !hz.is_finite() || hz <= 0.0 {
        return DEFAULT_REFRESH;
    }
    Duration::from_nanos((1e9 / hz.round().max(1.0)).round() as u64)
}
