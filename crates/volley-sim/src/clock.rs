//! The fixed-timestep clock: how many ticks a frame runs, and the interpolation alpha.
//!
//! Time is integer nanoseconds throughout ([`Duration`]): the accumulator never drifts and sim
//! time is `tick * timestep` exactly, however many frames of whatever length fed it. Adding
//! 1/60 s to an f32 every frame instead would lose about 2.8 s per hour of play.
//!
//! Each frame: the frame delta is clamped to `max_frame_delta` (default 250 ms, so a debugger
//! pause or a 5 s hitch cannot demand hundreds of ticks), scaled by `time_scale`, added to the
//! accumulator; whole timesteps come out as ticks, at most `max_steps_per_frame` (default 8), and
//! whole timesteps beyond the cap are dropped rather than carried (no spiral of death). Both kinds
//! of dropped time are counted. What is left is the fraction `alpha` of a tick, used to draw
//! between the previous and the current state.
//!
//! How the delta becomes ticks is the clock's [`LoopPolicy`] ([`policy`]): the plain
//! accumulator by default, or snapping, quantising or hysteresis; a policy never changes what a
//! tick computes.
//!
//! Frame deltas come from a [`FrameSource`]: the real monotonic clock in the window, or virtual
//! clocks (steady, seeded jitter, a hitch, a script) in headless runs and tests, which drive
//! this very clock.

use std::time::Duration;

use crate::instant::Instant;

use crate::rng::SplitMix64;

pub mod policy;

pub use policy::LoopPolicy;
use policy::PolicyState;

/// `a / b` in whole nanoseconds. Both fit 64 bits in any real run (584 years), and a 64-bit
/// division is several times cheaper than the 128-bit one `as_nanos` implies; the result is
/// the same integer either way.
#[inline]
fn whole_steps(a: Duration, b: Duration) -> u128 {
    let nanos = |d: Duration| {
        d.as_secs()
            .checked_mul(1_000_000_000)
            .and_then(|n| n.checked_add(u64::from(d.subsec_nanos())))
    };
    match (nanos(a), nanos(b)) {
        (Some(a), Some(b)) => u128::from(a / b),
        _ => a.as_nanos() / b.as_nanos(),
    }
}

/// Nanoseconds as f64, rounded once: through i64 when they fit (the same value as the u128
/// conversion, which costs a library call).
#[inline]
fn nanos_f64(d: Duration) -> f64 {
    let whole = i64::try_from(d.as_secs())
        .ok()
        .and_then(|s| s.checked_mul(1_000_000_000))
        .and_then(|n| n.checked_add(i64::from(d.subsec_nanos())));
    match whole {
        Some(n) => n as f64,
        None => d.as_nanos() as f64,
    }
}

/// Default clamp on one frame's delta: a quarter second.
pub const DEFAULT_MAX_FRAME_DELTA: Duration = Duration::from_millis(250);
/// Default cap on ticks per frame.
///
/// 8 ticks of a 60 Hz scene is 133 ms of sim time per frame: enough to catch up from a missed
/// frame or two at any display rate down to 8 Hz, small enough that a slow machine degrades to
/// slow motion instead of freezing.
pub const DEFAULT_MAX_STEPS_PER_FRAME: u32 = 8;

/// What one call to [`FixedClock::advance`] decided.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameTicks {
    /// Ticks to run this frame.
    pub steps: u32,
    /// Fraction of a tick left in the accumulator after them, in [0, 1).
    pub alpha: f64,
    /// Time dropped this frame (clamp plus cap).
    pub dropped: Duration,
}

/// Fixed-timestep accumulator.
#[derive(Clone, Debug, PartialEq)]
pub struct FixedClock {
    timestep: Duration,
    accumulator: Duration,
    /// Largest frame delta taken as is; longer frames are clamped to it.
    pub max_frame_delta: Duration,
    /// Most ticks one frame may run.
    pub max_steps_per_frame: u32,
    time_scale: f64,
    paused: bool,
    pending_steps: u32,
    tick: u64,
    dropped: Duration,
    last: FrameTicks,
    policy: LoopPolicy,
    policy_state: PolicyState,
}

/// Why a clock setting was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClockError {
    /// A time scale that is not a finite number from 0 to 100 (the value given).
    TimeScale(f64),
}

impl std::fmt::Display for ClockError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ClockError::TimeScale(_) => f.write_str("time scale must be a number from 0 to 100"),
        }
    }
}

impl std::error::Error for ClockError {}

impl FixedClock {
    /// A clock at tick 0 with the default clamp and cap. `timestep` must be at least 1 ns.
    pub fn new(timestep: Duration) -> FixedClock {
        FixedClock {
            timestep: timestep.max(Duration::from_nanos(1)),
            accumulator: Duration::ZERO,
            max_frame_delta: DEFAULT_MAX_FRAME_DELTA,
            max_steps_per_frame: DEFAULT_MAX_STEPS_PER_FRAME,
            time_scale: 1.0,
            paused: false,
            pending_steps: 0,
            tick: 0,
            dropped: Duration::ZERO,
            last: FrameTicks::default(),
            policy: LoopPolicy::Accumulator,
            policy_state: PolicyState::new(),
        }
    }

    /// The loop policy: how a frame's delta becomes ticks.
    pub fn policy(&self) -> LoopPolicy {
        self.policy
    }

    /// Changes the loop policy; what the old one carried (a history, a leftover) is forgotten,
    /// the accumulator and the tick are kept.
    pub fn set_policy(&mut self, policy: LoopPolicy) {
        self.policy = policy;
        self.policy_state = PolicyState::new();
    }

    /// Takes one frame's delta and returns how many ticks to run.
    pub fn advance(&mut self, frame_delta: Duration) -> FrameTicks {
        let mut dropped = Duration::ZERO;
        let steps = if self.paused {
            std::mem::take(&mut self.pending_steps)
        } else {
            let delta = if frame_delta > self.max_frame_delta {
                dropped += frame_delta - self.max_frame_delta;
                self.max_frame_delta
            } else {
                frame_delta
            };
            let delta = self.scale(delta);
            let due = match self.policy {
                LoopPolicy::Accumulator => {
                    self.accumulator += delta;
                    whole_steps(self.accumulator, self.timestep)
                }
                LoopPolicy::Snap {
                    refresh,
                    tolerance,
                    average,
                } => {
                    self.accumulator +=
                        policy::snap(&mut self.policy_state, delta, refresh, tolerance, average);
                    whole_steps(self.accumulator, self.timestep)
                }
                LoopPolicy::Quantise { refresh } => {
                    self.accumulator += policy::quantise(&mut self.policy_state, delta, refresh);
                    whole_steps(self.accumulator, self.timestep)
                }
                LoopPolicy::Hysteresis { jitter_fix } => {
                    let (due, left) = policy::hysteresis(
                        &mut self.policy_state,
                        self.accumulator,
                        delta,
                        self.timestep,
                        jitter_fix,
                    );
                    // The accumulator holds what is past the ticks it grants.
                    self.accumulator = left + self.timestep * due as u32;
                    u128::from(due)
                }
            };
            let steps = due.min(u128::from(self.max_steps_per_frame)) as u32;
            // Whole steps beyond the cap are dropped; the fraction of a step is kept.
            let over = (due - u128::from(steps)) as u32;
            dropped += self.timestep * over;
            self.accumulator -= self.timestep * (steps + over);
            steps
        };
        self.tick += u64::from(steps);
        self.dropped += dropped;
        self.last = FrameTicks {
            steps,
            alpha: self.alpha(),
            dropped,
        };
        self.last
    }

    /// Takes back `n` ticks the last frame granted but the caller did not run (a run that stops
    /// at a given tick): they go back into the accumulator, not into the dropped time.
    pub fn return_ticks(&mut self, n: u32) {
        let n = n.min(self.last.steps);
        self.tick -= u64::from(n);
        self.accumulator += self.timestep * n;
        self.last.steps -= n;
        self.last.alpha = self.alpha();
    }

    fn scale(&self, delta: Duration) -> Duration {
        if self.time_scale == 1.0 {
            delta
        } else {
            Duration::from_nanos((delta.as_nanos() as f64 * self.time_scale).round() as u64)
        }
    }

    /// Moves the clock to `tick` (after a seek on the timeline): the accumulator is emptied, so
    /// the state is drawn at that tick; pause, time scale and the dropped time are kept.
    pub fn set_tick(&mut self, tick: u64) {
        self.tick = tick;
        self.accumulator = Duration::ZERO;
        self.pending_steps = 0;
        self.last = FrameTicks::default();
    }

    /// Fraction of a tick in the accumulator, in [0, 1): how far past the current tick the
    /// displayed state should be drawn.
    pub fn alpha(&self) -> f64 {
        nanos_f64(self.accumulator) / nanos_f64(self.timestep)
    }

    /// The timestep.
    pub fn timestep(&self) -> Duration {
        self.timestep
    }

    /// Ticks issued so far.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// Sim time elapsed since tick 0, exactly `tick * timestep`.
    pub fn elapsed(&self) -> Duration {
        // Duration * u32 only; the product of u64 ticks and the step is formed in u128 nanos.
        let nanos = u128::from(self.tick) * self.timestep.as_nanos();
        Duration::new(
            (nanos / 1_000_000_000) as u64,
            (nanos % 1_000_000_000) as u32,
        )
    }

    /// Time in the accumulator.
    pub fn accumulator(&self) -> Duration {
        self.accumulator
    }

    /// Total time dropped by the clamp and the cap.
    pub fn dropped(&self) -> Duration {
        self.dropped
    }

    /// The last frame's decision.
    pub fn last_frame(&self) -> FrameTicks {
        self.last
    }

    /// Stops ticking; frame time passes without accumulating.
    pub fn pause(&mut self) {
        self.paused = true;
    }

    /// Resumes ticking from the accumulator as it was.
    pub fn resume(&mut self) {
        self.paused = false;
        self.pending_steps = 0;
    }

    /// Whether the clock is paused.
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// Pauses (if running) and queues exactly one tick for the next frame.
    pub fn single_step(&mut self) {
        self.paused = true;
        self.pending_steps += 1;
    }

    /// Speed of sim time relative to frame time (1 = real time).
    pub fn time_scale(&self) -> f64 {
        self.time_scale
    }

    /// Sets the time scale: finite and from 0 to 100.
    pub fn set_time_scale(&mut self, scale: f64) -> Result<(), ClockError> {
        if scale.is_finite() && (0.0..=100.0).contains(&scale) {
            self.time_scale = scale;
            Ok(())
        } else {
            Err(ClockError::TimeScale(scale))
        }
    }
}

/// Where frame deltas come from.
pub trait FrameSource {
    /// The time since the previous frame.
    fn next_delta(&mut self) -> Duration;
}

/// The real monotonic clock: the delta is the wall time since the previous call.
#[derive(Debug)]
pub struct RealClock {
    last: Option<Instant>,
}

impl RealClock {
    /// A real clock; its first delta is zero.
    pub fn new() -> RealClock {
        RealClock { last: None }
    }
}

impl Default for RealClock {
    fn default() -> Self {
        RealClock::new()
    }
}

impl FrameSource for RealClock {
    fn next_delta(&mut self) -> Duration {
        let now = Instant::now();
        let delta = self.last.map_or(Duration::ZERO, |l| now - l);
        self.last = Some(now);
        delta
    }
}

/// A virtual clock: scripted frame deltas, for headless runs and tests.
#[derive(Clone, Debug)]
pub enum VirtualClock {
    /// Every frame the same length (a display at a fixed rate).
    Steady(Duration),
    /// Frames of `base +- spread`, uniform, from a seeded generator.
    Jitter {
        /// Mean frame length.
        base: Duration,
        /// Largest deviation.
        spread: Duration,
        /// Generator state.
        rng: SplitMix64,
    },
    /// Steady frames with one long frame at index `at`.
    Hitch {
        /// Normal frame length.
        base: Duration,
        /// Frame index (0-based) of the hitch.
        at: u64,
        /// Length of the hitch frame.
        length: Duration,
        /// Frames produced so far.
        frame: u64,
    },
    /// Frame lengths from a list, repeated.
    Script {
        /// The lengths.
        deltas: Vec<Duration>,
        /// Next index.
        next: usize,
    },
}

impl VirtualClock {
    /// A display refreshing at `hz` frames per second, rounded to whole nanoseconds.
    pub fn display(hz: f64) -> VirtualClock {
        VirtualClock::Steady(Duration::from_nanos((1e9 / hz).round() as u64))
    }
}

impl FrameSource for VirtualClock {
    fn next_delta(&mut self) -> Duration {
        match self {
            VirtualClock::Steady(d) => *d,
            VirtualClock::Jitter { base, spread, rng } => {
                let offset = spread.as_nanos() as f64 * rng.next_signed();
                Duration::from_nanos((base.as_nanos() as f64 + offset).max(0.0).round() as u64)
            }
            VirtualClock::Hitch {
                base,
                at,
                length,
                frame,
            } => {
                let d = if *frame == *at { *length } else { *base };
                *frame += 1;
                d
            }
            VirtualClock::Script { deltas, next } => {
                let d = deltas.get(*next).copied().unwrap_or(Duration::ZERO);
                *next = (*next + 1) % deltas.len().max(1);
                d
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nanosecond_shortcuts_equal_the_u128_arithmetic() {
        let big = Duration::new(u64::MAX / 1_000_000_000 + 7, 999_999_999);
        let samples = [
            Duration::ZERO,
            Duration::from_nanos(1),
            Duration::from_nanos(16_666_667),
            Duration::new(5, 123_456_789),
            Duration::new(i64::MAX as u64 / 1_000_000_000, 999_999_999),
            big,
        ];
        for a in samples {
            assert_eq!(nanos_f64(a), a.as_nanos() as f64, "{a:?}");
            for b in samples.iter().filter(|b| !b.is_zero()) {
                assert_eq!(
                    whole_steps(a, *b),
                    a.as_nanos() / b.as_nanos(),
                    "{a:?} / {b:?}"
                );
            }
        }
    }
}
