//! The level scenes' pinned hashes: each bundled level scene stepped over its whole duration
//! under its own integrator ends on this state hash, here and in the wasm32 build (which steps
//! every bundled scene, tests/wasm32). A change to level contact that alters results fails here.

use volley_sim::internals::hash::hex;
use volley_sim::{World, state_hash};

use super::load;

/// `(scene, ticks, final hash)`, the ticks being the scene's duration.
const PINNED: [(&str, u64, &str); 8] = [
    ("hard/edge_vertex", 6, "0x2609b8237ff62640"),
    ("hard/grazing", 4, "0x6e704315a1baaa02"),
    ("hard/grenade_corner", 300, "0x6feaa727e0decd89"),
    ("hard/hill", 240, "0x472d1c6fb93d810c"),
    ("hard/plate_bullet", 7, "0x8ea315701a1a8e62"),
    ("hard/slope", 90, "0x62c6b4be9d304190"),
    ("hard/tick_boundary", 32, "0x098ca1facca23644"),
    ("range", 240, "0xd243c2cb4daaa46e"),
];

#[test]
fn every_level_scene_ends_on_its_pinned_hash() {
    let mut got = Vec::new();
    for (name, ticks, _) in PINNED {
        let scene = load(name);
        assert_eq!(
            scene.ticks_until(scene.start_time() + scene.duration()),
            ticks,
            "{name}"
        );
        let mut world = World::new(&scene);
        world.step_ticks(ticks).unwrap();
        got.push((name, ticks, hex(state_hash(&world))));
    }
    let expected: Vec<_> = PINNED
        .iter()
        .map(|(n, t, h)| (*n, *t, h.to_string()))
        .collect();
    assert_eq!(got, expected);
}
