//! One tick as a short list of named stages.
//!
//! This file is the table of contents, [`World::step`] and [`World::step_ticks`]; each stage
//! lives beside it in a file of its own: `chunk` (the structure-of-arrays views one thread works
//! on, and splitting them over threads), `kernel` (the per-body loop and its CPU-feature
//! dispatch), `batch` (many ticks block by block, with undo) and `guard` (the energy guard).
//!
//! ```text
//! step:  for each substep: integrate (declared forces only) -> contacts (inline, only near a
//!        surface or target) -> non-finite check (inline) -> burn (a declared motor only: each
//!        body's mass falls to what its motor has left)
//!        then: energy guard (every `guard.every` ticks)
//! ```
//!
//! Commands are applied by [`crate::World::apply`] before a step, at the tick boundary; hashing
//! is on demand ([`crate::hash::state_hash`]); neither happens inside a step. `staged` runs the
//! same stages as separate passes with a look at the world after each, for the sync test's
//! stage hashes only ([`World::step_staged`]).
//!
//! The integrate stage is one loop over the bodies, monomorphised over the integrator and the
//! force model (`integrate::visit`) and over whether the scene has any contacts and any level
//! surfaces, so a scene pays for exactly what it declares. With several threads the bodies are split into
//! contiguous chunks ([`rayon::join`]); each chunk writes its own event buffer and the buffers
//! are concatenated in chunk order, and the per-body arithmetic does not depend on the chunking,
//! so the state and the events are bit-identical for every thread count.

mod batch;
mod chunk;
mod guard;
mod kernel;
mod staged;

pub use crate::simd::{SimdLevel, simd_level};
use crate::world::LoopKind;
use crate::world::{Divergence, DivergenceCause, Halt, World};
pub use batch::{BATCH_BLOCK, BATCH_MAX_TICKS};
pub use kernel::STREAMING_MIN_BODIES;
pub use staged::Stage;
pub(crate) use staged::StageBuffers;

/// Bodies per chunk below which stepping stays on one thread.
pub const PARALLEL_MIN_CHUNK: usize = 16 * 1024;

impl World {
    /// Advances the world by one tick (`substeps` integrator steps), or returns the divergence
    /// that stopped it. A stopped world stays stopped and keeps the state it stopped at.
    pub fn step(&mut self) -> Result<(), Divergence> {
        match self.halt {
            Halt::Running => {}
            Halt::Diverged(d) => return Err(d),
            Halt::Stopped(_) => return Ok(()),
        }
        self.scratch.events.clear();
        let next_tick = self.state.tick + 1;
        let h_sub = self.params.h / f64::from(self.params.substeps);
        let motor = self.facts.motor;
        for k in 0..self.params.substeps {
            let t0 = self.time_of(self.state.tick) + f64::from(k) * h_sub;
            let since = self.state.tick as f64 * self.params.h + f64::from(k) * h_sub;
            let first_event = self.scratch.events.len();
            if let Some(i) = self.integrate(next_tick, (t0, since), h_sub, k) {
                self.state.tick = next_tick;
                return Err(self.stop(i, DivergenceCause::NonFinite));
            }
            if self.kind == LoopKind::Events {
                // A stop takes effect at the end of the tick: its other substeps still run.
                self.after_events(first_event);
            }
            if motor {
                // The next step's start, formed as that step forms it.
                let t1 = if k + 1 < self.params.substeps {
                    self.time_of(self.state.tick) + f64::from(k + 1) * h_sub
                } else {
                    self.time_of(next_tick)
                };
                self.burn(t1);
            }
        }
        self.state.tick = next_tick;
        self.guard_energy()
    }

    /// The motor's stage after a step ending at `t1`: each body's mass becomes what its motor
    /// has left then, and its momentum that mass times the velocity the step ended with (the
    /// momentum the burnt propellant carried off is dropped here; [`crate::forces::Thrust`]).
    fn burn(&mut self, t1: f64) {
        let Some(motor) = &self.state.forces.thrust else {
            return;
        };
        let b = &mut self.state.bodies;
        let mut burnt = false;
        for i in 0..b.len() {
            let m1 = motor.mass_at(t1 - b.launch_time[i], b.launch_mass[i]);
            if m1 != b.mass[i] {
                let v = b.mv.get(i) * b.inv_mass[i];
                b.mass[i] = m1;
                b.inv_mass[i] = 1.0 / m1;
                b.mv.set(i, m1 * v);
                burnt = true;
            }
        }
        // Velocity Verlet's carried force was scaled to the old mass: evaluate it afresh.
        if burnt {
            self.carry_valid = false;
            self.scratch.due.clear();
        }
    }

    /// Stops the run at storage index `i` for `cause`; the world keeps this state.
    pub(super) fn stop(&mut self, i: usize, cause: DivergenceCause) -> Divergence {
        let d = Divergence {
            tick: self.state.tick,
            body: self.state.bodies.id[i],
            cause,
        };
        self.halt = Halt::Diverged(d);
        d
    }

    /// After a substep of a world with declared events: their stops, and no body is fresh any
    /// more (a body's first segment has been searched).
    fn after_events(&mut self, first: usize) {
        self.scratch.fresh.clear();
        self.apply_stops(first);
    }

    /// Advances the world by `n` ticks: the same bits, events, force-evaluation count and
    /// divergence (tick, body, cause) as `n` calls of [`World::step`], stopping at the first
    /// divergence. Only the last tick's events are kept, so [`crate::SimLoop`] batches only
    /// when the observer asked for no tick in between.
    ///
    /// A world without contacts (so without events) runs **batches**: its bodies do not
    /// interact, so each block of `BATCH_BLOCK` bodies runs every tick of the batch while it
    /// sits in the core's cache before the next block is loaded, and the state crosses the
    /// memory bus once per batch instead of once per tick; the energy guard checks each block
    /// at the ticks it is due, while the block is still in cache. A batch is at most
    /// `BATCH_MAX_TICKS` long. Each body goes through exactly the operations `step` applies,
    /// in the same order, so the bits are the same. Before a batch the state is saved (as each
    /// block is loaded); if any body turns non-finite or trips the guard inside it, the batch
    /// is undone and run again tick by tick, so the run stops at exactly the tick, body and
    /// cause `step` names.
    /// With contacts the ticks run one by one.
    pub fn step_ticks(&mut self, n: u64) -> Result<(), Divergence> {
        if n == 0 {
            return Ok(());
        }
        match self.halt {
            Halt::Running => {}
            Halt::Diverged(d) => return Err(d),
            Halt::Stopped(_) => return Ok(()),
        }
        // A motor's mass changes between steps (`burn`), which a batch does not do.
        let batches = self.params.contacts.is_empty() && self.state.forces.thrust.is_none();
        let mut left = n;
        while left > 0 {
            let m = left.min(BATCH_MAX_TICKS);
            if batches && m >= 2 && self.integrate_batch(m) {
                self.state.tick += m;
            } else {
                for _ in 0..m {
                    self.step()?;
                    if self.halt != Halt::Running {
                        return Ok(());
                    }
                }
            }
            left -= m;
        }
        Ok(())
    }
}
