//! Many ticks of a world without contacts, block by block while each block sits in cache, with
//! the state saved first so a batch that diverges is undone and run again tick by tick.

use crate::contact::{Event, StepContext};
use crate::integrate::{Scheme, SchemeVisitor, visit};
use crate::world::World;

use super::chunk::{Chunk, Fixed};
use super::guard::{Guard, chunk_over_cap};
use super::kernel::{run, start_carry};

/// Bodies per block of a batch: with their backup (about 136 bytes a body) a block stays in
/// the L2 cache while it runs every tick of the batch.
pub const BATCH_BLOCK: usize = 2048;

/// The longest batch [`World::step_ticks`] runs: long enough that saving the state (one write
/// of 48 bytes a body per batch) costs little, short enough that undoing a batch that diverged
/// costs little.
pub const BATCH_MAX_TICKS: u64 = 64;

impl World {
    /// Runs `ticks` ticks of a world without contacts block by block; returns false, with the
    /// state, the carried force and the counters as they were, if a body turned non-finite or
    /// passed its energy bound at a tick the guard checks.
    pub(super) fn integrate_batch(&mut self, ticks: u64) -> bool {
        self.scratch.events.clear();
        let (chunks, carries) = self.prepare_chunks();
        let n = self.state.bodies.len();
        let t0 = self.time_of(self.state.tick);
        let saved = &mut self.scratch.batch_backup;
        saved.p.resize(n);
        saved.mv.resize(n);
        saved.carry.resize(if carries { n } else { 0 });
        let h = self.params.h / f64::from(self.params.substeps);
        let ctx = StepContext {
            contacts: &self.params.contacts,
            tick: self.state.tick + 1,
            t0,
            // Batches run only without contacts, where nothing reads it.
            since_start: self.state.tick as f64 * self.params.h,
            h,
            rest_speed: 0.0,
            levels: self.params.contacts.has_levels(),
            fresh: &[],
            horizon: None,
        };
        let b = &mut self.state.bodies;
        let (fixed, p, mv) = Fixed::of(b, self.facts.reads_launch);
        let chunk = fixed.chunk(p, mv, &mut self.state.carry, carries);
        let saved_chunk = fixed.chunk(&mut saved.p, &mut saved.mv, &mut saved.carry, carries);
        // The guard's test, on the model `guard_energy` uses, so it trips exactly where it would.
        let (caps, forces) = (fixed.energy_cap, &self.state.forces);
        let field = forces.constant_field();
        let over_cap = move |l: &Chunk| match &field {
            Some(field) => chunk_over_cap(l, field, caps),
            None => chunk_over_cap(l, forces, caps),
        };
        let guard = Guard {
            // Off where a term may add energy, as in `guard_energy`.
            every: if self.state.forces.adds_energy() {
                0
            } else {
                u64::from(self.params.guard.every)
            },
            first_tick: self.state.tick + 1,
            over_cap: &over_cap,
        };
        let out = visit(
            self.state.integrator,
            &self.state.forces,
            self.params.tolerance,
            Batch {
                chunk,
                saved: saved_chunk,
                events: &mut self.scratch.chunk_events[..chunks],
                carry_valid: self.carry_valid,
                work: BatchWork {
                    ctx: &ctx,
                    ticks,
                    substeps: self.params.substeps,
                    guard: &guard,
                    clock: (self.params.start_time, self.params.h),
                },
            },
        );
        if !out.ok {
            self.state.bodies.p.copy_from(&self.scratch.batch_backup.p);
            self.state
                .bodies
                .mv
                .copy_from(&self.scratch.batch_backup.mv);
            if carries {
                self.state.carry.copy_from(&self.scratch.batch_backup.carry);
            }
            return false;
        }
        self.carry_valid = out.carried;
        // Saturating: a keyframe read from a file may start the count anywhere (fuzzing found
        // one near u64::MAX).
        self.state.force_evals = self.state.force_evals.saturating_add(out.evals);
        true
    }
}

/// [`World::step_ticks`]'s batch over all bodies, saving their state into `saved` first.
pub(super) struct Batch<'a, 'f> {
    chunk: Chunk<'a>,
    saved: Chunk<'a>,
    events: &'a mut [Vec<Event>],
    carry_valid: bool,
    work: BatchWork<'f>,
}

/// What a batch reports.
#[derive(Clone, Copy)]
pub(super) struct BatchOut {
    evals: u64,
    /// No body turned non-finite or tripped the guard (otherwise the batch is undone, so
    /// which body does not matter).
    ok: bool,
    /// Whether the scheme wrote the carried force.
    carried: bool,
}

impl SchemeVisitor for Batch<'_, '_> {
    type Out = BatchOut;
    fn visit<S: Scheme>(self, scheme: S) -> BatchOut {
        let Batch {
            mut chunk,
            saved,
            events,
            carry_valid,
            work,
        } = self;
        let extra = start_carry(&scheme, &mut chunk, carry_valid, work.ctx.t0);
        let (evals, ok) = split_batch::<S>(&scheme, chunk, saved, events, &work);
        BatchOut {
            evals: evals + extra,
            ok,
            carried: S::CARRIES_FORCE,
        }
    }
}

/// What every chunk of a batch runs: `ticks` ticks of `substeps` steps each, with the guard.
pub(super) struct BatchWork<'f> {
    ctx: &'f StepContext<'f>,
    ticks: u64,
    substeps: u32,
    guard: &'f Guard<'f>,
    /// The world's start time and tick length (s): each step's start time is formed from
    /// them as [`World::step`] forms it, so a time-dependent term sees the same bits.
    clock: (f64, f64),
}

/// Splits a batch into `events.len()` chunks like [`split_run`], combining in order.
pub(super) fn split_batch<S: Scheme>(
    scheme: &S,
    chunk: Chunk,
    saved: Chunk,
    events: &mut [Vec<Event>],
    work: &BatchWork,
) -> (u64, bool) {
    if events.len() <= 1 {
        return batch_chunk::<S>(scheme, chunk, saved, &mut events[0], work);
    }
    let half = events.len() / 2;
    let mid = chunk.len() * half / events.len();
    let (left, right) = chunk.split_at(mid);
    let (saved_left, saved_right) = saved.split_at(mid);
    let (ev_left, ev_right) = events.split_at_mut(half);
    let (a, b) = rayon::join(
        || split_batch::<S>(scheme, left, saved_left, ev_left, work),
        || split_batch::<S>(scheme, right, saved_right, ev_right, work),
    );
    (a.0 + b.0, a.1 & b.1)
}

/// One chunk of a batch: block by block, save the block, then run it every tick of the batch
/// (each tick `substeps` times) through the same per-body loop as a tick, checking the guard
/// after the ticks it is due. Returns the force evaluations and whether every body stayed
/// finite and within its energy bound.
pub(super) fn batch_chunk<S: Scheme>(
    scheme: &S,
    mut l: Chunk,
    mut saved: Chunk,
    events: &mut Vec<Event>,
    work: &BatchWork,
) -> (u64, bool) {
    let n = l.len();
    let guard = work.guard;
    let (mut evals, mut ok) = (0, true);
    for start in (0..n).step_by(BATCH_BLOCK) {
        let end = (start + BATCH_BLOCK).min(n);
        let mut block = l.sub(start, end);
        saved.sub(start, end).copy_state(&block);
        for tick in guard.first_tick..guard.first_tick + work.ticks {
            for k in 0..work.substeps {
                let (start_time, dt) = work.clock;
                let ctx = StepContext {
                    tick,
                    t0: (start_time + (tick - 1) as f64 * dt) + f64::from(k) * work.ctx.h,
                    ..*work.ctx
                };
                let o = run::<S, false, false, false>(
                    scheme,
                    &mut block.sub(0, end - start),
                    &ctx,
                    events,
                );
                evals += o.evals;
                ok &= o.first_non_finite.is_none();
            }
            if guard.every != 0 && tick.is_multiple_of(guard.every) {
                ok &= !(guard.over_cap)(&block);
            }
        }
    }
    (evals, ok)
}
