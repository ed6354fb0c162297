//! The one fixed-timestep loop every mode runs: window, headless, record, replay, study.
//!
//! A frame delta goes into the [`FixedClock`]; for each tick it grants, the commands stamped at
//! the current tick are applied, the world steps, and the observer sees the result. Window and
//! headless differ only in where the deltas come from ([`crate::clock::FrameSource`]) and in the
//! observer (renderer, table writer, recorder, or nothing).

use std::collections::VecDeque;
use std::time::Duration;

use crate::clock::{FixedClock, FrameSource, FrameTicks, VirtualClock};
use crate::command::{Command, CommandError, Stamped};
use crate::world::{Divergence, World};

/// Sees the loop's ticks: table writers, recorders, renderers.
pub trait TickObserver {
    /// A command was applied at tick `stamped.tick` (before that tick's step).
    fn on_command(&mut self, _world: &World, _stamped: &Stamped) -> Result<(), ObserverError> {
        Ok(())
    }
    /// The next tick is the last of this frame: the state now is the "previous" state a
    /// renderer interpolates from.
    fn before_last_tick(&mut self, _world: &World) {}
    /// A tick finished.
    fn after_tick(&mut self, _world: &World) -> Result<(), ObserverError> {
        Ok(())
    }
    /// The world diverged at its current tick (its state is the bad one).
    fn on_divergence(&mut self, _world: &World, _divergence: &Divergence) {}
    /// The first tick after `tick` whose state this observer needs in `after_tick`. The loop
    /// may run the ticks up to it as one batch ([`World::step_ticks`], the same bits) and call
    /// `after_tick` once at its end; it batches only worlds without contacts, which have no
    /// events, so nothing between is lost. Default: every tick.
    fn next_needed_tick(&self, tick: u64) -> u64 {
        tick + 1
    }
}

/// The first multiple of `every` (at least 1) after `tick`, for [`TickObserver::next_needed_tick`]
/// of observers that look every so many ticks; no division when `every` is 1.
pub fn next_multiple(tick: u64, every: u64) -> u64 {
    if every == 1 {
        tick.saturating_add(1)
    } else {
        (tick / every).saturating_add(1).saturating_mul(every)
    }
}

/// An observer that does nothing (and needs no tick).
impl TickObserver for () {
    fn next_needed_tick(&self, _tick: u64) -> u64 {
        u64::MAX
    }
}

/// A borrowed observer is an observer, so a pair can hold observers its caller keeps.
impl<T: TickObserver + ?Sized> TickObserver for &mut T {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        (**self).on_command(world, stamped)
    }
    fn before_last_tick(&mut self, world: &World) {
        (**self).before_last_tick(world);
    }
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        (**self).after_tick(world)
    }
    fn on_divergence(&mut self, world: &World, divergence: &Divergence) {
        (**self).on_divergence(world, divergence);
    }
    fn next_needed_tick(&self, tick: u64) -> u64 {
        (**self).next_needed_tick(tick)
    }
}

/// A pair of observers is an observer: every call goes to the first, then to the second (an
/// error from the first stops the call there, as it stops the loop), and the pair needs the
/// earlier of the ticks either needs. `(table, frames)` replaces hand-written forwarding.
impl<A: TickObserver, B: TickObserver> TickObserver for (A, B) {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        self.0.on_command(world, stamped)?;
        self.1.on_command(world, stamped)
    }
    fn before_last_tick(&mut self, world: &World) {
        self.0.before_last_tick(world);
        self.1.before_last_tick(world);
    }
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.0.after_tick(world)?;
        self.1.after_tick(world)
    }
    fn on_divergence(&mut self, world: &World, divergence: &Divergence) {
        self.0.on_divergence(world, divergence);
        self.1.on_divergence(world, divergence);
    }
    fn next_needed_tick(&self, tick: u64) -> u64 {
        self.0
            .next_needed_tick(tick)
            .min(self.1.next_needed_tick(tick))
    }
}

/// An observer failed (a write error, a full disk); the loop stops.
///
/// This one stays a message: observers are any code on the loop (the window's renderer, a
/// caller's own [`TickObserver`]), so their failures are not a closed set the simulation could
/// name; the message is what the observer says, shown as it is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObserverError(pub String);

impl std::fmt::Display for ObserverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ObserverError {}

/// Why the loop stopped early.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopError {
    /// The simulation diverged.
    Diverged(Divergence),
    /// A command could not be applied.
    Command {
        /// Tick it was due at.
        tick: u64,
        /// The command.
        command: Command,
        /// Why (boxed: the error is rare, and a boxed one keeps every `Result` of the loop
        /// small).
        error: Box<CommandError>,
    },
    /// An observer failed.
    Observer(ObserverError),
}

impl std::fmt::Display for LoopError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoopError::Diverged(d) => write!(f, "{d}"),
            LoopError::Command {
                tick,
                command,
                error,
            } => write!(f, "command `{tick}: {command}` failed: {error}"),
            LoopError::Observer(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for LoopError {}

impl From<ObserverError> for LoopError {
    fn from(e: ObserverError) -> Self {
        LoopError::Observer(e)
    }
}

/// Ticks per frame of [`SimLoop::unpaced_source`] as `volley headless` and `volley record`
/// use it: one whole batch ([`crate::step::BATCH_MAX_TICKS`]) and the frame's last tick, which
/// always runs alone.
pub const UNPACED_FRAME_TICKS: u32 = crate::step::BATCH_MAX_TICKS as u32 + 1;

/// The world, its clock, and the commands waiting for their tick.
#[derive(Debug)]
pub struct SimLoop {
    /// The simulation.
    pub world: World,
    /// The fixed-timestep clock.
    pub clock: FixedClock,
    queue: VecDeque<Stamped>,
    stop_at: Option<u64>,
}

impl SimLoop {
    /// A loop over `world` with a clock at the world's timestep.
    pub fn new(world: World) -> SimLoop {
        let clock = FixedClock::new(world.scene().timestep);
        SimLoop {
            world,
            clock,
            queue: VecDeque::new(),
            stop_at: None,
        }
    }

    /// Queues commands (sorted by tick, as a script is); each applies when its tick comes.
    pub fn schedule(&mut self, commands: impl IntoIterator<Item = Stamped>) {
        self.queue.extend(commands);
        self.queue.make_contiguous().sort_by_key(|c| c.tick);
    }

    /// Queues a command for the next tick boundary (window input).
    pub fn push(&mut self, command: Command) {
        let tick = self.world.tick();
        self.schedule([Stamped { tick, command }]);
    }

    /// Forgets every queued command (a seek replaces them with the timeline's).
    pub fn clear_queued(&mut self) {
        self.queue.clear();
    }

    /// The commands waiting for their tick, in the order they will be applied.
    pub fn queued(&self) -> impl Iterator<Item = &Stamped> {
        self.queue.iter()
    }

    /// Runs no tick past `tick`: frames that would run more leave the time in the accumulator.
    pub fn stop_at(&mut self, tick: Option<u64>) {
        self.stop_at = tick;
    }

    /// Whether the stop tick has been reached.
    pub fn finished(&self) -> bool {
        self.stop_at.is_some_and(|t| self.world.tick() >= t)
    }

    /// One frame: advance the clock by `delta` and run the ticks it grants.
    ///
    /// A game calls this once per rendered frame with the frame's real duration; the clock keeps
    /// the remainder, so a 144 Hz display over a 60 Hz simulation runs 0 or 1 tick a frame and
    /// sim time stays `start_time + tick * dt`:
    ///
    /// ```
    /// use std::time::Duration;
    /// use volley_sim::{Command, SimLoop, World, parse_scene};
    ///
    /// let scene = parse_scene(
    ///     "Scene(dt: 0.016666667, integrator: SemiImplicitEuler, forces: [Gravity((0, 0, -9.81))])",
    ///     "game.ron", "game").unwrap();
    /// let mut sim = SimLoop::new(World::new(&scene));
    /// sim.push(Command::Fire); // applied at the next tick boundary
    /// let mut ticks = 0;
    /// for _ in 0..144 {
    ///     ticks += sim.frame(Duration::from_nanos(6_944_444), &mut ()).unwrap().steps;
    /// }
    /// assert_eq!((ticks, sim.world.tick()), (59, 59)); // one second, less the carried remainder
    /// assert_eq!(sim.world.bodies().len(), 1);
    /// ```
    pub fn frame(
        &mut self,
        delta: Duration,
        observer: &mut impl TickObserver,
    ) -> Result<FrameTicks, LoopError> {
        let mut ticks = self.clock.advance(delta);
        if let Some(stop) = self.stop_at {
            let allowed = stop.saturating_sub(self.world.tick());
            if u64::from(ticks.steps) > allowed {
                let unrun = ticks.steps - allowed as u32;
                self.clock.return_ticks(unrun);
                ticks.steps = allowed as u32;
                ticks.alpha = self.clock.alpha();
            }
        }
        let mut ran = 0;
        while ran < ticks.steps {
            let before = self.world.tick();
            let result = self.run_ticks(ticks.steps - ran, observer);
            // Counted from the world: a tick stepped before an error (a divergence, a failed
            // observer) counts, a tick not stepped (a failed command, a world already stopped)
            // does not.
            ran += (self.world.tick() - before) as u32;
            if let Err(e) = result {
                // The ticks this frame granted but did not run go back into the accumulator, so
                // the clock's tick count stays the world's and no time is silently lost.
                self.clock.return_ticks(ticks.steps - ran);
                return Err(e);
            }
        }
        Ok(ticks)
    }

    /// Due commands, then one tick, or a batch of ticks when `left` (the frame's ticks still to
    /// run) allows one: up to the next queued command and the observer's next needed tick,
    /// never the frame's last tick (a renderer keeps the state before it), in a world without
    /// contacts.
    fn run_ticks(&mut self, left: u32, observer: &mut impl TickObserver) -> Result<(), LoopError> {
        self.apply_due(observer)?;
        let batch = self.batch_len(left, observer);
        let stepped = if batch >= 2 {
            self.world.step_ticks(batch)
        } else {
            if left == 1 {
                observer.before_last_tick(&self.world);
            }
            self.world.step()
        };
        if let Err(d) = stepped {
            observer.on_divergence(&self.world, &d);
            return Err(LoopError::Diverged(d));
        }
        observer.after_tick(&self.world)?;
        Ok(())
    }

    /// How many ticks from now may run as one batch (below 2: none): never the frame's last,
    /// none past the next queued command or the observer's next needed tick, and only in a
    /// world without contacts. A frame of one or two ticks (a window) asks nothing more.
    fn batch_len(&self, left: u32, observer: &impl TickObserver) -> u64 {
        if left < 3 || !self.world.contacts().is_empty() {
            return 0;
        }
        let tick = self.world.tick();
        let mut batch = u64::from(left - 1);
        if let Some(next) = self.queue.front() {
            batch = batch.min(next.tick.saturating_sub(tick));
        }
        batch.min(observer.next_needed_tick(tick).saturating_sub(tick))
    }

    /// Applies every queued command due at or before the current tick.
    fn apply_due(&mut self, observer: &mut impl TickObserver) -> Result<(), LoopError> {
        let tick = self.world.tick();
        while self.queue.front().is_some_and(|c| c.tick <= tick) {
            let Some(due) = self.queue.pop_front() else {
                break;
            };
            let applied = Stamped {
                tick,
                command: due.command,
            };
            self.world
                .apply(&due.command)
                .map_err(|error| LoopError::Command {
                    tick: due.tick,
                    command: due.command,
                    error: Box::new(error),
                })?;
            observer.on_command(&self.world, &applied)?;
        }
        Ok(())
    }

    /// A frame source for a run without a display (headless, record): each frame grants up to
    /// `ticks` ticks (the clock's clamp and cap are raised to allow it), so the loop can batch
    /// the ticks its observer does not need. The result does not depend on it: any frame-delta
    /// sequence gives the same bits. The raised clamp and cap stay: this is for loops that
    /// never see a real clock (a window's loop keeps the defaults against a spiral of death).
    pub fn unpaced_source(&mut self, ticks: u32) -> VirtualClock {
        let step = self.clock.timestep();
        let (delta, ticks) = match step.checked_mul(ticks) {
            Some(delta) => (delta, ticks),
            None => (step, 1),
        };
        self.clock.max_frame_delta = self.clock.max_frame_delta.max(delta);
        self.clock.max_steps_per_frame = self.clock.max_steps_per_frame.max(ticks);
        VirtualClock::Steady(delta)
    }

    /// Runs frames from `source` until the world reaches `tick`.
    pub fn run_until(
        &mut self,
        tick: u64,
        source: &mut impl FrameSource,
        observer: &mut impl TickObserver,
    ) -> Result<(), LoopError> {
        let previous = self.stop_at.replace(tick);
        let result = (|| {
            while self.world.tick() < tick {
                self.frame(source.next_delta(), observer)?;
            }
            Ok(())
        })();
        self.stop_at = previous;
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Logs its calls into a shared list, needs every `every`-th tick, and can fail after ticks.
    struct Log<'a> {
        name: &'static str,
        every: u64,
        fail: bool,
        calls: &'a std::cell::RefCell<Vec<String>>,
    }

    impl TickObserver for Log<'_> {
        fn on_command(&mut self, _: &World, s: &Stamped) -> Result<(), ObserverError> {
            self.calls
                .borrow_mut()
                .push(format!("{} command {}", self.name, s.tick));
            Ok(())
        }
        fn before_last_tick(&mut self, w: &World) {
            self.calls
                .borrow_mut()
                .push(format!("{} before {}", self.name, w.tick()));
        }
        fn after_tick(&mut self, w: &World) -> Result<(), ObserverError> {
            self.calls
                .borrow_mut()
                .push(format!("{} after {}", self.name, w.tick()));
            match self.fail {
                true => Err(ObserverError(format!("{} failed", self.name))),
                false => Ok(()),
            }
        }
        fn next_needed_tick(&self, tick: u64) -> u64 {
            next_multiple(tick, self.every)
        }
    }

    fn world() -> World {
        let scene = crate::scene::parse(
            "Scene(dt: 0.1, integrator: SemiImplicitEuler, forces: [Gravity((0, 0, -10))],
                   bodies: [(mass: 1, position: (0, 0, 100))])",
            "pair.ron",
            "pair",
        )
        .unwrap();
        World::new(&scene)
    }

    #[test]
    fn a_pair_calls_the_first_then_the_second_and_needs_the_earlier_tick() {
        let calls = std::cell::RefCell::new(Vec::new());
        let a = Log {
            name: "a",
            every: 4,
            fail: false,
            calls: &calls,
        };
        let b = Log {
            name: "b",
            every: 3,
            fail: false,
            calls: &calls,
        };
        let mut pair = (a, b);
        assert_eq!(pair.next_needed_tick(0), 3);
        assert_eq!(pair.next_needed_tick(3), 4);
        let mut sim = SimLoop::new(world());
        sim.push(Command::Fire);
        let mut by_ref = (&mut pair, ());
        // `()` needs no tick, so the borrowed pair decides.
        assert_eq!(by_ref.next_needed_tick(0), 3);
        sim.frame(Duration::from_millis(100), &mut by_ref).unwrap();
        assert_eq!(
            *calls.borrow(),
            [
                "a command 0",
                "b command 0",
                "a before 0",
                "b before 0",
                "a after 1",
                "b after 1"
            ]
        );
    }

    #[test]
    fn an_error_from_the_first_stops_the_call_there() {
        let calls = std::cell::RefCell::new(Vec::new());
        let a = Log {
            name: "a",
            every: 1,
            fail: true,
            calls: &calls,
        };
        let b = Log {
            name: "b",
            every: 1,
            fail: false,
            calls: &calls,
        };
        let mut sim = SimLoop::new(world());
        let e = sim
            .frame(Duration::from_millis(100), &mut (a, b))
            .unwrap_err();
        assert!(
            matches!(e, LoopError::Observer(ObserverError(ref m)) if m == "a failed"),
            "{e}"
        );
        assert_eq!(*calls.borrow(), ["a before 0", "b before 0", "a after 1"]);
    }
}
