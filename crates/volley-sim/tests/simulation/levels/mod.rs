//! Level surfaces (issue 38): meshes and heightfields as scene surfaces, swept contact on the
//! curved sub-step path, and the hard cases 17 to 23 of docs/physics.md, one bundled scene each
//! under `assets/scenes/hard/`. Expected times come from closed forms where the integrator is
//! exact under the scene's force (each test says which), and from a converged run (the same
//! scene at a finer step) elsewhere.

mod corner;
mod files;
mod flat;
mod hashes;
mod plate;
mod shots;
mod terrain;

use volley_sim::internals::clock::VirtualClock;
use volley_sim::{Event, EventKind, Integrator, Scene, SimLoop, Surface, World};

pub use crate::hard_cases::{allowed, load, with};

/// Every event of `ticks` ticks of `scene`, and the world after them.
pub fn events(scene: &Scene, ticks: u64) -> (Vec<Event>, World) {
    let mut sim = SimLoop::new(World::new(scene));
    let mut out = Vec::new();
    for _ in 0..ticks {
        sim.run_until(
            sim.world.tick() + 1,
            &mut VirtualClock::Steady(scene.timestep()),
            &mut (),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", scene.name()));
        out.extend_from_slice(sim.world.events());
    }
    (out, sim.world)
}

/// The impacts of body `body` as `(time, surface, normal speed)`.
pub fn impacts(events: &[Event], body: u32) -> Vec<(f64, Surface, f64)> {
    events
        .iter()
        .filter(|e| e.body.0 == u64::from(body))
        .filter_map(|e| match e.kind {
            EventKind::Impact {
                surface,
                normal_speed,
                ..
            } => Some((e.time, surface, normal_speed)),
            _ => None,
        })
        .collect()
}

/// The integrators the plate and grazing cases check against their closed form: every one,
/// since x is linear in time under gravity along z for all of them.
pub fn every(scene: &Scene) -> Vec<Integrator> {
    allowed(scene)
}
