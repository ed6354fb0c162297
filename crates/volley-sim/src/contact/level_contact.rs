//! Swept and discrete contact with level surfaces (meshes and heightfields) for a sphere of the
//! body's radius: the first touch along the body's own sub-step path, found by
//! [`super::roots::first_root`] on the distance to the nearest triangle less the radius, and
//! handed back as the tangent plane at the contact, which the plane code then bounces off or
//! settles on like any other plane.

use glam::DVec3;

use super::bvh::Aabb;
use super::level_query::{LevelTriangles, Skip};
use super::roots::{BallCrossing, OnBall, PathPoint, first_root, margin};
use super::{Contacts, Plane, StepContext};
use crate::body::BodyState;

/// The radius a body of radius 0 meets level surfaces with (m): a point has no distance
/// function with a sign change at a triangle, a micron sphere does.
pub const MIN_LEVEL_RADIUS: f64 = 1e-6;

/// A body's contact radius against level surfaces (m).
#[inline]
pub(crate) fn level_radius(r: f64) -> f64 {
    r.max(MIN_LEVEL_RADIUS)
}

/// The distance a body at `p` counts as touching a triangle within: its radius, and rounding
/// of the position's size (a body put back on a surface lands there to a few ulps).
#[inline]
pub(crate) fn touch_limit(r: f64, p: DVec3) -> f64 {
    r * (1.0 + 1e-9) + 64.0 * f64::EPSILON * (1.0 + p.abs().max_element())
}

/// Whether the step from `s0` to `s1` may come near a level surface: its box, grown by the
/// radius and the path's margin, meets some surface's box.
#[inline]
pub(crate) fn may_reach_levels(
    contacts: &Contacts,
    r: f64,
    inv_m: f64,
    h: f64,
    s0: &BodyState,
    s1: &BodyState,
) -> bool {
    let grow = level_radius(r) + margin(s0, s1, inv_m, h);
    contacts.levels_overlap(&Aabb::of_segment(s0.p, s1.p, grow))
}

/// The distance to the nearest level triangle less the body's radius (capped at the radius:
/// nothing nearer than twice the radius is looked for).
struct LevelGap<'a, T: LevelTriangles> {
    tris: &'a T,
    r: f64,
    skip: Option<Skip>,
}

impl<T: LevelTriangles> BallCrossing for LevelGap<'_, T> {
    #[inline]
    fn value(&mut self, s: &BodyState) -> f64 {
        let reach = 2.0 * self.r;
        self.tris
            .level_nearest(s.p, reach, self.skip)
            .map_or(reach, |n| n.distance)
            - self.r
    }

    /// Whether the ball can bring the body's centre nearer a triangle than its radius less the
    /// touching tolerance: a path that only grazes at the touching distance (sliding along an
    /// edge it rests on) is no crossing, and pieces of it are cleared instead of split forever.
    #[inline]
    fn possible(&mut self, center: DVec3, radius: f64) -> bool {
        let slack = touch_limit(self.r, center) - self.r;
        self.tris
            .level_near(center, (radius + self.r - slack).max(0.0), self.skip)
    }

    #[inline]
    fn resolution(&self) -> f64 {
        self.r
    }
}

/// The first level contact on the segment from `s` over `duration` to `end` (the state at
/// `duration`), as `(tau, tangent plane)`. `path(tau)` is the body's state `tau` into the
/// segment. A body touching a surface at the segment's start meets it at `tau = 0` when it
/// moves into it, or rests on it (leaving it no faster than gravity's gain in a step, and
/// inside it at `end` or moving into it there); one leaving it searches past it.
///
/// With `sliding`, the body rests on the plane `(n, n . x)` of a surface and on what it touches
/// (the resting contact's step): those triangles and the ones in that plane are left out, and
/// only something else on its way is looked for.
pub(crate) fn first_level_contact(
    ctx: &StepContext,
    tris: &impl LevelTriangles,
    (r, inv_m, sliding): (f64, f64, Option<(DVec3, f64)>),
    s: BodyState,
    (duration, end): (f64, BodyState),
    path: &mut impl FnMut(f64) -> BodyState,
) -> Option<(f64, Plane)> {
    let contacts = ctx.contacts;
    if !contacts.has_levels() || !may_reach_levels(contacts, r, inv_m, duration, &s, &end) {
        return None;
    }
    let r = level_radius(r);
    let limit = touch_limit(r, s.p);
    // Of the triangles touched at the start, the one moved into fastest, if one is moved into
    // faster than a step of gravity gains; otherwise (resting, sliding or leaving) the nearest.
    // Comparing rates that are all zero to rounding picked any of them: a body resting on a
    // face, its centre a few micrometres from a neighbour's edge, took that edge's normal,
    // tilted by their ratio, as its resting plane, and met the next coplanar triangle's edge
    // in the step's fall under gravity (docs/physics.md, "Level surfaces").
    let v = s.mv * inv_m;
    let mut touched: Option<(f64, super::level_query::Nearest)> = None;
    let into = |rate: f64| rate < -ctx.rest_speed;
    tris.level_touching(s.p, limit, |n| {
        let rate = n.normal.dot(v);
        let better = touched.is_none_or(|(best, b)| match (into(rate), into(best)) {
            (true, true) => rate < best,
            (a, b_into) if a != b_into => a,
            _ => n.distance < b.distance,
        });
        if n.normal != DVec3::ZERO && better {
            touched = Some((rate, n));
        }
    });
    let mut skip = None;
    if sliding.is_some() {
        skip = Some(Skip {
            point: s.p,
            limit,
            plane: sliding,
        });
    } else if let Some((rate, n)) = touched {
        let plane = Plane {
            surface: n.surface,
            normal: n.normal,
            offset: n.normal.dot(s.p),
            restitution: n.restitution,
        };
        let mut gap = LevelGap {
            tris,
            r,
            skip: None,
        };
        // Resting: not leaving faster than gravity's gain in a step, and inside at the end or
        // moving into the face there (explicit Euler's step from rest only gains the speed).
        let resting =
            rate <= ctx.rest_speed && (gap.value(&end) < 0.0 || n.normal.dot(end.mv * inv_m) < 0.0);
        if rate < 0.0 || resting {
            return Some((0.0, plane));
        }
        skip = Some(Skip {
            point: s.p,
            limit,
            plane: None,
        });
    }
    let mut gap = LevelGap { tris, r, skip };
    let a = PathPoint {
        tau: 0.0,
        s,
        value: gap.value(&s),
    };
    if a.value <= 0.0 {
        return None; // unreachable: every triangle this near was touched, and skipped
    }
    let b = PathPoint {
        tau: duration,
        s: end,
        value: gap.value(&end),
    };
    let (lo, _) = first_root(
        path,
        a,
        b,
        &mut OnBall {
            crossing: &mut gap,
            inv_m,
        },
    )?;
    let n = tris.level_nearest(lo.s.p, 2.0 * r, skip)?;
    if n.normal == DVec3::ZERO {
        return None;
    }
    Some((
        lo.tau,
        Plane {
            surface: n.surface,
            normal: n.normal,
            offset: n.normal.dot(lo.s.p) - (n.distance - r).max(0.0),
            restitution: n.restitution,
        },
    ))
}

/// Discrete detection: a body overlapping a level triangle at the end of its step is pushed out
/// along the nearest one's normal. Returns that triangle's contact and the depth (m).
pub(crate) fn discrete_level_contact(
    contacts: &Contacts,
    r: f64,
    p: DVec3,
) -> Option<(Plane, f64)> {
    if !contacts.has_levels() {
        return None;
    }
    let r = level_radius(r);
    let n = contacts.level_nearest(p, r, None)?;
    if n.distance >= r || n.normal == DVec3::ZERO {
        return None;
    }
    Some((
        Plane {
            surface: n.surface,
            normal: n.normal,
            // The plane through the sphere's centre where it would just touch.
            offset: n.normal.dot(p) + (r - n.distance),
            restitution: n.restitution,
        },
        r - n.distance,
    ))
}
