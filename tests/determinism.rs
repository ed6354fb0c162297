//! Determinism pins: these tests run in the dev profile *and* in release (`scripts/test`), so
//! passing both means both profiles produce the same bits.

use std::path::Path;

use volley::clock::VirtualClock;
use volley::hash::{hex, state_hash};
use volley::{SimLoop, World, scene};

/// The seed scene after its 27 ticks (t = 5.0 to 10.4). A physics change that alters any bit of
/// the result must update this on purpose.
const SEED_HASH_AT_27: &str = "0xe02a9ef4a1ddb321";

#[test]
fn seed_scene_hash_is_pinned() {
    let scene = scene::load(Path::new("assets/scenes/seed.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.run_until(27, &mut VirtualClock::Steady(scene.timestep), &mut ())
        .unwrap();
    assert_eq!(hex(state_hash(&sim.world)), SEED_HASH_AT_27);
}
