//! Contacts and events: the ground plane, thin walls, target spheres, and level surfaces
//! (static triangle meshes and heightfields).
//!
//! Swept detection (the default) finds the time of impact *inside* the step: the body is
//! advanced from the start state by its own integrator over a sub-step `tau`, and `tau` is the
//! root of the signed distance along that path (a bracketed Illinois root finder, converged to a
//! few ulps of the step). The body is moved to the contact, its normal momentum reflected with
//! the surface's restitution (frictionless, as in the seed's collision response), and the rest of
//! the step is integrated from there. Integrators that are exact under constant force therefore
//! find the exact impact time. Discrete detection only looks at the end of each step, as many
//! games do; it is here to show what that costs (late impacts, penetration, tunnelling).

use glam::DVec3;

use crate::body::{BodyId, BodyState, Mass};
use crate::integrate::Scheme;

mod bvh;
mod drawn;
pub(crate) mod events;
mod heightfield;
mod level;
mod level_contact;
mod level_query;
mod resting;
mod roots;
mod surfaces;
mod triangle;

pub(crate) use drawn::straight_path;
use level_query::Candidates;
use resting::{clamp_outside, settle};
pub(crate) use roots::bracketed_root;

pub use bvh::{Aabb, Bvh, LEAF_SIZE};
pub use events::search::MAX_CROSSINGS;
pub use events::{EventCondition, EventDirection, EventSet, EventSpec, EventStop};
pub use heightfield::GridIndex;
pub use level::{
    BLOCK, HeightGrid, HeightfieldSurface, LevelSource, MeshGeometry, MeshSurface, Transform,
};
pub use level_contact::MIN_LEVEL_RADIUS;
pub use roots::{
    MAX_DEPTH as ROOT_MAX_DEPTH, MAX_PIECES as ROOT_MAX_PIECES, SAFETY as ROOT_SAFETY,
};
pub use surfaces::*;
pub use triangle::{Feature, closest_point, is_degenerate};

/// Where and when a step runs, as the contact stage needs it.
#[derive(Clone, Copy)]
pub(crate) struct StepContext<'a> {
    pub contacts: &'a Contacts,
    /// Tick number the step produces.
    pub tick: u64,
    /// Sim time at the start of the step (s).
    pub t0: f64,
    /// The same instant as time since tick 0 (s): `tick * H + k * h` for substep `k`, where
    /// moving targets are.
    pub since_start: f64,
    /// Step length (s).
    pub h: f64,
    /// Normal speed below which a bounce ends at rest (m/s): gravity's speed gain in one step.
    pub rest_speed: f64,
    /// Whether the scene has level surfaces ([`Contacts::has_levels`]), read once a tick: the
    /// kernel picks its `LEVELS` version by it ([`needs_resolution`]), so no body-step tests it.
    pub levels: bool,
    /// Bodies spawned since the last tick, in id order, for a step with declared events (their
    /// first segment reports a function exactly zero at its start); empty otherwise.
    pub fresh: &'a [BodyId],
    /// The declared events' horizons, in a world with events whose forces are a constant field
    /// ([`events::horizon`]); `None` searches every body every step.
    pub horizon: Option<&'a events::horizon::Horizon<'a>>,
}

/// The body being resolved.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Particle {
    pub id: BodyId,
    pub w: Mass,
    pub r: f64,
    /// Spawned since the last tick: its first segment reports a declared event whose function
    /// is exactly zero at its start.
    pub fresh: bool,
}

/// Most surface impacts resolved inside one step before the rest is clamped.
const MAX_IMPACTS_PER_STEP: usize = 16;

/// Most force evaluations one body's swept contacts may spend in one step. Every root search
/// takes partial steps, and an adaptive step may take up to
/// [`crate::integrate::DOPRI_MAX_ATTEMPTS`] attempts each, so without a bound one body's contacts
/// could cost a billion evaluations a tick (found by fuzzing a recording). Past it, the body's
/// step ends non-finite and the world reports the divergence, as the adaptive step's own cap
/// does. A fixed-step body spends at most a few thousand.
pub const MAX_CONTACT_EVALS: u64 = 1_000_000;

/// The state a step that ran out of its evaluations ends in: reported as non-finite.
const SPENT: BodyState = BodyState {
    p: DVec3::NAN,
    mv: DVec3::NAN,
};

/// Relative distance (of the plane offset's scale) within which a body counts as touching a
/// surface at the start of a segment, so a resting body costs no root search.
const TOUCHING: f64 = 1e-12;

/// A body already resting on a surface meets it again each step at gravity's gain over one step,
/// `h (m g) / m`, which equals `rest_speed = |g| h` only up to rounding; above it by this factor
/// is a body that arrived, so a resting body does not report "came to rest" every other tick.
const REST_MARGIN: f64 = 1.0 + 1e-9;

#[derive(Clone, Copy)]
struct Plane {
    surface: Surface,
    /// Unit normal pointing out of the solid towards the body's side.
    normal: DVec3,
    /// Offset: the signed distance of the body's centre is `normal . p - offset`.
    offset: f64,
    restitution: f64,
}

impl Plane {
    #[inline]
    fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// The planes a body of radius `r` at `p` can hit, facing it.
fn planes(contacts: &Contacts, p: DVec3, r: f64) -> impl Iterator<Item = Plane> + '_ {
    let ground = contacts.ground.map(|g| Plane {
        surface: Surface::Ground,
        normal: DVec3::Z,
        offset: g.height + r,
        restitution: g.restitution,
    });
    let walls = contacts.walls.iter().enumerate().map(move |(i, w)| {
        let s = w.normal.dot(p - w.point);
        let side = if s >= 0.0 { 1.0 } else { -1.0 };
        let normal = side * w.normal;
        Plane {
            surface: Surface::Wall(i as u32),
            normal,
            offset: normal.dot(w.point) + 0.5 * w.thickness + r,
            restitution: w.restitution,
        }
    });
    ground.into_iter().chain(walls)
}

/// Whether a body moving from `s0` to `s1` might need the contact stage at all.
/// `LEVELS` is [`StepContext::levels`] as a constant: the kernel is compiled once with level
/// surfaces and once without, so a scene of planes pays nothing for them (2 instructions a
/// body-step on `volley`, 1e4 bodies, callgrind).
#[inline]
pub(crate) fn needs_resolution<const LEVELS: bool>(
    ctx: &StepContext,
    r: f64,
    inv_m: f64,
    s0: &BodyState,
    s1: &BodyState,
) -> bool {
    let contacts = ctx.contacts;
    if let Some(g) = contacts.ground
        && s1.p.z - g.height - r < 0.0
    {
        return true;
    }
    for w in &contacts.walls {
        let (a, b) = (w.normal.dot(s0.p - w.point), w.normal.dot(s1.p - w.point));
        let reach = 0.5 * w.thickness + r;
        if b.abs() < reach || (a >= 0.0) != (b >= 0.0) {
            return true;
        }
    }
    if LEVELS && level_contact::may_reach_levels(contacts, r, inv_m, ctx.h, s0, s1) {
        return true;
    }
    // A closest approach inside the step (the approach rate turns from < 0 to >= 0), or an
    // entry into the target's reach: each test taken only as far as it can still pass.
    for t in &contacts.targets {
        let (c0, c1) = (
            t.center_at(ctx.since_start),
            t.center_at(ctx.since_start + ctx.h),
        );
        if approach_rate(t, c0, s0, inv_m) < 0.0 && approach_rate(t, c1, s1, inv_m) >= 0.0 {
            return true;
        }
        let reach2 = (t.radius + r) * (t.radius + r);
        if (s1.p - c1).length_squared() <= reach2 && (s0.p - c0).length_squared() > reach2 {
            return true;
        }
    }
    false
}

/// `(p - c) . (V - u)` for a target centred at `c` moving at `u`: negative while the body
/// approaches the target's centre.
#[inline]
fn approach_rate(t: &Target, c: DVec3, s: &BodyState, inv_m: f64) -> f64 {
    (s.p - c).dot(s.mv * inv_m - t.velocity)
}

/// Resolves contacts for one body over one step that went from `s0` (carried force `c0`) to
/// `s1` (`c1`) under `scheme`. Returns the corrected end state and carry, and the number of
/// extra force evaluations spent; pushes events to `out`. With `EVENTS`, the declared events
/// are looked for on every segment of the path (their force evaluations added to
/// `event_evals`, apart from the step's); swept detection only (discrete detection's step is
/// searched whole by the caller, before the push-out). `LEVELS` as in [`needs_resolution`].
pub(crate) fn resolve<S: Scheme, const LEVELS: bool, const EVENTS: bool>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    (s0, c0): (BodyState, DVec3),
    (s1, c1): (BodyState, DVec3),
    out: &mut Vec<Event>,
    event_evals: &mut u64,
) -> (BodyState, DVec3, u64) {
    match ctx.contacts.detection {
        Detection::Swept => {
            // Level surfaces' work compiled in only for scenes with levels: a scene of planes
            // steps as it did before levels existed.
            let (s, c, n) = resolve_swept::<S, LEVELS, EVENTS>(
                scheme,
                ctx,
                body,
                (s0, c0),
                (s1, c1),
                out,
                event_evals,
            );
            if n > MAX_CONTACT_EVALS {
                return (SPENT, c, n);
            }
            (s, c, n)
        }
        Detection::Discrete => {
            let (s, c) = resolve_discrete(scheme, ctx, body, s0, (s1, c1), out);
            (s, c, u64::from(S::CARRIES_FORCE))
        }
    }
}

/// The declared events on the segment from `a` (carried force `ca`) at `elapsed` s into the
/// step, over `duration`, to `b`: the path is the scheme's partial step from `a`. Its force
/// evaluations go to `event_evals`, at most [`MAX_CONTACT_EVALS`] (past them the path is
/// reported non-finite and the search ends without more events).
#[allow(clippy::too_many_arguments)]
pub(crate) fn events_on_segment<S: Scheme>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    elapsed: f64,
    (a, ca): (BodyState, DVec3),
    duration: f64,
    b: BodyState,
    out: &mut Vec<Event>,
    event_evals: &mut u64,
) {
    let seg = events::search::Segment {
        tick: ctx.tick,
        t0: ctx.t0 + elapsed,
        since: ctx.since_start + elapsed,
        duration,
        body,
        start: a,
        end: b,
        fresh: body.fresh && elapsed == 0.0,
    };
    let mut spent = 0u64;
    let mut path = |tau: f64| {
        if spent > MAX_CONTACT_EVALS {
            return SPENT;
        }
        let (s, _, n) = scheme.step_counted(a, body.w, ctx.t0 + elapsed, tau, ca);
        spent += n;
        s
    };
    events::search::on_segment(scheme, &ctx.contacts.events, &seg, &mut path, out);
    *event_evals += spent;
}

/// The declared events on a whole step from `a` to `b` of a scheme that kept the step's
/// continuous extension in `dense` ([`Scheme::DENSE`]): the path is the extension, at no force
/// evaluation.
pub(crate) fn events_on_dense_step<S: Scheme>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    (a, b): (BodyState, BodyState),
    dense: &crate::integrate::Dense,
    out: &mut Vec<Event>,
) {
    let seg = events::search::Segment {
        tick: ctx.tick,
        t0: ctx.t0,
        since: ctx.since_start,
        duration: ctx.h,
        body,
        start: a,
        end: b,
        fresh: body.fresh,
    };
    let mut path = |tau: f64| dense.at(tau);
    events::search::on_segment(scheme, &ctx.contacts.events, &seg, &mut path, out);
}

#[allow(clippy::too_many_arguments)]
fn resolve_swept<S: Scheme, const LEVELS: bool, const EVENTS: bool>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    (mut s, mut c): (BodyState, DVec3),
    (mut end, mut end_c): (BodyState, DVec3),
    out: &mut Vec<Event>,
    event_evals: &mut u64,
) -> (BodyState, DVec3, u64) {
    let mut evals = 0u64;
    let mut elapsed = 0.0; // time from the step start to the segment start
    let mut remaining = ctx.h;
    // A step of `tau` from `s` at time `t`.
    let step = |s: BodyState, c: DVec3, t: f64, tau: f64, evals: &mut u64| {
        if *evals > MAX_CONTACT_EVALS {
            return (SPENT, c);
        }
        let (s, c, n) = scheme.step_counted(s, body.w, t, tau, c);
        *evals += n;
        (s, c)
    };
    // The level triangles near the step, gathered once: every query of the step tests these.
    let cands = LEVELS.then(|| {
        let r = level_contact::level_radius(body.r);
        let grow = 2.0 * r + roots::margin(&s, &end, body.w.inv, ctx.h);
        Candidates::gather(ctx.contacts, Aabb::of_segment(s.p, end.p, grow))
    });
    for _ in 0..MAX_IMPACTS_PER_STEP {
        // Earliest surface crossing in this segment.
        let mut first: Option<(f64, Plane)> = None;
        for plane in planes(ctx.contacts, s.p, body.r) {
            let (d0, d1) = (plane.distance(s.p), plane.distance(end.p));
            if d1 >= 0.0 {
                continue;
            }
            if d0 <= TOUCHING * (1.0 + plane.offset.abs()) {
                // Touching or inside at the segment start: only the ground (a half-space) acts
                // at once; walls let a body that spawned inside pass.
                if plane.surface == Surface::Ground {
                    first = Some((0.0, plane));
                    break;
                }
                if d0 < 0.0 {
                    continue;
                }
            }
            let (tau, _) = bracketed_root(
                |tau| plane.distance(step(s, c, ctx.t0 + elapsed, tau, &mut evals).0.p),
                (0.0, d0),
                (remaining, d1),
            );
            if first.is_none_or(|(t, _)| tau < t) {
                first = Some((tau, plane));
            }
        }
        let mut cut = first.map_or(remaining, |(tau, _)| tau);
        let mut at_cut = match first {
            Some((tau, _)) if tau < remaining => step(s, c, ctx.t0 + elapsed, tau, &mut evals),
            _ => (end, end_c),
        };
        // Level surfaces, up to the first plane: the same path, searched by `roots`.
        if let Some(tris) = &cands {
            let t_seg = ctx.t0 + elapsed;
            let mut path = |tau: f64| step(s, c, t_seg, tau, &mut evals).0;
            let found = level_contact::first_level_contact(
                ctx,
                tris,
                (body.r, body.w.inv, None),
                s,
                (cut, at_cut.0),
                &mut path,
            );
            if let Some((tau, plane)) = found
                && (first.is_none() || tau < cut)
            {
                first = Some((tau, plane));
                cut = tau;
                at_cut = if tau < remaining {
                    step(s, c, t_seg, tau, &mut evals)
                } else {
                    (end, end_c)
                };
            }
        }
        targets_on_segment(
            scheme,
            ctx,
            body,
            elapsed,
            (s, c),
            cut,
            at_cut.0,
            out,
            &mut evals,
        );
        if EVENTS {
            let seg_body = Particle {
                fresh: body.fresh && elapsed == 0.0,
                ..body
            };
            events_on_segment(
                scheme,
                ctx,
                seg_body,
                elapsed,
                (s, c),
                cut,
                at_cut.0,
                out,
                event_evals,
            );
        }
        let Some((tau, plane)) = first else {
            return (end, end_c, evals);
        };
        (s, c) = at_cut;
        // On the surface exactly (the root is on the outside by a few ulps).
        s.p -= plane.distance(s.p).min(0.0) * plane.normal;
        elapsed += tau;
        remaining -= tau;
        let mv_n = plane.normal.dot(s.mv);
        let speed_in = -mv_n * body.w.inv;
        let time = ctx.t0 + elapsed;
        if speed_in > 0.0 {
            s.mv -= ((1.0 + plane.restitution) * mv_n) * plane.normal;
            if speed_in * plane.restitution > ctx.rest_speed {
                out.push(Event {
                    tick: ctx.tick,
                    time,
                    body: body.id,
                    kind: EventKind::Impact {
                        surface: plane.surface,
                        normal_speed: speed_in,
                        depth: 0.0,
                    },
                });
            } else {
                if speed_in > ctx.rest_speed * REST_MARGIN {
                    out.push(Event {
                        tick: ctx.tick,
                        time,
                        body: body.id,
                        kind: EventKind::Rest {
                            surface: plane.surface,
                        },
                    });
                }
                let at = (elapsed, remaining);
                let (s, c) = settle::<S, LEVELS, EVENTS>(
                    scheme,
                    ctx,
                    body,
                    plane,
                    (s, c),
                    at,
                    (&mut evals, event_evals),
                    out,
                    cands.as_ref(),
                );
                return (s, c, evals);
            }
        } else if -mv_n * body.w.inv <= ctx.rest_speed && tau == 0.0 {
            // Resting contact: slide along the surface for the rest of the step.
            let at = (elapsed, remaining);
            let (s, c) = settle::<S, LEVELS, EVENTS>(
                scheme,
                ctx,
                body,
                plane,
                (s, c),
                at,
                (&mut evals, event_evals),
                out,
                cands.as_ref(),
            );
            return (s, c, evals);
        }
        (end, end_c) = step(s, c, ctx.t0 + elapsed, remaining, &mut evals);
    }
    // Still bouncing after the cap (a body jittering in a corner): keep it outside every surface.
    let (mut s, mut c) = (end, end_c);
    clamp_outside::<LEVELS>(ctx, body, &mut s, cands.as_ref());
    if S::CARRIES_FORCE {
        c = scheme.start_carry(s, body.w, ctx.t0 + ctx.h);
        evals += 1; // the carried force: one evaluation
    }
    (s, c, evals)
}

/// Looks for target entries and closest approaches on the segment from `a` over `duration` to
/// `b`. The distance to a target's centre along the segment falls while `(p - c) . V < 0`, so
/// its minimum is at the sign change of that rate (if inside the segment) or at an end.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn targets_on_segment<S: Scheme>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    elapsed: f64,
    (a, ca): (BodyState, DVec3),
    duration: f64,
    b: BodyState,
    out: &mut Vec<Event>,
    evals: &mut u64,
) {
    // Every point of the path is a partial step, counted as it is taken.
    let spent = std::cell::Cell::new(0u64);
    let before = *evals;
    let path = |tau: f64| {
        if before + spent.get() > MAX_CONTACT_EVALS {
            return SPENT;
        }
        let (s, _, n) = scheme.step_counted(a, body.w, ctx.t0 + elapsed, tau, ca);
        spent.set(spent.get() + n);
        s
    };
    let since = ctx.since_start + elapsed;
    for (i, target) in ctx.contacts.targets.iter().enumerate() {
        let reach = target.radius + body.r;
        let at = |tau: f64| target.center_at(since + tau);
        let gap = |s: &BodyState, tau: f64| (s.p - at(tau)).length() - reach;
        let rate = |s: &BodyState, tau: f64| approach_rate(target, at(tau), s, body.w.inv);
        let (g0, g1) = (rate(&a, 0.0), rate(&b, duration));
        // Where along the segment the distance is smallest.
        let (tau_min, closest) = if g0 < 0.0 && g1 >= 0.0 {
            let (tau, _) = bracketed_root(|tau| rate(&path(tau), tau), (0.0, g0), (duration, g1));
            (Some(tau), path(tau))
        } else if g1 < 0.0 {
            (None, b)
        } else {
            (None, a)
        };
        let tau_closest = tau_min.unwrap_or(if g1 < 0.0 { duration } else { 0.0 });
        let gap_min = gap(&closest, tau_closest);
        // The start's gap only where the closest one touches (a body far from the target pays
        // one distance).
        if gap_min <= 0.0 {
            let gap0 = gap(&a, 0.0);
            if gap0 > 0.0 {
                let end = tau_min.unwrap_or(duration);
                let (tau_hit, _) =
                    bracketed_root(|tau| gap(&path(tau), tau), (0.0, gap0), (end, gap_min));
                out.push(Event {
                    tick: ctx.tick,
                    time: ctx.t0 + elapsed + tau_hit,
                    body: body.id,
                    kind: EventKind::Hit { target: i as u32 },
                });
            }
        }
        if let Some(tau) = tau_min {
            out.push(Event {
                tick: ctx.tick,
                time: ctx.t0 + elapsed + tau,
                body: body.id,
                kind: EventKind::Approach {
                    target: i as u32,
                    distance: gap_min + reach,
                    hit: gap_min <= 0.0,
                },
            });
        }
    }
    *evals += spent.get();
}

fn resolve_discrete<S: Scheme>(
    scheme: &S,
    ctx: &StepContext,
    body: Particle,
    s0: BodyState,
    (mut s, mut c): (BodyState, DVec3),
    out: &mut Vec<Event>,
) -> (BodyState, DVec3) {
    let t_end = ctx.t0 + ctx.h;
    let mut moved = false;
    for plane in planes(ctx.contacts, s0.p, body.r) {
        let d = plane.distance(s.p);
        let inside = match plane.surface {
            Surface::Ground => d < 0.0,
            // Overlapping the slab now: |distance to the mid-plane| below half thickness + r.
            Surface::Wall(i) => {
                let w = &ctx.contacts.walls[i as usize];
                w.normal.dot(s.p - w.point).abs() < 0.5 * w.thickness + body.r
            }
            // `planes` yields only the ground and walls.
            Surface::Mesh { .. } | Surface::Heightfield { .. } => false,
        };
        if !inside {
            continue;
        }
        let mv_n = plane.normal.dot(s.mv);
        s.p -= d * plane.normal;
        moved = true;
        if mv_n < 0.0 {
            s.mv -= ((1.0 + plane.restitution) * mv_n) * plane.normal;
            out.push(Event {
                tick: ctx.tick,
                time: t_end,
                body: body.id,
                kind: EventKind::Impact {
                    surface: plane.surface,
                    normal_speed: -mv_n * body.w.inv,
                    depth: -d,
                },
            });
        }
    }
    if let Some((plane, depth)) = level_contact::discrete_level_contact(ctx.contacts, body.r, s.p) {
        let mv_n = plane.normal.dot(s.mv);
        s.p += depth * plane.normal;
        moved = true;
        if mv_n < 0.0 {
            s.mv -= ((1.0 + plane.restitution) * mv_n) * plane.normal;
            out.push(Event {
                tick: ctx.tick,
                time: t_end,
                body: body.id,
                kind: EventKind::Impact {
                    surface: plane.surface,
                    normal_speed: -mv_n * body.w.inv,
                    depth,
                },
            });
        }
    }
    if moved && S::CARRIES_FORCE {
        c = scheme.start_carry(s, body.w, ctx.t0 + ctx.h);
    }
    for (i, target) in ctx.contacts.targets.iter().enumerate() {
        let reach = target.radius + body.r;
        let (d0, d1) = (
            (s0.p - target.center_at(ctx.since_start)).length(),
            (s.p - target.center_at(ctx.since_start + ctx.h)).length(),
        );
        if d1 <= reach && d0 > reach {
            out.push(Event {
                tick: ctx.tick,
                time: t_end,
                body: body.id,
                kind: EventKind::Hit { target: i as u32 },
            });
        }
    }
    (s, c)
}

#[cfg(test)]
mod tests;
