//! A body that came to rest reports it once, not every time gravity presses it back onto the
//! surface (the seed scene's long runs printed "came to rest" every other tick).

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::scene;
use volley_sim::{EventKind, SimLoop, TickObserver, World};

/// Counts the rest events the loop produces.
#[derive(Default)]
struct Rests(usize);

impl TickObserver for Rests {
    fn after_tick(
        &mut self,
        world: &World,
    ) -> Result<(), volley_sim::internals::sim_loop::ObserverError> {
        let rests = world
            .events()
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Rest { .. }));
        self.0 += rests.count();
        Ok(())
    }
}

#[test]
fn the_seed_projectile_reports_coming_to_rest_once_in_a_long_run() {
    let scene = scene::load(&crate::support::ws("assets/scenes/seed.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    let mut rests = Rests::default();
    sim.run_until(
        5_000,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut rests,
    )
    .unwrap();
    assert_eq!(rests.0, 1);
    // Still resting: its centre one radius above the ground, to the few ulps the clamp onto the
    // surface leaves (the contact offset is formed as height + radius in f64).
    let b = sim.world.bodies();
    let r = b.radii()[0];
    assert!(
        (b.positions().z[0] - r).abs() <= 4.0 * f64::EPSILON * r,
        "{}",
        b.positions().z[0]
    );
}
