//! One tick run stage by stage, with a look at the world after each: what the sync test
//! ([`crate::SyncTest`]) hashes to say in which stage two runs of a tick first part.
//!
//! [`World::step`] resolves a body's contacts right after its scheme step, inside one loop over
//! the bodies; here the same calls run as separate passes (every body's scheme step, then every
//! body's contacts, then the non-finite check), so the state between them can be seen. No body
//! reads another's state, so the passes give the same bits, events and force-evaluation count
//! as the one loop (a test runs both on every bundled scene under every integrator). This path
//! runs only when a sync test asks for stages; the normal step never pays for it.

use glam::DVec3;

use crate::contact::{self, Contacts, Event, Particle, StepContext};
use crate::forces::Forces;
use crate::integrate::{BodyState, Scheme, SchemeVisitor, visit};
use crate::world::{Divergence, DivergenceCause, Halt, World};

use super::chunk::{Chunk, Fixed};
use super::kernel::{finite, start_carry};

/// A stage of a tick, in the order a tick runs them. The sync test hashes the world after
/// each; the first whose hashes differ between two runs of a tick is where they part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// A saved state was put back (the first tick of a sync test's re-run only).
    Restore,
    /// The tick's commands were applied.
    Commands,
    /// Every body advanced by its scheme under the declared forces, before contacts.
    Integrate {
        /// The integrator step within the tick, from 0.
        substep: u32,
    },
    /// Contacts with the ground, walls and targets resolved inside the step.
    Contacts {
        /// The integrator step within the tick, from 0.
        substep: u32,
    },
    /// The check that every position and momentum is finite.
    NonFinite {
        /// The integrator step within the tick, from 0.
        substep: u32,
    },
    /// A declared motor burnt: each body's mass falls to what its motor has left.
    Burn {
        /// The integrator step within the tick, from 0.
        substep: u32,
    },
    /// The energy guard (every `guard.every` ticks).
    Guard,
}

impl Stage {
    /// The stage's name without its substep: `restore`, `commands`, `integrate`, `contacts`,
    /// `non-finite`, `burn`, `guard`.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Restore => "restore",
            Stage::Commands => "commands",
            Stage::Integrate { .. } => "integrate",
            Stage::Contacts { .. } => "contacts",
            Stage::NonFinite { .. } => "non-finite",
            Stage::Burn { .. } => "burn",
            Stage::Guard => "guard",
        }
    }

    /// The integrator step within the tick, for the stages that run once per substep.
    pub fn substep(self) -> Option<u32> {
        match self {
            Stage::Integrate { substep }
            | Stage::Contacts { substep }
            | Stage::NonFinite { substep }
            | Stage::Burn { substep } => Some(substep),
            Stage::Restore | Stage::Commands | Stage::Guard => None,
        }
    }
}

impl std::fmt::Display for Stage {
    /// The name, with `substep k` (counted from 1) after the stages that repeat per substep
    /// when it is not the first.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())?;
        match self.substep() {
            Some(k) if k > 0 => write!(f, " (substep {})", k + 1),
            _ => Ok(()),
        }
    }
}

/// What the passes of one substep keep between them: each body's state and carried force
/// before its scheme step, and the force the step returned. Reused from tick to tick.
#[derive(Clone, Debug, Default)]
pub(crate) struct StageBuffers {
    start: Vec<(BodyState, DVec3)>,
    end_force: Vec<DVec3>,
}

impl World {
    /// [`World::step`], stage by stage: after each stage, `each` sees (and may change) the
    /// world. The same bits, events, force evaluations and divergence as `step` when `each`
    /// changes nothing. Runs on the calling thread, one body after another. Not for a world
    /// with declared events (their search and stops are not staged; [`crate::SyncTest::new`]
    /// refuses such a world).
    pub(crate) fn step_staged(
        &mut self,
        buffers: &mut StageBuffers,
        each: &mut dyn FnMut(Stage, &mut World),
    ) -> Result<(), Divergence> {
        debug_assert!(self.params.contacts.events.is_empty());
        match self.halt {
            Halt::Running => {}
            Halt::Diverged(d) => return Err(d),
            Halt::Stopped(_) => return Ok(()),
        }
        self.scratch.events.clear();
        let next_tick = self.state.tick + 1;
        let h_sub = self.params.h / f64::from(self.params.substeps);
        let motor = self.state.forces.thrust.is_some();
        for k in 0..self.params.substeps {
            let t0 = self.time_of(self.state.tick) + f64::from(k) * h_sub;
            let since = self.state.tick as f64 * self.params.h + f64::from(k) * h_sub;
            self.integrate_pass(next_tick, (t0, since), h_sub, buffers);
            each(Stage::Integrate { substep: k }, self);
            self.contacts_pass(next_tick, (t0, since), h_sub, buffers);
            each(Stage::Contacts { substep: k }, self);
            if let Some(i) = first_non_finite(self) {
                self.state.tick = next_tick;
                let d = self.stop(i, DivergenceCause::NonFinite);
                each(Stage::NonFinite { substep: k }, self);
                return Err(d);
            }
            each(Stage::NonFinite { substep: k }, self);
            if motor {
                let t1 = if k + 1 < self.params.substeps {
                    self.time_of(self.state.tick) + f64::from(k + 1) * h_sub
                } else {
                    self.time_of(next_tick)
                };
                self.burn(t1);
                each(Stage::Burn { substep: k }, self);
            }
        }
        self.state.tick = next_tick;
        let guarded = self.guard_energy();
        each(Stage::Guard, self);
        // `each` may have stopped the run (a stage hook); the world's flag is the outcome.
        match self.halt {
            Halt::Diverged(d) => Err(d),
            _ => guarded,
        }
    }

    /// The integrate stage alone: every body's scheme step, no contacts.
    fn integrate_pass(
        &mut self,
        tick: u64,
        (t0, since): (f64, f64),
        h: f64,
        buffers: &mut StageBuffers,
    ) {
        let (_, carries) = self.prepare_chunks();
        let ctx = step_context(
            &self.params.contacts,
            &self.state.forces,
            tick,
            (t0, since),
            h,
        );
        let b = &mut self.state.bodies;
        let (fixed, p, mv) = Fixed::of(b, self.facts.reads_launch);
        let chunk = fixed.chunk(p, mv, &mut self.state.carry, carries);
        let (evals, carried) = visit(
            self.state.integrator,
            &self.state.forces,
            self.params.tolerance,
            IntegratePass {
                chunk,
                ctx: &ctx,
                carry_valid: self.carry_valid,
                buffers,
            },
        );
        self.carry_valid = carried;
        self.state.force_evals = self.state.force_evals.saturating_add(evals);
    }

    /// The contacts stage alone, over the states the integrate pass left (or a stage hook
    /// changed); a world without contacts does nothing here.
    fn contacts_pass(
        &mut self,
        tick: u64,
        (t0, since): (f64, f64),
        h: f64,
        buffers: &mut StageBuffers,
    ) {
        if self.params.contacts.is_empty() {
            return;
        }
        let (_, carries) = self.prepare_chunks();
        let ctx = step_context(
            &self.params.contacts,
            &self.state.forces,
            tick,
            (t0, since),
            h,
        );
        let b = &mut self.state.bodies;
        let (fixed, p, mv) = Fixed::of(b, self.facts.reads_launch);
        let chunk = fixed.chunk(p, mv, &mut self.state.carry, carries);
        let evals = visit(
            self.state.integrator,
            &self.state.forces,
            self.params.tolerance,
            ContactsPass {
                chunk,
                ctx: &ctx,
                buffers,
                events: &mut self.scratch.events,
            },
        );
        self.state.force_evals = self.state.force_evals.saturating_add(evals);
    }
}

/// What the contact code needs to know about the step from `t0`, as the step forms it.
fn step_context<'c>(
    contacts: &'c Contacts,
    forces: &Forces,
    tick: u64,
    (t0, since): (f64, f64),
    h: f64,
) -> StepContext<'c> {
    let gravity = forces.gravity.map_or(0.0, DVec3::length);
    StepContext {
        contacts,
        tick,
        t0,
        since_start: since,
        h,
        rest_speed: gravity * h,
        levels: contacts.has_levels(),
        fresh: &[],
        horizon: None,
    }
}

/// The first body (lowest index) whose position or momentum is not finite.
fn first_non_finite(world: &World) -> Option<usize> {
    let b = &world.state.bodies;
    (0..b.len()).find(|&i| !(finite(b.p.get(i)) & finite(b.mv.get(i))))
}

struct IntegratePass<'a, 'f> {
    chunk: Chunk<'a>,
    ctx: &'f StepContext<'f>,
    carry_valid: bool,
    buffers: &'f mut StageBuffers,
}

impl SchemeVisitor for IntegratePass<'_, '_> {
    /// Force evaluations, and whether the scheme carries its force.
    type Out = (u64, bool);
    fn visit<S: Scheme>(self, scheme: S) -> (u64, bool) {
        let IntegratePass {
            mut chunk,
            ctx,
            carry_valid,
            buffers,
        } = self;
        let extra = start_carry(&scheme, &mut chunk, carry_valid, ctx.t0);
        let l = &mut chunk;
        let n = l.len();
        let mut evals = if S::ADAPTIVE { 0 } else { n as u64 * S::EVALS };
        buffers.start.clear();
        buffers.end_force.clear();
        for i in 0..n {
            let w = l.launch.mass::<S>(i, l.mass[i], l.inv_mass[i]);
            let s0 = BodyState {
                p: DVec3::new(l.px[i], l.py[i], l.pz[i]),
                mv: DVec3::new(l.mx[i], l.my[i], l.mz[i]),
            };
            let c0 = if S::CARRIES_FORCE {
                DVec3::new(l.cx[i], l.cy[i], l.cz[i])
            } else {
                DVec3::ZERO
            };
            let (s1, c1) = if S::ADAPTIVE {
                let (s1, c1, k) = scheme.step_counted(s0, w, ctx.t0, ctx.h, c0);
                evals += k;
                (s1, c1)
            } else {
                scheme.step(s0, w, ctx.t0, ctx.h, c0)
            };
            buffers.start.push((s0, c0));
            buffers.end_force.push(c1);
            (l.px[i], l.py[i], l.pz[i]) = (s1.p.x, s1.p.y, s1.p.z);
            (l.mx[i], l.my[i], l.mz[i]) = (s1.mv.x, s1.mv.y, s1.mv.z);
            if S::CARRIES_FORCE {
                (l.cx[i], l.cy[i], l.cz[i]) = (c1.x, c1.y, c1.z);
            }
        }
        (evals + extra, S::CARRIES_FORCE)
    }
}

struct ContactsPass<'a, 'f> {
    chunk: Chunk<'a>,
    ctx: &'f StepContext<'f>,
    buffers: &'f StageBuffers,
    events: &'f mut Vec<Event>,
}

impl SchemeVisitor for ContactsPass<'_, '_> {
    /// Force evaluations the contact searches spent.
    type Out = u64;
    fn visit<S: Scheme>(self, scheme: S) -> u64 {
        let ContactsPass {
            mut chunk,
            ctx,
            buffers,
            events,
        } = self;
        if ctx.levels {
            contacts_pass::<S, true>(&scheme, &mut chunk, ctx, buffers, events)
        } else {
            contacts_pass::<S, false>(&scheme, &mut chunk, ctx, buffers, events)
        }
    }
}

/// The contact stage over the bodies of `l`, as the kernel runs it (`LEVELS` as there).
fn contacts_pass<S: Scheme, const LEVELS: bool>(
    scheme: &S,
    l: &mut Chunk,
    ctx: &StepContext,
    buffers: &StageBuffers,
    events: &mut Vec<Event>,
) -> u64 {
    // A stage hook may have changed the body count; only the bodies both passes saw.
    let n = l.len().min(buffers.start.len());
    let mut evals = 0;
    for i in 0..n {
        let w = l.launch.mass::<S>(i, l.mass[i], l.inv_mass[i]);
        let (s0, c0) = buffers.start[i];
        let s1 = BodyState {
            p: DVec3::new(l.px[i], l.py[i], l.pz[i]),
            mv: DVec3::new(l.mx[i], l.my[i], l.mz[i]),
        };
        if !contact::needs_resolution::<LEVELS>(ctx, l.radius[i], w.inv, &s0, &s1) {
            continue;
        }
        let body = Particle {
            id: l.ids[i],
            w,
            r: l.radius[i],
            fresh: false,
        };
        let c1 = buffers.end_force[i];
        let (s, c, extra) = contact::resolve::<S, LEVELS, false>(
            scheme,
            ctx,
            body,
            (s0, c0),
            (s1, c1),
            events,
            &mut 0,
        );
        evals += extra;
        (l.px[i], l.py[i], l.pz[i]) = (s.p.x, s.p.y, s.p.z);
        (l.mx[i], l.my[i], l.mz[i]) = (s.mv.x, s.mv.y, s.mv.z);
        if S::CARRIES_FORCE {
            (l.cx[i], l.cy[i], l.cz[i]) = (c.x, c.y, c.z);
        }
    }
    evals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Integrator;
    use crate::scene::{BUNDLED, bundled};

    /// Ticks each pair runs (fewer for the worlds of a thousand bodies or more, in the dev
    /// profile these tests run in).
    const TICKS: u64 = 120;
    const BIG_TICKS: u64 = 4;

    /// The staged passes are the step: every bundled scene under every integrator it allows,
    /// stepped both ways tick by tick, with the same state, events, evaluations and divergence.
    #[test]
    fn the_staged_step_is_the_step_on_every_bundled_scene_and_integrator() {
        let mut compared = 0;
        for (name, _) in BUNDLED {
            let base = bundled(name).expect("bundled scenes parse");
            for integrator in Integrator::ALL {
                let mut scene = base.clone();
                if scene.set_integrator(integrator).is_err() {
                    continue;
                }
                let (mut a, mut b) = (World::new(&scene), World::new(&scene));
                let ticks = if a.bodies().len() >= 1000 {
                    BIG_TICKS
                } else {
                    TICKS
                };
                let mut buffers = StageBuffers::default();
                for _ in 0..ticks {
                    let ra = a.step();
                    let rb = b.step_staged(&mut buffers, &mut |_, _| {});
                    let at = (name, integrator, a.tick());
                    assert_eq!(ra, rb, "{at:?}");
                    assert_eq!(a.snapshot(), b.snapshot(), "{at:?}");
                    assert_eq!(a.events(), b.events(), "{at:?}");
                    assert_eq!(a.carry_valid, b.carry_valid, "{at:?}");
                    compared += 1;
                    if ra.is_err() {
                        break;
                    }
                }
            }
        }
        assert!(compared > 10_000, "{compared} ticks compared");
    }

    /// Each stage is seen once per substep, in the order of the step.
    #[test]
    fn stages_come_in_the_steps_order() {
        let mut scene = bundled("model_rocket").expect("bundled scenes parse");
        scene.set_substeps(2).expect("two substeps are allowed");
        let mut world = World::new(&scene);
        let mut seen = Vec::new();
        world
            .step_staged(&mut StageBuffers::default(), &mut |s, _| seen.push(s))
            .expect("the rocket steps");
        let per_substep = |substep| {
            [
                Stage::Integrate { substep },
                Stage::Contacts { substep },
                Stage::NonFinite { substep },
                Stage::Burn { substep },
            ]
        };
        let mut expected = per_substep(0).to_vec();
        expected.extend(per_substep(1));
        expected.push(Stage::Guard);
        assert_eq!(seen, expected);
        assert_eq!(
            Stage::Integrate { substep: 1 }.to_string(),
            "integrate (substep 2)"
        );
        assert_eq!(Stage::NonFinite { substep: 0 }.to_string(), "non-finite");
    }
}
