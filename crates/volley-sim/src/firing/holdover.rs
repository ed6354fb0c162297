//! Zeroing and the holdover table: the elevation that hits at each range along a level line of
//! sight, solved by shooting on the stepped trajectory (the scene's integrator at its tick),
//! beside the textbook (vacuum) aim's miss at the same range.

use super::*;

/// One range of a [`Holdover`] table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoldoverRow {
    /// Distance along the line of sight (m).
    pub range: f64,
    /// The shot that hits the line of sight there: the low arc at the launcher's speed.
    pub shot: Shot,
    /// Its elevation less the zero's (mrad): how far to hold over (positive) or under.
    pub hold_mrad: f64,
    /// The same in minutes of angle.
    pub hold_moa: f64,
    /// The same as a length at the target (m): `range * tan(hold)`.
    pub hold_at_target: f64,
    /// The zeroed shot's height against the line of sight at this range (m), read by the
    /// range table's `Downrange` event on its path ([`range_table`]); `NaN` if it fell short.
    pub path_height: f64,
    /// The hold a one-trajectory calculator prints from that height, `atan(-path_height /
    /// range)` (mrad): the zeroed path held up by the angle it is low, ignoring that a shot fired
    /// higher flies a slightly different path (the difference from `hold_mrad`).
    pub path_hold_mrad: f64,
}

/// A zero and the holdover table beside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Holdover {
    /// The zero range (m) and the elevation (degrees) that hits it: the zero.
    pub zero: (f64, f64),
    /// One row per range asked for, in that order.
    pub rows: Vec<HoldoverRow>,
}

/// Minutes of angle per milliradian: `10.8 / pi`.
pub const MOA_PER_MRAD: f64 = 10.8 / std::f64::consts::PI;

/// The point on the line of sight `range` m out: `sight_height` above the launcher's muzzle,
/// level, along the launcher's azimuth.
pub fn sight_point(scene: &Scene, sight_height: f64, range: f64) -> DVec3 {
    let l = &scene.launcher;
    let az = l.azimuth_deg.to_radians();
    l.position + DVec3::new(range * libm::cos(az), range * libm::sin(az), sight_height)
}

/// The zero (the elevation that hits the line of sight at `zero` m) and, for each of `ranges`,
/// the elevation that hits there and its hold against the zero, every shot fired from the
/// launcher at its speed and checked in a world, with the textbook aim's miss beside it.
/// The line of sight is level, `sight_height` m above the muzzle, along the launcher's
/// azimuth; contacts are off (a table is about the flight, not what stands in the way).
pub fn holdover(
    scene: &Scene,
    sight_height: f64,
    zero: f64,
    ranges: &[f64],
) -> Result<Holdover, FiringError> {
    for (name, x) in [("sight height", sight_height), ("zero", zero)] {
        if !x.is_finite() || (name == "zero" && x <= 0.0) {
            return Err(FiringError::Invalid(format!(
                "{name}: expected a finite number{}, got {x}",
                if name == "zero" { " > 0" } else { "" }
            )));
        }
    }
    if let Some(r) = ranges.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        return Err(FiringError::Invalid(format!(
            "range: expected finite numbers > 0 m, got {r}"
        )));
    }
    let hit = |range: f64| -> Result<Shot, FiringError> {
        let mut r = Range::new(
            scene,
            Target {
                center: sight_point(scene, sight_height, range),
                radius: 0.01,
                velocity: DVec3::ZERO,
            },
        );
        r.contacts = false;
        let shots = solve(&r, Mode::Speed(scene.launcher.speed))?;
        // The low arc; a lone solution (at the edge of reach) is both.
        let low = shots.iter().find(|s| s.kind == ShotKind::Arc(Arc::Low));
        low.or(shots.first()).copied().ok_or_else(|| {
            FiringError::Invalid(format!(
                "no launch at the launcher's speed reaches {range} m"
            ))
        })
    };
    let zero_shot = hit(zero)?;
    // The zeroed shot's own path, read at every range by the same declared events.
    let mut zeroed = scene.clone();
    zeroed.launcher.elevation_deg = zero_shot.elevation_deg;
    zeroed.launcher.azimuth_deg = zero_shot.azimuth_deg;
    let horizon = DEFAULT_MAX_FLIGHT_TIME;
    let path = range_table(&zeroed, ranges, horizon)?;
    let height_at = |range: f64| {
        path.rows
            .iter()
            .find(|r| r.range == range)
            .map_or(f64::NAN, |r| r.height - sight_height)
    };
    let rows = ranges
        .iter()
        .map(|&range| {
            let shot = hit(range)?;
            let hold = (shot.elevation_deg - zero_shot.elevation_deg).to_radians();
            let path_height = height_at(range);
            Ok(HoldoverRow {
                path_height,
                path_hold_mrad: libm::atan(-path_height / range) * 1e3,
                range,
                shot,
                hold_mrad: hold * 1e3,
                hold_moa: hold * 1e3 * MOA_PER_MRAD,
                hold_at_target: range * libm::tan(hold),
            })
        })
        .collect::<Result<Vec<_>, FiringError>>()?;
    Ok(Holdover {
        zero: (zero, zero_shot.elevation_deg),
        rows,
    })
}
