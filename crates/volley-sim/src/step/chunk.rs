//! Views of the per-body columns that one thread works on, and splitting them over threads.
//!
//! A [`Chunk`] borrows a contiguous run of bodies: `p`, `mV` and the carried force mutably, the
//! ids, masses and radii shared. Splitting is by index, so the chunks of a parallel step are
//! contiguous and their results are combined in chunk order.

use crate::contact::{Event, StepContext};
use crate::integrate::Scheme;
use glam::DVec3;

use crate::body::{Bodies, Launch, Mass};
use crate::world::{BodyId, Vec3s, World};

use super::PARALLEL_MIN_CHUNK;
use super::kernel::{KernelOut, run};

impl World {
    /// The number of parallel chunks for this world's size and thread count, with an event
    /// buffer for each; sizes Verlet's carried force (invalidating it when the count changed).
    /// Returns the chunk count and whether the integrator carries a force.
    pub(super) fn prepare_chunks(&mut self) -> (usize, bool) {
        let n = self.state.bodies.len();
        let chunks = if self.threads > 1 && n >= 2 * PARALLEL_MIN_CHUNK {
            self.threads.min(n / PARALLEL_MIN_CHUNK)
        } else {
            1
        };
        if self.scratch.chunk_events.len() < chunks {
            self.scratch.chunk_events.resize_with(chunks, Vec::new);
        }
        let carries = matches!(
            self.state.integrator,
            crate::Integrator::VelocityVerlet | crate::Integrator::ForestRuth
        );
        if carries && self.state.carry.len() != n {
            self.state.carry.resize(n);
            self.carry_valid = false;
        }
        (chunks, carries)
    }
}

/// Mutable view of a contiguous run of bodies, the unit of work of one thread.
pub(super) struct Chunk<'a> {
    /// Storage index of the first body.
    pub(super) offset: usize,
    pub(super) ids: &'a [BodyId],
    pub(super) px: &'a mut [f64],
    pub(super) py: &'a mut [f64],
    pub(super) pz: &'a mut [f64],
    pub(super) mx: &'a mut [f64],
    pub(super) my: &'a mut [f64],
    pub(super) mz: &'a mut [f64],
    /// Carried force (velocity Verlet), empty otherwise.
    pub(super) cx: &'a mut [f64],
    pub(super) cy: &'a mut [f64],
    pub(super) cz: &'a mut [f64],
    pub(super) mass: &'a [f64],
    pub(super) inv_mass: &'a [f64],
    pub(super) radius: &'a [f64],
    pub(super) launch: Launches<'a>,
}

/// The launch columns ([`crate::body::Launch`]) of bodies `start..`: none unless a declared
/// term reads them ([`crate::Forces::reads_launch`]), so the loop fills a body's launch only
/// then. Three references and an offset, not five slices: every tick moves a chunk by value
/// (callgrind: 13 instructions of the seed's tick).
#[derive(Clone, Copy)]
pub(super) struct Launches<'a> {
    cols: Option<(&'a [f64], &'a [f64], &'a Vec3s)>,
    start: usize,
}

impl<'a> Launches<'a> {
    /// The columns, or none.
    #[inline]
    fn of(time: &'a [f64], mass: &'a [f64], spin: &'a Vec3s, read: bool) -> Launches<'a> {
        Launches {
            cols: read.then_some((time, mass, spin)),
            start: 0,
        }
    }

    /// Body `i`'s mass `m` with its reciprocal and launch (a zero launch without the columns,
    /// or when the scheme's model never reads it, decided at compile time).
    #[inline(always)]
    pub(super) fn mass<S: Scheme>(&self, i: usize, m: f64, inv: f64) -> Mass {
        let launch = match self.cols {
            Some((time, mass, spin)) if S::READS_LAUNCH => {
                let j = self.start + i;
                Launch {
                    time: time[j],
                    mass: mass[j],
                    spin: DVec3::new(spin.x[j], spin.y[j], spin.z[j]),
                }
            }
            _ => Launch::default(),
        };
        Mass { m, inv, launch }
    }

    /// Bodies `start..` of these (the end is the chunk's own length).
    fn sub(&self, start: usize) -> Launches<'a> {
        Launches {
            cols: self.cols,
            start: self.start + start,
        }
    }

    /// The first `mid` bodies and the rest.
    fn split_at(&self, mid: usize) -> (Launches<'a>, Launches<'a>) {
        (*self, self.sub(mid))
    }
}

#[inline]
pub(super) fn split_mut(s: &mut [f64], mid: usize) -> (&mut [f64], &mut [f64]) {
    if s.is_empty() {
        (&mut [], &mut [])
    } else {
        s.split_at_mut(mid)
    }
}

/// The per-body arrays a step reads but does not write.
#[derive(Clone, Copy)]
pub(super) struct Fixed<'a> {
    pub(super) ids: &'a [BodyId],
    pub(super) mass: &'a [f64],
    pub(super) inv_mass: &'a [f64],
    pub(super) radius: &'a [f64],
    pub(super) launch: Launches<'a>,
    /// The guard's bounds (the batch's guard reads them).
    pub(super) energy_cap: &'a [f64],
}

impl<'a> Fixed<'a> {
    /// The fixed columns of `b`, the launch ones only if the forces read them, beside its
    /// positions and momenta to write.
    #[inline]
    pub(super) fn of(
        b: &'a mut Bodies,
        reads_launch: bool,
    ) -> (Fixed<'a>, &'a mut Vec3s, &'a mut Vec3s) {
        let fixed = Fixed {
            ids: &b.id,
            mass: &b.mass,
            inv_mass: &b.inv_mass,
            radius: &b.radius,
            launch: Launches::of(&b.launch_time, &b.launch_mass, &b.spin, reads_launch),
            energy_cap: &b.energy_cap,
        };
        (fixed, &mut b.p, &mut b.mv)
    }

    /// Chunk over these bodies with `p`, `mV` and (if `carries`) the carried force.
    #[inline]
    pub(super) fn chunk(
        self,
        p: &'a mut Vec3s,
        mv: &'a mut Vec3s,
        carry: &'a mut Vec3s,
        carries: bool,
    ) -> Chunk<'a> {
        let (cx, cy, cz): (&mut [f64], &mut [f64], &mut [f64]) = if carries {
            (&mut carry.x, &mut carry.y, &mut carry.z)
        } else {
            (&mut [], &mut [], &mut [])
        };
        Chunk {
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
            launch: self.launch,
        }
    }
}

#[inline]
pub(super) fn sub_mut(s: &mut [f64], start: usize, end: usize) -> &mut [f64] {
    if s.is_empty() { s } else { &mut s[start..end] }
}

impl<'a> Chunk<'a> {
    #[inline]
    pub(super) fn len(&self) -> usize {
        self.ids.len()
    }

    /// The bodies `start..end` of these chunk, borrowed.
    #[inline]
    pub(super) fn sub(&mut self, start: usize, end: usize) -> Chunk<'_> {
        Chunk {
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
            launch: self.launch.sub(start),
        }
    }

    /// Copies the written state (p, mV, carried force) of `from` into these chunk.
    #[inline]
    pub(super) fn copy_state(&mut self, from: &Chunk) {
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

    #[inline]
    pub(super) fn split_at(self, mid: usize) -> (Chunk<'a>, Chunk<'a>) {
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
        let (l0, l1) = self.launch.split_at(mid);
        (
            Chunk {
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
                launch: l0,
            },
            Chunk {
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
                launch: l1,
            },
        )
    }
}

/// Splits the bodies into `events.len()` chunks and runs them in parallel, combining in order.
pub(super) fn split_run<S: Scheme, const CONTACTS: bool, const LEVELS: bool, const EVENTS: bool>(
    scheme: &S,
    mut chunk: Chunk,
    ctx: &StepContext,
    events: &mut [Vec<Event>],
) -> KernelOut {
    if events.len() <= 1 {
        return run::<S, CONTACTS, LEVELS, EVENTS>(scheme, &mut chunk, ctx, &mut events[0]);
    }
    let half = events.len() / 2;
    let mid = chunk.len() * half / events.len();
    let (left, right) = chunk.split_at(mid);
    let (ev_left, ev_right) = events.split_at_mut(half);
    let (a, b) = rayon::join(
        || split_run::<S, CONTACTS, LEVELS, EVENTS>(scheme, left, ctx, ev_left),
        || split_run::<S, CONTACTS, LEVELS, EVENTS>(scheme, right, ctx, ev_right),
    );
    a.then(b)
}
