//! The energy guard: every `guard.every` ticks, a body whose energy passed its bound (in a scene
//! that cannot add energy) stops the run as a divergence.

use glam::DVec3;

use crate::forces::ForceModel;
use crate::world::{Divergence, DivergenceCause, World};

use super::chunk::Chunk;

impl World {
    /// The energy guard stage: every `guard.every` ticks, the first body whose energy passed
    /// its bound stops the run.
    pub(super) fn guard_energy(&mut self) -> Result<(), Divergence> {
        let every = u64::from(self.params.guard.every);
        // A game's own term or a motor may add energy: then only finiteness is checked.
        if every == 0 || !self.state.tick.is_multiple_of(every) || self.facts.adds_energy {
            return Ok(());
        }
        let found = match self.facts.constant {
            Some(field) => first_over_cap(&self.state.bodies, &field),
            None => first_over_cap(&self.state.bodies, &self.state.forces),
        };
        match found {
            Some((i, energy)) => {
                let bound = self.state.bodies.energy_cap[i];
                Err(self.stop(i, DivergenceCause::EnergyGrowth { energy, bound }))
            }
            None => Ok(()),
        }
    }
}

/// Out of line, as it was before the step was split into files: inlined into the step it
/// measured slower (callgrind, 10 000 bodies).
#[inline(never)]
pub(super) fn first_over_cap<F: ForceModel>(
    b: &crate::world::Bodies,
    f: &F,
) -> Option<(usize, f64)> {
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
pub(super) fn chunk_over_cap<F: ForceModel>(l: &Chunk, f: &F, caps: &[f64]) -> bool {
    let n = l.len();
    let cap = &caps[l.offset..l.offset + n];
    (0..n).any(|i| {
        let v = DVec3::new(l.mx[i], l.my[i], l.mz[i]) * l.inv_mass[i];
        f.energy(DVec3::new(l.px[i], l.py[i], l.pz[i]), v, l.mass[i]) > cap[i]
    })
}

/// The energy guard inside a batch: due after the ticks `first_tick + k` that are multiples of
/// `every` (never if `every` is 0).
pub(super) struct Guard<'f> {
    pub(super) every: u64,
    pub(super) first_tick: u64,
    pub(super) over_cap: &'f (dyn Fn(&Chunk) -> bool + Sync),
}
