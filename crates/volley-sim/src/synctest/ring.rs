//! What the sync test keeps of each tick, and putting it back.
//!
//! A tick's [`Frame`] holds only what a step changes: positions and momenta (48 bytes a body),
//! the masses while a motor burns (8 more), velocity Verlet's and Forest-Ruth's carried force
//! while it is valid (24 more), and a few counters. Everything else a [`State`] holds (ids,
//! radii, energy bounds, launches, the generator, integrator, force toggles, launcher) changes
//! only when a command is applied, so it is kept once per tick that applied commands, as an
//! [`Epochs`] entry that the frames name.
//!
//! Restoring the oldest frame while saving the newest state is one exchange of buffers
//! ([`swap`]): the world's columns move into the ring and the frame's into the world, with no
//! copy. A window that reaches back across a command also copies the older epoch's columns
//! back.

use crate::body::{COLUMNS, Vec3s};
use crate::command::Command;
use crate::hash::canonical_bits;
use crate::step::Stage;
use crate::world::{Divergence, State, World};

/// `COLUMNS` from this index on are fixed between commands (radius, energy bound, launch).
const FIRST_STATIC_COLUMN: usize = 7;
/// The mass's index in `COLUMNS`: dynamic while a motor burns, fixed otherwise.
const MASS_COLUMN: usize = 6;

/// One tick boundary of the first run: what a step changes, and what the tick then did.
#[derive(Clone, Debug, Default)]
pub(super) struct Frame {
    pub(super) tick: u64,
    pub(super) force_evals: u64,
    /// The first run's divergence, if its step into this tick stopped it.
    pub(super) diverged: Option<Divergence>,
    pub(super) p: Vec3s,
    pub(super) mv: Vec3s,
    /// Masses, kept only while a motor burns (`has_mass`).
    pub(super) mass: Vec<f64>,
    pub(super) has_mass: bool,
    /// The carried force, meaningful only when `carry_valid`.
    pub(super) carry: Vec3s,
    pub(super) carry_valid: bool,
    /// The epoch in effect at this boundary, before the tick's commands.
    pub(super) epoch: u64,
    /// The commands the first run applied at this tick, before its step.
    pub(super) commands: Vec<Command>,
    /// With stage hashes: the first run's hash after each stage of this tick's step.
    pub(super) stages: Vec<(Stage, u64)>,
    /// With stage hashes: the stage hash of this state.
    pub(super) hash: u64,
}

impl Frame {
    /// Bytes this frame holds per body (the columns it keeps, 8 bytes a value).
    pub(super) fn bytes_per_body(&self) -> usize {
        let columns = 6 + usize::from(self.has_mass) + 3 * usize::from(self.carry_valid);
        8 * columns
    }
}

/// The states between commands' ticks: a full [`State`] after each tick's commands, by id.
#[derive(Clone, Debug)]
pub(super) struct Epochs {
    slots: Vec<(u64, State)>,
}

impl Epochs {
    /// Room for `n` epochs; a frame's epoch is never more than `n - 1` commands' ticks old.
    pub(super) fn new(n: usize, world: &World) -> Epochs {
        let mut slots = vec![(u64::MAX, world.snapshot()); n];
        slots[0] = (0, world.snapshot());
        Epochs { slots }
    }

    /// Epoch `id`'s state.
    pub(super) fn get(&self, id: u64) -> &State {
        let (stored, state) = &self.slots[(id % self.slots.len() as u64) as usize];
        debug_assert_eq!(*stored, id, "the ring keeps every epoch a frame names");
        state
    }

    /// Keeps the world's state now as epoch `id` (reusing the slot's buffers).
    pub(super) fn store(&mut self, id: u64, world: &World) {
        let n = self.slots.len() as u64;
        let (stored, state) = &mut self.slots[(id % n) as usize];
        *stored = id;
        state.assign_from(world.state(), false);
    }
}

/// Whether the world's forces burn a motor (its masses then change every step).
fn burns(world: &World) -> bool {
    world.state.forces.thrust.is_some()
}

/// Puts epoch `e`'s fixed part into the world: ids, the fixed columns, the masses unless a
/// motor burns them, generator, next id, integrator, forces, launcher.
fn load_static(world: &mut World, e: &State) {
    let w = &mut world.state;
    (w.next_id, w.rng, w.integrator, w.launcher) = (e.next_id, e.rng, e.integrator, e.launcher);
    w.forces.clone_from(&e.forces);
    // What the step reads of the forces (kept beside them) follows them back.
    world.facts = crate::world::ForceFacts::of(&world.state.forces);
    let w = &mut world.state;
    w.bodies.id.clone_from(&e.bodies.id);
    for column in &COLUMNS[FIRST_STATIC_COLUMN..] {
        column
            .get_mut(&mut w.bodies)
            .clone_from(column.get(&e.bodies));
    }
    if e.forces.thrust.is_none() {
        w.bodies.mass.clone_from(&e.bodies.mass);
    }
}

/// Saves the world's step-changed state into `f` by copying (the world keeps it).
pub(super) fn save_copy(world: &World, f: &mut Frame, epoch: u64) {
    let (s, b) = (&world.state, &world.state.bodies);
    (f.tick, f.force_evals, f.diverged, f.epoch) =
        (s.tick, s.force_evals, world.divergence(), epoch);
    f.p.copy_from(&b.p);
    f.mv.copy_from(&b.mv);
    f.has_mass = burns(world);
    if f.has_mass {
        f.mass.clone_from(&b.mass);
    }
    f.carry_valid = world.carry_valid;
    if f.carry_valid {
        f.carry.copy_from(&s.carry);
    }
    f.commands.clear();
    f.stages.clear();
}

/// Puts frame `f` back into the world by copying (the frame keeps it); `world_epoch` is the
/// epoch the world's fixed part is now.
pub(super) fn load_copy(world: &mut World, f: &Frame, epochs: &Epochs, world_epoch: u64) {
    let other_epoch = f.epoch != world_epoch;
    if other_epoch {
        load_static(world, epochs.get(f.epoch));
    }
    let s = &mut world.state;
    (s.tick, s.force_evals) = (f.tick, f.force_evals);
    s.bodies.p.copy_from(&f.p);
    s.bodies.mv.copy_from(&f.mv);
    if f.has_mass {
        s.bodies.mass.clone_from(&f.mass);
    }
    world.carry_valid = f.carry_valid;
    if f.carry_valid {
        world.state.carry.copy_from(&f.carry);
    }
    finish_restore(world, other_epoch || f.has_mass);
}

/// Saves the world's state into `f` and puts `f`'s back into the world in one exchange of
/// buffers; `world_epoch` is the epoch of the world's fixed part. Returns the world's epoch
/// afterwards (the frame's).
pub(super) fn swap(world: &mut World, f: &mut Frame, epochs: &Epochs, world_epoch: u64) -> u64 {
    let frame_epoch = f.epoch;
    let world_burns = burns(world);
    let s = &mut world.state;
    std::mem::swap(&mut s.bodies.p, &mut f.p);
    std::mem::swap(&mut s.bodies.mv, &mut f.mv);
    let frame_has_mass = f.has_mass;
    if world_burns || frame_has_mass {
        std::mem::swap(&mut s.bodies.mass, &mut f.mass);
    }
    f.has_mass = world_burns;
    std::mem::swap(&mut s.carry, &mut f.carry);
    std::mem::swap(&mut world.carry_valid, &mut f.carry_valid);
    std::mem::swap(&mut s.tick, &mut f.tick);
    std::mem::swap(&mut s.force_evals, &mut f.force_evals);
    f.diverged = world.divergence();
    f.epoch = world_epoch;
    f.commands.clear();
    f.stages.clear();
    let other_epoch = frame_epoch != world_epoch;
    if other_epoch {
        load_static(world, epochs.get(frame_epoch));
    }
    finish_restore(world, other_epoch || world_burns || frame_has_mass);
    frame_epoch
}

/// What every restore ends with: `1 / mass` as at spawn if the masses were replaced, then
/// what [`World::restore`] resets ([`World::reset_after_restore`]).
fn finish_restore(world: &mut World, masses_replaced: bool) {
    if masses_replaced {
        world.state.bodies.recompute_inv_mass();
    }
    world.reset_after_restore();
}

/// The full [`State`] of frame `f` into `out` (reusing its buffers), as a keyframe holds it.
pub(super) fn full_state(f: &Frame, epochs: &Epochs, out: &mut State) {
    out.assign_from(epochs.get(f.epoch), false);
    (out.tick, out.force_evals) = (f.tick, f.force_evals);
    out.bodies.p.copy_from(&f.p);
    out.bodies.mv.copy_from(&f.mv);
    if f.has_mass {
        out.bodies.mass.clone_from(&f.mass);
        out.bodies.recompute_inv_mass();
    }
    if f.carry_valid {
        out.carry.copy_from(&f.carry);
    }
}

/// Whether two columns hold the same values as the hash sees them (`-0.0` is `+0.0`, every
/// NaN the same): a compare of bit patterns over the whole column ([`bits_differ`]), then the
/// canonical compare only if that found a difference.
#[inline]
fn same_column(a: &[f64], b: &[f64]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    bits_differ(a, b) == 0
        || a.iter()
            .zip(b)
            .all(|(x, y)| canonical_bits(*x) == canonical_bits(*y))
}

/// The OR of the bit differences of two columns of one length: 0 when they are the same bits.
/// This compare is the sync test's one pass over the state a tick beyond the steps (48 bytes a
/// body on each side), and it costs what a cheap step costs, so it runs in AVX2 where the CPU
/// has it ([`crate::simd::simd_level`]). The eight-lane loop below took 300 ns a 1000-value
/// column compiled for SSE2 and 200 to 240 ns for AVX2; the fold over zipped iterators it
/// replaces ran 2.8 instructions a value under callgrind. Not in AVX-512, even where the step runs in it: on this project's
/// 2-core machine (which has it) the AVX-512 compare made the 1000-body sync tests slower than
/// the scalar fold had (9.8x plain stepping against 9.2x), the AVX2 one faster (`cargo bench
/// --bench synctest`, the binaries run alternately). A short column is compared in place:
/// choosing the width costs more than it saves there.
#[inline]
fn bits_differ(a: &[f64], b: &[f64]) -> u64 {
    if a.len() < SHORT_COLUMN {
        return bits_differ_plain(a, b);
    }
    #[cfg(target_arch = "x86_64")]
    {
        use crate::simd::{SimdLevel, simd_level};
        if simd_level() >= SimdLevel::Avx2 {
            // SAFETY: `simd_level` returns AVX2 or wider only when the CPU has AVX2.
            return unsafe { bits_differ_avx2(a, b) };
        }
    }
    bits_differ_lanes(a, b)
}

/// Columns shorter than this are compared without vectors.
const SHORT_COLUMN: usize = 32;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn bits_differ_avx2(a: &[f64], b: &[f64]) -> u64 {
    bits_differ_lanes(a, b)
}

/// Eight lanes of differences ORed together, a loop the compiler turns into vector
/// instructions of the width it is compiled for.
#[inline(always)]
fn bits_differ_lanes(a: &[f64], b: &[f64]) -> u64 {
    const LANES: usize = 8;
    let (ca, ra) = a.as_chunks::<LANES>();
    let (cb, rb) = b.as_chunks::<LANES>();
    let mut lanes = [0u64; LANES];
    for (x, y) in ca.iter().zip(cb) {
        for k in 0..LANES {
            lanes[k] |= x[k].to_bits() ^ y[k].to_bits();
        }
    }
    bits_differ_plain(ra, rb) | lanes.iter().fold(0, |acc, l| acc | l)
}

/// One value at a time: short columns, and the lanes' remainder.
#[inline(always)]
fn bits_differ_plain(a: &[f64], b: &[f64]) -> u64 {
    a.iter()
        .zip(b)
        .fold(0u64, |acc, (x, y)| acc | (x.to_bits() ^ y.to_bits()))
}

fn same_vec3s(a: &Vec3s, b: &Vec3s) -> bool {
    same_column(&a.x, &b.x) && same_column(&a.y, &b.y) && same_column(&a.z, &b.z)
}

/// Whether the world's state is frame `f`'s in everything a step changes: tick, force
/// evaluations, divergence, positions, momenta, masses while a motor burns, the carried force.
pub(super) fn same_dynamic(world: &World, f: &Frame) -> bool {
    let (s, b) = (&world.state, &world.state.bodies);
    s.tick == f.tick
        && s.force_evals == f.force_evals
        && world.divergence() == f.diverged
        && world.carry_valid == f.carry_valid
        && same_vec3s(&b.p, &f.p)
        && same_vec3s(&b.mv, &f.mv)
        && (!f.has_mass || same_column(&b.mass, &f.mass))
        && (!f.carry_valid || same_vec3s(&s.carry, &f.carry))
}

/// Whether the world's fixed part is epoch `e`'s: what only commands change.
pub(super) fn same_static(world: &World, e: &State) -> bool {
    let (w, b) = (&world.state, &world.state.bodies);
    let columns = COLUMNS[FIRST_STATIC_COLUMN..]
        .iter()
        .chain((e.forces.thrust.is_none()).then_some(&COLUMNS[MASS_COLUMN]))
        .all(|c| same_column(c.get(b), c.get(&e.bodies)));
    w.next_id == e.next_id
        && w.rng == e.rng
        && w.integrator == e.integrator
        && w.forces == e.forces
        && w.launcher == e.launcher
        && b.id == e.bodies.id
        && columns
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every length around the lanes' width, a difference in every place: found by the vector
    /// compare at the CPU's width and by the plain one, and the canonical values equal.
    #[test]
    fn the_column_compare_finds_one_flipped_bit_anywhere() {
        for n in (0..40).chain(SHORT_COLUMN - 2..SHORT_COLUMN + 20) {
            let a: Vec<f64> = (0..n).map(|i| 1.5 * i as f64 - 7.0).collect();
            assert_eq!(bits_differ(&a, &a), 0, "length {n}");
            assert!(same_column(&a, &a));
            for i in 0..n {
                let mut b = a.clone();
                b[i] = f64::from_bits(b[i].to_bits() ^ 1);
                assert_ne!(bits_differ(&a, &b), 0, "length {n}, place {i}");
                assert_ne!(bits_differ_lanes(&a, &b), 0, "length {n}, place {i}");
                assert!(!same_column(&a, &b), "length {n}, place {i}");
                // -0.0 and +0.0 differ in bits, not as the hash sees them.
                let (mut z0, mut z1) = (a.clone(), a.clone());
                (z0[i], z1[i]) = (0.0, -0.0);
                assert_ne!(bits_differ(&z0, &z1), 0);
                assert!(same_column(&z0, &z1), "length {n}, place {i}");
            }
        }
        assert!(!same_column(&[1.0], &[1.0, 2.0]), "lengths differ");
    }
}
