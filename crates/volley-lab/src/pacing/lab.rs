//! One loop-lab run: a world stepped by [`SimLoop`] under a display timing and a loop policy,
//! every draw mode evaluated on the same frames against the exact motion at each frame's
//! display time.
//!
//! Time origin: game time 0 (tick 0) is the first present's sample. A frame sampled at wall
//! time `s` and shown at `D` should show the body where the exact solution has it at `D - s0`;
//! what it shows is the draw mode's position, built from the state before and after the frame's
//! last tick as the window draws it.

use std::time::Duration;

use serde::{Deserialize, Serialize};

use glam::DVec3;

use volley_sim::internals::body::{BodyId, BodyState};
use volley_sim::internals::clock::LoopPolicy;
use volley_sim::internals::command::{Command, Stamped};
use volley_sim::internals::contact::EventKind;
use volley_sim::internals::exact::closed_form;
use volley_sim::internals::forces::Forces;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::scene::BodySpec;
use volley_sim::internals::scene::{self, Scene};
use volley_sim::internals::sim_loop::{LoopError, ObserverError, SimLoop, TickObserver};
use volley_sim::internals::world::World;

pub use volley_sim::internals::draw::{
    AtTargets, DrawMode, LEAD_WINDOW, Lead, swept_position, swept_position_at,
};

use super::DisplayTiming;
use super::metrics::{FrameRecord, Metrics};

/// The moving body a run measures, whose exact position is known at any time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Subject {
    /// A circular orbit of radius 10 m at 10 m/s around a point mass (the bundled `orbit`).
    Orbit,
    /// The seed's shot: 30 m/s on the high arc under gravity, with no ground, so it flies on
    /// for the whole run (its speed grows as it falls).
    Shot,
    /// A ball of radius 0.1 m dropped from 10.1 m onto the ground at restitution 1: it meets
    /// the ground at 14.0 m/s every 2.86 s, for ever.
    Bounce,
    /// The same drop at restitution 0.5: bounces of a quarter of the height before, until
    /// the rebound is slower than gravity's gain in a tick and the ball rests (after 4.2 s).
    BounceHalf,
    /// A ball of radius 0.1 m at 13 m/s between two walls 0.2 m thick at x = -6 and 6 m, at
    /// restitution 1 and with no force: a hit every 0.89 s (at 60 Hz, one in
    /// 13 on a tick boundary, the rest between), a triangle wave.
    Wall,
    /// A ball at 10 m/s with no force or surface, turned 90 degrees by a command every second
    /// (a game's input: `despawn` and `spawn` at the same point at a known tick), so it runs
    /// round a 10 m square. What no draw can foresee: its error after each turn is the
    /// misprediction.
    Command,
    /// Shots at a moving target: a target of radius 0.5 m crossing 40 m downrange at 3 m/s,
    /// and from a muzzle at the origin a shot of radius 0.1 m every second at 120 m/s with no
    /// force, aimed ahead so its line meets the target's centre. The game does what a game
    /// does with a shot: on the world's `Hit` event it stops drawing the shot and despawns it
    /// at the next tick. A straight shot's hit is a root of a quadratic, so it is exact; from
    /// the hit the reference is the point struck, riding on the target (where a shot that hit
    /// belongs until the game removes it), and the target is a surface: a shot drawn inside
    /// it was drawn through it. The draw knows the game removes shots ([`AtTargets::Stop`]).
    Target,
}

/// Gravity in the loop lab's scenes (m/s^2).
const G: f64 = 9.81;
/// The dropped ball's radius and starting height (m), as in `hard/bounce`.
const DROP: (f64, f64) = (0.1, 10.1);
/// The wall subject's ball radius, walls' half-spacing and thickness (m), and speed (m/s).
const WALLS: (f64, f64, f64, f64) = (0.1, 6.0, 0.2, 13.0);
/// The command subject's speed (m/s) and seconds between turns.
const TURN: (f64, f64) = (10.0, 1.0);
/// The target subject's target: radius (m), centre at tick 0 (m) and velocity (m/s).
const MOVER: (f64, DVec3, DVec3) = (0.5, DVec3::new(40.0, -90.0, 1.0), DVec3::new(0.0, 3.0, 0.0));
/// The target subject's shots: muzzle (m), radius (m), speed (m/s) and seconds between shots.
const SHOTS: (DVec3, f64, f64, f64) = (DVec3::new(0.0, 0.0, 1.0), 0.1, 120.0, 1.0);

/// Shot `j` (counted from 1) of the target subject at `rate` ticks per second: the time it is
/// fired (its spawn tick), its velocity (aimed ahead of the target: the root `T` of
/// `|c(t_f) - muzzle + u T| = speed T`), and the time it first touches the target.
fn shot(rate: f64, j: u64) -> (f64, DVec3, f64) {
    let (radius, c0, u) = MOVER;
    let (muzzle, r, speed, every) = SHOTS;
    let fired = (j * (every * rate).round() as u64) as f64 / rate;
    let d = c0 + u * fired - muzzle;
    // (u.u - s^2) T^2 + 2 (d.u) T + d.d = 0, with u.u < s^2: one positive root.
    let (a, b, c) = (
        u.length_squared() - speed * speed,
        2.0 * d.dot(u),
        d.length_squared(),
    );
    let lead = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    let v = (d + u * lead) / lead;
    // The gap closes along w = v - u from d0 = muzzle - c(t_f): |d0 + w s| = R + r.
    let (d0, w) = (-d, v - u);
    let reach = radius + r;
    let (aa, bb, cc) = (
        w.length_squared(),
        d0.dot(w),
        d0.length_squared() - reach * reach,
    );
    let hit = cc / (-bb + (bb * bb - aa * cc).sqrt());
    (fired, v, fired + hit)
}

impl Subject {
    /// Every subject: the smooth ones first, then the ones with discontinuities.
    pub const ALL: [Subject; 7] = [
        Subject::Orbit,
        Subject::Shot,
        Subject::Bounce,
        Subject::BounceHalf,
        Subject::Wall,
        Subject::Command,
        Subject::Target,
    ];

    /// The name the tables use.
    pub fn name(self) -> &'static str {
        match self {
            Subject::Orbit => "orbit",
            Subject::Shot => "shot",
            Subject::Bounce => "bounce",
            Subject::BounceHalf => "bounce-0.5",
            Subject::Wall => "wall",
            Subject::Command => "command",
            Subject::Target => "target",
        }
    }

    /// The subject called `name`.
    pub fn parse(name: &str) -> Option<Subject> {
        Subject::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The subject's scene at `rate` ticks per second, stepped by `integrator`.
    pub fn scene(self, rate: f64, integrator: Integrator) -> Scene {
        let dt = 1.0 / rate;
        let text = match self {
            Subject::Orbit => format!(
                "Scene(name: \"orbit\", dt: {dt:?}, integrator: VelocityVerlet, \
                 forces: [PointMass(center: (0.0, 0.0, 0.0), mu: 1000.0)], \
                 bodies: [(mass: 1.0, radius: 0.3, position: (10.0, 0.0, 0.0), \
                 launch: Velocity((0.0, 10.0, 0.0)))])"
            ),
            // The seed's launch, V = (7.6810, 0, 29.0000) m/s (the exact high-arc solution to
            // (50, 0, 20) at 30 m/s from (10, 0, 2)), without the ground.
            Subject::Shot => format!(
                "Scene(name: \"shot\", dt: {dt:?}, integrator: VelocityVerlet, \
                 forces: [Gravity((0.0, 0.0, -9.81))], \
                 bodies: [(mass: 2.5, radius: 0.1, position: (10.0, 0.0, 2.0), \
                 launch: Aim(target: (50.0, 0.0, 20.0), speed: 30.0, arc: High))])"
            ),
            Subject::Bounce | Subject::BounceHalf => {
                let e = self.restitution();
                let (r, z) = DROP;
                format!(
                    "Scene(name: \"{}\", dt: {dt:?}, integrator: VelocityVerlet, \
                     forces: [Gravity((0.0, 0.0, -{G:?}))], \
                     ground: (height: 0.0, restitution: {e:?}), \
                     bodies: [(mass: 1.0, radius: {r:?}, position: (0.0, 0.0, {z:?}))])",
                    self.name()
                )
            }
            Subject::Wall => {
                let (r, x, thick, v) = WALLS;
                format!(
                    "Scene(name: \"wall\", dt: {dt:?}, integrator: VelocityVerlet, forces: [], \
                     walls: [(point: ({x:?}, 0.0, 0.0), normal: (1.0, 0.0, 0.0), \
                     thickness: {thick:?}, restitution: 1.0), (point: (-{x:?}, 0.0, 0.0), \
                     normal: (1.0, 0.0, 0.0), thickness: {thick:?}, restitution: 1.0)], \
                     bodies: [(mass: 1.0, radius: {r:?}, position: (0.0, 0.0, 1.0), \
                     launch: Velocity(({v:?}, 0.0, 0.0)))])"
                )
            }
            Subject::Command => format!(
                "Scene(name: \"command\", dt: {dt:?}, integrator: VelocityVerlet, forces: [], \
                 bodies: [(mass: 1.0, radius: 0.1, position: (0.0, 0.0, 1.0), \
                 launch: Velocity(({:?}, 0.0, 0.0)))])",
                TURN.0
            ),
            Subject::Target => {
                let (radius, c, u) = MOVER;
                format!(
                    "Scene(name: \"target\", dt: {dt:?}, integrator: VelocityVerlet, forces: [], \
                     targets: [(center: ({:?}, {:?}, {:?}), radius: {radius:?}, \
                     velocity: ({:?}, {:?}, {:?}))])",
                    c.x, c.y, c.z, u.x, u.y, u.z
                )
            }
        };
        let mut scene = scene::parse(&text, "pacing.ron", self.name())
            .expect("the loop lab's own scene text is valid");
        scene
            .set_integrator(integrator)
            .expect("every integrator runs the loop lab's subjects (a point mass, gravity)");
        scene
    }

    /// The ground's restitution of a bounce subject (1 otherwise).
    fn restitution(self) -> f64 {
        match self {
            Subject::BounceHalf => 0.5,
            _ => 1.0,
        }
    }

    /// The commands the subject's game gives at `rate` ticks per second, up to `seconds`: the
    /// command subject's turns (a new body with the turned velocity where the old one is, at
    /// the exact position of the turn), none for the others.
    pub fn commands(self, rate: f64, seconds: f64) -> Vec<Stamped> {
        if self == Subject::Target {
            let every = (SHOTS.3 * rate).round() as u64;
            return (1..=(seconds / SHOTS.3) as u64)
                .map(|j| Stamped {
                    tick: j * every,
                    command: Command::Spawn(BodySpec {
                        mass: 1.0,
                        radius: SHOTS.1,
                        position: SHOTS.0,
                        velocity: shot(rate, j).1,
                        spin: DVec3::ZERO,
                    }),
                })
                .collect();
        }
        if self != Subject::Command {
            return Vec::new();
        }
        let dt = 1.0 / rate;
        let every = (TURN.1 * rate).round() as u64;
        let mut out = Vec::new();
        for j in 1..=(seconds / TURN.1) as u64 {
            let tick = j * every;
            let (position, velocity) = self.turn(dt, every, j);
            out.push(Stamped {
                tick,
                command: Command::Despawn(BodyId(j - 1)),
            });
            out.push(Stamped {
                tick,
                command: Command::Spawn(BodySpec {
                    mass: 1.0,
                    radius: 0.1,
                    position,
                    velocity,
                    spin: DVec3::ZERO,
                }),
            });
        }
        out
    }

    /// The command subject after `j` turns, one every `every` ticks of `dt`: where the turn
    /// is, and the velocity from it.
    fn turn(self, dt: f64, every: u64, j: u64) -> (DVec3, DVec3) {
        let velocity = |k: u64| match k % 4 {
            0 => DVec3::new(TURN.0, 0.0, 0.0),
            1 => DVec3::new(0.0, TURN.0, 0.0),
            2 => DVec3::new(-TURN.0, 0.0, 0.0),
            _ => DVec3::new(0.0, -TURN.0, 0.0),
        };
        let leg = (every as f64) * dt;
        let mut p = DVec3::new(0.0, 0.0, 1.0);
        for k in 0..j {
            p += velocity(k) * leg;
        }
        (p, velocity(j))
    }

    /// The bounce subjects' impacts at `rate` ticks per second, in order: each one's time and
    /// the speed the ball leaves the ground at, 0 at the impact whose rebound is slower than
    /// gravity's gain in a tick, where the sim rests it and the list ends.
    fn impacts(self, rate: f64) -> impl Iterator<Item = (f64, f64)> {
        let (r, z0) = DROP;
        let e = self.restitution();
        let fall = (2.0 * (z0 - r) / G).sqrt();
        let mut next = Some((fall, G * fall * e));
        std::iter::from_fn(move || {
            let (at, u) = next?;
            let u = if u <= G / rate { 0.0 } else { u };
            next = (u > 0.0).then(|| (at + 2.0 * u / G, e * u));
            Some((at, u))
        })
    }

    /// The exact position at game time `t` (s since tick 0) at `rate` ticks per second, from
    /// the scene's start `start` under its `forces`: the closed form for the smooth subjects,
    /// and for the others the closed form between the discontinuities, which are exact (a
    /// ground or wall hit is a root of a parabola or a line, a turn a known tick).
    pub fn exact(
        self,
        rate: f64,
        (forces, start, mass): (&Forces, BodyState, f64),
        t: f64,
    ) -> Option<DVec3> {
        match self {
            Subject::Orbit | Subject::Shot => closed_form(forces, start, mass, t).map(|s| s.p),
            Subject::Bounce | Subject::BounceHalf => {
                let (r, z0) = DROP;
                let arc =
                    |tau: f64, u: f64| DVec3::new(0.0, 0.0, r + u * tau - 0.5 * G * tau * tau);
                let mut impacts = self.impacts(rate);
                let (first, u) = impacts.next()?;
                if t <= first {
                    return Some(DVec3::new(0.0, 0.0, z0 - 0.5 * G * t * t));
                }
                if self.restitution() == 1.0 && u > 0.0 {
                    // Every flight the same: the one `t` falls in, by the remainder.
                    return Some(arc((t - first) % (2.0 * u / G), u));
                }
                for (at, u) in std::iter::once((first, u)).chain(impacts) {
                    if u == 0.0 {
                        return Some(DVec3::new(0.0, 0.0, r));
                    }
                    if t <= at + 2.0 * u / G {
                        return Some(arc(t - at, u));
                    }
                }
                None
            }
            Subject::Wall => {
                let (r, x, thick, v) = WALLS;
                let reach = x - 0.5 * thick - r;
                let u = (v * t + reach).rem_euclid(4.0 * reach);
                let x = if u < 2.0 * reach {
                    u - reach
                } else {
                    3.0 * reach - u
                };
                Some(DVec3::new(x, 0.0, start.p.z))
            }
            Subject::Command => {
                let dt = 1.0 / rate;
                let every = (TURN.1 * rate).round() as u64;
                let leg = every as f64 * dt;
                let j = (t / leg).floor().max(0.0) as u64;
                let (p, v) = self.turn(dt, every, j);
                Some(p + v * (t - j as f64 * leg))
            }
            // The last shot fired by `t` (none before the first).
            Subject::Target => {
                let j = (t * rate / (SHOTS.3 * rate).round()).floor();
                (j >= 1.0).then(|| Subject::shot_at(rate, j as u64, t))
            }
        }
    }

    /// Where shot `j` (from 1) of the target subject is at `t` (s since tick 0): on its line
    /// until it touches the target, then at the point struck, riding on the target.
    pub fn shot_at(rate: f64, j: u64, t: f64) -> DVec3 {
        let (fired, v, hit) = shot(rate, j);
        let at = |t: f64| SHOTS.0 + v * (t - fired);
        if t <= hit {
            at(t)
        } else {
            at(hit) + MOVER.2 * (t - hit)
        }
    }

    /// How deep a body of radius `r` drawn at `p`, at game time `t` (s since tick 0), is
    /// inside the target subject's target (m; 0 outside, and for the other subjects, whose
    /// targets a body passes through), beyond a nanometre of rounding.
    pub fn inside_target(self, r: f64, p: DVec3, t: f64) -> f64 {
        if self != Subject::Target {
            return 0.0;
        }
        let (radius, c0, u) = MOVER;
        let depth = radius + r - (p - (c0 + u * t)).length();
        if depth > 1e-9 { depth } else { 0.0 }
    }

    /// The times (s since tick 0) of the subject's discontinuities up to `until` at `rate`
    /// ticks per second: its impacts and its turns (none for the smooth subjects).
    pub fn discontinuities(self, rate: f64, until: f64) -> Vec<f64> {
        let mut out = Vec::new();
        match self {
            Subject::Orbit | Subject::Shot => {}
            Subject::Bounce | Subject::BounceHalf => {
                out.extend(
                    self.impacts(rate)
                        .map(|(at, _)| at)
                        .take_while(|&at| at <= until),
                );
            }
            Subject::Wall => {
                let (r, x, thick, v) = WALLS;
                let reach = x - 0.5 * thick - r;
                let mut k = 0.0;
                while (reach + 2.0 * reach * k) / v <= until {
                    out.push((reach + 2.0 * reach * k) / v);
                    k += 1.0;
                }
            }
            Subject::Command => {
                let every = (TURN.1 * rate).round() as u64;
                let leg = every as f64 / rate;
                let mut j = 1.0;
                while j * leg <= until {
                    out.push(j * leg);
                    j += 1.0;
                }
            }
            Subject::Target => {
                for j in 1.. {
                    let (fired, _, hit) = shot(rate, j);
                    if fired > until {
                        break;
                    }
                    out.push(hit);
                }
            }
        }
        out
    }
}

/// What one run is: a subject at a tick rate under an integrator, a loop policy, a display
/// timing, and the accumulator's starting phase.
#[derive(Clone, Debug)]
pub struct RunConfig {
    /// The moving body.
    pub subject: Subject,
    /// Ticks per second.
    pub rate: f64,
    /// The integrator (the scene's own is velocity Verlet; `Exact` shows the loop alone).
    pub integrator: Integrator,
    /// How frame deltas become ticks.
    pub policy: LoopPolicy,
    /// The first frame's delta, as a fraction of a tick: where the tick grid sits against the
    /// display's frames, which is set by when the game started (0 puts every sample on a tick
    /// boundary, the worst case for a noisy clock; 0.5 midway).
    pub phase: f64,
}

/// Keeps the state before the frame's last tick, as the window's renderer does, and the
/// bodies that hit a target in the frame's ticks (what the target subject's game reacts to).
struct Before {
    prev: Vec<(BodyId, BodyState)>,
    hits: Vec<BodyId>,
}

impl TickObserver for Before {
    fn before_last_tick(&mut self, world: &World) {
        self.prev.clear();
        let bodies = world.bodies();
        self.prev
            .extend((0..bodies.len()).map(|i| (bodies.ids()[i], bodies.state(i))));
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        for e in world.events() {
            if matches!(e.kind, EventKind::Hit { .. }) && !self.hits.contains(&e.body) {
                self.hits.push(e.body);
            }
        }
        Ok(())
    }
}

/// Runs `config` under `timing` and measures every draw mode.
pub fn run(config: &RunConfig, timing: &DisplayTiming) -> Result<Metrics, LoopError> {
    let subject = config.subject;
    let scene = subject.scene(config.rate, config.integrator);
    let world = World::new(&scene);
    let start: Vec<BodyState> = (0..world.bodies().len())
        .map(|i| world.bodies().state(i))
        .collect();
    let mass = world.bodies().masses().first().copied().unwrap_or(1.0);
    let forces = world.forces().clone();
    let mut sim = SimLoop::new(world);
    sim.clock.set_policy(config.policy);
    let dt = sim.world.dt();
    let timestep = sim.clock.timestep();
    let span = timing.presents.last().map_or(0.0, |p| {
        p.shown.unwrap_or(p.sampled).as_secs_f64() - timing.presents[0].sampled.as_secs_f64()
    }) + 1.0;
    sim.schedule(subject.commands(config.rate, span));
    // Frames shown this near a discontinuity (a tick and a refresh: what predict draws past
    // one) are the frames around it.
    let refresh = timing
        .median_display_interval()
        .map_or(1.0 / 60.0, |d| d.as_secs_f64());
    let near_window = dt + refresh;
    let jumps = subject.discontinuities(config.rate, span + 1.0);
    let first =
        Duration::from_nanos((config.phase.clamp(0.0, 1.0) * timestep.as_nanos() as f64) as u64);
    let mut before = Before {
        prev: Vec::new(),
        hits: Vec::new(),
    };
    before.before_last_tick(&sim.world);
    // The target subject's game: a shot that hit is drawn no more, and despawned.
    let mut hidden: Vec<BodyId> = Vec::new();
    let at_targets = if subject == Subject::Target {
        AtTargets::Stop
    } else {
        AtTargets::PassThrough
    };
    let mut lead_of = Lead::default();
    let mut records = Vec::with_capacity(timing.presents.len());
    let origin = timing
        .presents
        .first()
        .map_or(Duration::ZERO, |p| p.sampled);
    for (present, delta) in timing.presents.iter().zip(timing.deltas(first)) {
        let tick_before = sim.world.tick();
        let ticks = sim.frame(delta, &mut before)?;
        for id in before.hits.drain(..) {
            if !hidden.contains(&id) {
                hidden.push(id);
                sim.push(Command::Despawn(id));
            }
        }
        lead_of.push(delta);
        let lead = lead_of.get().as_secs_f64();
        let wall = present.sampled - origin;
        // Game time now: the ticks run plus what the accumulator holds, less the phase the
        // first frame was given, against the wall time since the first sample.
        let game = sim.clock.elapsed() + sim.clock.accumulator();
        let drift = game.as_secs_f64() - first.as_secs_f64() - wall.as_secs_f64();
        let shown = present.shown.map(|d| d.saturating_sub(origin));
        // The display time on the game's clock (tick 0 at the first sample, shifted by the
        // phase the first frame started with).
        let display = shown.map(|d| d.as_secs_f64() + first.as_secs_f64());
        let near = display.is_some_and(|t| {
            let k = jumps.partition_point(|&j| j < t - near_window);
            jumps.get(k).is_some_and(|&j| j <= t + near_window)
        });
        // The game time each mode draws, since tick 0.
        let offsets =
            DrawMode::ALL.map(|m| sim.world.tick() as f64 * dt + m.offset(ticks.alpha, dt, lead));
        // The body drawn: the first the game still shows (the target subject's shot may be
        // between shots, or hit and waiting for its despawn).
        let bodies = sim.world.bodies();
        let body = (0..bodies.len()).find(|&i| !hidden.contains(&bodies.ids()[i]));
        let mut record = FrameRecord {
            wall: wall.as_secs_f64(),
            shown: shown.map(|d| d.as_secs_f64()),
            delta: delta.as_secs_f64(),
            steps: ticks.steps,
            tick_before,
            tick_after: sim.world.tick(),
            alpha: ticks.alpha,
            drift,
            dropped: sim.clock.dropped().as_secs_f64(),
            drawn: [DVec3::ZERO; DrawMode::COUNT],
            // The game time drawn, on the wall clock (less the first frame's phase), so that
            // display time minus it is how old what is shown is.
            drawn_time: offsets.map(|t| t - first.as_secs_f64()),
            inside: [0.0; DrawMode::COUNT],
            exact: None,
            near,
        };
        if let Some(i) = body {
            let (id, cur) = (bodies.ids()[i], bodies.state(i));
            let v = cur.mv / bodies.masses()[i];
            let r = bodies.radii()[i];
            let prev = before
                .prev
                .iter()
                .find(|(p, _)| *p == id)
                .map_or(cur.p, |(_, s)| s.p);
            record.exact = display.and_then(|t| match subject {
                // Shot j is body j - 1 (the scene has none; spawns number from 0).
                Subject::Target => Some(Subject::shot_at(config.rate, id.0 + 1, t)),
                _ => {
                    let of = (&forces, *start.first()?, mass);
                    subject.exact(config.rate, of, t)
                }
            });
            record.drawn = DrawMode::ALL.map(|m| match m {
                DrawMode::Swept => {
                    let tau = m.offset(ticks.alpha, dt, lead);
                    swept_position_at(&sim.world, at_targets, r, (cur.p, v), tau)
                }
                m => m.position(prev, cur.p, v, ticks.alpha, dt, lead),
            });
            record.inside = std::array::from_fn(|k| {
                let p = record.drawn[k];
                let surface = sim.world.contacts().penetration(p, r);
                surface.max(subject.inside_target(r, p, offsets[k]))
            });
        }
        records.push(record);
    }
    Ok(Metrics::of(&records, sim.clock.dropped().as_secs_f64()))
}
