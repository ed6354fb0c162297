//! Where to draw a body between (or past) the ticks: the draw modes, the measured default, and
//! [`Draw`], which keeps what they need and gives each body's drawn position in one call.
//!
//! A stepped world exists only at tick boundaries; a frame is sampled between them. A draw
//! mode picks the moment the frame shows from the state before the frame's last tick, the
//! current one and the clock's alpha (its fraction of a tick). The loop lab (`volley pacing`,
//! docs/pacing.md) measures every mode against the exact motion at each frame's display time;
//! [`DEFAULT_POLICY`] and [`DEFAULT_DRAW`] are what it chose. The window draws through the
//! same [`Draw`], so a game that draws with it places every body where the window does.

use std::time::Duration;

use glam::DVec3;

use crate::clock::LoopPolicy;
use crate::sim_loop::TickObserver;
use crate::world::{BodyId, World};

/// Where a frame is drawn, given the state before and after the frame's last tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DrawMode {
    /// The state at the current tick. Shows game time `tick * dt`: on average half a tick
    /// behind the frame's sampled time, up to a whole tick.
    Current,
    /// Between the previous and the current tick by the clock's alpha (Fiedler; the window's
    /// default until the loop lab). Shows `(tick - 1 + alpha) * dt`: exactly one tick behind
    /// the sampled time, always.
    Interpolate,
    /// Past the current tick by the velocity over `alpha * dt` (Unity's extrapolate). Shows
    /// the sampled time; off by the curvature of the path over that fraction of a tick.
    Extrapolate,
    /// Extrapolated by the velocity to the frame's predicted present time: the sampled time
    /// plus the median of the last 15 frame deltas, the interval after which a vsynced frame
    /// reaches the screen (Volley's own: no display feedback is needed, only the deltas the
    /// game already measures). Shows the expected display time; off by the curvature over up
    /// to one refresh and a tick, and by a misprediction where frames are late.
    Predict,
    /// [`DrawMode::Predict`]'s straight path, met by the scene's surfaces as the contact stage
    /// meets a body: stopped at the ground, a wall or a level surface it reaches before the
    /// display time and reflected with the surface's restitution (Volley's own). It never draws
    /// a body inside a surface, and where nothing is in reach it is Predict exactly, bit for
    /// bit. Off by the curvature over the lead, as Predict is, and by what it cannot foresee:
    /// commands, and targets (sensors, which do not deflect).
    Swept,
}

impl DrawMode {
    /// Every draw mode, in the order the tables list them.
    pub const ALL: [DrawMode; DrawMode::COUNT] = [
        DrawMode::Current,
        DrawMode::Interpolate,
        DrawMode::Extrapolate,
        DrawMode::Predict,
        DrawMode::Swept,
    ];

    /// How many draw modes there are.
    pub const COUNT: usize = 5;

    /// The name the command line and the tables use.
    pub fn name(self) -> &'static str {
        match self {
            DrawMode::Current => "current",
            DrawMode::Interpolate => "interpolate",
            DrawMode::Extrapolate => "extrapolate",
            DrawMode::Predict => "predict",
            DrawMode::Swept => "swept",
        }
    }

    /// The draw mode called `name`.
    pub fn parse(name: &str) -> Option<DrawMode> {
        DrawMode::ALL.into_iter().find(|m| m.name() == name)
    }

    /// How far past the current tick the frame is drawn, in seconds: `alpha` is the clock's
    /// fraction of a tick, `lead` the predicted time to the present (for [`DrawMode::Predict`]
    /// and [`DrawMode::Swept`]).
    pub fn offset(self, alpha: f64, dt: f64, lead: f64) -> f64 {
        match self {
            DrawMode::Current => 0.0,
            DrawMode::Interpolate => (alpha - 1.0) * dt,
            DrawMode::Extrapolate => alpha * dt,
            DrawMode::Predict | DrawMode::Swept => alpha * dt + lead,
        }
    }

    /// The drawn position from the previous and current position and the current velocity, with
    /// no surface in the way ([`DrawMode::Swept`] is [`DrawMode::Predict`] here; [`Draw`] and
    /// [`swept_position`] meet the scene's surfaces).
    pub fn position(
        self,
        prev: DVec3,
        cur: DVec3,
        v: DVec3,
        alpha: f64,
        dt: f64,
        lead: f64,
    ) -> DVec3 {
        match self {
            DrawMode::Current => cur,
            DrawMode::Interpolate => prev + (cur - prev) * alpha,
            DrawMode::Extrapolate | DrawMode::Predict | DrawMode::Swept => {
                cur + v * self.offset(alpha, dt, lead)
            }
        }
    }
}

/// Where [`DrawMode::Swept`] draws a body of radius `r` at `cur` moving at `v`, `tau` seconds
/// past its tick, in `world`'s scene: the straight path met by the ground, the walls and the
/// level surfaces ([`Contacts::penetration`](crate::Contacts::penetration) is 0 there), or
/// `cur + v tau` exactly where the scene has none of them. A bounce slower than gravity's gain
/// in a tick comes to rest, as the contact stage's does. It reads the scene only: the world
/// is not changed and no random number is drawn. Targets let it through, as they let the
/// world's bodies ([`AtTargets::PassThrough`]); [`swept_position_at`] chooses.
pub fn swept_position(world: &World, r: f64, cur: DVec3, v: DVec3, tau: f64) -> DVec3 {
    Swept::of(world, AtTargets::PassThrough).position(r, cur, v, tau)
}

/// [`swept_position`], with targets met as `at` says.
pub fn swept_position_at(
    world: &World,
    at: AtTargets,
    r: f64,
    (cur, v): (DVec3, DVec3),
    tau: f64,
) -> DVec3 {
    Swept::of(world, at).position(r, cur, v, tau)
}

/// What [`DrawMode::Swept`] draws at a target sphere. The world's targets are sensors: a body
/// passes through one and the world reports a hit. Whether the body should then be seen past
/// it is the game's choice, which the draw cannot know.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AtTargets {
    /// Through it, as the world's bodies go (the default).
    #[default]
    PassThrough,
    /// Stopped on it at the point struck, riding with the target for the rest of the lead: for
    /// a game that removes a body when it hits a target (a shot), which therefore must not be
    /// drawn past the hit in the frames before the tick that reports it.
    Stop,
}

/// What [`DrawMode::Swept`] reads of a world, once a frame rather than once a body: the
/// surfaces (`None` without a ground, a wall or a level surface, or a target it stops at), the
/// rest speed, and when it stops at targets the seconds since tick 0.
struct Swept<'w> {
    solid: Option<&'w crate::Contacts>,
    rest_speed: f64,
    targets: Option<f64>,
}

impl<'w> Swept<'w> {
    fn of(world: &'w World, at: AtTargets) -> Swept<'w> {
        let contacts = world.contacts();
        let targets = (at == AtTargets::Stop && !contacts.targets.is_empty())
            .then(|| world.tick() as f64 * world.dt());
        let solid = contacts.has_solids() || targets.is_some();
        let gravity = world.forces().gravity.map_or(0.0, DVec3::length);
        Swept {
            solid: solid.then_some(contacts),
            rest_speed: gravity * world.dt(),
            targets,
        }
    }

    /// [`swept_position`].
    fn position(&self, r: f64, cur: DVec3, v: DVec3, tau: f64) -> DVec3 {
        match self.solid {
            Some(contacts) if tau > 0.0 => crate::contact::straight_path(
                contacts,
                (cur, v),
                r,
                (tau, self.rest_speed),
                self.targets,
            ),
            _ => cur + v * tau,
        }
    }
}

/// Volley's default loop policy, chosen by the sweep (`volley pacing`, docs/pacing/report.md)
/// over every subject (smooth motion, bounces, wall hits, commands): the lowest p99 display
/// error, as a ratio to predict's on each subject, over the bundled display models at 60 Hz, at
/// no more latency than the accumulator with interpolation, with the drift the policy causes
/// within one tick and no frame drawn inside a surface. The plain accumulator: every other
/// policy either let game time stray more than a tick from wall time on some model (both
/// snapping policies) or measured worse. `pacing_default_is_the_sweeps_choice` re-runs the
/// choice and fails if this disagrees.
pub const DEFAULT_POLICY: LoopPolicy = LoopPolicy::Accumulator;

/// Volley's default draw mode, chosen with [`DEFAULT_POLICY`]: [`DrawMode::Swept`], the
/// current tick extrapolated by the velocity to the frame's predicted display time and met by
/// the scene's surfaces. On smooth motion it is [`DrawMode::Predict`] exactly, which beats
/// interpolation's p99 display error on every bundled model at the same input latency; through
/// a bounce it never draws the body inside the surface, where predict drew it up to a tick and
/// a refresh past it. What it cannot foresee is an input: after a command it mispredicts as
/// predict does.
pub const DEFAULT_DRAW: DrawMode = DrawMode::Swept;

/// How many recent deltas [`DrawMode::Predict`] takes the median of.
pub const LEAD_WINDOW: usize = 15;

/// [`DrawMode::Predict`]'s lead: the median of the last [`LEAD_WINDOW`] frame deltas, the
/// interval after which a vsynced frame reaches the screen. The lab, the window and [`Draw`]
/// all keep one, so they predict alike.
#[derive(Clone, Debug, Default)]
pub struct Lead {
    deltas: std::collections::VecDeque<Duration>,
}

impl Lead {
    /// Takes the latest frame delta, forgetting the oldest past [`LEAD_WINDOW`].
    pub fn push(&mut self, delta: Duration) {
        if self.deltas.len() == LEAD_WINDOW {
            self.deltas.pop_front();
        }
        self.deltas.push_back(delta);
    }

    /// The median of the deltas kept (the upper one of an even count; 0 before any).
    pub fn get(&self) -> Duration {
        let mut v: Vec<Duration> = self.deltas.iter().copied().collect();
        v.sort_unstable();
        v.get(v.len() / 2).copied().unwrap_or_default()
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
    /// Where body `i` of `world` is drawn from its position before the frame's last tick, its
    /// current position and its velocity (`swept`: the world's surfaces, read once a frame).
    fn place(
        &self,
        world: &World,
        swept: &Swept<'_>,
        i: usize,
        (before, now, v): (DVec3, DVec3, DVec3),
    ) -> DVec3 {
        let dt = world.dt();
        match self.mode {
            DrawMode::Swept => {
                let r = world.bodies().radii()[i];
                swept.position(r, now, v, self.mode.offset(self.alpha, dt, self.lead))
            }
            mode => mode.position(before, now, v, self.alpha, dt, self.lead),
        }
    }

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
            // The trail ends at the tick: the swept body may have turned at a surface since.
            DrawMode::Current | DrawMode::Swept => 1.0,
            mode if dt > 0.0 => 1.0 + mode.offset(self.alpha, dt, self.lead) / dt,
            _ => 1.0,
        }
    }
}

/// Volley's measured draw in one call: the state before each frame's last tick, the lead
/// estimate, and each body's drawn position under a draw mode. Give it to the loop as a tick
/// observer (alone, or in a tuple with the game's own), tell it each frame's delta, and ask
/// where to draw.
///
/// ```
/// use std::time::Duration;
/// use volley_sim::{Draw, SimLoop, World, bundled_scene};
///
/// let scene = bundled_scene("seed")?;
/// let mut sim = SimLoop::new(World::new(&scene));
/// let mut draw = Draw::measured(&sim.world);
/// let delta = Duration::from_nanos(16_666_667); // a 60 Hz display
/// for _ in 0..30 {
///     let ticks = sim.frame(delta, &mut draw)?;
///     draw.frame(delta);
///     draw.positions(&sim.world, ticks.alpha, |i, p| assert!(p.is_finite(), "body {i}"));
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Draw {
    mode: DrawMode,
    at_targets: AtTargets,
    lead: Lead,
    time_scale: f64,
    previous: Previous,
}

/// Body positions before a frame's last tick, in id order.
#[derive(Clone, Debug, Default, PartialEq)]
struct Previous {
    ids: Vec<BodyId>,
    positions: Vec<DVec3>,
    tick: u64,
}

impl Previous {
    fn copy_from(&mut self, world: &World) {
        let bodies = world.bodies();
        self.ids.clear();
        self.ids.extend_from_slice(bodies.ids());
        self.positions.clear();
        self.positions.extend(bodies.positions().iter());
        self.tick = world.tick();
    }
}

impl Draw {
    /// A draw in `mode` starting at the world's current state.
    pub fn new(world: &World, mode: DrawMode) -> Draw {
        let mut previous = Previous::default();
        previous.copy_from(world);
        Draw {
            mode,
            at_targets: AtTargets::default(),
            lead: Lead::default(),
            time_scale: 1.0,
            previous,
        }
    }

    /// A draw in Volley's measured default, [`DEFAULT_DRAW`].
    pub fn measured(world: &World) -> Draw {
        Draw::new(world, DEFAULT_DRAW)
    }

    /// The draw mode.
    pub fn mode(&self) -> DrawMode {
        self.mode
    }

    /// Draws in `mode` from the next call on.
    pub fn set_mode(&mut self, mode: DrawMode) {
        self.mode = mode;
    }

    /// How [`DrawMode::Swept`] meets targets from the next call on (through them, unless
    /// the game removes a body on its hit: [`AtTargets`]).
    pub fn set_at_targets(&mut self, at: AtTargets) {
        self.at_targets = at;
    }

    /// Game seconds per wall second (1 unless the game runs slowed or sped up; 0 while
    /// paused): the lead is wall time to the present, drawn in game time.
    pub fn set_time_scale(&mut self, scale: f64) {
        self.time_scale = scale;
    }

    /// Takes the frame's measured delta, for [`DrawMode::Predict`]'s lead. Call once a frame,
    /// after the loop ran it.
    pub fn frame(&mut self, delta: Duration) {
        self.lead.push(delta);
    }

    /// The lead (s of game time): the median of the last [`LEAD_WINDOW`] deltas times the time
    /// scale.
    pub fn lead(&self) -> f64 {
        self.lead.get().as_secs_f64() * self.time_scale
    }

    /// Where this frame is drawn at the clock's `alpha`.
    pub fn at(&self, alpha: f64) -> DrawAt {
        DrawAt {
            mode: self.mode,
            alpha,
            lead: self.lead(),
        }
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position this frame, at the clock's `alpha`.
    pub fn positions(&self, world: &World, alpha: f64, visit: impl FnMut(usize, DVec3)) {
        self.drawn(world, self.at(alpha), visit);
    }

    /// The drawn position of the body at storage index `i` this frame, if there is one.
    pub fn position(&self, world: &World, i: usize, alpha: f64) -> Option<DVec3> {
        self.drawn_one(world, i, self.at(alpha))
    }

    /// Calls `visit(i, position)` for every body `i` of `world` (storage order) with its drawn
    /// position under `at`: [`DrawMode::position`] (or [`swept_position`]) from the position
    /// before the frame's last tick (the current one for a body spawned since), the current
    /// position and the current velocity (momentum / mass). Ids are sorted in both, so one
    /// merge pass pairs them.
    pub fn drawn(&self, world: &World, at: DrawAt, mut visit: impl FnMut(usize, DVec3)) {
        let bodies = world.bodies();
        let current = bodies.positions();
        let prev = &self.previous;
        let swept = Swept::of(world, self.at_targets);
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
                DrawMode::Extrapolate | DrawMode::Predict | DrawMode::Swept => bodies.velocity(i),
                DrawMode::Current | DrawMode::Interpolate => DVec3::ZERO,
            };
            visit(i, at.place(world, &swept, i, (before, now, v)));
        }
    }

    /// The drawn position of the body at storage index `i` under `at` (what [`Draw::drawn`]
    /// gives it), if there is such a body.
    pub fn drawn_one(&self, world: &World, i: usize, at: DrawAt) -> Option<DVec3> {
        let bodies = world.bodies();
        let id = *bodies.ids().get(i)?;
        let now = bodies.positions().get(i);
        let before = match self.previous.ids.binary_search(&id) {
            Ok(j) => self.previous.positions[j],
            Err(_) => now,
        };
        let v = bodies.velocity(i);
        Some(at.place(
            world,
            &Swept::of(world, self.at_targets),
            i,
            (before, now, v),
        ))
    }

    /// The game time in ticks since tick 0 that a frame drawn at `at` shows: between the tick
    /// before the frame's last and the current one when interpolating, else the current tick
    /// plus the draw mode's offset.
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

    /// The world's current state becomes the state before the last tick (after a seek or a
    /// reset: nothing to draw from but where the bodies are).
    pub fn restart(&mut self, world: &World) {
        self.previous.copy_from(world);
    }

    /// The tick the state before the frame's last tick was taken at.
    pub fn previous_tick(&self) -> u64 {
        self.previous.tick
    }

    /// How many bodies that state holds.
    pub fn previous_len(&self) -> usize {
        self.previous.ids.len()
    }
}

impl TickObserver for Draw {
    fn before_last_tick(&mut self, world: &World) {
        self.previous.copy_from(world);
    }
}
