//! Rewinding a session: every lane seeks on its own timeline ([`crate::timeline`]) to the same
//! tick; step back, jump to the start or the end, play backwards. In a replay the seek goes to
//! the recording itself (its keyframes, then re-simulation, verified as it runs).
//!
//! After a seek back the ticks already run are the recorded future: playing forward replays
//! them exactly (the timeline's commands are scheduled on the loop again). The first *new*
//! command at an earlier tick (fire, launch, aim, integrator, reset) drops that future in every
//! lane, and the panel says so ([`Session::future_dropped_at`]). A recording running when the timeline moves ends there, with
//! its footer, at the last tick it recorded (a recording's ticks only go forward); Record starts
//! a new file from the tick the timeline is at.

use std::time::Duration;

use super::{Session, SessionError};

/// What rewinding keeps besides each lane's timeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rewind {
    /// Memory budget of each lane's timeline (bytes).
    pub(super) budget: usize,
    /// Playing backwards: sim time owed to the reverse playback (scaled by the time scale).
    pub(super) reverse: Option<Duration>,
    /// The tick from which a new command last dropped the recorded future.
    pub(super) future_dropped_at: Option<u64>,
}

impl Default for Rewind {
    /// [`crate::timeline::DEFAULT_BUDGET`] a lane, playing forwards, no future dropped.
    fn default() -> Rewind {
        Rewind {
            budget: crate::timeline::DEFAULT_BUDGET,
            reverse: None,
            future_dropped_at: None,
        }
    }
}

impl Session {
    /// Each lane's timeline budget (bytes).
    pub fn history_budget(&self) -> usize {
        self.rewind.budget
    }

    /// Sets each lane's timeline budget (bytes); the timelines start again at the current tick.
    pub fn set_history_budget(&mut self, bytes: usize) {
        self.rewind.budget = bytes;
        for lane in &mut self.lanes {
            if lane.history.timeline.is_some() || self.replay.current.is_none() {
                lane.history.timeline = crate::timeline::Timeline::fits(&lane.sim.world, bytes)
                    .then(|| crate::timeline::Timeline::new(&lane.sim.world, bytes));
            }
        }
    }

    /// The ticks the timeline covers: live, the history every lane holds (`None` when a lane
    /// keeps none, its world being too large for the budget); in a replay, the recording's.
    pub fn history_range(&self) -> Option<(u64, u64)> {
        if let Some(replay) = &self.replay.current {
            return Some((0, replay.end_tick()));
        }
        // In the first lane's ticks; lanes with their own dt follow it by sim time.
        let h0 = self.lanes[0].sim.world.scene().timestep().as_nanos();
        let mut range = (0, u64::MAX);
        for lane in &self.lanes {
            let t = lane.history.timeline.as_ref()?;
            let h = lane.sim.world.scene().timestep().as_nanos();
            let to_first = |tick: u64| (u128::from(tick) * h / h0.max(1)) as u64;
            range = (
                range.0.max(to_first(t.start())),
                range.1.min(to_first(t.end())),
            );
        }
        Some(range)
    }

    /// Moves every lane to `tick` (clamped to [`Session::history_range`]); the clocks keep
    /// their pause and time scale. In a replay the recording is opened again at `tick`
    /// ([`Session::replays_opened`]). Returns why it could not (the last lane's reason, if
    /// several lanes failed; the others still moved).
    pub fn seek(&mut self, tick: u64) -> Result<(), SessionError> {
        let Some((start, end)) = self.history_range() else {
            return Err(SessionError::NoHistory {
                budget: self.rewind.budget,
            });
        };
        let tick = tick.clamp(start, end);
        if tick == self.world().tick() {
            return Ok(());
        }
        if let Some(replay) = &self.replay.current {
            let source = replay.source().clone();
            return self
                .start_replay_from(source, Some(tick))
                .map_err(SessionError::ReplaySeek);
        }
        if self.recording.current.is_some() {
            self.stop_recording(&format!("the timeline moved to tick {tick}"));
        }
        // `tick` is the first lane's; a lane with its own dt goes to its last tick at or
        // before the same sim time.
        let h0 = self.lanes[0].sim.world.scene().timestep().as_nanos();
        let mut refused = Ok(());
        for lane in &mut self.lanes {
            let Some(timeline) = lane.history.timeline.as_mut() else {
                continue;
            };
            let h = lane.sim.world.scene().timestep().as_nanos();
            let own = if h == h0 {
                tick
            } else {
                let t = u128::from(tick) * h0 / h.max(1);
                (t as u64).clamp(timeline.start(), timeline.end())
            };
            if let Err(e) = timeline.seek(&mut lane.sim.world, own) {
                refused = Err(SessionError::Seek(e));
                continue;
            }
            lane.sim.clear_queued();
            lane.sim
                .schedule(timeline.commands_from(own).iter().copied());
            lane.sim.clock.set_tick(own);
            lane.stopped = lane.sim.world.divergence();
            lane.history.after_seek(&lane.sim.world);
            lane.pushed = lane.history.commands_applied() + lane.refused;
            lane.refresh_stability();
        }
        refused
    }

    /// Pauses and goes back one tick, as [`Session::seek`] does.
    pub fn step_back(&mut self) -> Result<(), SessionError> {
        self.set_paused(true);
        self.rewind.reverse = None;
        let tick = self.world().tick();
        self.seek(tick.saturating_sub(1))
    }

    /// Pauses at the first tick held, as [`Session::seek`] does (nothing moves without a
    /// timeline).
    pub fn jump_to_start(&mut self) -> Result<(), SessionError> {
        self.set_paused(true);
        self.rewind.reverse = None;
        match self.history_range() {
            Some((start, _)) => self.seek(start),
            None => Ok(()),
        }
    }

    /// Goes to the last tick run (the end of the recorded future), paused, as
    /// [`Session::seek`] does (nothing moves without a timeline).
    pub fn jump_to_end(&mut self) -> Result<(), SessionError> {
        self.set_paused(true);
        self.rewind.reverse = None;
        match self.history_range() {
            Some((_, end)) => self.seek(end),
            None => Ok(()),
        }
    }

    /// Plays backwards (at the time scale) or stops doing so; playing backwards pauses the
    /// forward clocks, and stops at the first tick held.
    pub fn toggle_reverse(&mut self) {
        if self.rewind.reverse.take().is_none() {
            self.set_paused(true);
            self.rewind.reverse = Some(Duration::ZERO);
        }
    }

    /// Whether the session plays backwards.
    pub fn is_reversing(&self) -> bool {
        self.rewind.reverse.is_some()
    }

    /// A frame while playing backwards: the frame's delta, scaled, goes back in whole ticks
    /// (nothing when not playing backwards); returns why the seek failed, if it did.
    pub(super) fn reverse_frame(&mut self, delta: Duration) -> Result<(), SessionError> {
        let Some(owed) = self.rewind.reverse else {
            return Ok(());
        };
        let scaled = Duration::from_secs_f64(delta.as_secs_f64() * self.clock.time_scale);
        let owed = owed + scaled;
        let step = self.lanes[0].sim.world.scene().timestep();
        let ticks = (owed.as_nanos() / step.as_nanos().max(1)) as u64;
        let left = owed - step * ticks.min(u64::from(u32::MAX)) as u32;
        let now = self.world().tick();
        let start = self.history_range().map_or(now, |r| r.0);
        let to = now.saturating_sub(ticks).max(start);
        let sought = if to != now { self.seek(to) } else { Ok(()) };
        self.rewind.reverse = (to > start).then_some(left);
        sought
    }

    /// The tick from which a new command last dropped the recorded future (after a seek back),
    /// for the panel's note; `None` if no command has.
    pub fn future_dropped_at(&self) -> Option<u64> {
        self.rewind.future_dropped_at
    }

    /// Before a new command: if the lanes are behind their recorded future, that future is
    /// dropped (queued replays of it too), and [`Session::future_dropped_at`] says from which
    /// tick.
    pub(super) fn take_over_future(&mut self) {
        let mut dropped = None;
        for lane in &mut self.lanes {
            let tick = lane.sim.world.tick();
            let Some(timeline) = lane.history.timeline.as_mut() else {
                continue;
            };
            if timeline.is_rewound(tick) {
                lane.sim.clear_queued();
                timeline.truncate(tick);
                lane.history.series.truncate(tick);
                lane.pushed = lane.history.commands_applied() + lane.refused;
                dropped = Some(tick);
            }
        }
        if dropped.is_some() {
            self.rewind.future_dropped_at = dropped;
        }
    }
}
