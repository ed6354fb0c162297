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
use crate::pacing::DrawMode;
use crate::render::probe::ProbeHistory;
use crate::render::reference::References;
use crate::render::series::LaneSeries;
use crate::render::trails::TrailRing;
use crate::sim_loop::{ObserverError, TickObserver};
use crate::timeline::Timeline;
use crate::world::{BodyId, World};

/// Body positions at one moment, in id order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Positions {
    ids: Vec<BodyId>,
    positions: Vec<DVec3>,
    tick: u64,
}

impl Positions {
    /// Copies the world's positions, reusing this snapshot's allocation.
    pub fn copy_from(&mut self, world: &World) {
        let bodies = world.bodies();
        self.ids.clear();
        self.ids.extend_from_slice(bodies.ids());
        self.positions.clear();
        self.positions.extend(bodies.positions().iter());
        self.tick = world.tick();
    }

    /// The tick the snapshot was taken at.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// Number of bodies in the snapshot.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// Whether the snapshot holds no bodies.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
}

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
    previous: Positions,
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
            previous: Positions::default(),
            trails: TrailRing::new(origin),
            references: References::default(),
            passes: TargetPasses::default(),
            timeline: None,
            series: LaneSeries::default(),
            probe: ProbeHistory::default(),
            origin,
            commands: 0,
        };
        history.previous.copy_from(world);
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
        self.previous.copy_from(world);
        self.trails = TrailRing::new(self.origin);
        self.trails.record(world);
        self.probe.after_seek();
    }

    /// Commands the loop has applied so far (a replay of the recorded future after a seek is
    /// not counted again).
    pub fn commands_applied(&self) -> u64 {
        self.commands
    }

    /// The snapshot taken before the last tick of the latest frame.
    pub fn previous(&self) -> &Positions {
        &self.previous
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position: `previous + alpha (current - previous)`, or the current position for a body
    /// the snapshot does not hold. [`TickHistory::drawn`] with [`DrawMode::Interpolate`].
    pub fn interpolate(&self, world: &World, alpha: f64, visit: impl FnMut(usize, DVec3)) {
        self.drawn(world, DrawAt::interpolated(alpha), visit);
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position under `at`: [`DrawMode::position`] from the snapshot's position (the current
    /// one for a body the snapshot does not hold), the current position and the current
    /// velocity (momentum / mass). Ids are sorted in both, so one merge pass pairs them.
    pub fn drawn(&self, world: &World, at: DrawAt, mut visit: impl FnMut(usize, DVec3)) {
        let bodies = world.bodies();
        let current = bodies.positions();
        let prev = &self.previous;
        let dt = world.dt();
        let mut j = 0;
        for (i, &id) in bodies.ids().iter().enumerate() {
            while j < prev.ids.len() && prev.ids[j] < id {
                j += 1;
            }
            let now = current.get(i);
            let before = match prev.ids.get(j) {
                Some(&p) if p == id => prev.positions[j],
                _ => now,
            };
            let v = match at.mode {
                DrawMode::Extrapolate | DrawMode::Predict => bodies.velocity(i),
                DrawMode::Current | DrawMode::Interpolate => DVec3::ZERO,
            };
            visit(i, at.mode.position(before, now, v, at.alpha, dt, at.lead));
        }
    }

    /// The drawn position of the body at storage index `i` under `at` (what
    /// [`TickHistory::drawn`] gives it), if there is such a body.
    pub fn drawn_one(&self, world: &World, i: usize, at: DrawAt) -> Option<DVec3> {
        let bodies = world.bodies();
        let id = *bodies.ids().get(i)?;
        let now = bodies.positions().get(i);
        let before = match self.previous.ids.binary_search(&id) {
            Ok(j) => self.previous.positions[j],
            Err(_) => now,
        };
        let v = bodies.velocity(i);
        Some(
            at.mode
                .position(before, now, v, at.alpha, world.dt(), at.lead),
        )
    }

    /// The sim time in ticks since tick 0 that a frame drawn at `at` shows: between the
    /// snapshot's tick and the current one when interpolating, else the current tick plus the
    /// draw mode's offset.
    pub fn drawn_ticks(&self, world: &World, at: DrawAt) -> f64 {
        let now = world.tick() as f64;
        match at.mode {
            DrawMode::Interpolate => {
                let before = self.previous.tick as f64;
                before + at.alpha * (now - before)
            }
            mode => now + mode.offset(at.alpha, world.dt(), at.lead) / world.dt(),
        }
    }
}

/// Where a frame is drawn between (or past) the ticks: the draw mode, the clock's alpha, and
/// for [`DrawMode::Predict`] the time predicted to the present.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawAt {
    /// The draw mode.
    pub mode: DrawMode,
    /// The clock's fraction of a tick in the accumulator, in [0, 1).
    pub alpha: f64,
    /// How far after the frame's sample it is expected on screen, in sim seconds (the median
    /// of the last frame deltas times the time scale; 0 while paused). Only
    /// [`DrawMode::Predict`] uses it.
    pub lead: f64,
}

impl DrawAt {
    /// Interpolation at `alpha`: the window's draw before the loop lab, and what a headless
    /// `--frames` run and the golden image draw.
    pub fn interpolated(alpha: f64) -> DrawAt {
        DrawAt {
            mode: DrawMode::Interpolate,
            alpha,
            lead: 0.0,
        }
    }

    /// The fraction along a trail's newest segment (from the tick before to the current one)
    /// where the drawn body is: alpha when interpolating, 1 at the current tick, past 1 by the
    /// offset in ticks when extrapolating (along the segment, so the trail meets the sphere to
    /// within the path's curvature over the offset).
    pub fn trail_alpha(&self, dt: f64) -> f64 {
        match self.mode {
            DrawMode::Interpolate => self.alpha,
            DrawMode::Current => 1.0,
            mode if dt > 0.0 => 1.0 + mode.offset(self.alpha, dt, self.lead) / dt,
            _ => 1.0,
        }
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
        self.previous.copy_from(world);
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
