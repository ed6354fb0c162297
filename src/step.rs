//! One tick as a short list of named stages.
//!
//! ```text
//! step:  integrate (declared forces only) -> contacts (inline, only near a surface or target)
//!        -> non-finite check (inline) -> energy guard (every `guard.every` ticks)
//! ```
//!
//! Commands are applied by [`crate::World::apply`] before a step, at the tick boundary; hashing
//! is on demand ([`crate::hash::state_hash`]); neither happens inside a step.
//!
//! The integrate stage is one loop over the bodies, monomorphised over the integrator and the
//! force model (`integrate::visit`) and over whether the scene has any contacts, so a
//! scene pays for exactly what it declares. With several threads the bodies are split into
//! contiguous chunks ([`rayon::join`]); each chunk writes its own event buffer and the buffers
//! are concatenated in chunk order, and the per-body arithmetic does not depend on the chunking,
//! so the state and the events are bit-identical for every thread count.

use glam::DVec3;

use crate::contact::{self, Event, Particle, StepFrame};
use crate::forces::ForceModel;
use crate::integrate::{BodyState, Mass, Scheme, SchemeVisitor, visit};
use crate::world::{BodyId, Divergence, DivergenceCause, Vec3s, World};

/// Bodies per chunk below which stepping stays on one thread.
pub const PARALLEL_MIN_CHUNK: usize = 16 * 1024;

impl World {
    /// Advances the world by one tick (`substeps` integrator steps), or returns the divergence
    /// that stopped it. A stopped world stays stopped and keeps the state it stopped at.
    pub fn step(&mut self) -> Result<(), Divergence> {
        if let Some(d) = self.diverged {
            return Err(d);
        }
        self.events.clear();
        let next_tick = self.tick + 1;
        let h_sub = self.h / f64::from(self.substeps);
        for k in 0..self.substeps {
            let t0 = self.time_of(self.tick) + f64::from(k) * h_sub;
            if let Some(i) = self.integrate(next_tick, t0, h_sub) {
                self.tick = next_tick;
                return Err(self.stop(i, DivergenceCause::NonFinite));
            }
        }
        self.tick = next_tick;
        self.guard_energy()
    }

    fn stop(&mut self, i: usize, cause: DivergenceCause) -> Divergence {
        let d = Divergence {
            tick: self.tick,
            body: self.bodies.id[i],
            cause,
        };
        self.diverged = Some(d);
        d
    }

    /// Integrate + contacts over all bodies; returns the first body whose state is not finite.
    fn integrate(&mut self, tick: u64, t0: f64, h: f64) -> Option<usize> {
        let (chunks, carries) = self.prepare_chunks();
        let gravity = self.forces.gravity.map_or(0.0, DVec3::length);
        let frame = StepFrame {
            contacts: &self.contacts,
            tick,
            t0,
            h,
            rest_speed: gravity * h,
        };
        let b = &mut self.bodies;
        let fixed = Fixed {
            ids: &b.id,
            mass: &b.mass,
            inv_mass: &b.inv_mass,
            radius: &b.radius,
        };
        let lanes = fixed.lanes(&mut b.p, &mut b.mv, &mut self.carry, carries);
        let out = visit(
            self.integrator,
            &self.forces,
            Integrate {
                lanes,
                frame: &frame,
                events: &mut self.chunk_events[..chunks],
                carry_valid: self.carry_valid,
            },
        );
        self.carry_valid = out.carried;
        self.force_evals += out.evals;
        for buffer in &mut self.chunk_events[..chunks] {
            self.events.extend_from_slice(buffer);
            buffer.clear();
        }
        out.first_non_finite
    }

    /// The number of parallel chunks for this world's size and thread count, with an event
    /// buffer for each; sizes Verlet's carried force (invalidating it when the count changed).
    /// Returns the chunk count and whether the integrator carries a force.
    fn prepare_chunks(&mut self) -> (usize, bool) {
        let n = self.bodies.len();
        let chunks = if self.threads > 1 && n >= 2 * PARALLEL_MIN_CHUNK {
            self.threads.min(n / PARALLEL_MIN_CHUNK)
        } else {
            1
        };
        if self.chunk_events.len() < chunks {
            self.chunk_events.resize_with(chunks, Vec::new);
        }
        let carries = self.integrator == crate::Integrator::VelocityVerlet;
        if carries && self.carry.len() != n {
            self.carry.resize(n);
            self.carry_valid = false;
        }
        (chunks, carries)
    }

    /// Advances the world by `n` ticks: the same bits, events, force-evaluation count and
    /// divergence (tick, body, cause) as `n` calls of [`World::step`], stopping at the first
    /// divergence. Only the last tick's events are kept, so [`crate::SimLoop`] batches only
    /// when the observer asked for no tick in between.
    ///
    /// A world without contacts (so without events) runs **batches**: its bodies do not
    /// interact, so each block of [`BATCH_BLOCK`] bodies runs every tick of the batch while it
    /// sits in the core's cache before the next block is loaded, and the state crosses the
    /// memory bus once per batch instead of once per tick; the energy guard checks each block
    /// at the ticks it is due, while the block is still in cache. A batch is at most
    /// [`BATCH_MAX_TICKS`] long. Each body goes through exactly the operations `step` applies,
    /// in the same order, so the bits are the same. Before a batch the state is saved (as each
    /// block is loaded); if any body turns non-finite or trips the guard inside it, the batch
    /// is undone and run again tick by tick, so the run stops at exactly the tick, body and
    /// cause `step` names.
    /// With contacts the ticks run one by one.
    pub fn step_ticks(&mut self, n: u64) -> Result<(), Divergence> {
        if n == 0 {
            return Ok(());
        }
        if let Some(d) = self.diverged {
            return Err(d);
        }
        let batches = self.contacts.is_empty();
        let mut left = n;
        while left > 0 {
            let m = left.min(BATCH_MAX_TICKS);
            if batches && m >= 2 && self.integrate_batch(m) {
                self.tick += m;
            } else {
                for _ in 0..m {
                    self.step()?;
                }
            }
            left -= m;
        }
        Ok(())
    }

    /// Runs `ticks` ticks of a world without contacts block by block; returns false, with the
    /// state, the carried force and the counters as they were, if a body turned non-finite or
    /// passed its energy bound at a tick the guard checks.
    fn integrate_batch(&mut self, ticks: u64) -> bool {
        self.events.clear();
        let (chunks, carries) = self.prepare_chunks();
        let n = self.bodies.len();
        let t0 = self.time_of(self.tick);
        let saved = &mut self.batch_backup;
        saved.p.resize(n);
        saved.mv.resize(n);
        saved.carry.resize(if carries { n } else { 0 });
        let h = self.h / f64::from(self.substeps);
        let frame = StepFrame {
            contacts: &self.contacts,
            tick: self.tick + 1,
            t0,
            h,
            rest_speed: 0.0,
        };
        let b = &mut self.bodies;
        let fixed = Fixed {
            ids: &b.id,
            mass: &b.mass,
            inv_mass: &b.inv_mass,
            radius: &b.radius,
        };
        let lanes = fixed.lanes(&mut b.p, &mut b.mv, &mut self.carry, carries);
        let saved_lanes = fixed.lanes(&mut saved.p, &mut saved.mv, &mut saved.carry, carries);
        // The guard's test, on the model `guard_energy` uses, so it trips exactly where it would.
        let (caps, forces) = (&b.energy_cap[..], &self.forces);
        let field = forces.constant_field();
        let over_cap = move |l: &Lanes| match &field {
            Some(field) => lanes_over_cap(l, field, caps),
            None => lanes_over_cap(l, forces, caps),
        };
        let guard = Guard {
            every: u64::from(self.scene.guard.every),
            first_tick: self.tick + 1,
            over_cap: &over_cap,
        };
        let out = visit(
            self.integrator,
            &self.forces,
            Batch {
                lanes,
                saved: saved_lanes,
                events: &mut self.chunk_events[..chunks],
                carry_valid: self.carry_valid,
                work: BatchWork {
                    frame: &frame,
                    ticks,
                    substeps: self.substeps,
                    guard: &guard,
                },
            },
        );
        if !out.ok {
            self.bodies.p.copy_from(&self.batch_backup.p);
            self.bodies.mv.copy_from(&self.batch_backup.mv);
            if carries {
                self.carry.copy_from(&self.batch_backup.carry);
            }
            return false;
        }
        self.carry_valid = out.carried;
        self.force_evals += out.evals;
        true
    }

    /// The energy guard stage: every `guard.every` ticks, the first body whose energy passed
    /// its bound stops the run.
    fn guard_energy(&mut self) -> Result<(), Divergence> {
        let every = u64::from(self.scene.guard.every);
        if every == 0 || !self.tick.is_multiple_of(every) {
            return Ok(());
        }
        let found = match self.forces.constant_field() {
            Some(field) => first_over_cap(&self.bodies, &field),
            None => first_over_cap(&self.bodies, &self.forces),
        };
        match found {
            Some((i, energy)) => {
                let bound = self.bodies.energy_cap[i];
                Err(self.stop(i, DivergenceCause::EnergyGrowth { energy, bound }))
            }
            None => Ok(()),
        }
    }
}

fn first_over_cap<F: ForceModel>(b: &crate::world::Bodies, f: &F) -> Option<(usize, f64)> {
    let n = b.len();
    let (p, mv) = (&b.p, &b.mv);
    let (px, py, pz) = (&p.x[..n], &p.y[..n], &p.z[..n]);
    let (mx, my, mz) = (&mv.x[..n], &mv.y[..n], &mv.z[..n]);
    let (mass, inv_mass, cap) = (&b.mass[..n], &b.inv_mass[..n], &b.energy_cap[..n]);
    (0..n).find_map(|i| {
        // The velocity as `Bodies::velocity` forms it, from slices the compiler can see whole.
        let v = DVec3::new(mx[i], my[i], mz[i]) * inv_mass[i];
        let e = f.energy(DVec3::new(px[i], py[i], pz[i]), v, mass[i]);
        // NaN energy is caught by the non-finite check; `>` keeps it from tripping twice.
        (e > cap[i]).then_some((i, e))
    })
}

/// Whether any body of `l` has more energy than its bound: [`first_over_cap`]'s test.
fn lanes_over_cap<F: ForceModel>(l: &Lanes, f: &F, caps: &[f64]) -> bool {
    let n = l.len();
    let cap = &caps[l.offset..l.offset + n];
    (0..n).any(|i| {
        let v = DVec3::new(l.mx[i], l.my[i], l.mz[i]) * l.inv_mass[i];
        f.energy(DVec3::new(l.px[i], l.py[i], l.pz[i]), v, l.mass[i]) > cap[i]
    })
}

/// Mutable view of a contiguous run of bodies, the unit of work of one thread.
struct Lanes<'a> {
    /// Storage index of the first body.
    offset: usize,
    ids: &'a [BodyId],
    px: &'a mut [f64],
    py: &'a mut [f64],
    pz: &'a mut [f64],
    mx: &'a mut [f64],
    my: &'a mut [f64],
    mz: &'a mut [f64],
    /// Carried force (velocity Verlet), empty otherwise.
    cx: &'a mut [f64],
    cy: &'a mut [f64],
    cz: &'a mut [f64],
    mass: &'a [f64],
    inv_mass: &'a [f64],
    radius: &'a [f64],
}

fn split_mut(s: &mut [f64], mid: usize) -> (&mut [f64], &mut [f64]) {
    if s.is_empty() {
        (&mut [], &mut [])
    } else {
        s.split_at_mut(mid)
    }
}

/// The per-body arrays a step reads but does not write.
#[derive(Clone, Copy)]
struct Fixed<'a> {
    ids: &'a [BodyId],
    mass: &'a [f64],
    inv_mass: &'a [f64],
    radius: &'a [f64],
}

impl<'a> Fixed<'a> {
    /// Lanes over these bodies with `p`, `mV` and (if `carries`) the carried force.
    fn lanes(
        self,
        p: &'a mut Vec3s,
        mv: &'a mut Vec3s,
        carry: &'a mut Vec3s,
        carries: bool,
    ) -> Lanes<'a> {
        let (cx, cy, cz): (&mut [f64], &mut [f64], &mut [f64]) = if carries {
            (&mut carry.x, &mut carry.y, &mut carry.z)
        } else {
            (&mut [], &mut [], &mut [])
        };
        Lanes {
            offset: 0,
            ids: self.ids,
            px: &mut p.x,
            py: &mut p.y,
            pz: &mut p.z,
            mx: &mut mv.x,
            my: &mut mv.y,
            mz: &mut mv.z,
            cx,
            cy,
            cz,
            mass: self.mass,
            inv_mass: self.inv_mass,
            radius: self.radius,
        }
    }
}

/// The state [`World::step_ticks`] saves before a batch, to undo it.
#[derive(Clone, Debug, Default)]
pub(crate) struct BatchBackup {
    p: Vec3s,
    mv: Vec3s,
    carry: Vec3s,
}

/// Bodies per block of a batch: with their backup (about 136 bytes a body) a block stays in
/// the L2 cache while it runs every tick of the batch.
pub const BATCH_BLOCK: usize = 2048;

/// The longest batch [`World::step_ticks`] runs: long enough that saving the state (one write
/// of 48 bytes a body per batch) costs little, short enough that undoing a batch that diverged
/// costs little.
pub const BATCH_MAX_TICKS: u64 = 64;

fn sub_mut(s: &mut [f64], start: usize, end: usize) -> &mut [f64] {
    if s.is_empty() { s } else { &mut s[start..end] }
}

impl<'a> Lanes<'a> {
    fn len(&self) -> usize {
        self.ids.len()
    }

    /// The bodies `start..end` of these lanes, borrowed.
    fn sub(&mut self, start: usize, end: usize) -> Lanes<'_> {
        Lanes {
            offset: self.offset + start,
            ids: &self.ids[start..end],
            px: &mut self.px[start..end],
            py: &mut self.py[start..end],
            pz: &mut self.pz[start..end],
            mx: &mut self.mx[start..end],
            my: &mut self.my[start..end],
            mz: &mut self.mz[start..end],
            cx: sub_mut(self.cx, start, end),
            cy: sub_mut(self.cy, start, end),
            cz: sub_mut(self.cz, start, end),
            mass: &self.mass[start..end],
            inv_mass: &self.inv_mass[start..end],
            radius: &self.radius[start..end],
        }
    }

    /// Copies the written state (p, mV, carried force) of `from` into these lanes.
    fn copy_state(&mut self, from: &Lanes) {
        self.px.copy_from_slice(from.px);
        self.py.copy_from_slice(from.py);
        self.pz.copy_from_slice(from.pz);
        self.mx.copy_from_slice(from.mx);
        self.my.copy_from_slice(from.my);
        self.mz.copy_from_slice(from.mz);
        self.cx.copy_from_slice(from.cx);
        self.cy.copy_from_slice(from.cy);
        self.cz.copy_from_slice(from.cz);
    }

    fn split_at(self, mid: usize) -> (Lanes<'a>, Lanes<'a>) {
        let (ids0, ids1) = self.ids.split_at(mid);
        let (px0, px1) = self.px.split_at_mut(mid);
        let (py0, py1) = self.py.split_at_mut(mid);
        let (pz0, pz1) = self.pz.split_at_mut(mid);
        let (mx0, mx1) = self.mx.split_at_mut(mid);
        let (my0, my1) = self.my.split_at_mut(mid);
        let (mz0, mz1) = self.mz.split_at_mut(mid);
        let (cx0, cx1) = split_mut(self.cx, mid);
        let (cy0, cy1) = split_mut(self.cy, mid);
        let (cz0, cz1) = split_mut(self.cz, mid);
        let (m0, m1) = self.mass.split_at(mid);
        let (w0, w1) = self.inv_mass.split_at(mid);
        let (r0, r1) = self.radius.split_at(mid);
        (
            Lanes {
                offset: self.offset,
                ids: ids0,
                px: px0,
                py: py0,
                pz: pz0,
                mx: mx0,
                my: my0,
                mz: mz0,
                cx: cx0,
                cy: cy0,
                cz: cz0,
                mass: m0,
                inv_mass: w0,
                radius: r0,
            },
            Lanes {
                offset: self.offset + mid,
                ids: ids1,
                px: px1,
                py: py1,
                pz: pz1,
                mx: mx1,
                my: my1,
                mz: mz1,
                cx: cx1,
                cy: cy1,
                cz: cz1,
                mass: m1,
                inv_mass: w1,
                radius: r1,
            },
        )
    }
}

/// What one chunk's loop reports.
#[derive(Clone, Copy, Default)]
struct KernelOut {
    evals: u64,
    first_non_finite: Option<usize>,
    /// Whether the scheme wrote the carried force (velocity Verlet's carrying form only).
    carried: bool,
}

impl KernelOut {
    /// Combines two chunks in order: counts add, the lower index wins.
    fn then(self, later: KernelOut) -> KernelOut {
        KernelOut {
            evals: self.evals + later.evals,
            first_non_finite: self.first_non_finite.or(later.first_non_finite),
            carried: self.carried,
        }
    }
}

struct Integrate<'a, 'f> {
    lanes: Lanes<'a>,
    frame: &'f StepFrame<'f>,
    events: &'a mut [Vec<Event>],
    carry_valid: bool,
}

impl SchemeVisitor for Integrate<'_, '_> {
    type Out = KernelOut;
    fn visit<S: Scheme>(self, scheme: S) -> KernelOut {
        let Integrate {
            mut lanes,
            frame,
            events,
            carry_valid,
        } = self;
        let mut extra = 0;
        if S::CARRIES_FORCE && !carry_valid {
            extra = fill_carry(&scheme, &mut lanes);
        }
        let out = if frame.contacts.is_empty() {
            split_run::<S, false>(&scheme, lanes, frame, events)
        } else {
            split_run::<S, true>(&scheme, lanes, frame, events)
        };
        KernelOut {
            evals: out.evals + extra,
            carried: S::CARRIES_FORCE,
            ..out
        }
    }
}

/// [`World::step_ticks`]'s batch over all bodies, saving their state into `saved` first.
struct Batch<'a, 'f> {
    lanes: Lanes<'a>,
    saved: Lanes<'a>,
    events: &'a mut [Vec<Event>],
    carry_valid: bool,
    work: BatchWork<'f>,
}

/// What a batch reports.
#[derive(Clone, Copy)]
struct BatchOut {
    evals: u64,
    /// No body turned non-finite or tripped the guard (otherwise the batch is undone, so
    /// which body does not matter).
    ok: bool,
    /// Whether the scheme wrote the carried force.
    carried: bool,
}

/// The energy guard inside a batch: due after the ticks `first_tick + k` that are multiples of
/// `every` (never if `every` is 0).
struct Guard<'f> {
    every: u64,
    first_tick: u64,
    over_cap: &'f (dyn Fn(&Lanes) -> bool + Sync),
}

impl SchemeVisitor for Batch<'_, '_> {
    type Out = BatchOut;
    fn visit<S: Scheme>(self, scheme: S) -> BatchOut {
        let Batch {
            mut lanes,
            saved,
            events,
            carry_valid,
            work,
        } = self;
        let mut extra = 0;
        if S::CARRIES_FORCE && !carry_valid {
            extra = fill_carry(&scheme, &mut lanes);
        }
        let (evals, ok) = split_batch::<S>(&scheme, lanes, saved, events, &work);
        BatchOut {
            evals: evals + extra,
            ok,
            carried: S::CARRIES_FORCE,
        }
    }
}

/// What every chunk of a batch runs: `ticks` ticks of `substeps` steps each, with the guard.
struct BatchWork<'f> {
    frame: &'f StepFrame<'f>,
    ticks: u64,
    substeps: u32,
    guard: &'f Guard<'f>,
}

/// Splits a batch into `events.len()` chunks like [`split_run`], combining in order.
fn split_batch<S: Scheme>(
    scheme: &S,
    lanes: Lanes,
    saved: Lanes,
    events: &mut [Vec<Event>],
    work: &BatchWork,
) -> (u64, bool) {
    if events.len() <= 1 {
        return batch_chunk::<S>(scheme, lanes, saved, &mut events[0], work);
    }
    let half = events.len() / 2;
    let mid = lanes.len() * half / events.len();
    let (left, right) = lanes.split_at(mid);
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
fn batch_chunk<S: Scheme>(
    scheme: &S,
    mut l: Lanes,
    mut saved: Lanes,
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
            for _ in 0..work.substeps {
                let o = run::<S, false>(scheme, block.sub(0, end - start), work.frame, events);
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

fn fill_carry<S: Scheme>(scheme: &S, l: &mut Lanes) -> u64 {
    for i in 0..l.len() {
        let s = BodyState {
            p: DVec3::new(l.px[i], l.py[i], l.pz[i]),
            mv: DVec3::new(l.mx[i], l.my[i], l.mz[i]),
        };
        let w = Mass {
            m: l.mass[i],
            inv: l.inv_mass[i],
        };
        let f = scheme.start_carry(s, w);
        (l.cx[i], l.cy[i], l.cz[i]) = (f.x, f.y, f.z);
    }
    l.len() as u64 * S::EVALS
}

/// Splits the bodies into `events.len()` chunks and runs them in parallel, combining in order.
fn split_run<S: Scheme, const CONTACTS: bool>(
    scheme: &S,
    lanes: Lanes,
    frame: &StepFrame,
    events: &mut [Vec<Event>],
) -> KernelOut {
    if events.len() <= 1 {
        return run::<S, CONTACTS>(scheme, lanes, frame, &mut events[0]);
    }
    let half = events.len() / 2;
    let mid = lanes.len() * half / events.len();
    let (left, right) = lanes.split_at(mid);
    let (ev_left, ev_right) = events.split_at_mut(half);
    let (a, b) = rayon::join(
        || split_run::<S, CONTACTS>(scheme, left, frame, ev_left),
        || split_run::<S, CONTACTS>(scheme, right, frame, ev_right),
    );
    a.then(b)
}

/// `true` unless a component is NaN or infinite; branch-free so the loop vectorises.
#[inline(always)]
fn finite(v: DVec3) -> bool {
    (v.x.abs() <= f64::MAX) & (v.y.abs() <= f64::MAX) & (v.z.abs() <= f64::MAX)
}

/// The vector instruction set the per-body loop runs with, chosen once per process.
///
/// The loop is compiled three times: for the baseline target (SSE2 on x86-64) and, behind
/// `#[target_feature]`, for AVX2 and AVX-512, used when the CPU has them. Every version executes
/// the same IEEE-754 operations in the same order (Rust never fuses a multiply and an add on its
/// own, and the code never calls `mul_add`), so only the width differs and the results are
/// bit-identical on every machine. `VOLLEY_SIMD=baseline|avx2|avx512` caps the choice, to compare
/// the versions (tests/simd.rs does).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum SimdLevel {
    /// The target's baseline (SSE2 on x86-64, whatever the target has elsewhere).
    Baseline,
    /// 256-bit vectors, 4 f64 lanes.
    Avx2,
    /// 512-bit vectors, 8 f64 lanes.
    Avx512,
}

/// The [`SimdLevel`] in use: the widest the CPU supports, capped by `VOLLEY_SIMD`.
pub fn simd_level() -> SimdLevel {
    static LEVEL: std::sync::OnceLock<SimdLevel> = std::sync::OnceLock::new();
    *LEVEL.get_or_init(|| {
        let cap = match std::env::var("VOLLEY_SIMD").as_deref() {
            Ok("baseline") => SimdLevel::Baseline,
            Ok("avx2") => SimdLevel::Avx2,
            _ => SimdLevel::Avx512,
        };
        detected_level().min(cap)
    })
}

#[cfg(target_arch = "x86_64")]
fn detected_level() -> SimdLevel {
    if std::arch::is_x86_feature_detected!("avx512f") {
        SimdLevel::Avx512
    } else if std::arch::is_x86_feature_detected!("avx2") {
        SimdLevel::Avx2
    } else {
        SimdLevel::Baseline
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn detected_level() -> SimdLevel {
    SimdLevel::Baseline
}

/// The per-body loop of one chunk, in the widest version the CPU runs ([`simd_level`]).
fn run<S: Scheme, const CONTACTS: bool>(
    scheme: &S,
    l: Lanes,
    frame: &StepFrame,
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
                return unsafe { run_avx512::<S, CONTACTS, true>(scheme, l, frame, events) };
            }
            SimdLevel::Avx512 => {
                return unsafe { run_avx512::<S, CONTACTS, false>(scheme, l, frame, events) };
            }
            SimdLevel::Avx2 if streaming => {
                return unsafe { run_avx2::<S, CONTACTS, true>(scheme, l, frame, events) };
            }
            SimdLevel::Avx2 => {
                return unsafe { run_avx2::<S, CONTACTS, false>(scheme, l, frame, events) };
            }
            SimdLevel::Baseline => {}
        }
    }
    run_baseline::<S, CONTACTS>(scheme, l, frame, events)
}

#[inline(never)]
fn run_baseline<S: Scheme, const CONTACTS: bool>(
    scheme: &S,
    l: Lanes,
    frame: &StepFrame,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_lanes::<S, CONTACTS, false>(scheme, l, frame, events)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx2")]
fn run_avx2<S: Scheme, const CONTACTS: bool, const STREAMING: bool>(
    scheme: &S,
    l: Lanes,
    frame: &StepFrame,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_lanes::<S, CONTACTS, STREAMING>(scheme, l, frame, events)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx512f")]
fn run_avx512<S: Scheme, const CONTACTS: bool, const STREAMING: bool>(
    scheme: &S,
    l: Lanes,
    frame: &StepFrame,
    events: &mut Vec<Event>,
) -> KernelOut {
    run_lanes::<S, CONTACTS, STREAMING>(scheme, l, frame, events)
}

/// Chunks of at least this many bodies (about 30 MB of state, an L3's worth) stream from
/// memory: their loop divides `1 / m` instead of loading the stored reciprocal. Memory, not
/// arithmetic, bounds such a loop, so the division is free and 8 of the 112 bytes a body moves
/// per step are saved. `1.0 / m` is exactly what is stored at spawn, so the bits are the same.
pub const STREAMING_MIN_BODIES: usize = 1 << 18;

/// The per-body loop of one chunk, inlined into each instruction-set version of [`run`].
/// `STREAMING` recomputes `1 / m` instead of loading it (see [`STREAMING_MIN_BODIES`]).
#[inline(always)]
fn run_lanes<S: Scheme, const CONTACTS: bool, const STREAMING: bool>(
    scheme: &S,
    l: Lanes,
    frame: &StepFrame,
    events: &mut Vec<Event>,
) -> KernelOut {
    let n = l.len();
    let (px, py, pz) = (&mut l.px[..n], &mut l.py[..n], &mut l.pz[..n]);
    let (mx, my, mz) = (&mut l.mx[..n], &mut l.my[..n], &mut l.mz[..n]);
    let (mass, inv_mass) = (&l.mass[..n], &l.inv_mass[..n]);
    let (cx, cy, cz) = if S::CARRIES_FORCE {
        (&mut l.cx[..n], &mut l.cy[..n], &mut l.cz[..n])
    } else {
        (&mut l.cx[..0], &mut l.cy[..0], &mut l.cz[..0])
    };
    let h = frame.h;
    let mut evals = n as u64 * S::EVALS;
    let mut all_finite = true;
    for i in 0..n {
        let w = if STREAMING {
            Mass::new(mass[i])
        } else {
            Mass {
                m: mass[i],
                inv: inv_mass[i],
            }
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
        let (mut s1, mut c1) = scheme.step(s0, w, h, c0);
        if CONTACTS && contact::needs_resolution(frame.contacts, l.radius[i], w.inv, &s0, &s1) {
            let body = Particle {
                id: l.ids[i],
                w,
                r: l.radius[i],
            };
            let extra;
            (s1, c1, extra) = contact::resolve(scheme, frame, body, (s0, c0), (s1, c1), events);
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
    }
}
