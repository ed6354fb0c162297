//! The per-body loop: one scheme step per body, contacts inline where a body is near a surface,
//! the non-finite check branch-free, compiled for the baseline CPU, AVX2 and AVX-512 and
//! dispatched once per chunk by [`simd_level`].

use std::cell::RefCell;
use std::sync::atomic::Ordering::Relaxed;

use glam::DVec3;

use crate::contact::events::horizon::{DUE_BLOCK, Horizon, quiet_steps};
use crate::contact::{self, Detection, Event, Particle, StepContext};
use crate::integrate::{BodyState, Dense, Scheme, SchemeVisitor, visit_with};
#[cfg(target_arch = "x86_64")]
use crate::simd::{SimdLevel, simd_level};
use crate::world::{LoopKind, World};

use super::chunk::{Chunk, Fixed, split_run};

impl World {
    /// Integrate + contacts over all bodies; returns the first body whose state is not finite.
    /// `t0` is the step's start as sim time and as time since tick 0, `k` the substep.
    #[inline]
    pub(super) fn integrate(
        &mut self,
        tick: u64,
        (t0, since): (f64, f64),
        h: f64,
        k: u32,
    ) -> Option<usize> {
        let (chunks, carries) = self.prepare_chunks();
        let gravity = self.facts.gravity;
        let horizon = if self.kind == LoopKind::Events && self.prepare_horizons() {
            self.facts.constant.as_ref().map(|field| Horizon {
                // The step's number since tick 0, which horizons count in.
                step: (tick - 1) * u64::from(self.params.substeps) + u64::from(k),
                field,
                due: self.scratch.due.column(),
                blocks: self.scratch.due.blocks(),
                surfaces: self.params.contacts.has_surfaces(),
            })
        } else {
            None
        };
        let ctx = StepContext {
            contacts: &self.params.contacts,
            tick,
            t0,
            since_start: since,
            h,
            rest_speed: gravity * h,
            levels: self.params.contacts.has_levels(),
            fresh: &self.scratch.fresh,
            horizon: horizon.as_ref(),
        };
        let b = &mut self.state.bodies;
        let (fixed, p, mv) = Fixed::of(b, self.facts.reads_launch);
        let chunk = fixed.chunk(p, mv, &mut self.state.carry, carries);
        let out = visit_with(
            self.state.integrator,
            &self.state.forces,
            self.facts.constant.as_ref(),
            self.params.tolerance,
            Integrate {
                chunk,
                ctx: &ctx,
                events: &mut self.scratch.chunk_events[..chunks],
                carry_valid: self.carry_valid,
                kind: self.kind,
            },
        );
        self.carry_valid = out.carried;
        self.event_evals = self.event_evals.saturating_add(out.event_evals);
        // Saturating: a keyframe read from a file may start the count anywhere (fuzzing found
        // one near u64::MAX).
        self.state.force_evals = self.state.force_evals.saturating_add(out.evals);
        for buffer in &mut self.scratch.chunk_events[..chunks] {
            self.scratch.events.extend_from_slice(buffer);
            buffer.clear();
        }
        out.first_non_finite
    }
}

impl World {
    /// In a world with declared events: whether the step keeps horizons (every force a
    /// constant field), sizing them to the bodies if so. Out of line: no other world pays for
    /// it.
    #[inline(never)]
    fn prepare_horizons(&mut self) -> bool {
        let horizons = self.facts.constant.is_some() && !self.scratch.horizons_off;
        if horizons && self.scratch.due.len() != self.state.bodies.len() {
            self.scratch.due.reset(self.state.bodies.len());
        }
        horizons
    }
}

/// What one chunk's loop reports.
#[derive(Clone, Copy, Default)]
pub(super) struct KernelOut {
    pub(super) evals: u64,
    pub(super) first_non_finite: Option<usize>,
    /// Whether the scheme wrote the carried force (velocity Verlet's carrying form only).
    pub(super) carried: bool,
    /// Force evaluations the declared events' search spent (not the step's).
    pub(super) event_evals: u64,
}

impl KernelOut {
    /// Combines two chunks in order: counts add, the lower index wins.
    #[inline]
    pub(super) fn then(self, later: KernelOut) -> KernelOut {
        KernelOut {
            evals: self.evals + later.evals,
            first_non_finite: self.first_non_finite.or(later.first_non_finite),
            carried: self.carried,
            event_evals: self.event_evals + later.event_evals,
        }
    }
}

pub(super) struct Integrate<'a, 'f> {
    chunk: Chunk<'a>,
    ctx: &'f StepContext<'f>,
    events: &'a mut [Vec<Event>],
    carry_valid: bool,
    kind: LoopKind,
}

impl SchemeVisitor for Integrate<'_, '_> {
    type Out = KernelOut;
    fn visit<S: Scheme>(self, scheme: S) -> KernelOut {
        let Integrate {
            mut chunk,
            ctx,
            events,
            carry_valid,
            kind,
        } = self;
        let extra = start_carry(&scheme, &mut chunk, carry_valid, ctx.t0);
        let out = match kind {
            LoopKind::Bare => split_run::<S, false, false, false>(&scheme, chunk, ctx, events),
            LoopKind::Contacts if ctx.levels => {
                split_run::<S, true, true, false>(&scheme, chunk, ctx, events)
            }
            LoopKind::Contacts => split_run::<S, true, false, false>(&scheme, chunk, ctx, events),
            LoopKind::Events if ctx.levels => {
                split_run::<S, true, true, true>(&scheme, chunk, ctx, events)
            }
            LoopKind::Events => split_run::<S, true, false, true>(&scheme, chunk, ctx, events),
        };
        KernelOut {
            evals: out.evals + extra,
            carried: S::CARRIES_FORCE,
            ..out
        }
    }
}

/// What both visitors (the per-tick [`Integrate`] and the batch) do first: fill the carried
/// force where the scheme carries one and it is not valid yet. Returns the force evaluations
/// that cost (one per body), or 0.
#[inline]
pub(super) fn start_carry<S: Scheme>(
    scheme: &S,
    chunk: &mut Chunk,
    carry_valid: bool,
    t: f64,
) -> u64 {
    if S::CARRIES_FORCE && !carry_valid {
        fill_carry(scheme, chunk, t)
    } else {
        0
    }
}

pub(super) fn fill_carry<S: Scheme>(scheme: &S, l: &mut Chunk, t: f64) -> u64 {
    for i in 0..l.len() {
        let s = BodyState {
            p: DVec3::new(l.px[i], l.py[i], l.pz[i]),
            mv: DVec3::new(l.mx[i], l.my[i], l.mz[i]),
        };
        let w = l.launch.mass::<S>(i, l.mass[i], l.inv_mass[i]);
        let f = scheme.start_carry(s, w, t);
        (l.cx[i], l.cy[i], l.cz[i]) = (f.x, f.y, f.z);
    }
    l.len() as u64 // one evaluation per body
}

/// `true` unless a component is NaN or infinite; branch-free so the loop vectorises.
#[inline(always)]
pub(super) fn finite(v: DVec3) -> bool {
    (v.x.abs() <= f64::MAX) & (v.y.abs() <= f64::MAX) & (v.z.abs() <= f64::MAX)
}

/// The per-body loop of one chunk, in the widest version the CPU runs ([`simd_level`]).
#[inline]
pub(super) fn run<S: Scheme, const CONTACTS: bool, const LEVELS: bool, const EVENTS: bool>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    // A vector loop only pays off once there is a vector's worth of bodies; the versions give
    // the same bits, so this is only about speed.
    #[cfg(target_arch = "x86_64")]
    {
        let streaming = l.len() >= STREAMING_MIN_BODIES;
        // SAFETY: `simd_level` returns a level only if the CPU supports its features.
        match simd_level() {
            _ if l.len() < 8 => {}
            SimdLevel::Avx512 if streaming => {
                return unsafe {
                    run_avx512::<S, CONTACTS, LEVELS, EVENTS, true>(scheme, l, ctx, events)
                };
            }
            SimdLevel::Avx512 => {
                return unsafe {
                    run_avx512::<S, CONTACTS, LEVELS, EVENTS, false>(scheme, l, ctx, events)
                };
            }
            SimdLevel::Avx2 if streaming => {
                return unsafe {
                    run_avx2::<S, CONTACTS, LEVELS, EVENTS, true>(scheme, l, ctx, events)
                };
            }
            SimdLevel::Avx2 => {
                return unsafe {
                    run_avx2::<S, CONTACTS, LEVELS, EVENTS, false>(scheme, l, ctx, events)
                };
            }
            SimdLevel::Baseline => {}
        }
    }
    run_baseline::<S, CONTACTS, LEVELS, EVENTS>(scheme, l, ctx, events)
}

#[inline(never)]
pub(super) fn run_baseline<
    S: Scheme,
    const CONTACTS: bool,
    const LEVELS: bool,
    const EVENTS: bool,
>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_chunk::<S, CONTACTS, LEVELS, EVENTS, false>(scheme, l, ctx, events)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx2")]
pub(super) fn run_avx2<
    S: Scheme,
    const CONTACTS: bool,
    const LEVELS: bool,
    const EVENTS: bool,
    const STREAMING: bool,
>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_chunk::<S, CONTACTS, LEVELS, EVENTS, STREAMING>(scheme, l, ctx, events)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx512f")]
pub(super) fn run_avx512<
    S: Scheme,
    const CONTACTS: bool,
    const LEVELS: bool,
    const EVENTS: bool,
    const STREAMING: bool,
>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_chunk::<S, CONTACTS, LEVELS, EVENTS, STREAMING>(scheme, l, ctx, events)
}

/// Chunks of at least this many bodies (about 30 MB of state, an L3's worth) stream from
/// memory: their loop divides `1 / m` instead of loading the stored reciprocal. Memory, not
/// arithmetic, bounds such a loop, so the division is free and 8 of the 112 bytes a body moves
/// per step are saved. `1.0 / m` is exactly what is stored at spawn, so the bits are the same.
pub const STREAMING_MIN_BODIES: usize = 1 << 18;

/// The per-body loop of one chunk, inlined into each instruction-set version of [`run`].
/// `STREAMING` recomputes `1 / m` instead of loading it (see [`STREAMING_MIN_BODIES`]).
/// `CONTACTS` compiles the contact stage in, `LEVELS` its level surfaces (meshes, heightfields),
/// `EVENTS` the declared events' search.
#[inline(always)]
pub(super) fn run_chunk<
    S: Scheme,
    const CONTACTS: bool,
    const LEVELS: bool,
    const EVENTS: bool,
    const STREAMING: bool,
>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    if EVENTS && !S::DENSE && !LEVELS && ctx.horizon.is_some_and(|hz| !hz.surfaces) {
        return run_events_apart::<S, STREAMING>(scheme, l, ctx, events);
    }
    let n = l.len();
    let (px, py, pz) = (&mut l.px[..n], &mut l.py[..n], &mut l.pz[..n]);
    let (mx, my, mz) = (&mut l.mx[..n], &mut l.my[..n], &mut l.mz[..n]);
    let (mass, inv_mass) = (&l.mass[..n], &l.inv_mass[..n]);
    // Declared events' horizons, when the step keeps them.
    let due = match ctx.horizon {
        Some(hz) if EVENTS => &hz.due[l.offset..l.offset + n],
        _ => &[],
    };
    let (cx, cy, cz) = if S::CARRIES_FORCE {
        (&mut l.cx[..n], &mut l.cy[..n], &mut l.cz[..n])
    } else {
        (&mut l.cx[..0], &mut l.cy[..0], &mut l.cz[..0])
    };
    let (t, h) = (ctx.t0, ctx.h);
    // An adaptive scheme counts its own evaluations, body by body.
    let mut evals = if S::ADAPTIVE { 0 } else { n as u64 * S::EVALS };
    let mut event_evals = 0u64;
    // Dormand-Prince's continuous extension of each body's step, for the events' search.
    let mut dense = Dense::default();
    let mut all_finite = true;
    for i in 0..n {
        let w = if STREAMING {
            l.launch.mass::<S>(i, mass[i], 1.0 / mass[i])
        } else {
            l.launch.mass::<S>(i, mass[i], inv_mass[i])
        };
        let s0 = BodyState {
            p: DVec3::new(px[i], py[i], pz[i]),
            mv: DVec3::new(mx[i], my[i], mz[i]),
        };
        let c0 = if S::CARRIES_FORCE {
            DVec3::new(cx[i], cy[i], cz[i])
        } else {
            DVec3::ZERO
        };
        let (mut s1, mut c1) = if EVENTS && S::DENSE {
            let (s1, c1, n) = scheme.step_dense(s0, w, t, h, c0, &mut dense);
            evals += n;
            (s1, c1)
        } else if S::ADAPTIVE {
            let (s1, c1, n) = scheme.step_counted(s0, w, t, h, c0);
            evals += n;
            (s1, c1)
        } else {
            scheme.step(s0, w, t, h, c0)
        };
        if EVENTS {
            let body = Particle {
                id: l.ids[i],
                w,
                r: l.radius[i],
                fresh: ctx.fresh.binary_search(&l.ids[i]).is_ok(),
            };
            let resolves = contact::needs_resolution::<LEVELS>(ctx, l.radius[i], w.inv, &s0, &s1);
            let swept = ctx.contacts.detection == Detection::Swept;
            // Within its horizon a body's search would find nothing: skipped.
            let quiet = match ctx.horizon {
                Some(hz) if !due.is_empty() => !resolves && hz.step < due[i].load(Relaxed),
                _ => false,
            };
            if !(quiet || (resolves && swept)) {
                // The whole step is one segment (discrete detection's before its push-out).
                if S::DENSE {
                    contact::events_on_dense_step(scheme, ctx, body, (s0, s1), &dense, events);
                } else {
                    contact::events_on_segment(
                        scheme,
                        ctx,
                        body,
                        0.0,
                        (s0, c0),
                        h,
                        s1,
                        events,
                        &mut event_evals,
                    );
                }
            }
            if resolves {
                let extra;
                (s1, c1, extra) = contact::resolve::<S, LEVELS, true>(
                    scheme,
                    ctx,
                    body,
                    (s0, c0),
                    (s1, c1),
                    events,
                    &mut event_evals,
                );
                evals += extra;
            }
            if let Some(hz) = ctx.horizon
                && !due.is_empty()
                && !quiet
            {
                // A bounce is a new path: due again at once.
                let next = if resolves {
                    0
                } else {
                    let a = hz.field.gravity + hz.field.force * w.inv;
                    let set = &ctx.contacts.events;
                    hz.step + 1 + quiet_steps(set, body.id, &s1, w.inv, a, h)
                };
                hz.set_due(l.offset + i, next);
            }
        } else if CONTACTS && contact::needs_resolution::<LEVELS>(ctx, l.radius[i], w.inv, &s0, &s1)
        {
            let body = Particle {
                id: l.ids[i],
                w,
                r: l.radius[i],
                fresh: false,
            };
            let extra;
            (s1, c1, extra) = contact::resolve::<S, LEVELS, false>(
                scheme,
                ctx,
                body,
                (s0, c0),
                (s1, c1),
                events,
                &mut event_evals,
            );
            evals += extra;
        }
        all_finite &= finite(s1.p) & finite(s1.mv);
        (px[i], py[i], pz[i]) = (s1.p.x, s1.p.y, s1.p.z);
        (mx[i], my[i], mz[i]) = (s1.mv.x, s1.mv.y, s1.mv.z);
        if S::CARRIES_FORCE {
            (cx[i], cy[i], cz[i]) = (c1.x, c1.y, c1.z);
        }
    }
    let first_non_finite = if all_finite {
        None
    } else {
        (0..n)
            .find(|&i| {
                !(finite(DVec3::new(px[i], py[i], pz[i])) & finite(DVec3::new(mx[i], my[i], mz[i])))
            })
            .map(|i| i + l.offset)
    };
    KernelOut {
        evals,
        first_non_finite,
        carried: S::CARRIES_FORCE,
        event_evals,
    }
}

/// The due bodies of [`run_events_apart`] and the summary blocks it sets again: per thread,
/// capacity reused by every chunk the thread steps (cleared at each use, so nothing passes from
/// one chunk to the next), so a tick allocates nothing once the buffers have grown.
type ApartBuffers = (Vec<(usize, BodyState, DVec3)>, Vec<usize>);

thread_local! {
    static APART: RefCell<ApartBuffers> = RefCell::default();
}

/// A chunk of a world with declared events, horizons and nothing to hit: the bodies step as in
/// a world without events (the vectorised loop), then the search runs on the few whose
/// horizon ends, from the start states saved before the step. The same searches on the same
/// segments as the joint loop, in the same body order, so the same events and bits; a scheme
/// with a continuous extension ([`Scheme::DENSE`]) keeps the joint loop, which has it.
#[inline(always)]
fn run_events_apart<S: Scheme, const STREAMING: bool>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
) -> KernelOut {
    let Some(hz) = ctx.horizon else {
        unreachable!("called only with horizons")
    };
    // Taken out and put back rather than borrowed in a closure: the loop inlined here is
    // compiled for this function's vector width, which a closure's body would not inherit.
    let mut buffers = APART.take();
    let out = apart::<S, STREAMING>(scheme, l, ctx, events, hz, &mut buffers);
    APART.set(buffers);
    out
}

/// [`run_events_apart`] with its buffers, which it clears first.
#[inline(always)]
fn apart<S: Scheme, const STREAMING: bool>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    events: &mut Vec<Event>,
    hz: &Horizon,
    (starts, rebound): &mut ApartBuffers,
) -> KernelOut {
    starts.clear();
    rebound.clear();
    // The due bodies, with their start states and carried forces. A block of the summary
    // that lies wholly in this chunk and whose bound is later than this step is passed over
    // with one load, and its bound is set again here once its bodies are searched; the bodies
    // of a block shared with the next chunk are looked at one by one.
    let n = l.len();
    let due = &hz.due[l.offset..l.offset + n];
    let mut i = 0;
    while i < n {
        let global = l.offset + i;
        let k = global / DUE_BLOCK;
        let block_end = ((k + 1) * DUE_BLOCK - l.offset).min(n);
        let whole = global.is_multiple_of(DUE_BLOCK) && (k + 1) * DUE_BLOCK <= l.offset + n;
        if whole {
            if hz.blocks[k].load(Relaxed) > hz.step {
                i = block_end;
                continue;
            }
            rebound.push(k);
        }
        // `j` indexes the state's eight columns, not only `due`.
        #[allow(clippy::needless_range_loop)]
        for j in i..block_end {
            if due[j].load(Relaxed) <= hz.step {
                let s0 = BodyState {
                    p: DVec3::new(l.px[j], l.py[j], l.pz[j]),
                    mv: DVec3::new(l.mx[j], l.my[j], l.mz[j]),
                };
                let c0 = if S::CARRIES_FORCE {
                    DVec3::new(l.cx[j], l.cy[j], l.cz[j])
                } else {
                    DVec3::ZERO
                };
                starts.push((j, s0, c0));
            }
        }
        i = block_end;
    }
    let mut out = run_chunk::<S, false, false, false, STREAMING>(scheme, l, ctx, events);
    let mut event_evals = 0u64;
    for &(i, s0, c0) in starts.iter() {
        let w = if STREAMING {
            l.launch.mass::<S>(i, l.mass[i], 1.0 / l.mass[i])
        } else {
            l.launch.mass::<S>(i, l.mass[i], l.inv_mass[i])
        };
        let s1 = BodyState {
            p: DVec3::new(l.px[i], l.py[i], l.pz[i]),
            mv: DVec3::new(l.mx[i], l.my[i], l.mz[i]),
        };
        let body = Particle {
            id: l.ids[i],
            w,
            r: l.radius[i],
            fresh: ctx.fresh.binary_search(&l.ids[i]).is_ok(),
        };
        contact::events_on_segment(
            scheme,
            ctx,
            body,
            0.0,
            (s0, c0),
            ctx.h,
            s1,
            events,
            &mut event_evals,
        );
        let a = hz.field.gravity + hz.field.force * w.inv;
        let quiet = quiet_steps(&ctx.contacts.events, body.id, &s1, w.inv, a, ctx.h);
        hz.set_due(l.offset + i, hz.step + 1 + quiet);
    }
    for &k in rebound.iter() {
        let least = hz.due[k * DUE_BLOCK..(k + 1) * DUE_BLOCK]
            .iter()
            .fold(u64::MAX, |m, d| m.min(d.load(Relaxed)));
        hz.blocks[k].store(least, Relaxed);
    }
    out.event_evals += event_evals;
    out
}
