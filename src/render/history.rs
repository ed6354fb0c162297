//! What drawing needs from the ticks a frame ran: the previous state to interpolate from, the
//! trails, and each body's closed-form reference.
//!
//! [`TickHistory`] is a [`TickObserver`]: the loop hands it the world before the last tick of
//! each frame ([`TickObserver::before_last_tick`]) and after every tick. The snapshot taken
//! before the last tick is the "previous" state, so the drawn position
//! `previous + alpha (current - previous)` stays right however many ticks one frame ran. A body
//! that did not exist at the snapshot (spawned by a command in the last tick) has no previous
//! position and is drawn at its current one.
//!
//! Interpolation is one of the loop lab's draw modes ([`DrawMode`]): [`TickHistory::drawn`]
//! places bodies under any of them, [`DrawAt`] saying which and where (the current tick, between
//! the last two, or past the current one by the velocity), as the lab's measurement does.

use glam::DVec3;

use crate::command::Stamped;
use crate::contact::EventKind;
pub use crate::draw::{Draw, DrawAt, DrawMode};
use crate::render::probe::ProbeHistory;
use crate::render::reference::References;
use crate::render::series::LaneSeries;
use crate::render::trails::TrailRing;
use crate::sim_loop::{ObserverError, TickObserver};
use crate::timeline::Timeline;
use crate::world::{BodyId, World};

/// Most (body, target) pairs [`TargetPasses`] keeps; later pairs are not recorded.
pub const MAX_PASSES: usize = 256;

/// A body's closest pass by a target so far, from the contact stage's approach events.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pass {
    /// The body.
    pub body: BodyId,
    /// Index of the target in the scene.
    pub target: u32,
    /// Closest distance between the centres (m).
    pub distance: f64,
    /// Sim time of that closest approach (s).
    pub time: f64,
    /// Whether the spheres touched.
    pub hit: bool,
}

/// The closest pass of each body by each target: how the window shows whether a shot hit.
#[derive(Clone, Debug, Default)]
pub struct TargetPasses {
    list: Vec<Pass>,
    latest: Option<usize>,
}

impl TargetPasses {
    /// Takes a tick's approach events in: a pass closer than the one kept replaces it.
    pub fn record(&mut self, world: &World) {
        for e in world.events() {
            let EventKind::Approach {
                target,
                distance,
                hit,
            } = e.kind
            else {
                continue;
            };
            let key = (e.body, target);
            let pass = Pass {
                body: e.body,
                target,
                distance,
                time: e.time,
                hit,
            };
            match self.list.binary_search_by_key(&key, |p| (p.body, p.target)) {
                Ok(k) => {
                    if distance < self.list[k].distance {
                        self.list[k] = pass;
                    }
                    self.latest = Some(k);
                }
                Err(k) if self.list.len() < MAX_PASSES => {
                    self.list.insert(k, pass);
                    self.latest = Some(k);
                }
                Err(_) => {}
            }
        }
    }

    /// Every pass kept, by body then target.
    pub fn all(&self) -> &[Pass] {
        &self.list
    }

    /// The pass updated last.
    pub fn latest(&self) -> Option<&Pass> {
        self.latest.and_then(|k| self.list.get(k))
    }
}

/// The previous state, trails and references of one world, fed by the loop.
#[derive(Debug)]
pub struct TickHistory {
    /// The state before the frame's last tick and the drawn positions: the library's own
    /// [`Draw`], so a game drawing with it places bodies where the window does.
    draw: Draw,
    /// Recent positions of each body, one sample per tick.
    pub trails: TrailRing,
    /// Closed-form references, one per body, recorded the first time its id is seen.
    pub references: References,
    /// Each body's closest pass by each target.
    pub passes: TargetPasses,
    /// The run's keyframes and commands for rewinding (the window's lanes keep one; a
    /// headless `--frames` run does not).
    pub timeline: Option<Timeline>,
    /// The live plots' series, the whole run in bounded memory.
    pub series: LaneSeries,
    /// The first bodies' recent states and markers, for the probe and the markers.
    pub probe: ProbeHistory,
    origin: DVec3,
    commands: u64,
}

impl TickHistory {
    /// A history starting at the world's current state; trail samples are stored relative to
    /// `origin` (the render origin).
    pub fn new(world: &World, origin: DVec3) -> TickHistory {
        let mut history = TickHistory {
            draw: Draw::new(world, DrawMode::Interpolate),
            trails: TrailRing::new(origin),
            references: References::default(),
            passes: TargetPasses::default(),
            timeline: None,
            series: LaneSeries::default(),
            probe: ProbeHistory::default(),
            origin,
            commands: 0,
        };
        history.references.observe(world);
        history.trails.record(world);
        history
    }

    /// [`TickHistory::new`] with a timeline of `budget` bytes, if a keyframe of this world fits
    /// it ([`Timeline::fits`]).
    pub fn with_timeline(world: &World, origin: DVec3, budget: usize) -> TickHistory {
        let mut history = TickHistory::new(world, origin);
        if Timeline::fits(world, budget) {
            history.timeline = Some(Timeline::new(world, budget));
        }
        history
    }

    /// After a seek: the world's state is the previous one, and the trails start again there
    /// (the references, passes and timeline are the run's and stay).
    pub fn after_seek(&mut self, world: &World) {
        self.draw.restart(world);
        self.trails = TrailRing::new(self.origin);
        self.trails.record(world);
        self.probe.after_seek();
    }

    /// Commands the loop has applied so far (a replay of the recorded future after a seek is
    /// not counted again).
    pub fn commands_applied(&self) -> u64 {
        self.commands
    }

    /// The tick of the state taken before the last tick of the latest frame.
    pub fn previous_tick(&self) -> u64 {
        self.draw.previous_tick()
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position: `previous + alpha (current - previous)`, or the current position for a body
    /// the snapshot does not hold. [`TickHistory::drawn`] with [`DrawMode::Interpolate`].
    pub fn interpolate(&self, world: &World, alpha: f64, visit: impl FnMut(usize, DVec3)) {
        self.drawn(world, DrawAt::interpolated(alpha), visit);
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position under `at` ([`Draw::drawn`]).
    pub fn drawn(&self, world: &World, at: DrawAt, visit: impl FnMut(usize, DVec3)) {
        self.draw.drawn(world, at, visit);
    }

    /// The drawn position of the body at storage index `i` under `at` ([`Draw::drawn_one`]).
    pub fn drawn_one(&self, world: &World, i: usize, at: DrawAt) -> Option<DVec3> {
        self.draw.drawn_one(world, i, at)
    }

    /// The sim time in ticks since tick 0 that a frame drawn at `at` shows
    /// ([`Draw::drawn_ticks`]).
    pub fn drawn_ticks(&self, world: &World, at: DrawAt) -> f64 {
        self.draw.drawn_ticks(world, at)
    }
}

impl TickObserver for TickHistory {
    fn on_command(&mut self, world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        let again = self
            .timeline
            .as_ref()
            .is_some_and(|t| t.is_recorded(stamped));
        if !again {
            self.commands += 1;
        }
        if let Some(t) = self.timeline.as_mut() {
            let dropped = t.dropped_future();
            t.on_command(world, stamped)?;
            if t.dropped_future() != dropped {
                self.series.truncate(stamped.tick);
            }
        }
        self.references.observe(world);
        Ok(())
    }

    fn on_divergence(&mut self, world: &World, divergence: &crate::world::Divergence) {
        if let Some(t) = self.timeline.as_mut() {
            t.on_divergence(world, divergence);
        }
    }

    fn before_last_tick(&mut self, world: &World) {
        self.draw.before_last_tick(world);
        self.references.observe(world);
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.trails.record(world);
        self.references.after_tick(world);
        self.passes.record(world);
        self.series.sample(world, &self.references);
        self.probe.record(world, &self.references);
        if let Some(t) = self.timeline.as_mut() {
            t.after_tick(world)?;
        }
        Ok(())
    }
}
