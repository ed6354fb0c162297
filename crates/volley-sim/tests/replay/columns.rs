//! One list of per-body columns (`body::COLUMNS`) drives the state hash, the keyframe codec and
//! the replay's field diff: changing any one column of one body changes exactly what the list
//! says (the hash for the first `HASHED_COLUMNS`, the diff by the column's name, the keyframe's
//! bytes always), and a keyframe round trip gives every column back.

use volley_sim::internals::body::{COLUMNS, HASHED_COLUMNS};
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::hash::state_hash;
use volley_sim::internals::replay::diff::diff;
use volley_sim::internals::replay::format::{CRC_LEN, HEAD_LEN};
use volley_sim::internals::replay::keyframe::{decode_keyframe, encode_keyframe};
use volley_sim::{SimLoop, World};

fn world() -> World {
    let scene = crate::replay_support::coverage_scene();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.run_until(30, &mut VirtualClock::display(60.0), &mut ())
        .unwrap();
    assert!(sim.world.bodies().len() >= 2);
    sim.world
}

fn keyframe_bytes(world: &World) -> Vec<u8> {
    let mut out = Vec::new();
    encode_keyframe(&mut out, &world.snapshot()).unwrap();
    out
}

#[test]
fn names_are_unique_and_the_hashed_ones_come_first() {
    let names: Vec<_> = COLUMNS.iter().map(|c| c.name).collect();
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len(), "{names:?}");
    assert!(HASHED_COLUMNS <= COLUMNS.len());
    assert_eq!(
        &names[..HASHED_COLUMNS],
        [
            "p.x", "p.y", "p.z", "mV.x", "mV.y", "mV.z", "mass", "radius"
        ]
    );
}

#[test]
fn each_column_reaches_the_hash_the_keyframe_and_the_diff_as_listed() {
    let base = world();
    let (hash, bytes) = (state_hash(&base), keyframe_bytes(&base));
    for (k, column) in COLUMNS.iter().enumerate() {
        let mut state = base.snapshot();
        let value = &mut column.get_mut(&mut state.bodies)[1];
        *value = if *value == 0.0 { 0.25 } else { *value * 1.5 };
        let mut changed = base.clone();
        changed.restore(&state).unwrap();
        assert_eq!(
            state_hash(&changed) != hash,
            k < HASHED_COLUMNS,
            "{}: hashed only if listed as hashed",
            column.name
        );
        assert_ne!(keyframe_bytes(&changed), bytes, "{}: stored", column.name);
        let found = diff(&base.snapshot(), &changed.snapshot());
        assert_eq!(found.len(), 1, "{}: {found:?}", column.name);
        assert_eq!(found[0].field, column.name);
        assert_eq!(found[0].body, Some(base.bodies().ids()[1]));
    }
}

#[test]
fn a_keyframe_round_trip_gives_every_column_back() {
    let w = world();
    let bytes = keyframe_bytes(&w);
    let payload = &bytes[HEAD_LEN..bytes.len() - CRC_LEN];
    let mut decoded = World::new(w.scene()).snapshot();
    decode_keyframe(payload, w.scene().forces(), &mut decoded).unwrap();
    assert_eq!(decoded, w.snapshot());
    for column in &COLUMNS {
        assert_eq!(
            column.get(&decoded.bodies),
            column.get(w.bodies()),
            "{}",
            column.name
        );
    }
}
