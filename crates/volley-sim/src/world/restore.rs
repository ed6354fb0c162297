//! Snapshots and restoring them: what a keyframe holds, and the checks a state read from a file
//! passes before it becomes the world's.

use super::{Params, State, World};
use crate::body::{BodyId, Vec3s};

impl World {
    /// The state now, for keyframes and seeking. See [`World::snapshot_into`] to reuse buffers.
    pub fn snapshot(&self) -> State {
        let mut s = self.state.clone();
        if !self.carries_force() {
            s.carry = Vec3s::default();
        }
        s
    }

    /// Like [`World::snapshot`], reusing `out`'s allocations (no allocation once they fit).
    pub fn snapshot_into(&self, out: &mut State) {
        out.assign_from(&self.state, self.carries_force());
    }

    /// The state, as it is in the world (its carried-force buffer included, valid or not).
    #[inline]
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The parameters the world advances by.
    #[inline]
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Whether the carried force is state: velocity Verlet in its carrying form (forces of
    /// position only) or Forest-Ruth, after a step. In Verlet's predicted form (drag) the buffer
    /// is not read, and any switch between the forms goes through a command, which invalidates
    /// it.
    pub(crate) fn carries_force(&self) -> bool {
        self.carry_valid
            && self.state.carry.len() == self.state.bodies.len()
            && self.state.integrator.carries_force(&self.state.forces)
    }

    /// Puts `s` back, or says why it cannot belong to this world's scene (lengths that differ,
    /// ids not increasing or not below `next_id`, a mass not > 0, a radius not >= 0, a launch
    /// not finite or its mass not > 0, a force
    /// term the scene does not declare, an integrator the forces refuse, a carried force
    /// without velocity Verlet). The divergence flag and the last tick's events are cleared.
    pub fn restore(&mut self, s: &State) -> Result<(), RestoreError> {
        let b = &s.bodies;
        let n = b.id.len();
        if s.tick >= MAX_COUNT || s.next_id >= MAX_COUNT {
            return Err(RestoreError::Counts {
                tick: s.tick,
                next_id: s.next_id,
            });
        }
        if !b.lengths_agree() {
            return Err(RestoreError::Lengths { ids: n });
        }
        if !b.id.windows(2).all(|w| w[0] < w[1]) || b.id.last().is_some_and(|id| id.0 >= s.next_id)
        {
            return Err(RestoreError::Ids);
        }
        if let Some(i) = (0..n).find(|&i| !(b.mass[i].is_finite() && b.mass[i] > 0.0)) {
            return Err(RestoreError::Mass {
                body: b.id[i],
                mass: b.mass[i],
            });
        }
        if let Some(i) = (0..n).find(|&i| !(b.radius[i].is_finite() && b.radius[i] >= 0.0)) {
            return Err(RestoreError::Radius {
                body: b.id[i],
                radius: b.radius[i],
            });
        }
        if let Some(i) = (0..n).find(|&i| {
            let l = b.launch(i);
            !(l.time.is_finite() && l.mass.is_finite() && l.mass > 0.0 && l.spin.is_finite())
        }) {
            return Err(RestoreError::Launch { body: b.id[i] });
        }
        if s.forces != self.params.declared.filtered(|k| s.forces.has(k)) {
            return Err(RestoreError::Forces);
        }
        crate::scene::check_integrator(s.integrator, &s.forces)
            .map_err(RestoreError::Integrator)?;
        let l = &s.launcher;
        let numbers = [
            l.speed,
            l.elevation_deg,
            l.azimuth_deg,
            l.mass,
            l.radius,
            l.backspin,
            l.sidespin,
        ];
        let finite = numbers.iter().all(|x| x.is_finite()) && l.position.is_finite();
        if !(finite && l.speed >= 0.0 && l.mass > 0.0 && l.radius >= 0.0) {
            return Err(RestoreError::Launcher);
        }
        if !s.carry.is_empty() && (s.carry.len() != n || !s.integrator.carries_force(&s.forces)) {
            return Err(RestoreError::Carry);
        }
        let events = &self.params.contacts.events;
        if s.tallies.per_body.len() != n * events.body_slots()
            || s.tallies.run.len() != events.run_slots()
        {
            return Err(RestoreError::Tallies);
        }
        self.state.assign_from(s, true);
        self.facts = super::ForceFacts::of(&self.state.forces);
        self.carry_valid = !s.carry.is_empty();
        self.reset_after_restore();
        Ok(())
    }

    /// What every restore ends with, this one's and the sync test's ring: no divergence, no
    /// events, and the declared events' caches void (their horizons: each body is searched at
    /// its next step).
    pub(crate) fn reset_after_restore(&mut self) {
        self.scratch.events.clear();
        self.halt = super::Halt::Running;
        self.scratch.fresh.clear();
        self.scratch.due.clear();
    }
}

/// Bound on a restored state's tick and next body id (2^62): far past any run (146 years of
/// nanosecond ticks), and far enough below `u64::MAX` that counting on from it never overflows.
/// A keyframe read from a file is refused past it (fuzzing found one at `u64::MAX`).
pub const MAX_COUNT: u64 = 1 << 62;

/// Why [`World::restore`] refused a snapshot: the check it failed, with the values it names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RestoreError {
    /// The tick or the next body id is at or past [`MAX_COUNT`].
    Counts {
        /// The snapshot's tick.
        tick: u64,
        /// Its next body id.
        next_id: u64,
    },
    /// The body arrays are not all as long as the ids.
    Lengths {
        /// How many ids the snapshot has.
        ids: usize,
    },
    /// The ids do not increase, or one is not below `next_id`.
    Ids,
    /// A body's mass is not a finite number > 0.
    Mass {
        /// The body.
        body: BodyId,
        /// Its mass (kg).
        mass: f64,
    },
    /// A body's radius is not a finite number >= 0.
    Radius {
        /// The body.
        body: BodyId,
        /// Its radius (m).
        radius: f64,
    },
    /// A body's launch (time, mass, spin) is not finite, or its mass not > 0.
    Launch {
        /// The body.
        body: BodyId,
    },
    /// A force term is active that the scene does not declare (or with other values).
    Forces,
    /// The integrator is one the active forces refuse.
    Integrator(crate::scene::IntegratorError),
    /// The launcher has a value that is not finite, a negative speed or radius, or a mass not
    /// > 0.
    Launcher,
    /// A carried force without velocity Verlet, with velocity-dependent forces, or not one
    /// entry per body.
    Carry,
    /// Event counts that are not the scene's: one per body and event that stops a body after
    /// more than one occurrence, one per event that stops the run so.
    Tallies,
}

impl std::fmt::Display for RestoreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RestoreError::Lengths { ids } => {
                write!(f, "body arrays of different lengths ({ids} ids)")
            }
            RestoreError::Counts { tick, next_id } => write!(
                f,
                "tick {tick} and next_id {next_id} must be below 2^62 ({MAX_COUNT})"
            ),
            RestoreError::Ids => f.write_str("body ids must increase and stay below next_id"),
            RestoreError::Mass { body, mass } => {
                write!(f, "body {body}: mass must be > 0, got {mass}")
            }
            RestoreError::Radius { body, radius } => {
                write!(f, "body {body}: radius must be >= 0, got {radius}")
            }
            RestoreError::Launch { body } => write!(
                f,
                "body {body}: launch time, mass and spin must be finite and the mass > 0"
            ),
            RestoreError::Forces => {
                f.write_str("active forces are not a subset of the scene's declared terms")
            }
            RestoreError::Integrator(e) => write!(f, "{e}"),
            RestoreError::Launcher => {
                f.write_str("launcher: values must be finite, speed and radius >= 0, mass > 0")
            }
            RestoreError::Tallies => f.write_str(
                "event counts are not one per body and counted event of the scene's, and one \
                 per counted run-stopping event",
            ),
            RestoreError::Carry => f.write_str(
                "a carried force needs velocity Verlet, forces of position only and one entry \
                 per body",
            ),
        }
    }
}

impl std::error::Error for RestoreError {}
