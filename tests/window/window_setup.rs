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
    s.push(Command::SetIntegrator(Integrator::Rk4)).unwrap();
    s.push(Command::SetLaunch {
        speed: Some(25.0),
        elevation_deg: Some(60.0),
        azimuth_deg: Some(5.0),
        position: None,
    })
    .unwrap();
    s.single_step();
    s.frame(Duration::from_millis(10));
    let file = s.save_setup(&dir).unwrap();

    // The same setup made by hand from the original scene.
    let launcher = volley::Launcher {
        speed: 25.0,
        elevation_deg: 60.0,
        azimuth_deg: 5.0,
        ..original.launcher()
    };
    let mut expect = original.edit().launcher(launcher).build().unwrap();
    expect.set_dt(0.05).unwrap();
    expect.set_integrator(Integrator::Rk4).unwrap();
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
    assert_eq!(scene::load(&file).unwrap().compare(), s.compare_lanes());
    let args = [
        "window",
        file.to_str().unwrap(),
        "--exit-after-frames",
        "3",
        "--no-watch",
    ];
    let Some(stdout) = crate::window_smoke::window_stdout(test, &args, "640x400") else {
        return;
    };
    let opened: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("lane "))
        .map(|l| l.split(':').next().unwrap())
        .collect();
    assert_eq!(opened, ["explicit-euler", "midpoint", "rk4"], "{stdout}");
}

#[test]
fn the_camera_ray_through_a_pixel_projects_back_onto_that_pixel() {
    use volley::render::{OrbitCamera, SceneBounds, Viewport};
    let path = support::crate_path("assets/scenes/seed.ron");
    let bounds = SceneBounds::of_scene(&scene::load(&path).unwrap());
    let camera = OrbitCamera::framing(&bounds, 1.6);
    let viewport = Viewport {
        x: 340.0,
        y: 0.0,
        width: 940.0,
        height: 560.0,
    };
    for px in [
        glam::Vec2::new(400.0, 50.0),
        glam::Vec2::new(810.0, 280.0),
        glam::Vec2::new(1200.0, 500.0),
    ] {
        let (origin, dir) = camera.ray(px, &viewport);
        for t in [1.0, 30.0, 200.0] {
            let back = camera.project(origin + t * dir, &viewport).unwrap();
            // f32 matrices over a scene some 100 m across: a few hundredths of a pixel.
            assert!(back.distance(px) < 5e-2, "{px} -> {back} at {t}");
        }
    }
}

/// The value after `label` on the line starting with `prefix` in the window's report.
fn after<'a>(report: &'a str, prefix: &str, label: &str) -> &'a str {
    let line = report
        .lines()
        .find(|l| l.trim_start().starts_with(prefix))
        .unwrap_or_else(|| panic!("{report}"));
    line.split(label).nth(1).unwrap_or_else(|| panic!("{line}"))
}

fn triple(text: &str) -> [f64; 3] {
    let inner = text.trim_start_matches('(').split(')').next().unwrap();
    let v: Vec<f64> = inner
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

#[test]
fn a_script_drags_the_launcher_its_handle_and_a_target_then_aims_and_hits() {
    let test = "a_script_drags_the_launcher_its_handle_and_a_target_then_aims_and_hits";
    let dir = support::scratch_dir(test);
    let run = |script: &str, frames: &str| {
        let file = dir.join(format!("{frames}.script"));
        std::fs::write(&file, script).unwrap();
        let shot = dir.join(format!("{frames}.png"));
        let args = [
            "window",
            "seed",
            "--script",
            file.to_str().unwrap(),
            "--time-scale",
            "4",
            "--exit-after-frames",
            frames,
            "--no-watch",
            "--screenshot",
            shot.to_str().unwrap(),
        ];
        let out = crate::window_smoke::under_xvfb_sized(test, &[], &args, "1280x800")?;
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        Some(String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let Some(before) = run("wait 2\n", "3") else {
        return;
    };
    let Some(after_drags) = run(
        "wait 2\ndrag launcher 80 0\nwait 8\ndrag handle 0 20\nwait 8\n",
        "20",
    ) else {
        return;
    };
    let l0 = triple(after(&before, "launcher at ", "launcher at "));
    let l1 = triple(after(&after_drags, "launcher at ", "launcher at "));
    // Moved over the ground: same height, somewhere else.
    assert_eq!(l0[2], l1[2]);
    assert!(
        (l1[0] - l0[0]).abs() + (l1[1] - l0[1]).abs() > 0.5,
        "{l0:?} -> {l1:?}"
    );
    // The handle 20 px down: 10 degrees less elevation.
    let e = |r: &str| -> f64 {
        after(r, "launcher at ", "elevation ")
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(
        (e(&before) - 10.0 - e(&after_drags)).abs() < 1e-9,
        "{} -> {}",
        e(&before),
        e(&after_drags)
    );
    // A target dragged, then the aim (the low arc: about 9 ticks of flight, 27 frames at
    // this time scale): it hits the target where it now is.
    let Some(aimed) = run(
        "wait 2\ndrag target 0 -60 0\nwait 3\nkey shift+a\nwait 60\n",
        "70",
    ) else {
        return;
    };
    let t0 = triple(after(&before, "target 0 at ", "target 0 at "));
    let t1 = triple(after(&aimed, "target 0 at ", "target 0 at "));
    assert_eq!(t0[2], t1[2]);
    assert!(
        (t1[0] - t0[0]).abs() + (t1[1] - t0[1]).abs() > 0.5,
        "{t0:?} -> {t1:?}"
    );
    let pass = after(
        &aimed,
        "body 1 passed target 0 at ",
        "body 1 passed target 0 at ",
    );
    let miss: f64 = pass.split(' ').next().unwrap().parse().unwrap();
    assert!(miss < 1e-9, "{aimed}");
}
