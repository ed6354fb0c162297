//! The range table every ballistic calculator prints: the launcher's shot read at chosen
//! distances downrange, each row the exact crossing of a declared [`EventCondition::Downrange`]
//! event on the integrator's own path (docs/physics.md, "Declared events"), not a tick's state
//! or an interpolation between ticks.

use super::*;
use crate::contact::{EventCondition, EventSpec, EventStop};

/// One range of a [`RangeTable`]: the shot's state where it crosses the plane `range` m
/// downrange of the muzzle (horizontally, along the launcher's azimuth).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeRow {
    /// Distance downrange (m).
    pub range: f64,
    /// Time after launch (s).
    pub time: f64,
    /// Position (m).
    pub position: DVec3,
    /// Velocity (m/s).
    pub velocity: DVec3,
    /// Height above the muzzle (m).
    pub height: f64,
    /// Height against the bore line, the launch direction's straight line (m): negative below
    /// it. For a level barrel this is the height.
    pub drop: f64,
    /// Sideways offset from the vertical plane of the launcher's azimuth (m): positive to the
    /// left looking downrange.
    pub windage: f64,
    /// Speed (m/s).
    pub speed: f64,
    /// Mach number in the air of the scene's Mach drag (its wind and its speed of sound at this
    /// height); `None` for a scene without one.
    pub mach: Option<f64>,
    /// Kinetic energy (J), `m v^2 / 2` with the shot's mass at the end of the tick of the
    /// crossing (the launcher's mass unless a motor burns).
    pub energy: f64,
}

/// A [`range_table`]: the rows of the ranges the shot reached, in the order asked, and the
/// ranges it did not reach within the longest flight.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeTable {
    /// One row per range reached.
    pub rows: Vec<RangeRow>,
    /// The ranges not reached (the shot fell short, turned back or ran out of flight time).
    pub unreached: Vec<f64>,
}

/// The range table of `scene`'s launcher (its muzzle, speed, elevation, azimuth, mass, size and
/// spin) at each of `ranges` (m, each > 0), under the scene's forces, integrator, tick and
/// substeps, for at most `max_flight_time` s. Contacts are off (a table is about the flight,
/// not what stands in the way), as for [`holdover`]. Each range is a declared `Downrange` event,
/// rising, on the one shot; the farthest stops the run.
pub fn range_table(
    scene: &Scene,
    ranges: &[f64],
    max_flight_time: f64,
) -> Result<RangeTable, FiringError> {
    if let Some(r) = ranges.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        return Err(FiringError::Invalid(format!(
            "range: expected finite numbers > 0 m, got {r}"
        )));
    }
    if !(max_flight_time.is_finite() && max_flight_time > 0.0) {
        return Err(FiringError::Invalid(format!(
            "max flight time: expected a finite number > 0 s, got {max_flight_time}"
        )));
    }
    if ranges.is_empty() {
        return Ok(RangeTable {
            rows: Vec::new(),
            unreached: Vec::new(),
        });
    }
    let launcher = scene.launcher;
    let far = ranges.iter().copied().fold(0.0, f64::max);
    let mut flight = scene.clone();
    flight.start_time = 0.0;
    flight.volley = None;
    flight.bodies = vec![launcher.body()];
    flight.ground = None;
    flight.walls.clear();
    flight.targets.clear();
    flight.meshes.clear();
    flight.heightfields.clear();
    flight.detection = crate::contact::Detection::Swept;
    flight.events = ranges
        .iter()
        .map(|&r| {
            let e = EventSpec::new(EventCondition::Downrange(r)).rising();
            if r == far {
                e.stopping(EventStop::Run(1))
            } else {
                e
            }
        })
        .collect();
    let mut world = World::new(&flight);
    let ticks = (max_flight_time / world.dt()).ceil().min(u32::MAX as f64) as u64;
    let mut found: Vec<Option<RangeRow>> = vec![None; ranges.len()];
    let az = launcher.azimuth_deg.to_radians();
    let el = launcher.elevation_deg.to_radians();
    let left = DVec3::new(-libm::sin(az), libm::cos(az), 0.0);
    let drag = flight.forces.mach_drag.clone();
    for _ in 0..ticks {
        if let Err(d) = world.step() {
            return Err(FiringError::Diverged {
                flight_time: world.time(),
                tick: Some(d.tick),
            });
        }
        let mass = world
            .bodies()
            .mass
            .first()
            .copied()
            .unwrap_or(launcher.mass);
        for e in world.events() {
            let EventKind::Declared { event, state, .. } = e.kind else {
                continue;
            };
            let slot = &mut found[event as usize];
            if slot.is_some() {
                continue;
            }
            let range = ranges[event as usize];
            let v = state.mv / mass;
            let d = state.p - launcher.position;
            let speed = v.length();
            *slot = Some(RangeRow {
                range,
                time: e.time,
                position: state.p,
                velocity: v,
                height: d.z,
                drop: d.z - range * libm::tan(el),
                windage: d.dot(left),
                speed,
                mach: drag.as_ref().map(|m| m.mach(state.p, v)),
                energy: 0.5 * mass * speed * speed,
            });
        }
        if world.stopped().is_some() || world.bodies().is_empty() {
            break;
        }
    }
    let mut table = RangeTable {
        rows: Vec::new(),
        unreached: Vec::new(),
    };
    for (row, &range) in found.into_iter().zip(ranges) {
        match row {
            Some(r) => table.rows.push(r),
            None => table.unreached.push(range),
        }
    }
    Ok(table)
}
