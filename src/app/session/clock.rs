//! What every lane's clock shares: pause, single step and the time scale. They decide when
//! ticks run, never what a tick computes, so none of them is a command. A divergence or a
//! replay's mismatch pauses the clocks too (an alarm), and a reset resumes what an alarm paused.

use crate::clock::FrameTicks;
use crate::sim_loop::SimLoop;

use super::{Session, SessionError};

/// The clock settings every lane shares (they survive a restart), and what the last frame ran.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Clocks {
    /// Whether the clocks are paused.
    pub(super) paused: bool,
    /// The clocks were paused by a divergence or a replay's mismatch, not by the user.
    pub(super) paused_by_alarm: bool,
    /// Wall seconds to sim seconds (0 to 100).
    pub(super) time_scale: f64,
    /// What the last frame's clock decided (steps, alpha, dropped time), the first running
    /// lane's.
    pub(super) last: FrameTicks,
}

impl Default for Clocks {
    /// Running at real speed.
    fn default() -> Clocks {
        Clocks {
            paused: false,
            paused_by_alarm: false,
            time_scale: 1.0,
            last: FrameTicks::default(),
        }
    }
}

impl Session {
    /// Applies the shared clock settings (pause, time scale, loop policy) to a new lane's clock.
    pub(super) fn tune(&self, sim: &mut SimLoop) {
        if self.clock.paused {
            sim.clock.pause();
        }
        let _ = sim.clock.set_time_scale(self.clock.time_scale);
        sim.clock.set_policy(self.pacing.policy);
    }

    /// Pauses or resumes every lane (the user's pause: it replaces a pause a divergence caused).
    pub fn set_paused(&mut self, paused: bool) {
        if !paused {
            self.rewind.reverse = None;
        }
        self.clock.paused = paused;
        self.clock.paused_by_alarm = false;
        for lane in &mut self.lanes {
            if paused {
                lane.sim.clock.pause();
            } else {
                lane.sim.clock.resume();
            }
        }
    }

    /// Pauses and runs exactly one tick on the next frame, in every lane.
    pub fn single_step(&mut self) {
        self.clock.paused = true;
        for lane in &mut self.lanes {
            lane.sim.clock.single_step();
        }
    }

    /// Sets the time scale of every lane (0 to 100); a scale out of range changes nothing and
    /// says why.
    pub fn set_time_scale(&mut self, scale: f64) -> Result<(), SessionError> {
        for lane in &mut self.lanes {
            lane.sim
                .clock
                .set_time_scale(scale)
                .map_err(SessionError::Clock)?;
        }
        self.clock.time_scale = scale;
        Ok(())
    }

    /// Whether the clocks are paused.
    pub fn is_paused(&self) -> bool {
        self.clock.paused
    }

    /// The shared time scale.
    pub fn time_scale(&self) -> f64 {
        self.clock.time_scale
    }

    /// Whether the clocks are paused because of a divergence or a replay's mismatch.
    pub fn paused_by_alarm(&self) -> bool {
        self.clock.paused_by_alarm
    }

    /// What the last frame's clock decided (steps, alpha, dropped time).
    pub fn last_frame(&self) -> FrameTicks {
        self.clock.last
    }

    /// Pauses every clock on a divergence or a replay's mismatch, so the state stays on screen;
    /// a reset resumes what an alarm paused.
    pub(super) fn alarm(&mut self) {
        if !self.clock.paused {
            self.set_paused(true);
            self.clock.paused_by_alarm = true;
        }
    }
}
