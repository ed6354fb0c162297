//! The contact stage as a draw needs it: how deep a drawn sphere sits inside a surface, and the
//! straight path a drawn body takes past its tick, clipped and reflected at the surfaces.
//!
//! Neither touches the world: they read the scene's surfaces only, so a draw that calls them
//! changes nothing a tick computes (no state, no events, no random numbers).

use glam::DVec3;

use super::level_contact::{
    discrete_level_contact, first_level_contact, level_radius, touch_limit,
};
use super::level_query::Candidates;
use super::{Aabb, Contacts, MAX_IMPACTS_PER_STEP, Plane, StepContext, Surface, TOUCHING, planes};
use crate::body::BodyState;

impl Contacts {
    /// How deep a sphere of radius `r` centred at `p` is inside the ground, a wall or a level
    /// surface (m), beyond what rounding leaves a body the contact stage put back on it; 0
    /// outside. A wall is its whole slab, either side; targets are sensors and hold nothing.
    ///
    /// Rounding: the contact stage puts a body on a plane to within a few ulps of the plane's
    /// offset, so a depth of `1e-12 (1 + |offset|)` or less (the stage's own touching
    /// distance) counts as touching, not inside. A level surface allows the same margin as its
    /// own contact test.
    pub fn penetration(&self, p: DVec3, r: f64) -> f64 {
        let mut deepest = 0.0f64;
        for plane in planes(self, p, r) {
            let depth = match plane.surface {
                // A slab: inside when the centre is nearer its mid-plane than half its
                // thickness and the radius; `planes` faces the body's side.
                Surface::Wall(i) => {
                    let w = &self.walls[i as usize];
                    0.5 * w.thickness + r - w.normal.dot(p - w.point).abs()
                }
                _ => -plane.distance(p),
            };
            if depth > TOUCHING * (1.0 + plane.offset.abs()) {
                deepest = deepest.max(depth);
            }
        }
        if let Some((_, depth)) = discrete_level_contact(self, r, p) {
            let slack = touch_limit(level_radius(r), p) - level_radius(r);
            if depth > slack {
                deepest = deepest.max(depth);
            }
        }
        deepest
    }
}

/// Where a body of radius `r` at `p` moving at `v` is after `tau` seconds on a straight path
/// that meets the ground, the walls and the level surfaces as the contact stage does: it stops
/// at the first surface it reaches, reflects with the surface's restitution (or, arriving
/// slower than `rest_speed` after it, keeps only the tangential motion), and goes on for the
/// time left, up to the stage's impacts per step. A wall the body is already inside lets it
/// pass, as the stage's does; targets do not deflect.
///
/// `targets`: where the game removes a body that hits a target, the seconds since tick 0 at
/// `p`. The path then also ends at the first target sphere it reaches (the target moving at
/// its velocity), and the body rides on it from there, at the point it struck, for the time
/// left: the game will not show it past the hit. `None` (the contact stage's view: targets are
/// sensors) lets the path through them.
///
/// The path is straight because the draw it serves extrapolates by the velocity: with no
/// surface in reach it is exactly `p + v tau`, bit for bit.
pub(crate) fn straight_path(
    contacts: &Contacts,
    (mut p, mut v): (DVec3, DVec3),
    r: f64,
    (tau, rest_speed): (f64, f64),
    targets: Option<f64>,
) -> DVec3 {
    let mut left = tau;
    let levels = contacts.has_levels();
    for _ in 0..MAX_IMPACTS_PER_STEP {
        if left <= 0.0 {
            break;
        }
        // A target struck in this round ends the path unless a surface comes first.
        let struck =
            targets.and_then(|since| first_target(contacts, (p, v), r, since + tau - left));
        let limit = struck.map_or(left, |(at, _)| at.min(left));
        let mut first: Option<(f64, Plane)> = None;
        for plane in planes(contacts, p, r) {
            let rate = plane.normal.dot(v);
            if rate >= 0.0 {
                continue;
            }
            let d0 = plane.distance(p);
            if d0 < -TOUCHING * (1.0 + plane.offset.abs()) && plane.surface != Surface::Ground {
                continue;
            }
            let at = (d0 / -rate).max(0.0);
            if at < limit && first.is_none_or(|(t, _)| at < t) {
                first = Some((at, plane));
            }
        }
        if levels {
            let cut = first.map_or(limit, |(t, _)| t);
            let end = p + v * cut;
            let state = |q: DVec3| BodyState { p: q, mv: v };
            let grow = 2.0 * level_radius(r) + 8.0 * f64::EPSILON * (1.0 + p.abs().max_element());
            let tris = Candidates::gather(contacts, Aabb::of_segment(p, end, grow));
            let ctx = StepContext {
                contacts,
                tick: 0,
                t0: 0.0,
                since_start: 0.0,
                h: cut,
                rest_speed,
                levels,
                fresh: &[],
                horizon: None,
            };
            let mut path = |t: f64| state(p + v * t);
            let found = first_level_contact(
                &ctx,
                &tris,
                (r, 1.0, None),
                state(p),
                (cut, state(end)),
                &mut path,
            );
            if let Some((t, plane)) = found
                && t < cut
            {
                first = Some((t, plane));
            }
        }
        let Some((at, plane)) = first else {
            if let Some((at, u)) = struck
                && at < left
            {
                return p + v * at + u * (left - at);
            }
            break;
        };
        p += v * at;
        p -= plane.distance(p).min(0.0) * plane.normal;
        left -= at;
        let rate = plane.normal.dot(v);
        let bounce = if -rate * plane.restitution > rest_speed {
            1.0 + plane.restitution
        } else {
            1.0
        };
        v -= (bounce * rate) * plane.normal;
    }
    if left > 0.0 {
        p += v * left;
    }
    // Past the impacts cap (a body wedged in a corner, where each round meets a face it already
    // touches at no time at all and the rest of the lead is then drawn straight): out of the
    // ground, and out of the level surfaces by pushing out of the nearest overlapped triangle
    // in turn. In a concave corner these alternating projections converge on the point outside
    // both faces (geometrically, by the cosine of the angle between their normals squared).
    if let Some(g) = contacts.ground {
        p.z = p.z.max(g.height + r);
    }
    for _ in 0..MAX_IMPACTS_PER_STEP {
        let Some((plane, depth)) = discrete_level_contact(contacts, r, p) else {
            break;
        };
        let slack = touch_limit(level_radius(r), p) - level_radius(r);
        if depth <= slack {
            break;
        }
        p -= plane.distance(p).min(0.0) * plane.normal;
    }
    p
}

/// The first target a body of radius `r` at `p` moving at `v` reaches on its straight line,
/// `since` seconds after tick 0: the time from now (0 for one it already touches) and the
/// target's velocity. The gap to a target moving at `u` closes along `w = v - u` from
/// `d = p - c`: the smaller root of `|d + w s| = R + r`, a quadratic.
fn first_target(
    contacts: &Contacts,
    (p, v): (DVec3, DVec3),
    r: f64,
    since: f64,
) -> Option<(f64, DVec3)> {
    let mut first: Option<(f64, DVec3)> = None;
    for target in &contacts.targets {
        let reach = target.radius + r;
        let d = p - target.center_at(since);
        let w = v - target.velocity;
        let c = d.length_squared() - reach * reach;
        let at = if c <= 0.0 {
            0.0
        } else {
            let (a, b) = (w.length_squared(), d.dot(w));
            let disc = b * b - a * c;
            if b >= 0.0 || disc < 0.0 {
                continue;
            }
            // The smaller root, in the form that does not cancel: c / (-b + sqrt(disc)).
            c / (-b + disc.sqrt())
        };
        if first.is_none_or(|(t, _)| at < t) {
            first = Some((at, target.velocity));
        }
    }
    first
}
