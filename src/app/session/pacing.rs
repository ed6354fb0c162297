//! The loop lab in the window: the loop policy every lane's clock runs (and the refresh it is
//! given), how every lane is drawn, what the first lane's loop did with each frame, and what
//! the frame showed against the exact motion at the moment it reached the screen.
//!
//! A policy decides how many ticks a frame runs and a draw mode where a body is drawn between
//! ticks; neither changes what a tick computes, so neither is a command.
//!
//! Each frame `PacingLog::record` keeps the ticks the frame ran, the draw modes' display
//! errors for the measured body, and the drawn and exact positions for the judder ghosts, over
//! the last [`PACING_FRAMES`] frames. The error is the lab's ([`crate::pacing::lab`]): the
//! distance from the drawn position to the closed form at the frame's display time. That time
//! is the wall clock's, not the game's: the log keeps the game time the wall time since the
//! last discontinuity says (a restart, a seek, a pause, time dropped by the clamp), so a policy
//! that lets game time drift from wall time (snapping on a 59.94 Hz display) shows the drift as
//! error, as the lab measures it. An emulated display gives each frame's display time; on the
//! real clock or steady frames it is not known, and the error is taken at the frame's sample.

use std::collections::VecDeque;
use std::time::Duration;

use glam::DVec3;

use crate::app::display::{DEFAULT_REFRESH, Shown};
use crate::clock::LoopPolicy;
use crate::pacing::{DrawMode, Lead};
use crate::render::{DrawAt, JudderMark};
use crate::world::BodyId;

use super::{Lane, Session, SessionError};

/// Frames the log keeps: 10 s at 60 Hz.
pub const PACING_FRAMES: usize = 600;
/// Frames the cadence string and the swing count cover.
pub const CADENCE_FRAMES: usize = 60;
/// Frames the judder ghosts show.
pub const JUDDER_FRAMES: usize = 12;

/// The loop lab's settings, shared by every lane, and the first lane's last frames.
#[derive(Clone, Debug)]
pub(super) struct Pacing {
    /// The loop policy of every lane's clock.
    pub(super) policy: LoopPolicy,
    /// The refresh interval the snapping and quantising policies are given.
    pub(super) refresh: Duration,
    /// How every lane is drawn between (or past) its ticks.
    pub(super) draw: DrawMode,
    /// The first lane's last frames, for the pacing view and the judder ghosts.
    pub(super) log: PacingLog,
}

impl Default for Pacing {
    /// The loop lab's choices ([`crate::pacing::DEFAULT_POLICY`], [`crate::pacing::DEFAULT_DRAW`])
    /// on a display of [`DEFAULT_REFRESH`].
    fn default() -> Pacing {
        Pacing {
            policy: crate::pacing::DEFAULT_POLICY.with_refresh(DEFAULT_REFRESH),
            refresh: DEFAULT_REFRESH,
            draw: crate::pacing::DEFAULT_DRAW,
            log: PacingLog::default(),
        }
    }
}

impl Session {
    /// Every lane's loop policy.
    pub fn policy(&self) -> LoopPolicy {
        self.pacing.policy
    }

    /// Gives every lane `policy` from the next frame (what the old one carried from frame to
    /// frame is forgotten; the accumulator and the tick stay). A policy decides how many ticks
    /// a frame runs, never what a tick computes, so it is not a command: a recording is the
    /// same under any.
    pub fn set_policy(&mut self, policy: LoopPolicy) {
        self.pacing.policy = policy;
        for lane in &mut self.lanes {
            lane.sim.clock.set_policy(policy);
        }
    }

    /// [`Session::set_policy`] by name ([`LoopPolicy::NAMES`]), with the session's refresh; an
    /// unknown name is refused.
    pub fn set_policy_named(&mut self, name: &str) -> Result<(), SessionError> {
        let policy = LoopPolicy::from_name(name, self.pacing.refresh)
            .ok_or_else(|| SessionError::UnknownPolicy(name.to_string()))?;
        self.set_policy(policy);
        Ok(())
    }

    /// The refresh interval the snapping and quantising policies are given.
    pub fn refresh(&self) -> Duration {
        self.pacing.refresh
    }

    /// Sets the refresh interval the game believes in (the emulated display's, or the
    /// monitor's); the policy in use takes it.
    pub fn set_refresh(&mut self, refresh: Duration) {
        self.pacing.refresh = refresh;
        self.set_policy(self.pacing.policy.with_refresh(refresh));
    }

    /// How every lane is drawn.
    pub fn draw_mode(&self) -> DrawMode {
        self.pacing.draw
    }

    /// Draws every lane with `mode` from the next frame.
    pub fn set_draw_mode(&mut self, mode: DrawMode) {
        self.pacing.draw = mode;
    }

    /// The first lane's last frames.
    pub fn pacing(&self) -> &PacingLog {
        &self.pacing.log
    }

    /// Measures body `i` (storage index in the first lane) in the pacing view.
    pub fn set_pacing_body(&mut self, i: usize) {
        self.pacing.log.body = i;
    }
}

/// One frame as the pacing view plots it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PacingFrame {
    /// Wall time of the frame's sample since the window's first frame (s).
    pub wall: f64,
    /// Ticks the frame ran (the first lane's).
    pub steps: u32,
    /// Each draw mode's display error for the measured body (m), in [`DrawMode::ALL`]'s order;
    /// `None` where there is none (no closed form, a dropped frame, no such body).
    pub errors: [Option<f64>; DrawMode::COUNT],
    /// How deep the deepest body the frame draws (in the selected draw mode, every body of the
    /// first lane) is inside a surface (m; 0 when none is): a ball shown in the floor. It needs
    /// no reference, so it is measured on every scene.
    pub inside: f64,
    /// Game time minus the wall clock's game time at the frame's sample (s of sim time).
    pub drift: f64,
}

/// Why a frame has no display error.
#[derive(Clone, Debug, PartialEq)]
pub enum NoError {
    /// The measured body does not exist (the index is past the bodies).
    NoBody(usize),
    /// The body's forces have no closed form.
    NoClosedForm,
    /// The body's reference ended (an impact, a force switched) before the display time.
    Ended,
    /// The display dropped the frame: it was never shown.
    Dropped,
}

impl std::fmt::Display for NoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoError::NoBody(i) => write!(f, "no body {i} in the first lane"),
            NoError::NoClosedForm => f.write_str(
                "no closed form for this body's forces: the display error needs the exact \
                 motion at any time",
            ),
            NoError::Ended => f.write_str(
                "the body's closed form ended (an impact or a force switched): no exact motion \
                 to measure against",
            ),
            NoError::Dropped => f.write_str("the display dropped this frame"),
        }
    }
}

/// What one frame gives the log, besides the lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameInput {
    pub delta: Duration,
    pub shown: Shown,
    pub tick_before: u64,
    pub paused: bool,
    pub reversing: bool,
    pub time_scale: f64,
    pub draw: DrawMode,
}

/// The last frames of the first lane, for the pacing view and the judder ghosts.
#[derive(Clone, Debug, Default)]
pub struct PacingLog {
    frames: VecDeque<PacingFrame>,
    judder: Vec<JudderMark>,
    judder_body: Option<BodyId>,
    /// The frame deltas [`DrawMode::Predict`]'s lead is the median of, as the lab keeps them.
    deltas: Lead,
    wall: f64,
    /// The game time the wall clock says at the last frame's sample (s), since the last
    /// discontinuity.
    truth: Option<f64>,
    last_tick: Option<u64>,
    lead: f64,
    /// The body measured: its storage index in the first lane.
    pub body: usize,
    /// Why the last frame has no error, if it has none.
    pub note: Option<NoError>,
    /// Whether display times are known (an emulated display) or the error is taken at the
    /// frame's sample.
    pub display_times: bool,
    /// Every frame measured since the window opened: how many drew a body inside a surface
    /// (in the draw mode of that frame), and how deep the deepest was.
    inside: Inside,
}

/// Frames drawn with a body inside a surface, over the whole run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inside {
    /// Frames that drew some body inside a surface.
    pub frames: u64,
    /// Frames measured.
    pub of: u64,
    /// The deepest any body was drawn inside one (m).
    pub deepest: f64,
}

impl PacingLog {
    /// Frames drawn with a body inside a surface since the window opened: a ball shown in the
    /// floor. Needs no reference, so every scene has it.
    pub fn inside(&self) -> Inside {
        self.inside
    }

    /// The frames kept, oldest first.
    pub fn frames(&self) -> impl ExactSizeIterator<Item = &PacingFrame> + '_ {
        self.frames.iter()
    }

    /// The judder ghosts of the measured body, oldest first.
    pub fn judder(&self) -> &[JudderMark] {
        &self.judder
    }

    /// [`DrawMode::Predict`]'s lead for the frame being drawn (s of sim time): the median of
    /// the last [`crate::pacing::LEAD_WINDOW`] frame deltas times the time scale, 0 while paused.
    pub fn lead(&self) -> f64 {
        self.lead
    }

    /// The ticks of the last [`CADENCE_FRAMES`] frames, one digit each (`+` for 10 or more),
    /// oldest first.
    pub fn cadence(&self) -> String {
        self.last_steps()
            .map(|s| char::from_digit(s, 10).unwrap_or('+'))
            .collect()
    }

    /// 0-to-2 swings in the last [`CADENCE_FRAMES`] frames: a frame of no tick next to one of
    /// two or more (the lab's count).
    pub fn swings(&self) -> usize {
        let steps: Vec<u32> = self.last_steps().collect();
        steps
            .windows(2)
            .filter(|w| (w[0] == 0 && w[1] >= 2) || (w[0] >= 2 && w[1] == 0))
            .count()
    }

    /// The median display error of `mode` over the frames of the last `seconds` of wall time
    /// that have one (m).
    pub fn median_error(&self, mode: DrawMode, seconds: f64) -> Option<f64> {
        let k = DrawMode::ALL.iter().position(|&m| m == mode)?;
        let since = self.wall - seconds;
        let mut e: Vec<f64> = self
            .frames
            .iter()
            .filter(|f| f.wall >= since)
            .filter_map(|f| f.errors[k])
            .collect();
        e.sort_by(f64::total_cmp);
        e.get(e.len() / 2).copied()
    }

    fn last_steps(&self) -> impl Iterator<Item = u32> + '_ {
        let skip = self.frames.len().saturating_sub(CADENCE_FRAMES);
        self.frames.iter().skip(skip).map(|f| f.steps)
    }

    /// Forgets the judder ghosts and the wall clock's game time (the world restarted).
    pub(super) fn rebase(&mut self) {
        self.truth = None;
        self.last_tick = None;
        self.judder.clear();
    }

    /// Takes the frame the first lane just ran in.
    pub(super) fn record(&mut self, lane: &Lane, input: FrameInput) {
        let world = &lane.sim.world;
        let clock = &lane.sim.clock;
        self.wall += input.delta.as_secs_f64();
        self.deltas.push(input.delta);
        let still = input.paused || input.reversing;
        self.lead = if still {
            0.0
        } else {
            self.deltas.get().as_secs_f64() * input.time_scale
        };
        let tick = world.tick();
        let steps = u32::try_from(tick.saturating_sub(input.tick_before)).unwrap_or(u32::MAX);
        let alpha = clock.alpha();
        let dt = world.dt();
        let sampled = world.time() + alpha * dt;
        // Game seconds per wall second of the clock: a tick is `dt` of game time for each
        // whole-nanosecond timestep of scaled wall time.
        let rate = input.time_scale * dt / clock.timestep().as_secs_f64();
        let continuous = !still
            && lane.stopped.is_none()
            && clock.last_frame().dropped.is_zero()
            && self.last_tick == Some(input.tick_before)
            && tick >= input.tick_before;
        let truth = match self.truth {
            Some(t) if continuous => t + input.delta.as_secs_f64() * rate,
            _ => sampled,
        };
        if !continuous {
            self.judder.clear();
        }
        self.truth = Some(truth);
        self.last_tick = Some(tick);
        let (errors, mark) = self.measure(lane, input, truth, alpha, rate);
        let mut inside = 0.0f64;
        let drawn_at = DrawAt {
            mode: input.draw,
            alpha,
            lead: self.lead,
        };
        // Only a solid surface can hold a drawn body (the scenes without one skip the draw).
        if world.contacts().has_solids() {
            let radii = world.bodies().radii();
            lane.history.drawn(world, drawn_at, |i, p| {
                inside = inside.max(world.contacts().penetration(p, radii[i]));
            });
        }
        if let Some(mark) = mark {
            if self.judder.len() == JUDDER_FRAMES {
                self.judder.remove(0);
            }
            self.judder.push(mark);
        }
        if self.frames.len() == PACING_FRAMES {
            self.frames.pop_front();
        }
        self.frames.push_back(PacingFrame {
            wall: self.wall,
            steps,
            errors,
            inside,
            drift: sampled - truth,
        });
        self.inside.of += 1;
        if inside > 0.0 {
            self.inside.frames += 1;
            self.inside.deepest = self.inside.deepest.max(inside);
        }
    }

    /// Each draw mode's display error and the selected mode's judder mark, or why there is
    /// none (in [`PacingLog::note`]).
    fn measure(
        &mut self,
        lane: &Lane,
        input: FrameInput,
        truth: f64,
        alpha: f64,
        rate: f64,
    ) -> ([Option<f64>; DrawMode::COUNT], Option<JudderMark>) {
        let world = &lane.sim.world;
        let none = [None; DrawMode::COUNT];
        let Some(&id) = world.bodies().ids().get(self.body) else {
            self.note = Some(NoError::NoBody(self.body));
            self.judder.clear();
            return (none, None);
        };
        if self.judder_body != Some(id) {
            self.judder.clear();
            self.judder_body = Some(id);
        }
        let after = match input.shown {
            Shown::After(d) if !(input.paused || input.reversing) => d.as_secs_f64() * rate,
            Shown::After(_) | Shown::Unknown => 0.0,
            Shown::Dropped => {
                self.note = Some(NoError::Dropped);
                return (none, None);
            }
        };
        self.display_times = matches!(input.shown, Shown::After(_));
        let at = |mode| DrawAt {
            mode,
            alpha,
            lead: self.lead,
        };
        let drawn = DrawMode::ALL.map(|m| lane.history.drawn_one(world, self.body, at(m)));
        let selected = DrawMode::ALL
            .iter()
            .position(|&m| m == input.draw)
            .and_then(|k| drawn[k]);
        let exact = match lane.history.references.get(id) {
            Some(r) if !r.has_closed_form => Err(NoError::NoClosedForm),
            Some(r) => {
                let t = truth + after - r.spawn_time;
                let ended = r.ends_after(world.dt()).is_some_and(|end| t > end);
                match r.exact_at(t) {
                    Some(s) if !ended => Ok(s.p),
                    _ => Err(NoError::Ended),
                }
            }
            None => Err(NoError::NoClosedForm),
        };
        let exact = match exact {
            Ok(p) => {
                self.note = None;
                Some(p)
            }
            Err(why) => {
                self.note = Some(why);
                None
            }
        };
        let errors = drawn.map(|d| Some((d? - exact?).length()));
        let radius = world.bodies().radii()[self.body];
        let mark = selected.map(|drawn: DVec3| JudderMark {
            drawn,
            exact,
            radius,
        });
        (errors, mark)
    }
}
