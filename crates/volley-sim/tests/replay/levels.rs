//! The level golden recording (tests/data/levels_golden.vrec): a scene with every kind of level
//! surface (tests/data/levels_scene.ron), recorded for 300 ticks with a keyframe every 50,
//! verified tick by tick, its final hash pinned. A change to level contact that alters results
//! fails here, naming the first divergent tick; if it is intended, regenerate with
//! `VOLLEY_WRITE_GOLDEN=1 cargo test -p volley-sim --test replay level_golden` and update
//! [`LEVEL_GOLDEN_FINAL_HASH`] in the same commit.

use std::io::Cursor;

use volley_sim::internals::hash::hex;
use volley_sim::internals::replay::FlushPolicy;
use volley_sim::internals::scene;
use volley_sim::{RecordOptions, Recorder, Recording, Replay, SimLoop, World, state_hash};

use crate::support::ws;

/// The final state hash of the level golden recording, at tick 300.
const LEVEL_GOLDEN_FINAL_HASH: &str = "0x9e55116e738644b6";

fn record() -> Vec<u8> {
    let scene = scene::load(&ws("tests/data/levels_scene.ron")).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    let options = RecordOptions {
        hash_every: 1,
        keyframe_every: 50,
        flush: FlushPolicy::OnFinish,
        scene_file: "tests/data/levels_scene.ron".into(),
    };
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options).unwrap();
    let mut clock = volley_sim::internals::clock::VirtualClock::Steady(scene.timestep());
    sim.run_until(300, &mut clock, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap().0
}

#[test]
fn the_level_golden_recording_verifies_every_tick_and_its_final_hash_is_pinned() {
    let path = ws("tests/data/levels_golden.vrec");
    if std::env::var("VOLLEY_WRITE_GOLDEN").is_ok() {
        std::fs::write(&path, record()).unwrap();
    }
    let bytes = std::fs::read(&path).unwrap();
    let recording = Recording::from_reader(Cursor::new(bytes), "levels_golden.vrec").unwrap();
    // The header keeps the three level files' hashes (the inline ramp is in the source).
    let files: Vec<&str> = recording
        .header()
        .levels
        .iter()
        .map(|l| l.file.as_str())
        .collect();
    assert_eq!(
        files,
        [
            "../../assets/levels/corner.obj",
            "../../assets/levels/plate.gltf",
            "../../assets/levels/hill.png"
        ]
    );
    let mut replay = Replay::start(recording, None).unwrap();
    replay.run_to(u64::MAX, &mut ()).unwrap();
    assert!(replay.first_divergence().is_none(), "diverged");
    assert_eq!(replay.hashes_checked(), 301);
    assert_eq!(replay.keyframes_checked(), 7);
    assert_eq!(hex(state_hash(replay.world())), LEVEL_GOLDEN_FINAL_HASH);
    // Recording again today gives the same file, byte for byte but the build's own header
    // fields: the same final hash.
    let again = Recording::from_reader(Cursor::new(record()), "again.vrec").unwrap();
    assert_eq!(
        again.footer().map(|f| hex(f.final_hash)).as_deref(),
        Some(LEVEL_GOLDEN_FINAL_HASH)
    );
}

#[test]
fn the_level_golden_scene_meets_every_kind_of_level_surface() {
    // What the golden covers: impacts on the corner, the plate and the inline ramp (meshes 0, 1
    // and 2) and on the hill's cells, and rests, within its 300 ticks.
    let scene = scene::load(&ws("tests/data/levels_scene.ron")).unwrap();
    let mut world = World::new(&scene);
    let (mut meshes, mut cells, mut rests) = ([0u32; 3], 0, 0);
    for _ in 0..300 {
        world.step_ticks(1).unwrap();
        for e in world.events() {
            match e.kind {
                volley_sim::EventKind::Impact {
                    surface: volley_sim::Surface::Mesh { surface, .. },
                    ..
                } => meshes[surface as usize] += 1,
                volley_sim::EventKind::Impact {
                    surface: volley_sim::Surface::Heightfield { .. },
                    ..
                } => cells += 1,
                volley_sim::EventKind::Rest { .. } => rests += 1,
                _ => {}
            }
        }
    }
    assert!(meshes.iter().all(|&n| n > 0), "mesh impacts {meshes:?}");
    assert!(
        cells > 0 && rests > 0,
        "{cells} cell impacts, {rests} rests"
    );
}
