//! A scene cannot change after it is checked: an edit goes through `Scene::edit`, which checks
//! the whole scene again and writes its text anew, so a recording embeds the scene that ran.
//! (Once, setting a built scene's ground restitution to 0.3 through a public field made a
//! recording whose replay parted from the run at tick 70, the first bounce.)

use glam::DVec3;
use volley_sim::{BodySpec, Ground, Integrator, Scene};

use crate::replay_support::{options, record, replay};

/// The case: a scene built in code, its ground made softer afterwards, recorded for
/// 300 ticks and replayed: every stored hash and keyframe equal, nothing parts.
#[test]
fn an_edited_scene_records_and_replays_with_no_divergence() {
    let built = Scene::builder("drop", 1.0 / 60.0)
        .integrator(Integrator::SemiImplicitEuler)
        .gravity(DVec3::new(0.0, 0.0, -9.81))
        .ground(Ground {
            height: 0.0,
            restitution: 0.8,
        })
        .body(BodySpec {
            mass: 1.0,
            radius: 0.1,
            position: DVec3::new(0.0, 0.0, 5.0),
            velocity: DVec3::new(1.0, 0.0, 0.0),
            spin: DVec3::ZERO,
        })
        .build()
        .unwrap();
    let softer = built
        .edit()
        .ground(Ground {
            height: 0.0,
            restitution: 0.3,
        })
        .build()
        .unwrap();
    assert_eq!(softer.ground().unwrap().restitution, 0.3);
    assert!(
        softer.source().contains("restitution: 0.3"),
        "{}",
        softer.source()
    );
    let bytes = record(&softer, 300, &[], options(1, 50));
    let replay = replay(&bytes, None);
    assert!(
        replay.first_divergence().is_none(),
        "{:?}",
        replay.first_divergence()
    );
    assert_eq!(replay.world().tick(), 300);
    // Every tick's hash, tick 0's included.
    assert_eq!(replay.hashes_checked(), 301);
    // The two runs differ (the edit took effect): the built scene's replay of its own
    // recording ends on another hash.
    let original = replay_support_hash(&record(&built, 300, &[], options(1, 50)));
    assert_ne!(original, volley_sim::state_hash(replay.world()));
}

fn replay_support_hash(bytes: &[u8]) -> u64 {
    volley_sim::state_hash(replay(bytes, None).world())
}

/// An edit is checked as a whole, as a file is: a bad value names the field, and the scene it
/// came from is untouched.
#[test]
fn an_edit_is_checked_as_a_file_is() {
    let bounce = volley_sim::bundled_scene("bounce").unwrap();
    let err = bounce
        .edit()
        .ground(Ground {
            height: 0.0,
            restitution: 1.5,
        })
        .build()
        .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("ground.restitution"), "{err}");
    assert_eq!(bounce.ground().unwrap().restitution, 0.8);
}

/// An edit of a scene read from a file finds the level files its text names where the file
/// found them (beside it), not beside the working folder.
#[test]
fn an_edit_of_a_scene_with_its_own_level_file_finds_the_file_again() {
    let dir = std::env::temp_dir().join(format!("volley-edit-level-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let plate = crate::support::ws("assets/levels/plate.obj");
    std::fs::copy(&plate, dir.join("my_plate.obj")).unwrap();
    let scene_file = dir.join("range.ron");
    std::fs::write(
        &scene_file,
        "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81))],
               meshes: [(name: \"plate\", file: \"my_plate.obj\", restitution: 0.2)],
               bodies: [(mass: 1, position: (0, 0, 3))])",
    )
    .unwrap();
    let scene = volley_sim::load_scene(&scene_file).unwrap();
    let edited = scene
        .edit()
        .ground(Ground {
            height: -5.0,
            restitution: 0.5,
        })
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(edited.meshes(), scene.meshes());
    let _ = std::fs::remove_dir_all(&dir);
}
