//! The first root of a function along a body's own curved path inside a step: the one search
//! every swept query over the path uses: the level surfaces' contacts and the declared
//! events ([`super::events`]).
//!
//! ## The path
//! Inside a segment that starts at state `s0`, the body is at `P(tau) = step(s0, tau).p`: the
//! integrator's own partial step of length `tau`, the map the contact stage moves bodies along.
//! Its shape depends on the scheme: explicit Euler's is the straight line `p0 + tau V0`;
//! semi-implicit (and implicit) Euler's is `p0 + tau V0 + tau^2 a`, so `P'' = 2a`; the schemes
//! exact under constant force (exact, RK4, midpoint, Verlet, Forest-Ruth, Dormand-Prince,
//! implicit midpoint) follow the parabola `p0 + tau V0 + tau^2 a / 2`, `P'' = a`.
//!
//! ## The bound
//! On a piece `[ta, tb]` of length `T`, a path with `|P''| <= K` stays within `K T^2 / 8` of
//! its chord (the interpolation error of a line through the piece's ends). The search takes
//! `K = 2 |V(tb) - V(ta)| / T` from the partial steps' own end velocities: under a constant
//! force `V(tau) = V0 + tau a` for every scheme above, so that `K = 2 |a|` bounds `P''` for all
//! of them (with equality for the Eulers). The margin is then
//! `M = |V(tb) - V(ta)| T / 4 * SAFETY + rounding`, with [`SAFETY`] = 2 for forces that change
//! along the piece (drag, springs, a point mass): the estimate's error falls as the pieces
//! shrink, and the factor covers a force changing by up to its own size across a piece. The
//! bound is rigorous under constant force (gravity, a constant force: every hard case), and a
//! bounded heuristic otherwise.
//!
//! ## The search
//! The piece's path lies in the ball around the chord's midpoint of radius `|chord| / 2 + M`.
//! If the [`Crossing`] says nothing in that ball can reach zero, the piece is clear. Otherwise
//! it is halved (one partial step at the midpoint), earlier half first, depth first. A piece
//! whose end value is `<= 0` holds a root; once such a piece is shorter than the crossing's
//! resolution (chord plus margin), it is handed to the bracketed root finder
//! ([`bracketed_root`], Illinois), which converges to a few ulps of time. So:
//! - no miss: a piece is dropped only when the bound proves the path cannot come within reach;
//! - the first root: earlier pieces are settled before later ones are looked at, and two roots
//!   closer than the resolution (in path length) are not told apart;
//! - a graze that dips in and out between two samples is found once the pieces are shorter
//!   than its dip; a tangent touch, which never goes below zero, ends at [`MAX_DEPTH`] (pieces
//!   of `2^-MAX_DEPTH` of the segment) as no root, and a [`Crossing`] may clear pieces that
//!   only come within its own tolerance of zero (the level gap does, at the touching
//!   distance); at most [`MAX_PIECES`] pieces are looked at;
//! - a root exactly on a segment boundary is found once: the search looks at `(ta, tb]`, a
//!   value `<= 0` at `tb` is that segment's root, and the next segment starts there, touching,
//!   which its caller handles before searching.

use glam::DVec3;

use crate::body::BodyState;

/// Factor on the constant-force margin, for forces that change along a piece.
pub const SAFETY: f64 = 2.0;

/// Most halvings of a segment: pieces of `2^-48` of it are below the rounding of any time
/// inside it, so a tangent graze ends here.
pub const MAX_DEPTH: u32 = 48;

/// Most pieces one search looks at. A path that keeps within rounding of the crossing's zero
/// without crossing it could otherwise be split down to [`MAX_DEPTH`] everywhere (2^48 pieces);
/// past this budget the search ends with no root, and the contact stage's end-of-step push-out
/// keeps the body outside. Far more than a search needs: a root found through 48 halvings with
/// every sibling asked about is under a hundred pieces.
pub const MAX_PIECES: u32 = 4096;

/// A point of the path: time from the segment's start (s) and the state there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathPoint {
    pub tau: f64,
    pub s: BodyState,
    /// The crossing's value there.
    pub value: f64,
}

/// What the search looks for the first root of: a function along the path and what can be
/// said of a piece from its two ends.
pub(crate) trait Crossing {
    /// The function at time `tau` into the segment, in state `s`, continuous along the path; a
    /// root is where it goes from `> 0` to `<= 0`.
    fn value(&mut self, tau: f64, s: &BodyState) -> f64;
    /// Whether the function can reach `<= 0` anywhere on the piece from `a` to `b` (both `> 0`
    /// there); `false` only when certain.
    fn possible(&mut self, a: &PathPoint, b: &PathPoint) -> bool;
    /// Whether the piece from `a` (`> 0`) to `b` (`<= 0`) can be handed to the bracketed root
    /// finder as it is: it holds one root, or two too close to tell apart.
    fn bracketed(&mut self, a: &PathPoint, b: &PathPoint) -> bool;
    /// Time (s) below which the root finder stops telling roots apart, or 0 for a few ulps of
    /// the time into the segment. A declared event's is a few ulps of the sim time it reports.
    fn resolution_time(&self) -> f64 {
        0.0
    }
}

/// A crossing of the position alone that answers for a ball (the level surfaces): the search
/// asks it about the ball around the piece's chord midpoint of radius `|chord| / 2 + M`
/// ([`margin`]), through [`OnBall`].
pub(crate) trait BallCrossing {
    /// The function at `s`, continuous along the path.
    fn value(&mut self, s: &BodyState) -> f64;
    /// Whether the function can reach zero anywhere in the ball `(center, radius)`; `false`
    /// only when certain.
    fn possible(&mut self, center: DVec3, radius: f64) -> bool;
    /// Path length (m) below which a piece with a root is bracketed at once.
    fn resolution(&self) -> f64;
}

/// A [`BallCrossing`] asked about the balls of a body of `1 / mass` `inv_m`.
pub(crate) struct OnBall<'a, C> {
    pub crossing: &'a mut C,
    pub inv_m: f64,
}

impl<C: BallCrossing> Crossing for OnBall<'_, C> {
    #[inline]
    fn value(&mut self, _tau: f64, s: &BodyState) -> f64 {
        self.crossing.value(s)
    }

    #[inline]
    fn possible(&mut self, a: &PathPoint, b: &PathPoint) -> bool {
        let m = margin(&a.s, &b.s, self.inv_m, b.tau - a.tau);
        let chord = (b.s.p - a.s.p).length();
        self.crossing
            .possible(0.5 * (a.s.p + b.s.p), 0.5 * chord + m)
    }

    #[inline]
    fn bracketed(&mut self, a: &PathPoint, b: &PathPoint) -> bool {
        let m = margin(&a.s, &b.s, self.inv_m, b.tau - a.tau);
        let chord = (b.s.p - a.s.p).length();
        chord + m <= self.crossing.resolution()
    }
}

/// The margin of the piece from `a` to `b`: how far its path may leave its chord (m).
#[inline]
pub(crate) fn margin(a: &BodyState, b: &BodyState, inv_m: f64, duration: f64) -> f64 {
    let dv = ((b.mv - a.mv) * inv_m).length();
    let rounding = 8.0 * f64::EPSILON * (a.p.abs().max_element() + b.p.abs().max_element());
    0.25 * SAFETY * dv * duration + rounding
}

/// The first root of `crossing` on the path from `a` (value `> 0`; an event's search may start
/// it at exactly 0, a point already counted) to `b`, `path(tau)` being the state at `tau`.
/// Returns the last point before it (value `> 0`, within a few ulps of time of the root) and
/// the first at or after it, or `None` if the path stays clear.
pub(crate) fn first_root(
    path: &mut impl FnMut(f64) -> BodyState,
    a: PathPoint,
    b: PathPoint,
    crossing: &mut impl Crossing,
) -> Option<(PathPoint, PathPoint)> {
    debug_assert!(a.value >= 0.0);
    // Depth first, earlier half on top: at most one pending piece per level. Each entry is
    // written before it is read; the array starts as `None`s, which writes a tag per entry
    // where copies of `(a, b)` wrote 136 bytes: filling those cost more than a search that
    // ends at its first piece, most of them (perf, the events bench's busy window).
    let mut stack: [Option<(PathPoint, PathPoint, u32)>; MAX_DEPTH as usize + 2] =
        [None; MAX_DEPTH as usize + 2];
    stack[0] = Some((a, b, 0));
    let mut top = 1;
    let mut pieces = 0;
    while top > 0 && pieces < MAX_PIECES {
        pieces += 1;
        top -= 1;
        let Some((a, b, depth)) = stack[top] else {
            break;
        };
        if b.value <= 0.0 {
            if depth >= MAX_DEPTH || crossing.bracketed(&a, &b) {
                return Some(refine(path, crossing, a, b));
            }
        } else if depth >= MAX_DEPTH || !crossing.possible(&a, &b) {
            continue;
        }
        let tau = 0.5 * (a.tau + b.tau);
        if !(tau > a.tau && tau < b.tau) {
            // No time left between them: the root (if any) is at `b`.
            if b.value <= 0.0 {
                return Some((a, b));
            }
            continue;
        }
        let s = path(tau);
        let mid = PathPoint {
            tau,
            s,
            value: crossing.value(tau, &s),
        };
        if mid.value > 0.0 {
            stack[top] = Some((mid, b, depth + 1));
            top += 1;
        }
        stack[top] = Some((a, mid, depth + 1));
        top += 1;
    }
    None
}

/// Illinois on a piece with `a.value > 0 >= b.value`.
fn refine(
    path: &mut impl FnMut(f64) -> BodyState,
    crossing: &mut impl Crossing,
    a: PathPoint,
    b: PathPoint,
) -> (PathPoint, PathPoint) {
    let mut last: Option<PathPoint> = None;
    let within = crossing.resolution_time();
    let (tau, _) = bracketed_root_within(
        |tau| {
            let s = path(tau);
            let value = crossing.value(tau, &s);
            last = Some(PathPoint { tau, s, value });
            value
        },
        (a.tau, a.value),
        (b.tau, b.value),
        within,
    );
    // The finder returns the lo side's time; its state is the last evaluated there, or `a`.
    let lo = match last {
        Some(p) if p.tau == tau && p.value > 0.0 => p,
        _ if tau == a.tau => a,
        _ => {
            let s = path(tau);
            PathPoint {
                tau,
                s,
                value: crossing.value(tau, &s),
            }
        }
    };
    (lo, b)
}

/// Finds a root of `f` between `lo.0` and `hi.0`, where `f(lo.0) = lo.1` and `f(hi.0) = hi.1`
/// have opposite signs (`>= 0` counts as positive). Illinois regula falsi with a bisection every
/// fourth step, so it converges superlinearly on smooth functions and never slower than
/// bisection. Returns the point on `lo`'s side of the root (for a contact: not yet touching)
/// within a few ulps, and the number of evaluations of `f`.
pub(crate) fn bracketed_root(
    f: impl FnMut(f64) -> f64,
    lo: (f64, f64),
    hi: (f64, f64),
) -> (f64, u64) {
    bracketed_root_within(f, lo, hi, 0.0)
}

/// [`bracketed_root`], ending once the bracket is `within` wide (when `within > 0`). Each new
/// point then keeps `within / 2` from both ends, so a root that sits at one end (where regula
/// falsi would keep landing beside it, shrinking the far side only by the Illinois halvings and
/// the fourth-step bisections) is bracketed at the next evaluation: a few instead of dozens.
#[inline(always)]
pub(crate) fn bracketed_root_within(
    mut f: impl FnMut(f64) -> f64,
    lo: (f64, f64),
    hi: (f64, f64),
    within: f64,
) -> (f64, u64) {
    let ((mut a, mut fa), (mut b, mut fb)) = (lo, hi);
    let positive_at_a = fa >= 0.0;
    // Absolute floor of the tolerance, so a root at 0 ends the search too.
    let floor = 1e-3 * (b - a).abs();
    let mut evals = 0;
    let mut last_side = 0i8;
    for i in 0..400 {
        let width = b - a;
        if width.abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(floor)
            || width.abs() <= within
        {
            break;
        }
        let mut x = if i % 4 == 3 {
            0.5 * (a + b)
        } else {
            (a * fb - b * fa) / (fb - fa)
        };
        if !((x > a.min(b)) && (x < a.max(b))) {
            x = 0.5 * (a + b);
        }
        if within > 0.0 {
            if fa == 0.0 {
                // Exactly on the root: the point just past it closes the bracket.
                x = a + 0.5 * within * (b - a).signum();
            }
            x = x.clamp(a.min(b) + 0.5 * within, a.max(b) - 0.5 * within);
        }
        let fx = f(x);
        evals += 1;
        if (fx >= 0.0) == positive_at_a {
            a = x;
            fa = fx;
            if last_side == -1 {
                fb *= 0.5;
            }
            last_side = -1;
        } else {
            b = x;
            fb = fx;
            if last_side == 1 {
                fa *= 0.5;
            }
            last_side = 1;
        }
    }
    (a, evals)
}

#[cfg(test)]
mod tests;
