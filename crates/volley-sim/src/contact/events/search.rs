//! Every sign change of every declared event on one segment of a body's sub-step path.
//!
//! ## The bound
//! A piece of path from `A` to `B` over `T` seconds is judged from its ends alone. Its mean
//! acceleration is `abar = (V_B - V_A) / T`. How far the acceleration can move from it comes
//! from the force model's [`Rates`] over the piece's reach: `|a'| <= kj = SAFETY (p vmax + v
//! |abar| + t) / (1 - SAFETY (v T + p T^2 / 8))`, so `|a| <= ka = |abar| + kj T`, and the
//! path bends by `|P''| <= kp = CURVATURE ka` (the scheme's partial step: 1 for the schemes that
//! follow the flow, 2 for semi- and implicit Euler, 0 for explicit Euler). Then the position
//! stays within `kp T^2 / 8` of its chord and the velocity within `kj T^2 / 8` of its own: under
//! gravity and a constant force every rate is 0, `kj = 0` and `ka = |abar| = |a|` exactly, and
//! the bound is rigorous; under other forces it is as good as the rates (bounds for every
//! built-in term; a game's own term is taken to change by up to its own size across a piece).
//! Explicit and semi-implicit Euler's partial steps move at their start's acceleration whatever
//! the forces, so for them it is exact too.
//!
//! ## What each piece is asked
//! From those, each event's function gets a range over the piece (a plane's `n . p` within the
//! chord's values and the sag; the speed within the velocity chord's nearest and farthest
//! points from zero and the velocity's sag) and, where it can be shown, that it is monotone (a
//! plane's `n . V` keeping its sign over the velocity tube; the apex's `a.z` keeping its sign).
//! A piece whose range excludes zero is clear. A monotone piece with a sign change holds one
//! root, found by the bracketed root finder. Anything else is halved by
//! [`first_root`], earlier half first. So two crossings inside one tick are two pieces'
//! roots, and a crossing is reported once: the search looks at `(ta, tb]`, a root exactly at
//! a segment's end belongs to that segment, and the next one starts on the zero and does not
//! report it again.
//!
//! ## Grazes
//! A path that touches zero without crossing (a tangent) is found where a piece cannot be
//! cleared although its bound stays within rounding of zero: reported once, as a graze, at
//! the point nearest zero. Two opposite crossings with nothing between them farther from zero
//! than rounding are the same touch, sampled on both sides: reported once, as a graze.

use std::cell::RefCell;

use glam::DVec3;

use super::{EventDirection, EventSet, Test};
use crate::body::{BodyState, Mass};
use crate::contact::roots::{Crossing, PathPoint, SAFETY, first_root};
use crate::contact::{Event, EventKind, Particle};
use crate::forces::Reach;
use crate::integrate::Scheme;

/// Most crossings of one event looked for on one segment: a spring orbiting many times a
/// tick has many, a body riding along the event's zero would have no end of them.
pub const MAX_CROSSINGS: usize = 64;

/// A segment of a body's sub-step path, as the event search needs it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Segment {
    /// The tick the step produces.
    pub tick: u64,
    /// Sim time at the segment's start (s).
    pub t0: f64,
    /// The same instant as time since tick 0 (s), where moving points are.
    pub since: f64,
    /// Its length (s).
    pub duration: f64,
    /// The body.
    pub body: Particle,
    /// State at the start, and at the end.
    pub start: BodyState,
    /// State at the end.
    pub end: BodyState,
    /// The body's first segment since it was spawned: a function exactly zero at its start is
    /// an event there (at `t0`), which no earlier segment reported.
    pub fresh: bool,
}

/// What can be said of a piece of path from its two ends.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounds {
    /// Its length (s).
    t: f64,
    /// `|a| <= ka` (m/s^2).
    ka: f64,
    /// `|a'| <= kj` (m/s^3).
    kj: f64,
    /// How far the position can leave its chord (m), rounding included.
    dp: f64,
    /// How far the velocity can leave its chord (m/s), rounding included.
    dv: f64,
    /// The mean acceleration (m/s^2).
    abar: DVec3,
    /// Velocities at the ends (m/s).
    va: DVec3,
    vb: DVec3,
}

/// Distance from the origin to the segment from `a` to `b`.
#[inline]
fn nearest_to_zero(a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let l2 = d.length_squared();
    let s = if l2 > 0.0 {
        (-a.dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + s * d).length()
}

/// Rounding of a value formed from numbers of size `x`: a few ulps.
#[inline]
fn rounding(x: f64) -> f64 {
    8.0 * f64::EPSILON * x
}

impl Bounds {
    /// The bounds of the piece from `a` to `b` of a body of mass `w`, whose segment starts at
    /// sim time `t0`.
    pub(crate) fn of<S: Scheme>(
        scheme: &S,
        w: Mass,
        t0: f64,
        a: &PathPoint,
        b: &PathPoint,
    ) -> Bounds {
        let t = b.tau - a.tau;
        let (va, vb) = (a.s.mv * w.inv, b.s.mv * w.inv);
        let dvel = vb - va;
        let abar = if t > 0.0 { dvel / t } else { DVec3::ZERO };
        let (ka, kj) = if S::CONSTANT_ACCEL_PATH {
            (abar.length(), 0.0)
        } else {
            let vm0 = va.length().max(vb.length()) + dvel.length();
            let grow = DVec3::splat(0.5 * vm0 * t);
            let reach = Reach {
                lo: a.s.p.min(b.s.p) - grow,
                hi: a.s.p.max(b.s.p) + grow,
                vmax: vm0,
                vmin: (nearest_to_zero(va, vb) - dvel.length()).max(0.0),
                mean_accel: abar,
                t0: t0 + a.tau,
                duration: t,
            };
            let r = scheme.rates(&reach, w);
            let denom = 1.0 - SAFETY * (r.v * t + r.p * t * t / 8.0);
            let kj = if denom >= 0.5 {
                SAFETY * (r.p * vm0 + r.v * abar.length() + r.t) / denom
            } else {
                f64::INFINITY
            };
            (abar.length() + kj * t, kj)
        };
        let kp = S::CURVATURE * ka;
        let size_p = a.s.p.abs().max_element() + b.s.p.abs().max_element();
        let size_v = va.abs().max_element() + vb.abs().max_element();
        Bounds {
            t,
            ka,
            kj,
            dp: kp * t * t / 8.0 + rounding(size_p),
            dv: kj * t * t / 8.0 + rounding(size_v),
            abar,
            va,
            vb,
        }
    }

    /// The largest speed on the piece (m/s).
    #[inline]
    fn vmax(&self) -> f64 {
        self.va.length().max(self.vb.length()) + self.dv
    }
}

/// What one event's function does on a piece: bounds on it, whether it is monotone, and the
/// rounding of its values.
#[derive(Clone, Copy, Debug)]
struct Judged {
    lo: f64,
    hi: f64,
    monotone: bool,
    tol: f64,
}

impl Test {
    /// The function's range over the piece from `a` to `b` (their values `ga`, `gb`).
    fn judge(&self, a: &PathPoint, b: &PathPoint, (ga, gb): (f64, f64), k: &Bounds) -> Judged {
        let t = k.t;
        match self {
            Test::Linear { n, d } => {
                let tol = rounding(a.s.p.abs().max_element() + b.s.p.abs().max_element() + d.abs());
                let (sa, sb) = (n.dot(k.va), n.dot(k.vb));
                Judged {
                    lo: ga.min(gb) - k.dp - tol,
                    hi: ga.max(gb) + k.dp + tol,
                    monotone: sa.min(sb) - k.dv > 0.0 || sa.max(sb) + k.dv < 0.0,
                    tol,
                }
            }
            Test::Apex => {
                let tol = rounding(k.va.abs().max_element() + k.vb.abs().max_element());
                let spread = k.kj * t;
                Judged {
                    lo: ga.min(gb) - k.dv - tol,
                    hi: ga.max(gb) + k.dv + tol,
                    monotone: (k.abar.z - spread > 0.0) || (k.abar.z + spread < 0.0),
                    tol,
                }
            }
            Test::Speed(speed) => {
                let nearest = nearest_to_zero(k.va, k.vb) - k.dv;
                let tol = rounding(k.vmax() + speed.abs());
                let curve = if nearest > 0.0 {
                    k.ka * k.ka / nearest + k.kj
                } else {
                    f64::INFINITY
                };
                Judged {
                    lo: nearest - speed - tol,
                    hi: k.vmax() - speed + tol,
                    monotone: (gb - ga).abs() > curve * t * t + 2.0 * tol,
                    tol,
                }
            }
            Test::Mach { mach, drag } => {
                // The air over the heights the piece can reach: the speed of sound's range and
                // how much the wind can differ between them.
                let grow = k.dp + 0.5 * (a.s.p.z - b.s.p.z).abs();
                let zmid = 0.5 * (a.s.p.z + b.s.p.z);
                let (z0, z1) = (zmid - grow, zmid + grow);
                let (c0, c1) = (drag.air.at(z0).1, drag.air.at(z1).1);
                let (c_lo, c_hi) = (c0.min(c1), c0.max(c1));
                let (wa, wb) = (drag.wind_at(a.s.p.z), drag.wind_at(b.s.p.z));
                let shear = (drag.wind_at(z0) - drag.wind_at(z1)).length();
                let (ua, ub) = (k.va - wa, k.vb - wb);
                let spread = k.dv + shear;
                let u_lo = nearest_to_zero(ua, ub) - spread;
                let u_hi = ua.length().max(ub.length()) + spread;
                let tol = rounding(u_hi / c_lo + mach.abs());
                let curve = if u_lo > 0.0 {
                    SAFETY * ((k.ka + shear / t.max(f64::MIN_POSITIVE)).powi(2) / u_lo + k.kj)
                        / c_lo
                } else {
                    f64::INFINITY
                };
                Judged {
                    lo: u_lo.max(0.0) / c_hi - mach - tol,
                    hi: u_hi / c_lo - mach + tol,
                    monotone: (gb - ga).abs() > curve * t * t + 2.0 * tol,
                    tol,
                }
            }
            Test::Closest { u, .. } => {
                // g = r . w with r = p - c, w = V - u: g' = |w|^2 + r . a, g'' = 3 w . a + r . a'.
                let (wa, wb) = (k.va - *u, k.vb - *u);
                let wmax = wa.length().max(wb.length()) + k.dv;
                let wmin = nearest_to_zero(wa, wb) - k.dv;
                // The positions here are relative to the point (the caller moves them).
                let rmax = a.s.p.length().max(b.s.p.length()) + wmax * t;
                let curve = 3.0 * wmax * k.ka + rmax * k.kj;
                let tol = rounding(rmax * wmax);
                Judged {
                    lo: ga.min(gb) - curve * t * t / 8.0 - tol,
                    hi: ga.max(gb) + curve * t * t / 8.0 + tol,
                    monotone: (wmin > 0.0 && wmin * wmin > rmax * k.ka)
                        || (gb - ga).abs() > curve * t * t + 2.0 * tol,
                    tol,
                }
            }
        }
    }
}

/// One search for the first root of `sigma g` (sigma = 1: a fall through zero; -1: a rise).
struct Search<'a, S> {
    scheme: &'a S,
    test: &'a Test,
    sigma: f64,
    /// The segment: its body, its start (as sim time and as time since tick 0), and its end, a
    /// tick boundary ([`on_boundary`]).
    seg: &'a Segment,
    /// Touches: pieces whose bound came within rounding of zero without a sign change, each at
    /// its end nearest zero.
    touches: &'a mut Vec<PathPoint>,
    /// Every value looked at, `(tau, sigma g)`, when `record` (a round that follows a
    /// crossing, which may merge with it into a graze; no other round reads them).
    seen: &'a mut Vec<(f64, f64)>,
    record: bool,
}

impl<S: Scheme> Search<'_, S> {
    fn judged(&self, a: &PathPoint, b: &PathPoint) -> (Judged, f64) {
        let k = Bounds::of(self.scheme, self.seg.body.w, self.seg.t0, a, b);
        let (ga, gb) = (self.sigma * a.value, self.sigma * b.value);
        let j = match self.test {
            Test::Closest { c0, u } => {
                // Positions relative to the point at each end's own time.
                let rel = |p: &PathPoint| {
                    let c = *c0 + (self.seg.since + p.tau) * *u;
                    PathPoint {
                        tau: p.tau,
                        s: BodyState {
                            p: p.s.p - c,
                            mv: p.s.mv,
                        },
                        value: p.value,
                    }
                };
                self.test.judge(&rel(a), &rel(b), (ga, gb), &k)
            }
            _ => self.test.judge(a, b, (ga, gb), &k),
        };
        // In the searched sign: the values are `sigma g`.
        let (lo, hi) = if self.sigma > 0.0 {
            (j.lo, j.hi)
        } else {
            (-j.hi, -j.lo)
        };
        (Judged { lo, hi, ..j }, k.t)
    }
}

impl<S: Scheme> Crossing for Search<'_, S> {
    #[inline]
    fn value(&mut self, tau: f64, s: &BodyState) -> f64 {
        let v = self.sigma
            * self
                .test
                .value(self.seg.since + tau, s, self.seg.body.w.inv);
        if self.record {
            self.seen.push((tau, v));
        }
        v
    }

    fn possible(&mut self, a: &PathPoint, b: &PathPoint) -> bool {
        let (j, _) = self.judged(a, b);
        // The segment's end is a tick boundary, which belongs to this segment when the
        // function there is within the boundary's rounding ([`on_boundary`]) and to the next
        // one otherwise: a touch there is this segment's, however the piece's bound reads.
        let at_end = b.tau == self.seg.duration;
        let end_is_ours = at_end && on_boundary(self.test, self.seg, b, b.value);
        if j.lo > 0.0 {
            if end_is_ours {
                self.touches.push(*b);
            }
            return false;
        }
        // It may reach zero, but not by more than rounding, and an end is within rounding of
        // it: a touch (the piece is not split further).
        if j.lo >= -2.0 * j.tol && a.value.min(b.value) <= 2.0 * j.tol {
            if a.value <= b.value {
                self.touches.push(*a);
            } else if !at_end || end_is_ours {
                self.touches.push(*b);
            }
            // A touch nearest a boundary farther from zero than its rounding is the next
            // segment's, which starts there and reports it.
            return false;
        }
        true
    }

    fn bracketed(&mut self, a: &PathPoint, b: &PathPoint) -> bool {
        self.judged(a, b).0.monotone
    }

    /// Four ulps of the sim time the event reports (`t0 + tau`): finer is not written.
    fn resolution_time(&self) -> f64 {
        4.0 * f64::EPSILON * self.seg.t0.abs()
    }
}

/// A sign change found, before the direction filter and the graze merge.
#[derive(Clone, Copy, Debug)]
struct Found {
    tau: f64,
    s: BodyState,
    direction: EventDirection,
    graze: bool,
}

/// The buffers a search fills, kept per thread and reused: growing fresh vectors for every
/// search was 6 % of a busy window's instructions (callgrind, 1e4 bodies through the apex),
/// and a tick allocated. Each use starts by clearing them, so nothing passes from one search to
/// the next: they are capacity, not state. Borrowed once per event looked for; nothing inside
/// (the path, the scheme's step) searches again.
#[derive(Debug, Default)]
struct Scratch {
    found: Vec<Found>,
    touches: Vec<PathPoint>,
    seen: Vec<(f64, f64)>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::default();
}

/// Looks for every declared event on `seg` and pushes each one that counts to `out`, in time
/// order for this body. `path(tau)` is the body's state `tau` s into the segment.
pub(crate) fn on_segment<S: Scheme>(
    scheme: &S,
    set: &EventSet,
    seg: &Segment,
    path: &mut impl FnMut(f64) -> BodyState,
    out: &mut Vec<Event>,
) {
    let first = out.len();
    let w = seg.body.w;
    let a = PathPoint {
        tau: 0.0,
        s: seg.start,
        value: 0.0,
    };
    let b = PathPoint {
        tau: seg.duration,
        s: seg.end,
        value: 0.0,
    };
    let mut top: Option<Bounds> = None;
    for (index, watch) in set.watches().iter().enumerate() {
        if watch.body.is_some_and(|id| id != seg.body.id) {
            continue;
        }
        let ga = watch.test.value(seg.since, &seg.start, w.inv);
        let gb = watch.test.value(seg.since + seg.duration, &seg.end, w.inv);
        let on_zero = ga == 0.0;
        if !on_zero || !seg.fresh {
            // The whole segment at once: most ticks of most bodies end here.
            let k = *top.get_or_insert_with(|| Bounds::of(scheme, w, seg.t0, &a, &b));
            let j = match &watch.test {
                Test::Closest { c0, u } => {
                    let rel = |p: &PathPoint, tau: f64| PathPoint {
                        s: BodyState {
                            p: p.s.p - (*c0 + (seg.since + tau) * *u),
                            mv: p.s.mv,
                        },
                        ..*p
                    };
                    watch
                        .test
                        .judge(&rel(&a, 0.0), &rel(&b, seg.duration), (ga, gb), &k)
                }
                _ => watch.test.judge(&a, &b, (ga, gb), &k),
            };
            let riding = j.lo >= -j.tol && j.hi <= j.tol;
            let clear = j.lo > 0.0 || j.hi < 0.0;
            if riding || (clear && !on_boundary(&watch.test, seg, &b, gb)) {
                // Riding along zero, within rounding, where nothing crosses; or clear of it,
                // up to an end on it that is this segment's to report.
                continue;
            }
        }
        SCRATCH.with_borrow_mut(|scratch| {
            crossings(scheme, &watch.test, seg, (ga, gb), path, scratch);
            let found = &mut scratch.found;
            if on_zero && seg.fresh {
                for f in found.iter_mut().filter(|f| f.tau == 0.0 && !f.graze) {
                    if let Some(way) = departure(&watch.test, seg, path) {
                        f.direction = way;
                    }
                }
            }
            if let Test::Linear { n, d } = watch.test {
                for f in found.iter_mut().filter(|f| f.graze) {
                    refine_graze(f, (n, d), seg, path);
                }
            }
            for f in found.iter() {
                if watch.direction.counts(f.direction) {
                    out.push(Event {
                        tick: seg.tick,
                        time: seg.t0 + f.tau,
                        body: seg.body.id,
                        kind: EventKind::Declared {
                            event: index as u32,
                            direction: f.direction,
                            graze: f.graze,
                            state: f.s,
                        },
                    });
                }
            }
        });
    }
    if out.len() - first > 1 {
        out[first..].sort_by(|x, y| x.time.total_cmp(&y.time));
    }
}

/// The sign changes of one event's function on the segment, in time order, grazes merged, into
/// `scratch.found`.
fn crossings<S: Scheme>(
    scheme: &S,
    test: &Test,
    seg: &Segment,
    (ga, gb): (f64, f64),
    path: &mut impl FnMut(f64) -> BodyState,
    scratch: &mut Scratch,
) {
    let Scratch {
        found,
        touches: touches_buf,
        seen: seen_buf,
    } = scratch;
    found.clear();
    let mut start = PathPoint {
        tau: 0.0,
        s: seg.start,
        value: ga,
    };
    // On the zero: look for a fall first; if the path rises instead, that is the event (for a
    // fresh body) or was reported by the segment before.
    let mut sigma = if ga < 0.0 { -1.0 } else { 1.0 };
    // The crossing the round before found (its index in `found`) and its rounding.
    let mut previous: Option<(usize, f64)> = None;
    for round in 0..MAX_CROSSINGS {
        let on_zero = start.value == 0.0;
        touches_buf.clear();
        seen_buf.clear();
        let mut search = Search {
            scheme,
            test,
            sigma,
            seg,
            touches: touches_buf,
            seen: seen_buf,
            record: previous.is_some(),
        };
        let a = PathPoint {
            value: sigma * start.value,
            ..start
        };
        let b = PathPoint {
            tau: seg.duration,
            s: seg.end,
            value: sigma * gb,
        };
        let root = if b.tau > a.tau {
            first_root(path, a, b, &mut search)
        } else {
            None
        };
        let direction = if sigma > 0.0 {
            EventDirection::Falling
        } else {
            EventDirection::Rising
        };
        let until = root.map_or(f64::INFINITY, |(lo, _)| lo.tau);
        // Touches before the root: each run of them one graze, at its value nearest zero.
        let touches = &mut *search.touches;
        touches.retain(|t| t.tau < until);
        touches.sort_by(|x, y| x.tau.total_cmp(&y.tau));
        let touched = !touches.is_empty();
        let mut cluster: Option<PathPoint> = None;
        for &t in touches.iter() {
            cluster = match cluster {
                Some(c) if t.tau - c.tau <= 1e-6 * seg.duration => {
                    Some(if t.value < c.value { t } else { c })
                }
                Some(c) => {
                    found.push(graze(c, direction));
                    Some(t)
                }
                None => Some(t),
            };
        }
        if let Some(c) = cluster {
            found.push(graze(c, direction));
        }
        let fresh_start = seg.fresh && round == 0 && on_zero && start.tau == 0.0;
        let Some((lo, hi)) = root else {
            if fresh_start {
                // It rose from the zero and never came back: a rise at the spawn.
                found.insert(0, at_start(seg, EventDirection::Rising));
            }
            break;
        };
        let mut pushed = None;
        // The zero it started on, left this way: the finder's last point before the root is
        // the start, or a point so near it that the function is still exactly zero there (the
        // position has not yet moved by an ulp: on a plane, for `tau < ulp(p) / |V|`).
        let left_start =
            lo.tau == start.tau || (lo.value == 0.0 && lo.tau - start.tau <= 1e-6 * seg.duration);
        if on_zero && left_start {
            if fresh_start {
                found.push(at_start(seg, direction));
            }
        } else {
            if fresh_start {
                found.insert(0, at_start(seg, EventDirection::Rising));
            }
            // A crossing right after an opposite one, nothing between them farther from zero
            // than rounding: both sides of one touch, reported once, as a graze.
            let deepest = || {
                search
                    .seen
                    .iter()
                    .filter(|(tau, _)| *tau > start.tau && *tau < lo.tau)
                    .map(|(_, v)| *v)
                    .fold(lo.value, f64::max)
            };
            let tol = rounding_of(test, seg, &lo);
            match previous {
                Some((i, prev_tol)) if !touched && deepest() <= 2.0 * tol.max(prev_tol) => {
                    let prev = &mut found[i];
                    prev.tau = 0.5 * (prev.tau + lo.tau);
                    prev.graze = true;
                }
                _ => {
                    found.push(Found {
                        tau: lo.tau,
                        s: lo.s,
                        direction,
                        graze: false,
                    });
                    pushed = Some((found.len() - 1, tol));
                }
            }
        }
        previous = pushed;
        start = PathPoint {
            value: sigma * hi.value,
            ..hi
        };
        sigma = -sigma;
        if hi.tau >= seg.duration {
            break;
        }
    }
    let start = PathPoint {
        tau: 0.0,
        s: seg.start,
        value: ga,
    };
    merge_touches(found, test, seg, on_boundary(test, seg, &start, ga));
}

/// One report per touch of zero. A path within rounding of zero over a stretch (a tangent, a
/// root on a step boundary) is sampled on both sides of zero many times: sign changes closer
/// together than a millionth of the segment are one group, reported once, as a crossing where
/// the group's crossings change the sign an odd number of times (at its first, going that
/// way), as a graze otherwise (where the path is most nearly tangent). A segment that starts
/// on zero continues the touch the segment before reported: its first group is dropped, but
/// for a fresh body's report at its spawn.
fn merge_touches(found: &mut Vec<Found>, test: &Test, seg: &Segment, starts_on_zero: bool) {
    if found.is_empty() {
        return;
    }
    let window = touch_window(test, seg);
    let inv = seg.body.w.inv;
    // The reports go back into `found`, each at or before its group's first entry, which
    // is read before it is written.
    let mut out = 0;
    let mut i = 0;
    while i < found.len() {
        let mut j = i + 1;
        while j < found.len() && found[j].tau - found[j - 1].tau <= window {
            j += 1;
        }
        let group = &found[i..j];
        i = j;
        if starts_on_zero && group[0].tau <= window {
            // The zero the segment started on: reported by the segment before, or here at a
            // fresh body's spawn.
            if seg.fresh
                && let Some(spawn) = group.iter().find(|f| f.tau == 0.0 && !f.graze)
            {
                found[out] = *spawn;
                out += 1;
            }
            continue;
        }
        // An odd number of sign changes is a crossing, at the first, the way it went; an even
        // number (or only touches) a graze, where the path is most nearly tangent.
        let changes = group.iter().filter(|f| !f.graze).count();
        let first_change = group.iter().find(|f| !f.graze);
        let mut report = if let Some(first) = first_change
            && changes % 2 == 1
        {
            *first
        } else {
            Found {
                graze: true,
                direction: group[0].direction,
                ..group[group.len() / 2]
            }
        };
        if let Test::Linear { n, d } = test {
            // A plane: whether the path turns back within rounding decides, whatever the
            // samples' signs said (a root on a step's end is sampled on both sides; a tangent
            // may be sampled on one).
            let slope = |f: &Found| n.dot(f.s.mv * inv).abs();
            let nearest = *group
                .iter()
                .min_by(|a, b| slope(a).total_cmp(&slope(b)))
                .unwrap_or(&report);
            let tol = 2.0
                * rounding_of(
                    test,
                    seg,
                    &PathPoint {
                        tau: nearest.tau,
                        s: nearest.s,
                        value: 0.0,
                    },
                );
            // Sign changes both ways closer together than the window are a path that passed
            // the plane by no more than rounding and came back: a graze, kept where the path
            // is tangent, unless the group runs into the segment's end, where the way it goes
            // on is the next segment's.
            let both_ways = changes >= 2 && changes % 2 == 0;
            let before_end = group[group.len() - 1].tau + window < seg.duration;
            if (both_ways && before_end) || turns_back((*n, *d), &nearest, seg, tol) {
                report = Found {
                    graze: true,
                    direction: group[0].direction,
                    ..nearest
                };
            } else if report.graze {
                let rate = n.dot(nearest.s.mv * inv);
                report = Found {
                    graze: false,
                    direction: if rate > 0.0 {
                        EventDirection::Rising
                    } else {
                        EventDirection::Falling
                    },
                    ..group[0]
                };
            }
        }
        found[out] = report;
        out += 1;
    }
    found.truncate(out);
}

/// How close together (s) sign changes must be to be one touch: a millionth of the segment,
/// or for a plane, the time over which a path tangent to it stays within rounding of it. A
/// path at `a` along the normal that overshoots the plane by `delta <= tol` (rounding) crosses
/// it twice, `2 sqrt(2 delta / |a|)` apart: at 2 m/s^2 and 40 m, about 3e-7 s, more than a
/// millionth of a 60 Hz tick.
fn touch_window(test: &Test, seg: &Segment) -> f64 {
    let window = 1e-6 * seg.duration;
    let Test::Linear { n, d } = test else {
        return window;
    };
    let a = n.dot((seg.end.mv - seg.start.mv) * seg.body.w.inv).abs() / seg.duration;
    let size = seg
        .start
        .p
        .abs()
        .max_element()
        .max(seg.end.p.abs().max_element())
        + d.abs();
    let tol = 2.0 * rounding(size);
    let width = 2.0 * (2.0 * tol / a).sqrt();
    if width.is_finite() {
        window.max(width)
    } else {
        window
    }
}

/// Whether a plane's function, at the report `f`, turns back within `tol` of zero. At the
/// segment's mean acceleration along the normal `a`, the path through `f` (value `g`, rate `r`)
/// is the parabola that goes on for `r^2 / 2|a|` before turning, to the extreme value `g - r^2
/// / 2a`. It is a tangent when either is within rounding: a path that turns within rounding of
/// a sample that is itself on the zero, or one whose extreme is, wherever on it the sample
/// fell (a sample 1.7e-7 s before a tangent, 2e-13 m below the plane, has 2e-13 m of rise
/// left: the first reading alone would call that a crossing; a sample whose value is rounding
/// noise has the second's extreme off by that noise).
fn turns_back((n, d): (DVec3, f64), f: &Found, seg: &Segment, tol: f64) -> bool {
    let inv = seg.body.w.inv;
    let r = n.dot(f.s.mv * inv);
    let a = n.dot((seg.end.mv - seg.start.mv) * inv) / seg.duration;
    if r == 0.0 {
        return true;
    }
    // Either side of the turn: a sample just past it moves away from the plane, but the path
    // it is on turned within `r^2 / 2|a|` of it all the same.
    let g = n.dot(f.s.p) - d;
    r * r <= 2.0 * a.abs() * tol || (a != 0.0 && (g - r * r / (2.0 * a)).abs() <= tol)
}

/// Whether a tick boundary, the point `p` with the function's value `g`, is on the zero: the
/// one rule both segments that meet there apply to the same bits. A segment ending on the zero
/// reports the touch (or the crossing) there, whatever its pieces' bounds read; the segment
/// starting on it drops its first group of sign changes as that touch's other side. So a root
/// on a boundary, or a tangent there, is reported once, by the earlier segment; a value just
/// outside is the later segment's, which reports it at its start.
fn on_boundary(test: &Test, seg: &Segment, p: &PathPoint, g: f64) -> bool {
    g.abs() <= 2.0 * rounding_of(test, seg, p)
}

/// Rounding of a function's value near the point `p`.
fn rounding_of(test: &Test, seg: &Segment, p: &PathPoint) -> f64 {
    let v = p.s.mv * seg.body.w.inv;
    match test {
        Test::Linear { d, .. } => rounding(p.s.p.abs().max_element() + d.abs()),
        Test::Apex => rounding(v.abs().max_element()),
        Test::Speed(s) => rounding(v.length() + s.abs()),
        Test::Mach { mach, .. } => rounding(2.0 * mach.abs() + 1.0),
        Test::Closest { c0, u } => {
            let c = *c0 + (seg.since + p.tau) * *u;
            rounding((p.s.p - c).length() * (v - *u).length())
        }
    }
}

/// A plane's graze is where the path is tangent to it: where `n . V` changes sign, a root the
/// finder finds to a few ulps, where the touch itself is known only to the width over which the
/// path stays within rounding of the plane (`sqrt(rounding / curvature)`). Looked for around
/// the touch, within a millionth of the segment; kept as found if it does not change sign there.
fn refine_graze(
    f: &mut Found,
    (n, d): (DVec3, f64),
    seg: &Segment,
    path: &mut impl FnMut(f64) -> BodyState,
) {
    let inv = seg.body.w.inv;
    let half = touch_window(&Test::Linear { n, d }, seg);
    let (lo, hi) = ((f.tau - half).max(0.0), (f.tau + half).min(seg.duration));
    let rate = |s: &BodyState| n.dot(s.mv * inv);
    let (a, b) = (path(lo), path(hi));
    let (ra, rb) = (rate(&a), rate(&b));
    if ra * rb >= 0.0 || (ra * rb).is_nan() {
        // No sign change of the rate inside: the tangent is a Newton step away at the
        // segment's mean acceleration along the normal (a touch on the segment's end).
        let accel = n.dot((seg.end.mv - seg.start.mv) * inv) / seg.duration;
        let r = rate(&f.s);
        if accel != 0.0 && accel.is_finite() {
            let tau = (f.tau - r / accel).clamp(lo, hi);
            if tau != f.tau {
                f.tau = tau;
                f.s = path(tau);
            }
        }
        return;
    }
    let (tau, _) = crate::contact::roots::bracketed_root(|t| rate(&path(t)), (lo, ra), (hi, rb));
    f.tau = tau;
    f.s = path(tau);
}

/// The way a path that starts exactly on zero leaves it: the sign of the function where it
/// first gets farther from zero than rounding, looked at from the touch window on, doubling.
/// Near the start the function can be rounding noise of either sign (a position that has not
/// moved an ulp, a partial step whose sub-steps round the other way, a speed's square root),
/// which the first-root search would otherwise take for the way it left.
fn departure(
    test: &Test,
    seg: &Segment,
    path: &mut impl FnMut(f64) -> BodyState,
) -> Option<EventDirection> {
    let mut tau = touch_window(test, seg);
    while tau < seg.duration {
        let s = path(tau);
        let value = test.value(seg.since + tau, &s, seg.body.w.inv);
        let p = PathPoint { tau, s, value };
        if value.abs() > 2.0 * rounding_of(test, seg, &p) {
            return Some(if value > 0.0 {
                EventDirection::Rising
            } else {
                EventDirection::Falling
            });
        }
        tau *= 2.0;
    }
    None
}

/// A run of touches, as one graze approached from the side `direction` says.
fn graze(t: PathPoint, direction: EventDirection) -> Found {
    Found {
        tau: t.tau,
        s: t.s,
        direction,
        graze: true,
    }
}

/// The event at a fresh body's spawn: its function starts on zero and leaves it `direction`.
fn at_start(seg: &Segment, direction: EventDirection) -> Found {
    Found {
        tau: 0.0,
        s: seg.start,
        direction,
        graze: false,
    }
}
