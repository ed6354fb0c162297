//! Closed-form references: where each body would be if the integrator were exact.
//!
//! The first time a body's id is seen (ids are stable and increase), its spawn tick, state and
//! mass and the active force terms are recorded. Its exact state at tick `n` is then
//! [`crate::exact::closed_form`] over `(n - spawn_tick) h`, an integer number of ticks times the
//! step, so the error shown is the integrator's alone. The closed form knows no contacts: a
//! reference ends at the body's first contact ([`ends_reference`]: an impact, coming to rest,
//! a target hit) or when a force term is switched, and from then on the body shows no error
//! and no ghost rather than a meaningless one.

use glam::DVec3;

use crate::contact::EventKind;
use crate::exact::closed_form;
use crate::forces::Forces;
use crate::integrate::BodyState;
use crate::world::{BodyId, World};

/// Samples on a ghost trajectory.
pub const GHOST_SAMPLES: usize = 128;
/// Longest ghost trajectory drawn (s of sim time).
pub const GHOST_HORIZON_S: f64 = 120.0;
/// Most points one drawn trajectory takes ([`Reference::trajectory`]).
pub const MAX_TRAJECTORY_POINTS: usize = 4096;
/// Most halvings of one of the even intervals ([`Reference::trajectory`]): 1/256 of it.
const MAX_REFINE_DEPTH: u32 = 8;

/// Why a reference stopped applying.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceEnd {
    /// The body hit a surface during the step to this tick.
    Contact {
        /// The tick whose step had the impact.
        tick: u64,
        /// Sim time of the impact (s).
        time: f64,
    },
    /// A force term was switched on or off at this tick.
    ForcesChanged {
        /// The tick the change applied at.
        tick: u64,
    },
}

/// Whether an event ends its body's reference: every contact does. An impact reflects the
/// body's momentum and coming to rest removes it, which no contact-free reference follows; a
/// target hit leaves the path as it was, but it is where the scene's question was answered, and
/// a target may stand for a body that stops the shot. A closest approach without contact
/// ([`EventKind::Approach`]) touches nothing.
pub fn ends_reference(kind: &EventKind) -> bool {
    matches!(
        kind,
        EventKind::Impact { .. } | EventKind::Rest { .. } | EventKind::Hit { .. }
    )
}

/// One body's reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// The body.
    pub id: BodyId,
    /// Tick at which it was first seen (its spawn tick).
    pub spawn_tick: u64,
    /// Sim time of that tick (s).
    pub spawn_time: f64,
    /// Its state then.
    pub state: BodyState,
    /// Its mass (kg).
    pub mass: f64,
    /// Its launch: a spin's and a motor's clock and values, which the numerical reference reads.
    pub launch: crate::integrate::Launch,
    /// Force terms active then.
    pub forces: Forces,
    /// Whether the forces have a closed form at all.
    pub has_closed_form: bool,
    /// Without one, whether this body gets the numerical reference
    /// ([`crate::exact::extrapolate`]): the first [`NUMERIC_BODIES`] do.
    pub numeric: bool,
    /// The numerical reference's last state: (seconds after spawn, state, error estimate), so
    /// each frame advances it from there instead of from the spawn.
    pub cache: std::cell::Cell<Option<(f64, BodyState, f64)>>,
    /// When the reference stopped applying, if it has.
    pub end: Option<ReferenceEnd>,
}

/// Bodies without a closed form that get the numerical reference (the first ones in id order):
/// it costs some hundreds of force evaluations a body a tick.
pub const NUMERIC_BODIES: usize = 64;

/// Tolerance of the numerical reference, relative (far below any error it is used to measure).
pub const NUMERIC_TOLERANCE: f64 = 1e-12;

/// A body's numerical error against its reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BodyError {
    /// Distance (m) and speed difference (m/s) from the closed form at the current tick.
    Measured {
        /// `|p - p_exact|` (m).
        position: f64,
        /// `|v - v_exact|` (m/s).
        velocity: f64,
    },
    /// The force terms have no closed form.
    NoClosedForm,
    /// The reference ended.
    Ended(ReferenceEnd),
    /// The body was never seen.
    Unknown,
}

/// The references of every body seen, in id order.
#[derive(Clone, Debug, Default)]
pub struct References {
    list: Vec<Reference>,
    forces: Option<Forces>,
}

impl References {
    /// Records bodies not seen before (those with ids above the last one recorded) and drops
    /// references of bodies that are gone.
    pub fn observe(&mut self, world: &World) {
        self.note_forces(world);
        let bodies = world.bodies();
        let ids = bodies.ids();
        if self.list.len() > ids.len() || self.list.iter().zip(ids).any(|(r, id)| r.id != *id) {
            self.list.retain(|r| ids.binary_search(&r.id).is_ok());
        }
        let last = self.list.last().map(|r| r.id);
        let first_new = ids.partition_point(|id| last.is_some_and(|l| *id <= l));
        let forces = world.forces();
        for (i, &id) in ids.iter().enumerate().skip(first_new) {
            let (state, mass) = (bodies.state(i), bodies.masses()[i]);
            let has_closed_form = closed_form(forces, state, mass, 0.0).is_some();
            self.list.push(Reference {
                id,
                spawn_tick: world.tick(),
                spawn_time: world.time(),
                state,
                mass,
                launch: bodies.launch(i),
                forces: forces.clone(),
                has_closed_form,
                numeric: !has_closed_form && self.list.len() < NUMERIC_BODIES,
                cache: std::cell::Cell::new(None),
                end: None,
            });
        }
    }

    /// After a tick: contacts (an impact, coming to rest, a target hit) end their bodies'
    /// references; new bodies are recorded.
    pub fn after_tick(&mut self, world: &World) {
        self.observe(world);
        for event in world.events() {
            if ends_reference(&event.kind)
                && let Ok(k) = self.list.binary_search_by_key(&event.body, |r| r.id)
                && self.list[k].end.is_none()
            {
                self.list[k].end = Some(ReferenceEnd::Contact {
                    tick: event.tick,
                    time: event.time,
                });
            }
        }
    }

    /// A change of the active force terms ends every open reference.
    fn note_forces(&mut self, world: &World) {
        let now = world.forces();
        if self.forces.as_ref().is_some_and(|f| f != now) {
            for r in self.list.iter_mut().filter(|r| r.end.is_none()) {
                r.end = Some(ReferenceEnd::ForcesChanged { tick: world.tick() });
            }
        }
        self.forces = Some(now.clone());
    }

    /// The reference of `id`.
    pub fn get(&self, id: BodyId) -> Option<&Reference> {
        self.list
            .binary_search_by_key(&id, |r| r.id)
            .ok()
            .map(|k| &self.list[k])
    }

    /// Every reference, in id order.
    pub fn all(&self) -> &[Reference] {
        &self.list
    }

    /// Error of the body at storage index `i` against its reference at the world's tick.
    pub fn error(&self, world: &World, i: usize) -> BodyError {
        let bodies = world.bodies();
        let Some(r) = self.get(bodies.ids()[i]) else {
            return BodyError::Unknown;
        };
        if let Some(end) = r.end {
            return BodyError::Ended(end);
        }
        let ticks = world.tick().saturating_sub(r.spawn_tick) as f64;
        match r.exact_at(ticks * world.dt()) {
            Some(exact) => BodyError::Measured {
                position: (bodies.state(i).p - exact.p).length(),
                velocity: (bodies.velocity(i) - exact.mv / r.mass).length(),
            },
            None => BodyError::NoClosedForm,
        }
    }
}

impl Reference {
    /// The exact state `t` seconds after spawn: the closed form where the forces have one,
    /// else, for the first bodies, the numerical reference (adaptive extrapolation to
    /// [`NUMERIC_TOLERANCE`], advanced from where it last was).
    pub fn exact_at(&self, t: f64) -> Option<BodyState> {
        if self.has_closed_form {
            return closed_form(&self.forces, self.state, self.mass, t);
        }
        if !self.numeric {
            return None;
        }
        let (t0, s0, e0) = match self.cache.get() {
            Some(c) if c.0 <= t => c,
            _ => (0.0, self.state, 0.0),
        };
        let w = crate::integrate::Mass::launched(self.mass, self.launch);
        let start = self.spawn_time + t0;
        let (s, e) =
            crate::exact::extrapolate_from(&self.forces, s0, w, start, t - t0, NUMERIC_TOLERANCE)
                .ok()?;
        self.cache.set(Some((t, s, e0 + e)));
        Some(s)
    }

    /// Which reference the body is measured against, and that reference's own error estimate
    /// (m) where it has one: for the panel.
    pub fn kind(&self) -> (&'static str, Option<f64>) {
        if self.has_closed_form {
            ("closed form", None)
        } else if self.numeric {
            (
                "extrapolation (Gragg-Bulirsch-Stoer, 1e-12)",
                self.cache.get().map(|c| c.2),
            )
        } else {
            (
                "none (only the first 64 bodies get the numerical reference)",
                None,
            )
        }
    }

    /// Seconds from spawn to the end of the reference, if it ended.
    pub fn ends_after(&self, dt: f64) -> Option<f64> {
        match self.end? {
            ReferenceEnd::Contact { time, .. } => Some(time - self.spawn_time),
            ReferenceEnd::ForcesChanged { tick } => {
                Some(tick.saturating_sub(self.spawn_tick) as f64 * dt)
            }
        }
    }

    /// Points along the exact trajectory from spawn over `horizon` seconds (cut at the
    /// reference's end and where the body's centre would pass below `floor`), each with its
    /// time after spawn (s), into `out`:
    /// `GHOST_SAMPLES` evenly spaced, each interval then halved while the path's midpoint is more
    /// than `tolerance` (m) from the chord's, so a drawn chord stays within `tolerance` of the
    /// path (an orbit's 62.8 s in 128 even samples cut across the circle by metres). At most
    /// [`MAX_TRAJECTORY_POINTS`] points.
    pub fn trajectory(
        &self,
        horizon: f64,
        dt: f64,
        floor: Option<f64>,
        tolerance: f64,
        out: &mut Vec<(f64, DVec3)>,
    ) {
        out.clear();
        let horizon = self
            .ends_after(dt)
            .unwrap_or(horizon)
            .min(self.period().unwrap_or(f64::INFINITY))
            .clamp(0.0, GHOST_HORIZON_S);
        let mut previous: Option<(f64, DVec3)> = None;
        for k in 0..GHOST_SAMPLES {
            let t = horizon * k as f64 / (GHOST_SAMPLES - 1) as f64;
            let Some(s) = self.exact_at(t) else {
                return;
            };
            if floor.is_some_and(|z| s.p.z < z) && k > 0 {
                return;
            }
            if let Some(a) = previous {
                self.refine(a, (t, s.p), tolerance, 0, out);
            }
            out.push((t, s.p));
            previous = Some((t, s.p));
        }
    }

    /// The period of the motion where it repeats exactly, so a path drawn longer would only
    /// retrace itself (and even samples over many periods would alias, their chords cutting
    /// across it): a bound orbit of a lone point mass (Kepler's period from the energy), or an
    /// undamped zero-rest-length spring with at most uniform forces beside it (`2 pi / w`,
    /// `w^2 = k / m`: the oscillation about the shifted equilibrium). `None` otherwise.
    pub fn period(&self) -> Option<f64> {
        use crate::forces::ForceModel;
        use std::f64::consts::TAU;
        let f = &self.forces;
        if let Some(pm) = f.lone_point_mass() {
            let v = self.state.mv / self.mass;
            let r = (self.state.p - pm.center).length();
            let energy = 0.5 * v.length_squared() - pm.mu / r;
            if !(energy < 0.0 && r > 0.0) {
                return None;
            }
            let a = -pm.mu / (2.0 * energy);
            return Some(TAU * (a * a * a / pm.mu).sqrt());
        }
        let spring = f.spring?;
        let uniform_only = f.linear_drag.is_none()
            && f.quadratic_drag.is_none()
            && f.point_mass.is_none()
            && f.mach_drag.is_none()
            && f.custom.is_empty()
            && f.thrust.is_none();
        (uniform_only
            && spring.rest_length == 0.0
            && spring.damping == 0.0
            && spring.stiffness > 0.0)
            .then(|| TAU / (spring.stiffness / self.mass).sqrt())
    }

    /// The points strictly between `a` and `b` (time, position) that keep the chords within
    /// `tolerance` of the path, in time order.
    fn refine(
        &self,
        a: (f64, DVec3),
        b: (f64, DVec3),
        tolerance: f64,
        depth: u32,
        out: &mut Vec<(f64, DVec3)>,
    ) {
        if depth >= MAX_REFINE_DEPTH || out.len() + 2 >= MAX_TRAJECTORY_POINTS {
            return;
        }
        let t = 0.5 * (a.0 + b.0);
        let Some(mid) = self.exact_at(t) else {
            return;
        };
        if (mid.p - 0.5 * (a.1 + b.1)).length() <= tolerance {
            return;
        }
        self.refine(a, (t, mid.p), tolerance, depth + 1, out);
        out.push((t, mid.p));
        self.refine((t, mid.p), b, tolerance, depth + 1, out);
    }
}
