//! The one-dimensional search over arrival time: a log-spaced scan, the slowest shot, golden
//! section and bracketed roots, and what to say when the target is out of reach.

use super::*;

/// One sample of the scan: an arrival time and its launch, if the solve succeeded.
#[derive(Clone, Copy)]
pub(super) struct Sample {
    pub(super) t: f64,
    pub(super) v: Option<DVec3>,
}

impl Sample {
    pub(super) fn speed(&self) -> f64 {
        self.v.map_or(f64::INFINITY, DVec3::length)
    }
}

/// The scan, and the first failure among its arrival times (if any failed).
pub(super) fn scan(range: &Range, shooter: &dyn Shooter) -> (Vec<Sample>, Option<FiringError>) {
    let (lo, hi) = (MIN_FLIGHT_TIME, range.max_flight_time);
    let mut first_error = None;
    let samples: Vec<Sample> = (0..SCAN_POINTS)
        .map(|k| {
            let t = if k + 1 == SCAN_POINTS {
                hi
            } else {
                lo * libm::pow(hi / lo, k as f64 / (SCAN_POINTS - 1) as f64)
            };
            let v = shooter
                .launch_for(t)
                .map_err(|e| {
                    first_error.get_or_insert(e);
                })
                .ok();
            Sample { t, v }
        })
        .collect();
    (samples, first_error)
}

/// The arrival time minimising `|v(T)|` near the slowest sample, by golden-section search.
pub(super) fn slowest(samples: &[Sample], shooter: &dyn Shooter) -> Option<Sample> {
    let k = (0..samples.len())
        .filter(|&k| samples[k].v.is_some())
        .min_by(|&a, &b| samples[a].speed().total_cmp(&samples[b].speed()))?;
    let bracket = (
        samples[k.saturating_sub(1)].t,
        samples[(k + 1).min(samples.len() - 1)].t,
    );
    let speed = |t: f64| shooter.launch_for(t).map_or(f64::INFINITY, |v| v.length());
    let (t, _) = golden(speed, bracket, 1e-13 * bracket.1);
    let best = Sample {
        t,
        v: shooter.launch_for(t).ok(),
    };
    Some(if best.speed() <= samples[k].speed() {
        best
    } else {
        samples[k]
    })
}

/// The minimum of `f` on `[a, b]` by golden-section search, until the bracket is below `tol`
/// (at most 200 steps): returns `(x, f(x))` at the bracket's middle.
pub(super) fn golden(
    mut f: impl FnMut(f64) -> f64,
    (mut a, mut b): (f64, f64),
    tol: f64,
) -> (f64, f64) {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    let x = 0.5 * (a + b);
    (x, f(x))
}

/// The root of `f` in the bracket `(a, b)` (values of opposite sign), then the launch there.
pub(super) fn root(
    shooter: &dyn Shooter,
    f: impl Fn(&Sample) -> f64,
    a: Sample,
    b: Sample,
) -> Result<(f64, DVec3), FiringError> {
    let value = |t: f64| {
        f(&Sample {
            t,
            v: shooter.launch_for(t).ok(),
        })
    };
    let (t, _) = bracketed_root(value, (a.t, f(&a)), (b.t, f(&b)));
    Ok((t, shooter.launch_for(t)?))
}

/// What the solve found, before the checks: kind, arrival time, launch.
pub(super) type Found = Vec<(ShotKind, f64, DVec3)>;

pub(super) fn solve_with(
    range: &Range,
    mode: Mode,
    shooter: &dyn Shooter,
) -> Result<Found, FiringError> {
    let (mut samples, failure) = scan(range, shooter);
    // Where no arrival time could be solved, the solver's own failure is the answer, except
    // at a given speed, where an independent search says whether the target is in reach.
    let nothing = samples.iter().all(|s| s.v.is_none());
    if let (true, Some(e), false) = (nothing, &failure, matches!(mode, Mode::Speed(_))) {
        return Err(e.clone());
    }
    match mode {
        Mode::MinSpeed => {
            let best =
                slowest(&samples, shooter).ok_or_else(|| out_of_reach(range, f64::NAN, None))?;
            let v = shooter.launch_for(best.t)?;
            Ok(vec![(ShotKind::MinSpeed, best.t, v)])
        }
        Mode::Speed(speed) => {
            if !(speed.is_finite() && speed > 0.0) {
                return Err(FiringError::Invalid(format!(
                    "speed: expected a positive number of m/s, got {speed}"
                )));
            }
            let best = slowest(&samples, shooter);
            let Some(best) = best.filter(|b| b.speed() <= speed) else {
                let answer = out_of_reach(range, speed, best.map(|b| b.speed()));
                // A shot at this speed that touches the target does reach it: then the solver
                // failed, and says where.
                if let (FiringError::OutOfReach { best_miss, .. }, Some(e)) = (&answer, failure)
                    && *best_miss <= range.target.radius + range.radius
                {
                    return Err(e);
                }
                return Err(answer);
            };
            let at = samples.partition_point(|s| s.t < best.t);
            samples.insert(at, best);
            let f = |s: &Sample| s.speed() - speed;
            let mut found = Vec::new();
            // Low arc: the last sample before the minimum still too slow to need... the last
            // one above the speed, going down towards the minimum.
            if let Some(k) = (0..at).rev().find(|&k| f(&samples[k]) > 0.0) {
                let (t, v) = root(shooter, f, samples[k], samples[k + 1])?;
                found.push((ShotKind::Arc(Arc::Low), t, v));
            }
            if let Some(k) = (at + 1..samples.len()).find(|&k| f(&samples[k]) > 0.0) {
                let (t, v) = root(shooter, f, samples[k - 1], samples[k])?;
                found.push((ShotKind::Arc(Arc::High), t, v));
            }
            // High arc first, as `exact::aim` orders them.
            found.reverse();
            Ok(found)
        }
        Mode::Elevation(elevation) => {
            if !(elevation.is_finite() && elevation.abs() <= 90.0) {
                return Err(FiringError::Invalid(format!(
                    "elevation: expected -90 to 90 degrees, got {elevation}"
                )));
            }
            let d = range.target.center - range.from;
            let a = range.scene.forces.linear_part(range.mass).a0;
            let straight_up = d.x == 0.0 && d.y == 0.0;
            if straight_up
                && a.x == 0.0
                && a.y == 0.0
                && range.target.velocity.truncate() == glam::DVec2::ZERO
            {
                let min_speed = slowest(&samples, shooter).map_or(f64::NAN, |s| s.speed());
                return Err(FiringError::VerticalNeedsSpeed { min_speed });
            }
            let elevation_of = |s: &Sample| s.v.map_or(90.0, |v| angles_of(v).0);
            let f = |s: &Sample| elevation_of(s) - elevation;
            let valid: Vec<&Sample> = samples.iter().filter(|s| s.v.is_some()).collect();
            let lowest = valid.first().map_or(f64::NAN, |s| elevation_of(s));
            let highest = valid
                .iter()
                .map(|s| elevation_of(s))
                .fold(f64::NEG_INFINITY, f64::max);
            let k = (1..samples.len()).find(|&k| {
                samples[k - 1].v.is_some() && f(&samples[k - 1]) < 0.0 && f(&samples[k]) >= 0.0
            });
            let Some(k) = k else {
                return Err(FiringError::NoArcAtElevation {
                    elevation_deg: elevation,
                    lowest_deg: lowest,
                    highest_deg: highest,
                });
            };
            let (t, v) = root(shooter, f, samples[k - 1], samples[k])?;
            Ok(vec![(ShotKind::Elevation, t, v)])
        }
    }
}

/// The out-of-reach answer at `speed`, with the closest shot at that speed.
pub(super) fn out_of_reach(range: &Range, speed: f64, min_speed: Option<f64>) -> FiringError {
    let (best_miss, best_elevation_deg) = if speed.is_finite() {
        best_miss(range, speed)
    } else {
        (f64::NAN, f64::NAN)
    };
    FiringError::OutOfReach {
        speed,
        min_speed: min_speed.filter(|v| v.is_finite()),
        best_miss,
        best_elevation_deg,
    }
}

/// The closest the stepped shot gets to the target at `speed`: the best of a 5 degree grid of
/// elevations towards the target, then golden-section searches on elevation and azimuth in
/// turn (six rounds, the windows shrinking), so a crosswind's drift is searched out too.
/// Returns (miss, elevation).
pub(super) fn best_miss(range: &Range, speed: f64) -> (f64, f64) {
    let d = range.target.center - range.from;
    let miss_at = |elevation: f64, azimuth: f64| {
        let v = crate::scene::angles_to_velocity(speed, elevation, azimuth);
        closest_approach(range, v, range.max_flight_time).map_or(f64::INFINITY, |(m, _)| m)
    };
    let mut azimuth = libm::atan2(d.y, d.x).to_degrees();
    let (mut best, mut elevation) = (f64::INFINITY, 0.0);
    for k in 0..=36 {
        let e = -90.0 + 5.0 * k as f64;
        let m = miss_at(e, azimuth);
        if m < best {
            (best, elevation) = (m, e);
        }
    }
    let mut window = 5.0;
    for _ in 0..6 {
        let around = |x: f64, lo: f64, hi: f64| ((x - window).max(lo), (x + window).min(hi));
        let (e, m) = golden(
            |e| miss_at(e, azimuth),
            around(elevation, -90.0, 90.0),
            1e-9,
        );
        if m < best {
            (best, elevation) = (m, e);
        }
        let (a, m) = golden(
            |a| miss_at(elevation, a),
            around(azimuth, -360.0, 360.0),
            1e-9,
        );
        if m < best {
            (best, azimuth) = (m, a);
        }
        window *= 0.3;
    }
    (best, elevation)
}
