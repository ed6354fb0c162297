//! Writes the generated part of the fuzz corpora into `DIR/<target>/`: the bundled scenes and
//! each one's saved setup (`Scene::to_ron`, with compare lanes), and recordings of the replay
//! tests' scene under every integrator, started mid-run, hashing every 3 ticks, ending in a
//! divergence and cut short. `scripts/fuzz` adds the files of assets/, tests/data/ and seeds/.
//!
//! `cargo run -p volley-fuzz --example seeds -- DIR`

use std::path::Path;

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::command::parse_script;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::replay::{FlushPolicy, RecordOptions, Recorder};
use volley_sim::internals::scene::{self, CompareLane, Scene};
use volley_sim::{SimLoop, World};

fn main() {
    let Some(dir) = std::env::args().nth(1) else {
        eprintln!("usage: seeds DIR");
        std::process::exit(2);
    };
    let dir = Path::new(&dir);
    let write = |target: &str, name: &str, bytes: &[u8]| {
        let sub = dir.join(target);
        std::fs::create_dir_all(&sub).expect("corpus directory");
        std::fs::write(sub.join(name), bytes).expect("corpus file");
    };
    for (name, _) in scene::BUNDLED {
        let s = scene::bundled(name).expect("a valid bundled scene");
        let s = s
            .edit()
            .compare(vec![
                CompareLane::of(s.integrator()),
                CompareLane {
                    integrator: Integrator::Rk4,
                    dt: Some(4.0 * s.dt()),
                    substeps: Some(2),
                },
            ])
            .build()
            .expect("lanes a bundled scene runs");
        write(
            "scene",
            &format!("saved-{}.ron", name.replace('/', "-")),
            s.to_ron().as_bytes(),
        );
    }
    let replay =
        scene::parse(volley_fuzz::COMMAND_SCENE, "replay_scene.ron", "replay").expect("valid");
    let commands = parse_script(
        include_str!("../../tests/data/replay_commands.txt"),
        "commands",
    )
    .expect("valid");
    for (k, integrator) in Integrator::ALL.iter().enumerate() {
        let mut s = replay.clone();
        if s.set_integrator(*integrator).is_err() {
            continue;
        }
        let file = record(&s, 0, 60 + 10 * k as u64, &commands, 1 + k as u64 % 3, 20);
        write("recording", &format!("{}.vrec", integrator.name()), &file);
    }
    let started = record(&replay, 50, 75, &commands, 1, 15);
    write("recording", "started-mid-run.vrec", &started);
    let stiff = scene::parse(
        "Scene(dt: 0.016666667, integrator: ExplicitEuler,
               forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
               bodies: [(mass: 1, position: (1, 0, 0))])",
        "stiff.ron",
        "stiff",
    )
    .expect("valid");
    write(
        "recording",
        "diverges.vrec",
        &record(&stiff, 0, 100, &[], 1, 5),
    );
    let mut cut = record(&replay, 0, 70, &commands, 1, 20);
    cut.truncate(cut.len() - 30);
    write("recording", "cut-short.vrec", &cut);
}

/// A recording of `scene` from tick `from` to `to`, with `commands`.
fn record(
    scene: &Scene,
    from: u64,
    to: u64,
    commands: &[volley_sim::internals::command::Stamped],
    hash_every: u64,
    keyframe_every: u64,
) -> Vec<u8> {
    let mut sim = SimLoop::new(World::new(scene));
    sim.schedule(commands.iter().copied());
    let mut source = VirtualClock::Steady(scene.timestep());
    let _ = sim.run_until(from, &mut source, &mut ());
    let options = RecordOptions {
        hash_every,
        keyframe_every,
        flush: FlushPolicy::OnFinish,
        scene_file: "seed.ron".into(),
    };
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options).expect("in memory");
    let _ = sim.run_until(to, &mut source, &mut recorder);
    recorder.finish(&sim.world).expect("in memory").0
}
