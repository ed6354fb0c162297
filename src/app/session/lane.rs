//! One simulation of a session: its loop, what drawing needs of its ticks, whether a divergence
//! stopped it, and the stability pre-check of its world.

use glam::DVec3;

use crate::render::TickHistory;
use crate::render::draw::{self, Rgba};
use crate::sim_loop::SimLoop;
use crate::stability::{StabilityReport, check_world};
use crate::world::Divergence;

/// One simulation of the session.
#[derive(Debug)]
pub struct Lane {
    /// The loop (world, clock, queued commands).
    pub sim: SimLoop,
    /// Previous state, trails and references for drawing.
    pub history: TickHistory,
    /// The divergence that stopped the lane, if one did (the lane then runs no ticks).
    pub stopped: Option<Divergence>,
    /// Commands pushed to this lane so far.
    pub pushed: u64,
    /// Commands the loop refused.
    pub refused: u64,
    /// The stability pre-check of this lane's world (its integrator, dt and substeps).
    pub stability: StabilityReport,
    /// The pre-check's warnings (empty when the lane's integrator is stable at its step).
    pub warnings: Vec<String>,
    /// The last aim this lane solved for itself, or why it could not.
    pub aim: Option<AimNote>,
}

/// What an aim solved for one lane: the shot fired, or why none was.
#[derive(Clone, Debug, PartialEq)]
pub struct AimNote {
    /// The target aimed at (index in the scene).
    pub target: usize,
    /// The tick the shot was fired at (the next tick boundary after the request).
    pub tick: u64,
    /// The id the fired shot gets (the world's next id after the commands queued before it).
    pub body: crate::world::BodyId,
    /// The solution fired, or the solver's answer why there is none.
    pub outcome: Result<crate::firing::Shot, super::SessionError>,
}

impl Lane {
    /// A lane running `sim`, drawn relative to `origin`, keeping a timeline of `budget` bytes
    /// for rewinding if one is given (and a keyframe of its world fits it).
    pub(super) fn new(sim: SimLoop, origin: DVec3, budget: Option<usize>) -> Lane {
        let stability = check_world(&sim.world);
        let history = match budget {
            Some(b) => TickHistory::with_timeline(&sim.world, origin, b),
            None => TickHistory::new(&sim.world, origin),
        };
        Lane {
            history,
            warnings: stability.warnings(),
            stability,
            sim,
            stopped: None,
            pushed: 0,
            refused: 0,
            aim: None,
        }
    }

    /// Recomputes the pre-check if a command switched the integrator (dt, substeps and scene
    /// change only by building new lanes).
    pub(super) fn refresh_stability(&mut self) {
        if self.stability.chosen != self.sim.world.integrator() {
            self.stability = check_world(&self.sim.world);
            self.warnings = self.stability.warnings();
        }
    }

    /// Force evaluations per simulated second so far (the cost equal-cost compare mode
    /// levels), once the lane has run a tick.
    pub fn evals_per_second(&self) -> Option<f64> {
        let w = &self.sim.world;
        let elapsed = w.tick() as f64 * w.dt();
        (elapsed > 0.0).then(|| w.force_evals() as f64 / elapsed)
    }

    /// The colour of the lane's integrator.
    pub fn colour(&self) -> Rgba {
        draw::integrator_colour(self.sim.world.integrator())
    }

    /// Commands pushed but not yet applied (they wait for the next tick).
    pub fn pending(&self) -> u64 {
        self.pushed
            .saturating_sub(self.history.commands_applied() + self.refused)
    }
}
