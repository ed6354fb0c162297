//! "Save setup": the window's setup as a scene file that `volley headless FILE` and
//! `volley window FILE` open to the same state (the same hash after N ticks; the same lanes).

use crate::support;

use std::time::Duration;

use volley::app::session::Session;
use volley::hash::{hex, state_hash};
use volley::{Command, Integrator, World, scene};

const TICKS: u64 = 80;

#[test]
fn a_saved_setup_steps_to_the_same_hash_headless_as_the_setup_it_was_saved_from() {
    let dir = support::scratch_dir("a_saved_setup_steps_to_the_same_hash");
    let path = support::crate_path("assets/scenes/seed.ron");
    let original = scene::load(&path).unwrap();
    let mut s = Session::new(original.clone(), &path, Vec::new());
    // The user's setup: a finer step, RK4, a new launch.
    s.set_dt(0.05).unwrap();
    s.push(Command::SetIntegrator(Integrator::Rk4));
    s.push(Command::SetLaunch {
        speed: Some(25.0),
        elevation_deg: Some(60.0),
        azimuth_deg: Some(5.0),
        position: None,
    });
    s.single_step();
    s.frame(Duration::from_millis(10));
    let file = s.save_setup(&dir).unwrap();

    // The same setup made by hand from the original scene.
    let mut expect = original;
    expect.set_dt(0.05).unwrap();
    expect.set_integrator(Integrator::Rk4).unwrap();
    expect.launcher.speed = 25.0;
    expect.launcher.elevation_deg = 60.0;
    expect.launcher.azimuth_deg = 5.0;
    let mut by_hand = World::new(&expect);
    by_hand.step_ticks(TICKS).unwrap();
    // Fire from the saved launcher too, so the launcher is part of what is compared.
    by_hand.apply(&Command::Fire).unwrap();
    by_hand.step_ticks(TICKS).unwrap();

    let saved = scene::load(&file).unwrap();
    let mut reopened = World::new(&saved);
    reopened.step_ticks(TICKS).unwrap();
    reopened.apply(&Command::Fire).unwrap();
    reopened.step_ticks(TICKS).unwrap();
    assert_eq!(state_hash(&reopened), state_hash(&by_hand));

    // And `volley headless FILE` reaches the same hash (without the fire: its own run).
    let mut plain = World::new(&expect);
    plain.step_ticks(TICKS).unwrap();
    let want = hex(state_hash(&plain));
    let ticks = TICKS.to_string();
    let out = support::volley_output(
        &[
            "headless",
            file.to_str().unwrap(),
            "--ticks",
            &ticks,
            "--no-table",
            "--expect-hash",
            &want,
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_saved_compare_setup_opens_the_window_in_its_lanes() {
    let test = "a_saved_compare_setup_opens_the_window_in_its_lanes";
    let dir = support::scratch_dir(test);
    let path = support::crate_path("assets/scenes/drag.ron");
    let lanes = vec![
        Integrator::ExplicitEuler,
        Integrator::Midpoint,
        Integrator::Rk4,
    ];
    let s = Session::new(scene::load(&path).unwrap(), &path, lanes);
    let file = s.save_setup(&dir).unwrap();
    assert_eq!(scene::load(&file).unwrap().compare, s.compare());
    let args = [
        "window",
        file.to_str().unwrap(),
        "--exit-after-frames",
        "3",
        "--no-watch",
    ];
    let Some(out) = crate::window_smoke::under_xvfb(test, &args) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let opened: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("lane "))
        .map(|l| l.split(':').next().unwrap())
        .collect();
    assert_eq!(opened, ["explicit-euler", "midpoint", "rk4"], "{stdout}");
}
