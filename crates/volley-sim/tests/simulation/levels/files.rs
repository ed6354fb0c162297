//! Level files in scenes: the OBJ and glTF readers agree, errors name the file, a scene with
//! levels writes back to itself, and a recording refuses a changed level.

use std::io::Cursor;

use volley_sim::internals::replay::{FlushPolicy, Recording, ReplayError};
use volley_sim::internals::scene;
use volley_sim::{RecordOptions, Recorder, SimLoop, World};

use super::load;

#[test]
fn the_plate_reads_the_same_from_obj_and_from_gltf() {
    let obj = load("hard/plate_bullet");
    let gltf = load("hard/grazing");
    let (a, b) = (&obj.meshes()[0].geometry, &gltf.meshes()[0].geometry);
    assert_eq!(a.vertices.len(), 8);
    assert_eq!((a.degenerate, b.degenerate), (0, 0));
    // tobj numbers the vertices in the order faces first use them, glTF keeps the file's: the
    // same triangles as corner points. glTF's y-up (x, z, -y) reads back to z-up to f32's
    // rounding of 0.005 (2e-10).
    let corners = |g: &volley_sim::MeshGeometry| -> Vec<[glam::DVec3; 3]> {
        g.triangles
            .iter()
            .map(|t| t.map(|i| g.vertices[i as usize]))
            .collect()
    };
    let (ta, tb) = (corners(a), corners(b));
    assert_eq!(ta.len(), 12);
    assert_eq!(tb.len(), 12);
    for t in &ta {
        let same = |u: &[glam::DVec3; 3]| (0..3).all(|k| (t[k] - u[k]).length() < 1e-9);
        assert!(tb.iter().any(same), "{t:?} is not in the glTF");
    }
}

#[test]
fn a_bad_level_file_is_one_line_naming_the_scene_the_field_and_the_file() {
    let dir = std::env::temp_dir().join(format!("volley-levels-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene_file = dir.join("s.ron");
    let cases = [
        (
            "missing.obj",
            None,
            "meshes[0].file: missing.obj: cannot read",
        ),
        (
            "bad.obj",
            Some(&b"v 0 0 0\nf 1 2 3\n"[..]),
            "meshes[0].file: bad.obj: ",
        ),
        (
            "bad.glb",
            Some(&b"glTF\x02\0\0\0"[..]),
            "meshes[0].file: bad.glb: not a readable glTF",
        ),
        (
            "mesh.stl",
            Some(&b"solid"[..]),
            "meshes[0].file: mesh.stl: expected a .obj, .gltf or .glb file",
        ),
    ];
    for (file, bytes, expected) in cases {
        if let Some(b) = bytes {
            std::fs::write(dir.join(file), b).unwrap();
        }
        let text =
            format!("Scene(dt: 0.01, integrator: Rk4, meshes: [(name: \"m\", file: \"{file}\")])");
        std::fs::write(&scene_file, &text).unwrap();
        let e = scene::load(&scene_file).unwrap_err().to_string();
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.starts_with(&scene_file.display().to_string()), "{e}");
        assert!(e.contains(expected), "{e}\nexpected: {expected}");
    }
    let png = scene::write_heightmap_png(2, 2, |_, _| 0);
    std::fs::write(dir.join("h.png"), &png[..png.len() / 2]).unwrap();
    let text = "Scene(dt: 0.01, integrator: Rk4, heightfields: [(name: \"h\", png: \"h.png\", cell_size: 1.0)])";
    std::fs::write(&scene_file, text).unwrap();
    let e = scene::load(&scene_file).unwrap_err().to_string();
    assert!(
        e.contains("heightfields[0].png: h.png: not a readable PNG"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_level_scene_writes_back_to_itself_and_steps_to_the_same_bits() {
    for name in [
        "hard/plate_bullet",
        "hard/grazing",
        "hard/edge_vertex",
        "hard/hill",
        "hard/grenade_corner",
        "hard/tick_boundary",
        "hard/slope",
    ] {
        let s = load(name);
        let file = volley_sim::internals::scene::BUNDLED
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap();
        let _ = file;
        let path = crate::support::ws(format!("assets/scenes/{name}.ron"));
        let back = scene::parse(&s.to_ron(), &path.display().to_string(), "back").unwrap();
        assert_eq!(back.meshes(), s.meshes(), "{name}");
        assert_eq!(back.heightfields(), s.heightfields(), "{name}");
        let (mut a, mut b) = (World::new(&s), World::new(&back));
        a.step_ticks(60).unwrap();
        b.step_ticks(60).unwrap();
        assert_eq!(
            volley_sim::state_hash(&a),
            volley_sim::state_hash(&b),
            "{name}"
        );
    }
}

#[test]
fn a_recording_refuses_to_replay_against_a_changed_level() {
    let dir = std::env::temp_dir().join(format!("volley-level-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = crate::support::ws("assets/levels/plate.obj");
    std::fs::copy(&obj, dir.join("plate.obj")).unwrap();
    let text = "Scene(dt: 0.01, integrator: Rk4, duration: 0.1,
        meshes: [(name: \"plate\", file: \"plate.obj\", transform: (position: (5.0, 0.0, 0.0)))],
        bodies: [(mass: 1.0, radius: 0.1, position: (0.0, 0.0, 0.0), launch: Velocity((100.0, 0.0, 0.0)))])";
    let scene_file = dir.join("level.ron");
    std::fs::write(&scene_file, text).unwrap();
    let scene = scene::load(&scene_file).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    let options = RecordOptions {
        hash_every: 1,
        keyframe_every: 0,
        flush: FlushPolicy::OnFinish,
        scene_file: scene_file.display().to_string(),
    };
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options).unwrap();
    let mut clock = volley_sim::internals::clock::VirtualClock::Steady(scene.timestep());
    sim.run_until(10, &mut clock, &mut recorder).unwrap();
    let bytes = recorder.finish(&sim.world).unwrap().0;
    let open = || Recording::from_reader(Cursor::new(bytes.clone()), "level.vrec").unwrap();
    // The same level: the embedded scene reads, with the recorded hash.
    assert_eq!(open().scene().unwrap().meshes(), scene.meshes());
    // A changed level: refused, naming the file.
    let mut changed = std::fs::read_to_string(dir.join("plate.obj")).unwrap();
    changed = changed.replace("v 0.005 ", "v 0.006 ");
    std::fs::write(dir.join("plate.obj"), changed).unwrap();
    let e: ReplayError = open().scene().unwrap_err();
    let e = e.to_string();
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.contains("the level file plate.obj changed since the recording"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
