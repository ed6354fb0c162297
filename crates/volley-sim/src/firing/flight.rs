//! The world check: every solution flown in a real world, with its contacts, to the tick it
//! passes the target, and the textbook aim beside it.

use super::*;

/// A world with one shot fired at `v0` and the target, over `duration` seconds.
pub(super) fn flight_world(range: &Range, v0: DVec3, contacts: bool) -> World {
    let mut scene = range.scene.clone();
    scene.start_time = 0.0;
    scene.volley = None;
    scene.bodies = vec![BodySpec {
        mass: range.mass,
        radius: range.radius,
        position: range.from,
        velocity: v0,
        spin: range
            .scene
            .launcher
            .spin_at(libm::atan2(v0.y, v0.x).to_degrees()),
    }];
    scene.targets = vec![Target {
        radius: range.target.radius,
        ..range.target
    }];
    scene.detection = crate::contact::Detection::Swept;
    if !contacts {
        scene.ground = None;
        scene.walls.clear();
        scene.meshes.clear();
        scene.heightfields.clear();
    }
    World::new(&scene)
}

/// Closest approach (distance, time after launch) of the stepped path at `v0` to the target's
/// centre over at most `duration`: the nearest substep boundary, refined by golden-section
/// search over the steps either side of it on the path the integrator steps.
///
/// This is the minimum of the distance along the path itself. (The engine's approach event
/// finds where `(p - c) . V` changes sign with the *state's* velocity, which for most
/// integrators is not the slope of the path inside a step, so its distance can be a few
/// micrometres above this one at coarse steps.)
pub(super) fn closest_approach(range: &Range, v0: DVec3, duration: f64) -> Option<(f64, f64)> {
    let stepped = Stepped::new(range);
    let hs = stepped.hs;
    let count = ((duration / hs).ceil() as u64).min(u64::from(u32::MAX));
    let path = stepped.samples(v0, count);
    let dist = |k: usize| (path[k].0.p - range.target_at(k as f64 * hs)).length();
    let k = (0..path.len())
        .filter(|&k| dist(k).is_finite())
        .min_by(|&a, &b| dist(a).total_cmp(&dist(b)))?;
    // Inside the steps either side of boundary k: a partial step from the boundary before.
    let at = |t: f64| {
        let j = ((t / hs).floor() as usize).min(path.len() - 1);
        let (s, carry) = path[j];
        let partial = Partial {
            s,
            carry,
            w: stepped.mass_for(v0),
            t: stepped.t0 + j as f64 * hs,
            tau: t - j as f64 * hs,
        };
        let p = visit(
            stepped.integrator,
            &stepped.forces,
            stepped.tolerance,
            partial,
        )
        .p;
        (p - range.target_at(t)).length()
    };
    let bracket = (k.saturating_sub(1) as f64 * hs, (k + 1) as f64 * hs);
    let (t, d) = golden(at, bracket, 1e-15 * bracket.1.max(hs));
    let best = (d, t);
    Some(if best.0 <= dist(k) {
        best
    } else {
        (dist(k), k as f64 * hs)
    })
}

/// Fires each found launch in a world: the engine's miss, a block before arrival, the
/// textbook's miss.
pub(super) fn finish(range: &Range, mode: Mode, found: Found) -> Result<Vec<Shot>, FiringError> {
    let h = range.scene.dt();
    let mut shots = Vec::new();
    for (kind, flight_time, velocity) in found {
        let mut world = flight_world(range, velocity, range.contacts);
        let arrival_tick = split_time(flight_time, h).0 + 1;
        let mut blocked = None;
        let mut approaches = Vec::new();
        for _ in 0..=arrival_tick {
            if let Err(d) = world.step() {
                return Err(FiringError::Diverged {
                    flight_time,
                    tick: Some(d.tick),
                });
            }
            for e in world.events() {
                match e.kind {
                    // A rest is a contact too: on a surface of restitution 0 (a steel plate,
                    // the rifle's ground) every contact is reported as one, at any speed.
                    EventKind::Impact { surface, .. } | EventKind::Rest { surface }
                        if blocked.is_none() && e.time < flight_time =>
                    {
                        blocked = Some(Blocked {
                            surface,
                            time: e.time,
                            tick: e.tick,
                        });
                    }
                    EventKind::Approach { distance, .. } => approaches.push((distance, e.time)),
                    _ => {}
                }
            }
        }
        let miss = if blocked.is_some() {
            // Whatever comes after a bounce is not this shot: measure it with contacts off.
            closest_approach(range, velocity, flight_time + h).map_or(f64::NAN, |m| m.0)
        } else {
            approaches
                .iter()
                .min_by(|a, b| {
                    (a.1 - flight_time)
                        .abs()
                        .total_cmp(&(b.1 - flight_time).abs())
                })
                .map_or(f64::NAN, |a| a.0)
        };
        if miss.is_nan() {
            return Err(FiringError::Unverified { flight_time });
        }
        let (elevation_deg, azimuth_deg) = angles_of(velocity);
        let textbook = textbook_velocity(range, mode, kind).map(|v| {
            let horizon = (2.0 * flight_time + 1.0).min(range.max_flight_time);
            let (miss, time) = closest_approach(range, v, horizon).unwrap_or((f64::NAN, f64::NAN));
            Textbook {
                velocity: v,
                miss,
                time,
            }
        });
        shots.push(Shot {
            kind,
            velocity,
            speed: velocity.length(),
            elevation_deg,
            azimuth_deg,
            flight_time,
            arrival_tick,
            miss,
            blocked,
            textbook,
        });
    }
    if !shots.is_empty() && shots.iter().all(|s| s.blocked.is_some()) {
        return Err(FiringError::Blocked(
            shots.iter().map(|s| (s.kind, s.blocked.unwrap())).collect(),
        ));
    }
    Ok(shots)
}

/// The textbook answer to the same question: the closed form under the scene's gravity alone,
/// at the target's centre at launch (it knows no drag, wind, step or target motion).
pub(super) fn textbook_velocity(range: &Range, mode: Mode, kind: ShotKind) -> Option<DVec3> {
    let g = range.scene.forces.gravity.map_or(0.0, |g| -g.z);
    let (from, to) = (range.from, range.target.center);
    let d = to - from;
    let dh = (d.x * d.x + d.y * d.y).sqrt();
    let azimuth = libm::atan2(d.y, d.x).to_degrees();
    match (mode, kind) {
        (Mode::Speed(speed), ShotKind::Arc(arc)) => {
            let [high, low] = exact::aim(from, to, speed, g).ok()?;
            Some(if arc == Arc::High {
                high.velocity
            } else {
                low.velocity
            })
        }
        (Mode::Elevation(elevation), _) => {
            // v^2 = g dh^2 / (2 cos^2 e (dh tan e - dz)).
            let e = elevation.to_radians();
            let (s, c) = (libm::sin(e), libm::cos(e));
            let lift = dh * s / c - d.z;
            if !(g > 0.0 && lift > 0.0 && c > 0.0) {
                return None;
            }
            let speed = (g * dh * dh / (2.0 * c * c * lift)).sqrt();
            Some(crate::scene::angles_to_velocity(speed, elevation, azimuth))
        }
        (Mode::MinSpeed, _) if g > 0.0 && dh > 0.0 => {
            // tan e = (dz + r) / dh, v^2 = g (dz + r).
            let r = d.length();
            let elevation = libm::atan2(d.z + r, dh).to_degrees();
            Some(crate::scene::angles_to_velocity(
                (g * (d.z + r)).sqrt(),
                elevation,
                azimuth,
            ))
        }
        _ => None,
    }
}
