//! Resting contact: a body whose bounce is slower than gravity's gain in a step stays on the
//! surface, sliding along it without friction (docs/physics.md, "Level surfaces", the resting
//! model), and the clamps that keep a body outside every surface.

use glam::DVec3;

use super::level_query::{Candidates, LevelTriangles};
use super::{
    Event, EventKind, Particle, Plane, StepContext, Surface, level_contact, planes, roots,
};
use crate::body::BodyState;
use crate::integrate::Scheme;

/// A body resting on `plane`: integrate the rest of the step with no normal momentum into the
/// surface and clamp it onto the surface. With level surfaces in the scene, the slide is
/// searched for another level triangle on its way (a wall it slides into, however thin): met,
/// the body is stopped there, clamped, bounced off it and the rest of the step integrated
/// again. The end is then pushed out of any level triangle it overlaps (a slope's next
/// triangle, a corner's other face), its momentum into that triangle removed.
///
/// `at` is `(elapsed, remaining)`: the time from the step's start to the contact, and the rest
/// of the step. With `EVENTS`, the declared events are looked for on the slide (the rest of the
/// step, searched on the integrator's path from the contact with the normal momentum removed,
/// ending at the clamped end), their evaluations in `evals.1`.
#[allow(clippy::too_many_arguments)]
pub(super) fn settle<S: Scheme, const LEVELS: bool, const EVENTS: bool>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    plane: Plane,
    (mut s, mut c): (BodyState, DVec3),
    (elapsed, mut remaining): (f64, f64),
    (evals, event_evals): (&mut u64, &mut u64),
    out: &mut Vec<Event>,
    cands: Option<&Candidates>,
) -> (BodyState, DVec3) {
    let mut t = ctx.t0 + elapsed;
    let mut slid = elapsed;
    let mv_n = plane.normal.dot(s.mv);
    s.mv -= mv_n * plane.normal;
    let slide_start = (s, c);
    let step = |s: BodyState, c: DVec3, t: f64, tau: f64, evals: &mut u64| {
        if tau > 0.0 {
            let (end, end_c, n) = scheme.step_counted(s, body.w, t, tau, c);
            *evals += n;
            (end, end_c)
        } else {
            (s, c)
        }
    };
    let (mut end, mut end_c) = step(s, c, t, remaining, evals);
    // On a flat part of a level (every triangle near the slide in the resting plane) there is
    // nothing else to meet and nothing to push out of: the clamp onto the plane is all. The
    // surface's own plane is the centre's less the radius it keeps.
    let surface = (
        plane.normal,
        plane.offset - level_contact::level_radius(body.r),
    );
    let flat = LEVELS
        && cands.is_some_and(|tris| {
            let reach = 0.5 * (end.p - s.p).length()
                + roots::margin(&s, &end, body.w.inv, remaining)
                + 2.0 * level_contact::level_radius(body.r);
            tris.only_plane(0.5 * (s.p + end.p), reach, surface)
        });
    let cands = if flat || !LEVELS { None } else { cands };
    if let Some(tris) = cands
        && remaining > 0.0
    {
        let mut spent = 0;
        let mut path = |tau: f64| {
            let (s, _, n) = scheme.step_counted(s, body.w, t, tau, c);
            spent += n;
            s
        };
        let met = level_contact::first_level_contact(
            ctx,
            tris,
            (body.r, body.w.inv, Some(surface)),
            s,
            (remaining, end),
            &mut path,
        );
        *evals += spent;
        if let Some((tau, other)) = met {
            (s, c) = step(s, c, t, tau, evals);
            let d = plane.distance(s.p);
            if d < 0.0 {
                s.p -= d * plane.normal;
            }
            let mv_n = other.normal.dot(s.mv);
            if mv_n < 0.0 {
                s.mv -= ((1.0 + other.restitution) * mv_n) * other.normal;
                let speed = -mv_n * body.w.inv;
                if speed * other.restitution > ctx.rest_speed {
                    out.push(Event {
                        tick: ctx.tick,
                        time: t + tau,
                        body: body.id,
                        kind: EventKind::Impact {
                            surface: other.surface,
                            normal_speed: speed,
                            depth: 0.0,
                        },
                    });
                }
            }
            if S::CARRIES_FORCE {
                c = scheme.start_carry(s, body.w, t + tau);
                *evals += 1;
            }
            if EVENTS {
                // The slide up to the wall it met, then on from there.
                let (met_at, _, n) =
                    scheme.step_counted(slide_start.0, body.w, t, tau, slide_start.1);
                *event_evals += n;
                super::events_on_segment(
                    scheme,
                    ctx,
                    Particle {
                        fresh: false,
                        ..body
                    },
                    slid,
                    slide_start,
                    tau,
                    met_at,
                    out,
                    event_evals,
                );
                slid += tau;
            }
            t += tau;
            remaining -= tau;
            (end, end_c) = step(s, c, t, remaining, evals);
        }
    }
    let d = plane.distance(end.p);
    if d < 0.0 {
        end.p -= d * plane.normal;
        if S::CARRIES_FORCE {
            end_c = scheme.start_carry(end, body.w, t + remaining);
            *evals += 1;
        }
    }
    let mv_n = plane.normal.dot(end.mv);
    if mv_n < 0.0 {
        end.mv -= mv_n * plane.normal;
    }
    if let Some(tris) = cands
        && push_out_of_levels(tris, body.r, &mut end)
        && S::CARRIES_FORCE
    {
        end_c = scheme.start_carry(end, body.w, t + remaining);
        *evals += 1;
    }
    if EVENTS && remaining > 0.0 {
        let from = if slid > elapsed { (s, c) } else { slide_start };
        super::events_on_segment(
            scheme,
            ctx,
            Particle {
                fresh: body.fresh && slid == 0.0,
                ..body
            },
            slid,
            from,
            remaining,
            end,
            out,
            event_evals,
        );
    }
    (end, end_c)
}

/// Pushes `s` out of the level triangles it overlaps and removes its momentum into the last
/// one; returns whether it moved.
fn push_out_of_levels(tris: &impl LevelTriangles, r: f64, s: &mut BodyState) -> bool {
    let r = level_contact::level_radius(r);
    let Some(n) = tris.level_depenetrate(&mut s.p, r) else {
        return false;
    };
    let mv_n = n.dot(s.mv);
    if mv_n < 0.0 {
        s.mv -= mv_n * n;
    }
    true
}

pub(super) fn clamp_outside<const LEVELS: bool>(
    ctx: &StepContext,
    body: Particle,
    s: &mut BodyState,
    cands: Option<&Candidates>,
) {
    if LEVELS && let Some(tris) = cands {
        push_out_of_levels(tris, body.r, s);
    }
    if let Some(plane) = planes(ctx.contacts, s.p, body.r).next()
        && plane.surface == Surface::Ground
    {
        let d = plane.distance(s.p);
        if d < 0.0 {
            s.p -= d * plane.normal;
            let mv_n = plane.normal.dot(s.mv);
            s.mv -= mv_n.min(0.0) * plane.normal;
        }
    }
}
