//! Parallel stepping: with `World::set_threads(n)` large worlds are split into contiguous chunks
//! stepped with `rayon::join`, and the result must not depend on `n` in any bit: the state
//! hash, the events and where a divergence is reported.
//!
//! Chunking starts at `2 * PARALLEL_MIN_CHUNK` bodies, so these worlds are a little larger than
//! three chunks (`3 * PARALLEL_MIN_CHUNK + 7`, not a multiple of anything): 2 threads split them
//! in two, 3 threads in three uneven chunks. The stepping runs inside a two-thread pool so the
//! chunks really run concurrently, whatever the machine's core count.

use glam::DVec3;
use volley_sim::internals::hash::state_hash;
use volley_sim::internals::scene::{self, BodySpec, Scene};
use volley_sim::internals::step::PARALLEL_MIN_CHUNK;
use volley_sim::{Event, Integrator, World};

const BODIES: u32 = 3 * PARALLEL_MIN_CHUNK as u32 + 7;

fn pool() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a two-thread pool")
}

fn scene(text: &str) -> Scene {
    scene::parse(text, "parallel.ron", "parallel").expect("the test scene is valid")
}

/// Gravity and drag (so every integrator takes its velocity-dependent path), no contacts.
fn free_flight(integrator: Integrator) -> Scene {
    let mut s = scene(&format!(
        "Scene(dt: 0.01, integrator: ExplicitEuler, seed: 3,
               forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag(0.2)],
               launcher: (position: (0.0, 0.0, 1.0), speed: 20.0, elevation_deg: 50.0, azimuth_deg: 0.0),
               volley: (count: {BODIES}, speed_spread: 5.0, angle_spread_deg: 20.0))"
    ));
    s.set_integrator(integrator)
        .expect("drag has a closed form");
    s
}

/// Steps a world of `scene` on `threads` threads; returns the hash after every tick and every
/// event, in order.
fn run(scene: &Scene, threads: usize, ticks: u64) -> (Vec<u64>, Vec<Event>) {
    pool().install(|| {
        let mut world = World::new(scene);
        world.set_threads(threads);
        let (mut hashes, mut events) = (Vec::new(), Vec::new());
        for _ in 0..ticks {
            world.step().expect("the test scenes do not diverge");
            hashes.push(state_hash(&world));
            events.extend_from_slice(world.events());
        }
        (hashes, events)
    })
}

#[test]
fn every_integrator_hashes_the_same_on_one_two_and_three_threads() {
    for integrator in Integrator::ALL {
        let scene = free_flight(integrator);
        let one = run(&scene, 1, 4);
        assert_eq!(run(&scene, 2, 4), one, "{integrator}, 2 threads");
        assert_eq!(run(&scene, 3, 4), one, "{integrator}, 3 threads");
    }
}

#[test]
fn contacts_and_events_are_the_same_on_one_two_and_three_threads() {
    // Launched low at a wall 3 m away, over the ground, through two targets: within 30 ticks
    // bodies in every chunk hit the wall and the ground and pass the targets.
    let scene = scene(&format!(
        "Scene(dt: 0.02, integrator: SemiImplicitEuler, seed: 5,
               forces: [Gravity((0.0, 0.0, -9.81))],
               ground: (height: 0.0, restitution: 0.6),
               walls: [(point: (3.0, 0.0, 0.0), normal: (1.0, 0.0, 0.0), thickness: 0.1)],
               targets: [(center: (1.5, 0.0, 1.0), radius: 0.4), (center: (2.0, 0.5, 0.5), radius: 0.3)],
               launcher: (position: (0.0, 0.0, 0.5), speed: 8.0, elevation_deg: 20.0, azimuth_deg: 0.0),
               volley: (count: {BODIES}, speed_spread: 3.0, angle_spread_deg: 25.0))"
    ));
    let one = run(&scene, 1, 30);
    let bodies_with_events = {
        let mut ids: Vec<_> = one.1.iter().map(|e| e.body).collect();
        ids.sort();
        ids.dedup();
        ids.len()
    };
    assert!(
        bodies_with_events > 2 * PARALLEL_MIN_CHUNK,
        "{bodies_with_events}"
    );
    assert_eq!(run(&scene, 2, 30), one, "2 threads");
    assert_eq!(run(&scene, 3, 30), one, "3 threads");
}

#[test]
fn a_divergence_in_a_later_chunk_names_the_same_tick_and_body() {
    // A stiff spring (w h = 10) makes explicit Euler grow every body by about 10x per step;
    // one body in the last chunk starts 1e290 m out and overflows first, the rest near 1 m.
    let scene = scene(
        "Scene(dt: 0.01, integrator: ExplicitEuler, guard: (every: 0),
               forces: [Spring(anchor: (0.0, 0.0, 0.0), stiffness: 1000000.0)],
               bodies: [(mass: 1.0, position: (1.0, 0.0, 0.0), launch: Velocity((0.0, 0.0, 0.0)))])",
    );
    let late = BODIES as usize - 5;
    let outcome = |threads: usize| {
        pool().install(|| {
            let mut world = World::new(&scene);
            world.set_threads(threads);
            for i in 1..BODIES as usize {
                let x = if i == late {
                    1e290
                } else {
                    1.0 + i as f64 * 1e-6
                };
                world.spawn(&BodySpec {
                    mass: 1.0,
                    radius: 0.0,
                    position: DVec3::new(x, 0.0, 0.0),
                    velocity: DVec3::ZERO,
                    spin: Default::default(),
                });
            }
            (0..100).find_map(|_| world.step().err())
        })
    };
    let one = outcome(1).expect("the far body overflows");
    assert_eq!(one.body.0, late as u64);
    assert_eq!(outcome(2), Some(one));
    assert_eq!(outcome(3), Some(one));
}
