//! Loop policies: how a frame's measured delta becomes ticks.
//!
//! A policy decides how many ticks a frame runs and how far past the last tick the frame is
//! drawn (the clock's alpha). It never changes what a tick computes: the state and the hash at
//! every tick are the same under every policy, only the ticks' grouping into frames differs.
//!
//! Every policy works in integer nanoseconds. The four kinds, each after its source:
//!
//! - [`LoopPolicy::Accumulator`]: the plain accumulator of Glenn Fiedler's "Fix Your Timestep!"
//!   (gafferongames.com, 2004): the delta as measured. With a noisy frame clock whose samples
//!   fall near a tick boundary it runs 0 ticks one frame and 2 the next.
//! - [`LoopPolicy::Snap`]: Tyler Glaiel's vsync snapping ("How to make your game run at 60fps",
//!   2019, and `frame_timer.cpp` in TylerGlaiel/FrameTimingControl): a delta within `tolerance`
//!   of 1 to 4 refresh intervals (or half of one) is taken as exactly that, then optionally
//!   averaged over the last `average` deltas with the division's remainder carried, so no time
//!   is lost to rounding. Removes the 0/2 swings; on a display slower than `refresh` (59.94 Hz
//!   taken as 60) game time runs slower than wall time without bound.
//! - [`LoopPolicy::Quantise`]: rounding to whole refresh intervals with the remainder carried
//!   (Frank Force's frame-rate delta buffering; the core of Godot's `DeltaSmoother`,
//!   `main/main_timer_sync.cpp`, PR #48390): `leftover += delta`, `units = max(1, leftover /
//!   refresh)`, `leftover -= units * refresh`. Deltas under 1 ms or over 1 s pass unchanged, as in
//!   Godot. Game time stays within about one refresh of wall time; a display whose true rate is
//!   not `refresh` gets one two-interval delta each time the leftover reaches an interval.
//! - [`LoopPolicy::Hysteresis`]: Godot's `physics_jitter_fix` (`MainTimerSync::advance_core`
//!   and `advance_checked`, PR #17353), ported to integer nanoseconds: the tick count of each
//!   frame is kept consistent with the typical counts of the last 1 to 12 frames, bent within
//!   `floor(accumulated / dt +- jitter_fix)`, and the difference between game time and wall time
//!   (Godot's `time_deficit`) is kept within `jitter_fix * dt`.
//!
//! The refresh interval a policy snaps or rounds to is what the game believes the display runs
//! at. Glaiel's code hard-codes 60 Hz and Godot's estimator rounds to whole frames per second,
//! so the loop lab gives these policies the display's rate rounded to whole hertz: a 59.94 Hz
//! display is taken as 60 Hz, which is where their trade-offs show.

use std::time::Duration;

/// Godot's control window: the tick counts of the last 12 frames (`CONTROL_STEPS`).
const CONTROL_STEPS: usize = 12;

/// How a frame's delta becomes ticks. Plain data; the state a policy carries from frame to frame
/// lives in the clock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LoopPolicy {
    /// The delta as measured (Fiedler).
    #[default]
    Accumulator,
    /// Deltas near whole refresh intervals snapped to them, then averaged (Glaiel).
    Snap {
        /// The refresh interval the game believes in.
        refresh: Duration,
        /// How close a delta must be to a multiple of `refresh` to be snapped (Glaiel: 0.2 ms).
        tolerance: Duration,
        /// Deltas averaged, 1 for none (Glaiel: 4).
        average: u32,
    },
    /// Deltas rounded to whole refresh intervals, the remainder carried (Force; Godot's
    /// delta smoother).
    Quantise {
        /// The refresh interval the game believes in.
        refresh: Duration,
    },
    /// Hysteresis on the tick count with |game time - wall time| bounded (Godot's
    /// `physics_jitter_fix`).
    Hysteresis {
        /// The bound, as a fraction of a tick (Godot's default: 0.5).
        jitter_fix: f64,
    },
}

impl LoopPolicy {
    /// Glaiel's snapping at `refresh`: 0.2 ms tolerance, averaged over 4 deltas.
    pub fn glaiel(refresh: Duration) -> LoopPolicy {
        LoopPolicy::Snap {
            refresh,
            tolerance: Duration::from_micros(200),
            average: 4,
        }
    }

    /// Godot's jitter fix at its default, 0.5 of a tick.
    pub fn godot() -> LoopPolicy {
        LoopPolicy::Hysteresis { jitter_fix: 0.5 }
    }

    /// The short name the command line and the tables use: `accumulator`, `snap`, `snap-avg`,
    /// `quantise`, `hysteresis`.
    pub fn name(&self) -> &'static str {
        match self {
            LoopPolicy::Accumulator => "accumulator",
            LoopPolicy::Snap { average, .. } if *average > 1 => "snap-avg",
            LoopPolicy::Snap { .. } => "snap",
            LoopPolicy::Quantise { .. } => "quantise",
            LoopPolicy::Hysteresis { .. } => "hysteresis",
        }
    }

    /// The policy called `name` (see [`LoopPolicy::name`]), with `refresh` for the ones that
    /// need the display's interval and their sources' defaults otherwise.
    pub fn from_name(name: &str, refresh: Duration) -> Option<LoopPolicy> {
        Some(match name {
            "accumulator" => LoopPolicy::Accumulator,
            "snap" => LoopPolicy::Snap {
                refresh,
                tolerance: Duration::from_micros(200),
                average: 1,
            },
            "snap-avg" => LoopPolicy::glaiel(refresh),
            "quantise" => LoopPolicy::Quantise { refresh },
            "hysteresis" => LoopPolicy::godot(),
            _ => return None,
        })
    }

    /// Every policy name, in the order the tables list them.
    pub const NAMES: [&'static str; 5] =
        ["accumulator", "snap", "snap-avg", "quantise", "hysteresis"];

    /// The same policy with its refresh interval replaced (a display change).
    pub fn with_refresh(self, refresh: Duration) -> LoopPolicy {
        match self {
            LoopPolicy::Snap {
                tolerance, average, ..
            } => LoopPolicy::Snap {
                refresh,
                tolerance,
                average,
            },
            LoopPolicy::Quantise { .. } => LoopPolicy::Quantise { refresh },
            other => other,
        }
    }
}

/// What a policy carries from one frame to the next.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PolicyState {
    /// Snap: the last snapped deltas (ns), newest last, at most `average` of them.
    history: Vec<i64>,
    /// Snap: the remainder of the averaging division; Quantise: the leftover time (ns).
    carry: i64,
    /// Hysteresis: Godot's `typical_physics_steps`, `accumulated_physics_steps`, `time_deficit`.
    typical: [i64; CONTROL_STEPS],
    accumulated: [i64; CONTROL_STEPS],
    deficit: i64,
}

impl PolicyState {
    pub(crate) fn new() -> PolicyState {
        let ramp: [i64; CONTROL_STEPS] = std::array::from_fn(|i| i as i64);
        PolicyState {
            history: Vec::new(),
            carry: 0,
            typical: ramp,
            accumulated: ramp,
            deficit: 0,
        }
    }
}

fn ns(d: Duration) -> i64 {
    i64::try_from(d.as_nanos()).unwrap_or(i64::MAX)
}

fn dur(n: i64) -> Duration {
    Duration::from_nanos(n.max(0) as u64)
}

/// Snap then average (Glaiel): the delta the accumulator takes.
pub(crate) fn snap(
    state: &mut PolicyState,
    delta: Duration,
    refresh: Duration,
    tolerance: Duration,
    average: u32,
) -> Duration {
    let (d, r, tol) = (ns(delta), ns(refresh).max(1), ns(tolerance));
    // Glaiel's snap list: 1 to 4 refresh intervals and half of one (a 120 Hz display under a
    // 60 Hz belief).
    let candidates = [r, 2 * r, 3 * r, 4 * r, (r + 1) / 2];
    let snapped = candidates
        .into_iter()
        .find(|c| (d - c).abs() < tol)
        .unwrap_or(d);
    let n = average.max(1) as usize;
    if n == 1 {
        return dur(snapped);
    }
    // Glaiel's history starts filled with the ideal interval, so the first frames average
    // against it instead of against nothing.
    if state.history.is_empty() {
        state.history = vec![r; n];
    }
    state.history.push(snapped);
    if state.history.len() > n {
        state.history.remove(0);
    }
    let count = state.history.len() as i64;
    let sum: i64 = state.history.iter().sum();
    let mut out = sum / count;
    state.carry += sum % count;
    out += state.carry / count;
    state.carry %= count;
    dur(out)
}

/// Round to whole refresh intervals, carrying the remainder (Force; Godot's smoother).
pub(crate) fn quantise(state: &mut PolicyState, delta: Duration, refresh: Duration) -> Duration {
    let (d, r) = (ns(delta), ns(refresh).max(1));
    // Godot passes deltas over 1 s (a resume) and under 1 ms (vsync off) back unmodified.
    if !(1_000_000..=1_000_000_000).contains(&d) {
        return delta;
    }
    state.carry += d;
    let units = (state.carry / r).max(1);
    state.carry -= units * r;
    dur(units * r)
}

fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

/// Godot's jitter fix: `advance_checked` around `advance_core`, in nanoseconds. Takes the
/// accumulator (ns, in [0, dt)) and the frame's delta; returns the ticks and the new
/// accumulator.
pub(crate) fn hysteresis(
    state: &mut PolicyState,
    accumulator: Duration,
    delta: Duration,
    timestep: Duration,
    jitter_fix: f64,
) -> (u64, Duration) {
    let h = ns(timestep).max(1);
    let jitter = (jitter_fix * h as f64).round() as i64;
    let raw = ns(delta);
    let min_output = (raw / 8).max(1_000);
    // Compensate for the last frame's deficit.
    let p = raw + state.deficit;

    // advance_core
    let mut acc = ns(accumulator) + p;
    let mut steps = floor_div(acc, h);
    let mut min_typical = state.typical[0];
    let mut max_typical = min_typical + 1;
    let mut update_typical = false;
    for i in 0..CONTROL_STEPS - 1 {
        let left = state.typical[i + 1] - state.accumulated[i];
        if left > max_typical || left + 1 < min_typical {
            update_typical = true;
            break;
        }
        min_typical = min_typical.max(left);
        max_typical = max_typical.min(left + 1);
    }
    if steps < min_typical {
        let most = floor_div(acc + jitter, h);
        if most < min_typical {
            steps = most;
            update_typical = true;
        } else {
            steps = min_typical;
        }
    } else if steps > max_typical {
        let least = floor_div(acc - jitter, h);
        if least > max_typical {
            steps = least;
            update_typical = true;
        } else {
            steps = max_typical;
        }
    }
    steps = steps.max(0);
    acc -= steps * h;
    for i in (0..CONTROL_STEPS - 1).rev() {
        state.accumulated[i + 1] = state.accumulated[i] + steps;
    }
    state.accumulated[0] = steps;
    if update_typical {
        for i in (0..CONTROL_STEPS).rev() {
            if state.typical[i] > state.accumulated[i] {
                state.typical[i] = state.accumulated[i];
            } else if state.typical[i] < state.accumulated[i] - 1 {
                state.typical[i] = state.accumulated[i] - 1;
            }
        }
    }

    // advance_checked: clamp the frame's game-time step, keeping the accumulator in step.
    let process_minus_acc = p - acc;
    let mut out = p;
    if let Some((lo, hi)) = average_steps(state) {
        out = clamp_step(out, (lo * h as f64) as i64, (hi * h as f64) as i64);
    }
    let deviation = jitter;
    out = clamp_step(out, p - deviation, p + deviation);
    out = clamp_step(out, process_minus_acc, process_minus_acc + h);
    out = out.max(min_output);
    acc = out - process_minus_acc;
    if acc > h {
        let extra = floor_div(acc, h);
        acc -= extra * h;
        steps += extra;
    }
    state.deficit = p - out;
    (steps as u64, dur(acc))
}

/// Godot's `clamp_process_step`: below `lo` becomes `lo`, else above `hi` becomes `hi`.
fn clamp_step(x: i64, lo: i64, hi: i64) -> i64 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

/// Godot's `get_average_physics_steps`: the range of average ticks per frame consistent with
/// the typical counts, when more than 3 frames back agree.
fn average_steps(state: &PolicyState) -> Option<(f64, f64)> {
    let mut lo = state.typical[0] as f64;
    let mut hi = lo + 1.0;
    let mut consistent = CONTROL_STEPS;
    for i in 1..CONTROL_STEPS {
        let typical = state.typical[i] as f64;
        let current_min = typical / (i + 1) as f64;
        if current_min > hi {
            consistent = i;
            break;
        } else if current_min > lo {
            lo = current_min;
        }
        let current_max = (typical + 1.0) / (i + 1) as f64;
        if current_max < lo {
            consistent = i;
            break;
        } else if current_max < hi {
            hi = current_max;
        }
    }
    (consistent > 3).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn snapping_takes_a_delta_near_a_refresh_as_the_refresh() {
        let mut s = PolicyState::new();
        let r = Duration::from_nanos(16_666_667);
        let d = snap(&mut s, Duration::from_nanos(16_683_350), r, MS / 5, 1);
        assert_eq!(d, r);
        let far = Duration::from_nanos(17_000_000);
        assert_eq!(snap(&mut s, far, r, MS / 5, 1), far);
    }

    #[test]
    fn averaging_a_steady_display_gives_its_snapped_interval_every_frame() {
        let mut s = PolicyState::new();
        let r = Duration::from_nanos(16_666_667);
        for _ in 0..20 {
            assert_eq!(
                snap(&mut s, Duration::from_nanos(16_683_350), r, MS / 5, 4),
                r
            );
        }
        // Unequal deltas: the average with its remainder carried spends, over the window, what
        // came in (the 4-frame window here ends full, so nothing is pending but the remainder).
        let mut s = PolicyState::new();
        let deltas = [15, 18, 17, 16, 19, 14, 17, 16].map(|m| MS * m + Duration::from_nanos(1));
        let out: Vec<Duration> = deltas
            .iter()
            .map(|&d| snap(&mut s, d, r, MS / 5, 4))
            .collect();
        assert_eq!(
            out[7],
            (MS * (19 + 14 + 17 + 16) + Duration::from_nanos(4)) / 4
        );
        assert!((0..4).contains(&s.carry));
    }

    #[test]
    fn quantising_carries_the_remainder() {
        let mut s = PolicyState::new();
        let r = Duration::from_nanos(16_666_667);
        let d = Duration::from_nanos(16_683_350); // 59.94 Hz
        let mut two = 0;
        let mut total = Duration::ZERO;
        for _ in 0..2000 {
            let q = quantise(&mut s, d, r);
            assert!(q == r || q == 2 * r, "{q:?}");
            two += usize::from(q == 2 * r);
            total += q;
        }
        // 2000 frames of 59.94 Hz are 33.367 s; quantised, within one interval of it.
        assert_eq!(two, 2);
        let wall = d * 2000;
        assert!(wall.abs_diff(total) < r, "{total:?} vs {wall:?}");
    }

    #[test]
    fn hysteresis_keeps_one_tick_a_frame_on_a_noisy_clock_at_the_tick_rate() {
        let mut s = PolicyState::new();
        let h = Duration::from_nanos(16_666_667);
        let mut acc = Duration::ZERO;
        let mut ticks = Vec::new();
        // Alternating +-0.5 ms around 60 Hz: the plain accumulator would swing 0/2 near a tick
        // boundary; the jitter fix runs one tick a frame once its history has settled.
        for i in 0..240 {
            let d = if i % 2 == 0 { h + MS / 2 } else { h - MS / 2 };
            let (n, a) = hysteresis(&mut s, acc, d, h, 0.5);
            acc = a;
            ticks.push(n);
        }
        assert!(ticks[24..].iter().all(|&n| n == 1), "{ticks:?}");
    }
}
