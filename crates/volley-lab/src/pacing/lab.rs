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

use volley_sim::internals::body::BodyState;
use volley_sim::internals::clock::LoopPolicy;
use volley_sim::internals::exact::closed_form;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::scene::{self, Scene};
use volley_sim::internals::sim_loop::{LoopError, SimLoop, TickObserver};
use volley_sim::internals::world::World;

pub use volley_sim::internals::draw::{DrawMode, LEAD_WINDOW, Lead};

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
}

impl Subject {
    /// Both subjects.
    pub const ALL: [Subject; 2] = [Subject::Orbit, Subject::Shot];

    /// The name the tables use.
    pub fn name(self) -> &'static str {
        match self {
            Subject::Orbit => "orbit",
            Subject::Shot => "shot",
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
        };
        let mut scene = scene::parse(&text, "pacing.ron", self.name())
            .expect("the loop lab's own scene text is valid");
        scene
            .set_integrator(integrator)
            .expect("every integrator runs the loop lab's subjects (a point mass, gravity)");
        scene
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

/// Keeps the state before the frame's last tick, as the window's renderer does.
struct Before {
    prev: Vec<BodyState>,
}

impl TickObserver for Before {
    fn before_last_tick(&mut self, world: &World) {
        self.prev.clear();
        self.prev
            .extend((0..world.bodies().len()).map(|i| world.bodies().state(i)));
    }
}

/// Runs `config` under `timing` and measures every draw mode.
pub fn run(config: &RunConfig, timing: &DisplayTiming) -> Result<Metrics, LoopError> {
    let scene = config.subject.scene(config.rate, config.integrator);
    let world = World::new(&scene);
    let start: Vec<BodyState> = (0..world.bodies().len())
        .map(|i| world.bodies().state(i))
        .collect();
    let masses: Vec<f64> = world.bodies().masses().to_vec();
    let forces = world.forces().clone();
    let mut sim = SimLoop::new(world);
    sim.clock.set_policy(config.policy);
    let dt = sim.world.dt();
    let timestep = sim.clock.timestep();
    let first =
        Duration::from_nanos((config.phase.clamp(0.0, 1.0) * timestep.as_nanos() as f64) as u64);
    let mut before = Before {
        prev: start.clone(),
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
        lead_of.push(delta);
        let lead = lead_of.get().as_secs_f64();
        let wall = present.sampled - origin;
        // Game time now: the ticks run plus what the accumulator holds, less the phase the
        // first frame was given, against the wall time since the first sample.
        let game = sim.clock.elapsed() + sim.clock.accumulator();
        let drift = game.as_secs_f64() - first.as_secs_f64() - wall.as_secs_f64();
        let body = 0;
        let cur = sim.world.bodies().state(body);
        let v = cur.mv / masses[body];
        let prev = before.prev.get(body).map_or(cur.p, |s| s.p);
        let shown = present.shown.map(|d| d.saturating_sub(origin));
        let exact = shown.and_then(|d| {
            // The exact position at the display time, on the game's clock (tick 0 at the first
            // sample, shifted by the phase the first frame started with).
            let t = d.as_secs_f64() + first.as_secs_f64();
            closed_form(&forces, start[body], masses[body], t).map(|s| s.p)
        });
        let drawn = DrawMode::ALL.map(|m| m.position(prev, cur.p, v, ticks.alpha, dt, lead));
        // The game time drawn, on the wall clock (less the first frame's phase), so that
        // display time minus it is how old what is shown is.
        let drawn_time = DrawMode::ALL.map(|m| {
            sim.world.tick() as f64 * dt + m.offset(ticks.alpha, dt, lead) - first.as_secs_f64()
        });
        records.push(FrameRecord {
            wall: wall.as_secs_f64(),
            shown: shown.map(|d| d.as_secs_f64()),
            delta: delta.as_secs_f64(),
            steps: ticks.steps,
            tick_before,
            tick_after: sim.world.tick(),
            alpha: ticks.alpha,
            drift,
            dropped: sim.clock.dropped().as_secs_f64(),
            drawn,
            drawn_time,
            exact,
        });
    }
    Ok(Metrics::of(&records, sim.clock.dropped().as_secs_f64()))
}
