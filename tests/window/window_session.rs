//! The window's simulations without a window: lanes, commands, restarts, hot reload.

use crate::support;

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
    assert_eq!(world.time(), world.scene().start_time() + 2.0 * 0.05);
    assert!(session.set_dt(-1.0).is_err(), "a negative step is refused");
}

#[test]
fn commands_pushed_while_paused_wait_for_the_next_tick() {
    let mut session = seed();
    session.set_paused(true);
    session.push(Command::Fire).unwrap();
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
    session
        .push(Command::SetIntegrator(Integrator::Rk4))
        .unwrap();
    session.frame(FRAME);
    session.frame(FRAME);
    assert_eq!(session.world().integrator(), Integrator::Rk4);
    session.set_dt(0.1).unwrap();
    assert_eq!(session.world().integrator(), Integrator::Rk4);
}

/// The reference's stiff spring: k/m = 1e4 at h = 1/60 (w h = 1.667); explicit Euler's energy
/// passes 10 times its start within a few steps, semi-implicit Euler stays bounded (w h < 2).
fn stiff_spring() -> scene::Scene {
    let text = "Scene(dt: 0.0166666667, integrator: ExplicitEuler,
        forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
        bodies: [(mass: 1, position: (0.1, 0, 0))])";
    scene::parse(text, "stiff.ron", "stiff").unwrap()
}

/// Where the stiff spring diverges, from the library alone.
fn stiff_divergence() -> volley::Divergence {
    let mut world = volley::World::new(&stiff_spring());
    (0..100).find_map(|_| world.step().err()).unwrap()
}

#[test]
fn a_divergence_stops_its_lane_pauses_every_clock_and_names_tick_and_body() {
    let expected = stiff_divergence();
    let mut session = Session::new(stiff_spring(), Path::new("stiff.ron"), Vec::new());
    session.frame(FRAME);
    assert_eq!(session.lanes()[0].stopped, Some(expected));
    assert_eq!(session.world().divergence(), Some(expected));
    assert_eq!(
        session.world().tick(),
        expected.tick,
        "the bad state stays on screen"
    );
    assert!(session.is_paused() && session.paused_by_alarm());
    session.set_paused(false);
    session.frame(FRAME);
    assert_eq!(
        session.world().tick(),
        expected.tick,
        "a stopped lane does not step"
    );
}

#[test]
fn reset_after_a_divergence_is_a_reset_command_the_tick_keeps_counting_and_the_clock_resumes() {
    let d = stiff_divergence();
    let mut session = Session::new(stiff_spring(), Path::new("stiff.ron"), Vec::new());
    session.frame(FRAME);
    session.reset().unwrap();
    assert!(!session.is_paused(), "the pause the divergence caused ends");
    assert!(session.lanes()[0].stopped.is_none());
    session.frame(FRAME);
    // The reset put the body back at its start at tick d.tick (under a new id: ids are never
    // reused); the spring is autonomous, so it diverges again after as many steps, with the
    // same energy.
    let again = session.lanes()[0].stopped.expect("it diverges again");
    let body = session.world().bodies().ids()[0];
    assert_ne!(body, d.body);
    assert_eq!(
        again,
        volley::Divergence {
            tick: 2 * d.tick,
            body,
            ..d
        }
    );
    assert_eq!(session.lanes()[0].history.commands_applied(), 1);
}

#[test]
fn a_reset_while_the_user_pauses_waits_for_the_next_tick_without_a_new_alarm() {
    let d = stiff_divergence();
    let mut session = Session::new(stiff_spring(), Path::new("stiff.ron"), Vec::new());
    session.frame(FRAME);
    session.set_paused(true);
    session.reset().unwrap();
    session.frame(FRAME);
    assert!(session.is_paused() && !session.paused_by_alarm());
    assert!(
        session.lanes()[0].stopped.is_none(),
        "the reset waits, not a new divergence"
    );
    assert_eq!(session.lanes()[0].pending(), 1);
    session.single_step();
    session.frame(FRAME);
    assert_eq!(session.world().tick(), d.tick + 1);
    assert_eq!(session.world().divergence(), None);
}

#[test]
fn in_compare_mode_reset_after_a_divergence_restarts_every_lane_at_tick_0() {
    let compared = vec![Integrator::ExplicitEuler, Integrator::SemiImplicitEuler];
    let mut session = Session::new(stiff_spring(), Path::new("stiff.ron"), compared);
    session.frame(FRAME);
    let lanes = session.lanes();
    assert_eq!(lanes[0].stopped, Some(stiff_divergence()));
    assert!(
        lanes[1].stopped.is_none(),
        "semi-implicit Euler is stable at w h = 1.667"
    );
    // The stable lane ran its whole frame before the pause (100 ms of 16.666667 ms ticks).
    let ticks = FRAME.as_nanos() / stiff_spring().timestep().as_nanos();
    assert_eq!(u128::from(lanes[1].sim.world.tick()), ticks);
    assert!(session.is_paused());
    session.reset().unwrap();
    assert!(
        session
            .lanes()
            .iter()
            .all(|l| l.sim.world.tick() == 0 && l.stopped.is_none())
    );
    assert!(!session.is_paused());
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

#[test]
fn the_panel_ticks_the_integrators_compare_mode_runs() {
    // `--compare explicit-euler,rk4` must show those two ticked, not the default four.
    let path = support::crate_path("assets/scenes/seed.ron");
    let compared = vec![Integrator::ExplicitEuler, Integrator::Rk4];
    let session = Session::new(scene::load(&path).unwrap(), &path, compared.clone());
    let panel = volley::app::panel::PanelState::new(&session, Vec::new());
    assert_eq!(panel.compare_pick, compared);
    let panel = volley::app::panel::PanelState::new(&seed(), Vec::new());
    assert_eq!(
        panel.compare_pick,
        volley::app::input::DEFAULT_COMPARE.to_vec()
    );
}
