//! A run's history in memory, for rewinding: keyframes within a memory budget, every command
//! applied, and re-simulation from the nearest keyframe.
//!
//! A [`Timeline`] is a [`TickObserver`]: it takes a keyframe (the world's [`State`]) every
//! [`Timeline::every`] ticks and logs each command as the loop applies it. [`Timeline::seek`]
//! restores the keyframe at or before the tick asked for and steps on to it, applying the
//! logged commands at their ticks, so the state it arrives at is bit-identical to the one first
//! computed at that tick (the loop is deterministic; `tests/replay/timeline.rs` checks the hash
//! for every integrator, with commands in between and across keyframe boundaries).
//!
//! **Budget.** Keyframes and the command log together stay within [`Timeline::budget`] bytes
//! (default [`DEFAULT_BUDGET`], 64 MiB). When they would not, every other keyframe is dropped
//! and the interval doubles, up to [`MAX_EVERY`] ticks; past that the oldest keyframe goes and
//! the history starts later. A seek re-simulates at most `every` ticks.
//!
//! **The future.** After a seek back, the ticks already run are the timeline's recorded future:
//! running forward replays them (the caller schedules [`Timeline::commands_from`] on its loop),
//! and nothing is recorded twice. A *new* command at an earlier tick makes a different future:
//! [`Timeline::on_command`] then drops everything after that tick first.

use crate::command::Stamped;
use crate::sim_loop::{ObserverError, TickObserver};
use crate::world::{State, World};

/// Default memory budget of one timeline (bytes): 64 MiB.
pub const DEFAULT_BUDGET: usize = 64 << 20;
/// Ticks between keyframes at the start. A keyframe copies about 100 bytes a body, some tens of
/// nanoseconds, while a tick costs a few nanoseconds a body: one every 64 ticks keeps the
/// timeline's cost to about a tenth of the stepping's in the cheapest worlds, and a seek then
/// re-simulates at most 64 ticks.
pub const FIRST_EVERY: u64 = 64;
/// Largest interval the thinning goes to (ticks): past it the oldest history is dropped, so a
/// seek never re-simulates more than this many ticks.
pub const MAX_EVERY: u64 = 4096;

/// Why a seek could not be done.
#[derive(Clone, Debug, PartialEq)]
pub enum SeekError {
    /// The tick is outside the history held.
    OutOfRange {
        /// The tick asked for.
        tick: u64,
        /// The first tick held.
        start: u64,
        /// The last tick held.
        end: u64,
    },
    /// Re-simulating failed (a logged command was refused, or the run diverged before the
    /// tick); names the tick.
    Resimulate {
        /// Where it failed.
        tick: u64,
        /// What failed.
        why: String,
    },
}

impl std::fmt::Display for SeekError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SeekError::OutOfRange { tick, start, end } => write!(
                f,
                "tick {tick} is outside the history held (ticks {start} to {end})"
            ),
            SeekError::Resimulate { tick, why } => {
                write!(f, "re-simulating to the tick failed at tick {tick}: {why}")
            }
        }
    }
}

impl std::error::Error for SeekError {}

/// Keyframes and commands of one run, within a memory budget.
#[derive(Clone, Debug)]
pub struct Timeline {
    keyframes: Vec<State>,
    commands: Vec<Stamped>,
    /// Index of the next logged command a re-run past a seek will apply again.
    replay: usize,
    every: u64,
    budget: usize,
    bytes: usize,
    start: u64,
    end: u64,
    dropped_future: u64,
    /// Keyframes thinned out, kept to take the next snapshots into without allocating.
    spare: Vec<State>,
}

/// Thinned keyframes kept for reuse.
const SPARE: usize = 4;

/// Bytes a keyframe holds: the body columns, ids, inverse masses and carried forces.
fn state_bytes(s: &State) -> usize {
    let n = s.bodies.len();
    std::mem::size_of::<State>()
        + n * (crate::body::COLUMNS.len() + 2) * std::mem::size_of::<f64>()
        + s.carry.len() * 3 * std::mem::size_of::<f64>()
}

const COMMAND_BYTES: usize = std::mem::size_of::<Stamped>();

impl Timeline {
    /// A timeline starting at the world's current tick, within `budget` bytes, a keyframe
    /// every `FIRST_EVERY` ticks to begin with.
    pub fn new(world: &World, budget: usize) -> Timeline {
        Timeline::with_interval(world, budget, FIRST_EVERY)
    }

    /// [`Timeline::new`] with a keyframe every `every` ticks (at least 1) to begin with.
    pub fn with_interval(world: &World, budget: usize, every: u64) -> Timeline {
        let first = world.snapshot();
        Timeline {
            bytes: state_bytes(&first),
            start: first.tick,
            end: first.tick,
            keyframes: vec![first],
            commands: Vec::new(),
            replay: 0,
            every: every.max(1),
            budget,
            dropped_future: 0,
            spare: Vec::new(),
        }
    }

    /// The first tick held.
    pub fn start(&self) -> u64 {
        self.start
    }

    /// The last tick run (the end of the recorded future).
    pub fn end(&self) -> u64 {
        self.end
    }

    /// Ticks between keyframes now.
    pub fn every(&self) -> u64 {
        self.every
    }

    /// Keyframes held.
    pub fn keyframes(&self) -> usize {
        self.keyframes.len()
    }

    /// Bytes held (keyframes and commands).
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// The budget (bytes).
    pub fn budget(&self) -> usize {
        self.budget
    }

    /// Ticks of recorded future dropped so far by new commands at earlier ticks.
    pub fn dropped_future(&self) -> u64 {
        self.dropped_future
    }

    /// The logged commands at or after `tick`, in order: what a re-run from `tick` applies.
    pub fn commands_from(&self, tick: u64) -> &[Stamped] {
        let k = self.commands.partition_point(|c| c.tick < tick);
        &self.commands[k..]
    }

    /// Restores `world` to its state at `tick`: the keyframe at or before it, then the logged
    /// commands and ticks up to it. The state is the one first computed at that tick, before
    /// the commands stamped with it. A run that diverged can be sought to its divergence tick.
    pub fn seek(&mut self, world: &mut World, tick: u64) -> Result<(), SeekError> {
        if tick < self.start || tick > self.end {
            return Err(SeekError::OutOfRange {
                tick,
                start: self.start,
                end: self.end,
            });
        }
        let k = self.keyframes.partition_point(|s| s.tick <= tick) - 1;
        let fail = |tick: u64, why: String| SeekError::Resimulate { tick, why };
        world
            .restore(&self.keyframes[k])
            .map_err(|e| fail(self.keyframes[k].tick, e.to_string()))?;
        let mut c = self.commands.partition_point(|s| s.tick < world.tick());
        while world.tick() < tick {
            while let Some(s) = self.commands.get(c).filter(|s| s.tick == world.tick()) {
                world
                    .apply(&s.command)
                    .map_err(|e| fail(s.tick, e.to_string()))?;
                c += 1;
            }
            if let Err(d) = world.step()
                && world.tick() < tick
            {
                return Err(fail(d.tick, d.to_string()));
            }
        }
        self.replay = self.commands.partition_point(|s| s.tick < tick);
        Ok(())
    }

    /// Drops everything after `tick`: keyframes past it, commands stamped at or after it.
    pub fn truncate(&mut self, tick: u64) {
        if tick >= self.end {
            return;
        }
        self.dropped_future += self.end - tick;
        let k = self.keyframes.partition_point(|s| s.tick <= tick);
        for s in self.keyframes.drain(k..) {
            self.bytes -= state_bytes(&s);
        }
        let c = self.commands.partition_point(|s| s.tick < tick);
        self.bytes -= (self.commands.len() - c) * COMMAND_BYTES;
        self.commands.truncate(c);
        self.replay = self.commands.len();
        self.end = tick;
    }

    /// Whether `stamped` is the next command of the recorded future: a re-run applying it
    /// again, not a new command.
    pub fn is_recorded(&self, stamped: &Stamped) -> bool {
        self.commands.get(self.replay) == Some(stamped)
    }

    /// Whether a single keyframe of `world` fits the budget at least eight times over: a
    /// history worth keeping (a world too large for it should not keep one).
    pub fn fits(world: &World, budget: usize) -> bool {
        let s = world.state();
        let n = s.bodies.len();
        let bytes = std::mem::size_of::<State>()
            + n * (crate::body::COLUMNS.len() + 5) * std::mem::size_of::<f64>();
        bytes.saturating_mul(8) <= budget
    }

    /// Whether the world at `tick` is behind the recorded future (after a seek back).
    pub fn is_rewound(&self, tick: u64) -> bool {
        tick < self.end || self.replay < self.commands.len()
    }

    /// Keeps the budget: thins the keyframes (every other one, interval doubled) while that
    /// is allowed, then drops the oldest history.
    fn keep_budget(&mut self) {
        while self.bytes > self.budget && self.keyframes.len() > 1 {
            if self.every < MAX_EVERY {
                self.every *= 2;
                let (start, every) = (self.start, self.every);
                let (kept, thinned): (Vec<State>, Vec<State>) = std::mem::take(&mut self.keyframes)
                    .into_iter()
                    .partition(|s| (s.tick - start).is_multiple_of(every));
                self.keyframes = kept;
                for s in thinned {
                    self.bytes -= state_bytes(&s);
                    if self.spare.len() < SPARE {
                        self.spare.push(s);
                    }
                }
            } else {
                let old = self.keyframes.remove(0);
                self.bytes -= state_bytes(&old);
                self.start = self.keyframes[0].tick;
                let c = self.commands.partition_point(|s| s.tick < self.start);
                self.commands.drain(..c);
                self.bytes -= c * COMMAND_BYTES;
                self.replay = self.replay.saturating_sub(c);
            }
        }
    }
}

impl TickObserver for Timeline {
    /// Logs a command; one the re-run of the recorded future applies again is recognised and
    /// not logged twice, and a new one behind the end drops the future after its tick.
    fn on_command(&mut self, _world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        if self.is_recorded(stamped) {
            self.replay += 1;
            return Ok(());
        }
        if self.is_rewound(stamped.tick) {
            self.truncate(stamped.tick);
        }
        self.commands.push(*stamped);
        self.replay = self.commands.len();
        self.bytes += COMMAND_BYTES;
        self.keep_budget();
        Ok(())
    }

    /// A divergence ends the history at the bad state, which a seek can return to.
    fn on_divergence(&mut self, world: &World, _divergence: &crate::world::Divergence) {
        self.end = self.end.max(world.tick());
    }

    /// Records a keyframe every [`Timeline::every`] ticks past the recorded end.
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        let tick = world.tick();
        if tick <= self.end {
            return Ok(());
        }
        self.end = tick;
        if (tick - self.start).is_multiple_of(self.every) {
            let s = match self.spare.pop() {
                Some(mut s) => {
                    world.snapshot_into(&mut s);
                    s
                }
                None => world.snapshot(),
            };
            self.bytes += state_bytes(&s);
            self.keyframes.push(s);
            self.keep_budget();
        }
        Ok(())
    }
}
