//! The window's simulations without a window: lanes, commands, restarts, hot reload.

mod support;

use std::path::Path;
use std::time::{Duration, Instant};

use volley::app::session::Session;
use volley::app::watch::SceneWatch;
use volley::{Command, Integrator, scene};

fn seed() -> Session {
    let path = support::crate_path("assets/scenes/seed.ron");
    Session::new(scene::load(&path).unwrap(), &path, Vec::new())
}

const FRAME: Duration = Duration::from_millis(100);

#[test]
fn compare_mode_drives_one_world_per_integrator_with_the_same_frames() {
    let path = support::crate_path("assets/scenes/seed.ron");
    let compared = vec![Integrator::ExplicitEuler, Integrator::SemiImplicitEuler];
    let mut session = Session::new(scene::load(&path).unwrap(), &path, compared.clone());
    for _ in 0..7 {
        session.frame(FRAME);
    }
    let lanes = session.lanes();
    let integrators: Vec<_> = lanes.iter().map(|l| l.sim.world.integrator()).collect();
    assert_eq!(integrators, compared);
    // 700 ms of frames at h = 0.2 s is 3 ticks in both, with the same 0.5 tick left over.
    assert!(lanes.iter().all(|l| l.sim.world.tick() == 3));
    assert!(lanes.iter().all(|l| l.sim.clock.alpha() == 0.5));
    // Explicit Euler ends high, semi-implicit low: the same launch, two different states.
    let z: Vec<f64> = lanes
        .iter()
        .map(|l| l.sim.world.bodies().positions().get(0).z)
        .collect();
    assert!(z[0] > z[1], "explicit {} vs semi-implicit {}", z[0], z[1]);
}

#[test]
fn changing_dt_restarts_at_tick_0_with_the_new_step() {
    let mut session = seed();
    for _ in 0..5 {
        session.frame(FRAME);
    }
    assert!(session.world().tick() > 0);
    session.set_dt(0.05).unwrap();
    assert_eq!(session.world().tick(), 0);
    session.frame(FRAME);
    let world = session.world();
    assert_eq!(world.tick(), 2);
    assert_eq!(world.time(), world.scene().start_time + 2.0 * 0.05);
    assert!(session.set_dt(-1.0).is_err(), "a negative step is refused");
}

#[test]
fn commands_pushed_while_paused_wait_for_the_next_tick() {
    let mut session = seed();
    session.set_paused(true);
    session.push(Command::Fire);
    session.frame(FRAME);
    assert_eq!(session.world().bodies().len(), 1);
    assert_eq!(session.lanes()[0].pending(), 1);
    session.single_step();
    session.frame(FRAME);
    assert_eq!(session.world().tick(), 1);
    assert_eq!(session.world().bodies().len(), 2);
    assert_eq!(session.lanes()[0].pending(), 0);
}

#[test]
fn switching_the_integrator_goes_through_a_command_and_survives_a_dt_change() {
    let mut session = seed();
    session.push(Command::SetIntegrator(Integrator::Rk4));
    session.frame(FRAME);
    session.frame(FRAME);
    assert_eq!(session.world().integrator(), Integrator::Rk4);
    session.set_dt(0.1).unwrap();
    assert_eq!(session.world().integrator(), Integrator::Rk4);
}

#[test]
fn reset_after_a_divergence_restarts_at_tick_0() {
    // The reference's stiff spring: k/m = 1e4 at h = 1/60 (w h = 1.667); explicit Euler's
    // energy passes 10 times its start within a few steps.
    let text = "Scene(dt: 0.0166666667, integrator: ExplicitEuler,
        forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
        bodies: [(mass: 1, position: (0.1, 0, 0))])";
    let scene = scene::parse(text, "stiff.ron", "stiff").unwrap();
    let mut session = Session::new(scene, Path::new("stiff.ron"), Vec::new());
    for _ in 0..20 {
        session.frame(FRAME);
    }
    let stopped = session.lanes()[0].stopped.clone();
    assert!(
        stopped.is_some_and(|s| s.contains("diverged")),
        "the run diverged"
    );
    let tick = session.world().tick();
    session.frame(FRAME);
    assert_eq!(session.world().tick(), tick, "a stopped lane does not step");
    session.reset();
    assert_eq!(session.world().tick(), 0);
    assert!(session.lanes()[0].stopped.is_none());
}

#[test]
fn saving_the_scene_file_is_noticed() {
    let dir = support::scratch_dir("watch");
    let file = dir.join("scene.ron");
    std::fs::write(&file, "Scene(dt: 0.1, integrator: Rk4)").unwrap();
    let mut watch = SceneWatch::new(&file).unwrap();
    assert!(!watch.poll(Instant::now()), "nothing changed yet");
    std::fs::write(&file, "Scene(dt: 0.2, integrator: Rk4)").unwrap();
    // The watcher thread delivers the event asynchronously; wait for it (up to 10 s) rather
    // than assert on timing.
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut noticed = false;
    while !noticed && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
        // Polling as if the settle time had passed since the event.
        noticed = watch.poll(Instant::now() + 2 * volley::app::watch::SETTLE);
    }
    assert!(noticed, "the save was not noticed");
    std::fs::write(dir.join("other.ron"), "x").unwrap();
    std::thread::sleep(Duration::from_millis(200));
    assert!(
        !watch.poll(Instant::now() + 2 * volley::app::watch::SETTLE),
        "another file in the folder is not the scene"
    );
}

#[test]
fn every_shortcut_the_panel_lists_is_in_the_readme() {
    let readme = std::fs::read_to_string(support::crate_path("README.md")).unwrap();
    let rows: Vec<String> = readme.lines().map(|l| l.replace('`', "")).collect();
    let listed = volley::app::input::SHORTCUTS
        .iter()
        .chain(volley::app::input::MOUSE.iter());
    for (keys, what) in listed {
        let row = format!("| {keys} | {what} |");
        assert!(rows.contains(&row), "README lacks the row `{row}`");
    }
}
