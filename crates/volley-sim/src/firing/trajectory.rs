//! The stepped trajectory a shot flies: its state at a time on the path the integrator steps
//! (whole steps, then one step of the remainder), sampled along the way.

use super::*;

/// The state of a body launched from `from` at `v0`, `t` seconds later, on the path the
/// integrator steps (whole steps of `hs`, then one step of the remainder). `t0` is the launch
/// on the world's clock (the scene's start time): where a time-dependent term's clock starts.
pub(super) struct At {
    pub(super) s0: BodyState,
    pub(super) t0: f64,
    pub(super) w: Mass,
    pub(super) hs: f64,
    pub(super) steps: u64,
    pub(super) tau: f64,
}

impl SchemeVisitor for At {
    type Out = BodyState;
    fn visit<S: Scheme>(self, scheme: S) -> BodyState {
        let (s, carry) = fly(
            &scheme,
            (self.s0, self.t0),
            self.w,
            self.hs,
            self.steps,
            |_, _| true,
        );
        let t = self.t0 + self.steps as f64 * self.hs;
        partial(&scheme, (s, carry), self.w, (t, self.tau))
    }
}

/// One step of `tau` from `s` and its carried force, or `s` itself when `tau` is 0: the
/// remainder after the whole steps, shared by [`At`] and [`Partial`].
fn partial<S: Scheme>(
    scheme: &S,
    (s, carry): (BodyState, DVec3),
    w: Mass,
    (t, tau): (f64, f64),
) -> BodyState {
    if tau > 0.0 {
        scheme.step(s, w, t, tau, carry).0
    } else {
        s
    }
}

/// `steps` whole steps of `hs` from `s0` at time `t0` as a world takes them (the carried force
/// started as at a spawn), calling `each` with every state reached and stopping early when it
/// says so. Returns the last state and carry.
pub(super) fn fly<S: Scheme>(
    scheme: &S,
    (s0, t0): (BodyState, f64),
    w: Mass,
    hs: f64,
    steps: u64,
    mut each: impl FnMut(BodyState, DVec3) -> bool,
) -> (BodyState, DVec3) {
    let (mut s, mut carry) = (s0, scheme.start_carry(s0, w, t0));
    for i in 0..steps {
        (s, carry) = scheme.step(s, w, t0 + i as f64 * hs, hs, carry);
        if !each(s, carry) {
            break;
        }
    }
    (s, carry)
}

/// The state and carried force at every step boundary `0..=count` of a body launched as in
/// [`At`] (stopping early where it stops being finite).
pub(super) struct Samples {
    pub(super) s0: BodyState,
    pub(super) t0: f64,
    pub(super) w: Mass,
    pub(super) hs: f64,
    pub(super) count: u64,
}

impl SchemeVisitor for Samples {
    type Out = Vec<(BodyState, DVec3)>;
    fn visit<S: Scheme>(self, scheme: S) -> Self::Out {
        let mut out = Vec::with_capacity(self.count as usize + 1);
        out.push((self.s0, scheme.start_carry(self.s0, self.w, self.t0)));
        fly(
            &scheme,
            (self.s0, self.t0),
            self.w,
            self.hs,
            self.count,
            |s, carry| {
                out.push((s, carry));
                s.p.is_finite()
            },
        );
        out
    }
}

/// One partial step of `tau` from a state and its carried force at time `t`.
pub(super) struct Partial {
    pub(super) s: BodyState,
    pub(super) carry: DVec3,
    pub(super) w: Mass,
    pub(super) t: f64,
    pub(super) tau: f64,
}

impl SchemeVisitor for Partial {
    type Out = BodyState;
    fn visit<S: Scheme>(self, scheme: S) -> BodyState {
        partial(&scheme, (self.s, self.carry), self.w, (self.t, self.tau))
    }
}

/// The rounding floor of a position stepped `steps` times at coordinates of magnitude `size`:
/// `steps` ulps of `size` (each step rounds by up to half an ulp, and the partial step and the
/// target's own position once more). Below this no launch correction is meaningful.
pub fn rounding_floor(steps: f64, size: f64) -> f64 {
    steps * f64::EPSILON * size
}

/// Whole steps of `hs` and the remainder in `t`.
pub(super) fn split_time(t: f64, hs: f64) -> (u64, f64) {
    let mut steps = (t / hs).floor().max(0.0) as u64;
    let mut tau = t - steps as f64 * hs;
    if tau < 0.0 && steps > 0 {
        steps -= 1;
        tau += hs;
    }
    if tau >= hs {
        steps += 1;
        tau -= hs;
    }
    (steps, tau.max(0.0))
}
