//! Where the window's frames come from: the real clock, steady virtual frames
//! (`--frame-rate`), or an emulated display (`--display`): a display model's or a PresentMon
//! capture's timing ([`crate::pacing`]), whose deltas drive the loop and whose display times
//! the pacing view measures the drawn position against.
//!
//! An emulated display is virtual time, like `--frame-rate`: the window draws as fast as it can
//! and each frame takes the next present's delta, so a run is the same on every machine, under
//! Xvfb and in tests. When the timing runs out it starts again from its first present (the
//! delta across the seam is the timing's median delta).

use std::time::Duration;

use crate::clock::{FrameSource, RealClock, VirtualClock};
use crate::pacing::{Present, SweepDisplay};

/// Seconds of a display model's timing the window plays before starting it again: long enough
/// for a 59.94 Hz display's two-tick frame (one every 16.7 s at 60 Hz ticks) to come round
/// three times, and for the `60-hitch` model's hitch at 5 s.
pub const MODEL_SECONDS: f64 = 60.0;

/// The refresh believed without a display model, and for a rate in hertz: the loop lab's.
pub use crate::pacing::display::{DEFAULT_REFRESH, believed_refresh};

/// When a frame reached the screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shown {
    /// This long after the frame sampled its clock (an emulated display's present).
    After(Duration),
    /// Never: the display dropped it (a missed vsync in a capture).
    Dropped,
    /// Not known: the real clock, or steady frames. The pacing view then measures at the
    /// frame's sampled time.
    Unknown,
}

/// One frame's timing: the delta the loop steps by, and when the frame was shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameTiming {
    /// Time since the previous frame's sample.
    pub delta: Duration,
    /// When this frame reached the screen.
    pub shown: Shown,
}

/// An emulated display's presents, played in a loop.
#[derive(Clone, Debug)]
pub struct DisplayFrames {
    presents: Vec<Present>,
    next: usize,
    last: Option<Duration>,
    /// The delta across the seam, from the last present to the first one again.
    wrap: Duration,
    /// How many times the timing has started again.
    pub laps: u64,
}

impl DisplayFrames {
    /// Plays `display`'s presents from the first (whose delta is 0, as the real clock's first
    /// is).
    pub fn new(display: &SweepDisplay) -> DisplayFrames {
        let presents = display.timing.presents.clone();
        let mut deltas: Vec<Duration> = display
            .timing
            .deltas(Duration::ZERO)
            .skip(1)
            .filter(|d| !d.is_zero())
            .collect();
        deltas.sort_unstable();
        let wrap = deltas
            .get(deltas.len() / 2)
            .copied()
            .unwrap_or(display.refresh);
        DisplayFrames {
            presents,
            next: 0,
            last: None,
            wrap,
            laps: 0,
        }
    }

    /// The next frame; with no presents at all, frames of the wrap delta shown at once.
    pub fn next_frame(&mut self) -> FrameTiming {
        let Some(present) = self.presents.get(self.next).copied() else {
            return FrameTiming {
                delta: self.wrap,
                shown: Shown::Unknown,
            };
        };
        let delta = match self.last {
            None => Duration::ZERO,
            Some(_) if self.next == 0 => self.wrap,
            Some(last) => present.sampled.saturating_sub(last),
        };
        self.last = Some(present.sampled);
        self.next += 1;
        if self.next == self.presents.len() {
            self.next = 0;
            self.laps += 1;
        }
        FrameTiming {
            delta,
            shown: match present.shown {
                Some(at) => Shown::After(at.saturating_sub(present.sampled)),
                None => Shown::Dropped,
            },
        }
    }
}

/// The window's frame source.
pub enum Frames {
    /// The real monotonic clock or steady virtual frames: deltas only.
    Clock(Box<dyn FrameSource>),
    /// An emulated display: deltas and display times.
    Display(DisplayFrames),
}

impl std::fmt::Debug for Frames {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Frames::Clock(_) => f.write_str("Frames::Clock"),
            Frames::Display(d) => f.debug_tuple("Frames::Display").field(d).finish(),
        }
    }
}

impl Frames {
    /// The frames a window with these options runs on: the display if one is emulated, else
    /// steady frames of `frame_rate`, else the real clock.
    pub fn of(display: Option<&SweepDisplay>, frame_rate: Option<f64>) -> Frames {
        match (display, frame_rate) {
            (Some(d), _) => Frames::Display(DisplayFrames::new(d)),
            (None, Some(hz)) => Frames::Clock(Box::new(VirtualClock::display(hz))),
            (None, None) => Frames::Clock(Box::new(RealClock::new())),
        }
    }

    /// The next frame's timing.
    pub fn next_frame(&mut self) -> FrameTiming {
        match self {
            Frames::Clock(source) => FrameTiming {
                delta: source.next_delta(),
                shown: Shown::Unknown,
            },
            Frames::Display(d) => d.next_frame(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pacing::{DisplayModel, DisplayTiming};

    fn display(presents: &[(u64, Option<u64>)]) -> SweepDisplay {
        let ms = Duration::from_millis;
        SweepDisplay {
            name: "test".into(),
            timing: DisplayTiming {
                name: "test".into(),
                presents: presents
                    .iter()
                    .map(|&(s, d)| Present {
                        sampled: ms(s),
                        shown: d.map(ms),
                    })
                    .collect(),
            },
            refresh: ms(10),
            capture: false,
        }
    }

    #[test]
    fn a_display_plays_its_deltas_and_display_times_then_starts_again() {
        let ms = Duration::from_millis;
        // Deltas 10, 12 and 10 ms (median 10); the second frame dropped.
        let d = display(&[(0, Some(15)), (10, None), (22, Some(40)), (32, Some(45))]);
        let mut frames = DisplayFrames::new(&d);
        let got: Vec<FrameTiming> = (0..6).map(|_| frames.next_frame()).collect();
        let f = |delta, shown| FrameTiming {
            delta: ms(delta),
            shown,
        };
        assert_eq!(
            got,
            [
                f(0, Shown::After(ms(15))),
                f(10, Shown::Dropped),
                f(12, Shown::After(ms(18))),
                f(10, Shown::After(ms(13))),
                // The seam: the median delta, then the first lap's deltas again.
                f(10, Shown::After(ms(15))),
                f(10, Shown::Dropped),
            ]
        );
        assert_eq!(frames.laps, 1);
    }

    #[test]
    fn the_refresh_believed_is_the_rate_rounded_to_whole_hertz() {
        assert_eq!(believed_refresh(60_000.0 / 1001.0), DEFAULT_REFRESH);
        assert_eq!(believed_refresh(144.0), Duration::from_nanos(6_944_444));
        assert_eq!(believed_refresh(f64::NAN), DEFAULT_REFRESH);
        let m = DisplayModel::named("59.94").unwrap();
        assert_eq!(
            SweepDisplay::model("59.94", &m, MODEL_SECONDS).refresh,
            m.believed_refresh()
        );
    }
}
