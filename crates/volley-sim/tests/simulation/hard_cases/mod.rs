//! Thirteen of the hard cases of docs/physics.md ("Hard cases"; the fourteenth is `transonic.rs`), one scene each under `assets/scenes/hard/`, asserted for
//! every integrator: who stays bounded, who diverges, and when the guard catches it.
//!
//! Every expected number is derived in the test from the math of the case (growth factors of
//! the linear test equation, closed forms, the clock's documented rule), never copied from a run.

mod contact;
mod drag;
mod orbit;
mod precision;
mod stiff;
mod time;

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::scene::{self, Scene};
use volley_sim::internals::sim_loop::{ObserverError, TickObserver};
use volley_sim::{Integrator, LoopError, SimLoop, World};

/// A bundled scene by name (`hard/stiff_spring`).
pub fn load(name: &str) -> Scene {
    let path = format!("assets/scenes/{name}.ron");
    scene::load(&crate::support::ws(&path)).unwrap_or_else(|e| panic!("{e}"))
}

/// `scene` with `integrator` (the scene must allow it).
pub fn with(scene: &Scene, integrator: Integrator) -> Scene {
    let mut s = scene.clone();
    s.set_integrator(integrator)
        .unwrap_or_else(|e| panic!("{integrator}: {e}"));
    s
}

/// Every integrator `scene` allows.
pub fn allowed(scene: &Scene) -> Vec<Integrator> {
    Integrator::ALL
        .into_iter()
        .filter(|i| scene::check_integrator(*i, scene.forces()).is_ok())
        .collect()
}

/// Records body 0's energy and state after every tick, and every event.
#[derive(Default)]
pub struct Trace {
    /// Energy (J) of body 0 at tick 0, 1, 2, ...
    pub energy: Vec<f64>,
    /// Position (m) of body 0 at tick 0, 1, 2, ...
    pub p: Vec<glam::DVec3>,
    /// Velocity (m/s) of body 0 at tick 0, 1, 2, ...
    pub v: Vec<glam::DVec3>,
    /// Every event, in order.
    pub events: Vec<volley_sim::Event>,
}

impl Trace {
    fn push(&mut self, world: &World) {
        self.energy.push(world.energy_of(0));
        self.p.push(world.bodies().positions().get(0));
        self.v.push(world.velocity(0));
    }
}

impl TickObserver for Trace {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.push(world);
        self.events.extend_from_slice(world.events());
        Ok(())
    }
}

/// Runs `scene` for `ticks` through the ordinary loop (one tick per frame), tracing body 0.
pub fn run(scene: &Scene, ticks: u64) -> (Trace, Result<(), LoopError>, World) {
    let mut sim = SimLoop::new(World::new(scene));
    let mut trace = Trace::default();
    trace.push(&sim.world);
    let result = sim.run_until(
        ticks,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut trace,
    );
    (trace, result, sim.world)
}

/// The divergence a run stopped with, or a panic naming the integrator.
pub fn diverged(result: &Result<(), LoopError>, what: &str) -> volley_sim::Divergence {
    match result {
        Err(LoopError::Diverged(d)) => *d,
        other => panic!("{what}: expected a divergence, got {other:?}"),
    }
}

/// Smallest n with `growth^n > factor`: the tick at which energy growing by `growth` per step
/// passes `factor` times its start.
pub fn ticks_to_pass(growth: f64, factor: f64) -> u64 {
    (factor.ln() / growth.ln()).floor() as u64 + 1
}
