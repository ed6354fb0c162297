//! The window's aim: every lane solves its own shot (`volley::firing`) and fires it through
//! commands; the shot passes the target's centre in that lane. Driven through the session (no
//! window) and through the real window under Xvfb with an input script.

use crate::support;
use crate::window_smoke::number_after;

use std::time::Duration;

use volley::app::session::Session;
use volley::exact::Arc;
use volley::{Integrator, scene};

const FRAME: Duration = Duration::from_millis(50);
/// The promise of `volley::firing`: the stepped shot passes the centre within this (m).
const HIT: f64 = 1e-9;

fn session(name: &str, compare: Vec<Integrator>) -> Session {
    let path = support::crate_path(&format!("assets/scenes/{name}.ron"));
    Session::new(scene::load(&path).unwrap(), &path, compare)
}

/// Runs frames until every lane's aimed shot has passed, or `max` frames; returns each lane's
/// miss.
fn misses(session: &mut Session, max: usize) -> Vec<f64> {
    for _ in 0..max {
        session.frame(FRAME);
        if session.lanes().iter().all(|l| aimed(l).is_some()) {
            break;
        }
    }
    session
        .lanes()
        .iter()
        .map(|l| aimed(l).unwrap_or(f64::NAN))
        .collect()
}

fn aimed(lane: &volley::app::session::Lane) -> Option<f64> {
    let note = lane.aim.as_ref()?;
    let shot = note.outcome.as_ref().ok()?;
    volley::app::panel::aimed_pass(lane, note, shot).map(|p| p.distance)
}

#[test]
fn in_compare_mode_each_lane_aims_for_itself_and_hits() {
    let lanes = vec![
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::Rk4,
    ];
    for arc in [Arc::High, Arc::Low] {
        let mut s = session("seed", lanes.clone());
        s.frame(FRAME);
        s.aim(arc, 0).unwrap();
        // Each lane got its own launch: different integrators, different elevations.
        let elevations: Vec<f64> = s
            .lanes()
            .iter()
            .map(|l| {
                l.aim
                    .as_ref()
                    .unwrap()
                    .outcome
                    .as_ref()
                    .unwrap()
                    .elevation_deg
            })
            .collect();
        assert!(elevations[0] != elevations[1] && elevations[1] != elevations[2]);
        for (lane, miss) in lanes.iter().zip(misses(&mut s, 400)) {
            assert!(miss < HIT, "{lane:?} {arc:?}: {miss}");
        }
        // The aim went through commands: the launcher shows the solved angles.
        for l in s.lanes() {
            let shot = l.aim.as_ref().unwrap().outcome.as_ref().unwrap();
            assert_eq!(l.sim.world.launcher().elevation_deg, shot.elevation_deg);
        }
    }
}

#[test]
fn aiming_at_a_moving_target_leads_it() {
    // The wind scene (quadratic drag and a crosswind) with its target moving.
    let path = support::crate_path("assets/scenes/wind.ron");
    let scene = scene::load(&path).unwrap();
    let mut targets = scene.targets().to_vec();
    targets[0].velocity = glam::DVec3::new(-2.0, 1.5, 0.0);
    let scene = scene.edit().targets(targets).no_volley().build().unwrap();
    let mut s = Session::new(
        scene,
        &path,
        vec![Integrator::SemiImplicitEuler, Integrator::Rk4],
    );
    for _ in 0..10 {
        s.frame(FRAME);
    }
    s.aim(Arc::Low, 0).unwrap();
    for miss in misses(&mut s, 400) {
        assert!(miss < HIT, "{miss}");
    }
}

#[test]
fn a_scene_without_targets_says_so_and_a_failed_solve_fires_nothing() {
    let mut s = session("spring", Vec::new());
    let e = s.aim(Arc::High, 0).unwrap_err().to_string();
    assert!(e.contains("no target 0"), "{e}");
    // 5 m/s cannot reach the seed's target: the note says why and nothing is fired.
    let path = support::crate_path("assets/scenes/seed.ron");
    let scene = scene::load(&path).unwrap();
    let launcher = volley::Launcher {
        speed: 5.0,
        ..scene.launcher()
    };
    let scene = scene.edit().launcher(launcher).build().unwrap();
    let mut s = Session::new(scene, &path, Vec::new());
    let bodies = s.world().bodies().len();
    s.aim(Arc::High, 0).unwrap();
    s.frame(Duration::from_millis(500));
    let note = s.lanes()[0].aim.as_ref().unwrap();
    let why = note.outcome.as_ref().unwrap_err().to_string();
    assert!(why.contains("out of reach"), "{why}");
    assert_eq!(s.world().bodies().len(), bodies);
}

#[test]
fn a_script_drives_the_real_window_to_aim_both_arcs_and_each_lane_hits() {
    let test = "a_script_drives_the_real_window_to_aim_both_arcs_and_each_lane_hits";
    let dir = support::scratch_dir(test);
    let script = dir.join("aim.script");
    std::fs::write(&script, "wait 3\nkey a\nwait 3\nkey shift+a\n").unwrap();
    let shot = dir.join("aim.png");
    let args = [
        "window",
        "seed",
        "--compare",
        "explicit-euler,semi-implicit-euler,rk4",
        "--script",
        script.to_str().unwrap(),
        "--time-scale",
        "4",
        "--exit-after-frames",
        "110",
        "--no-watch",
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    let Some(stdout) = crate::window_smoke::window_stdout(test, &args, "640x400") else {
        return;
    };
    // Per lane: bodies 1 (the high arc, fired at tick 1) and 2 (the low arc) pass the centre.
    let lanes: Vec<&str> = stdout.split("lane ").skip(1).collect();
    assert_eq!(lanes.len(), 3, "{stdout}");
    for lane in lanes {
        for body in ["body 1 passed target 0 at ", "body 2 passed target 0 at "] {
            let miss = number_after(lane, body);
            assert!(miss < HIT, "{lane}");
        }
        assert!(lane.contains("aim at target 0 from tick"), "{lane}");
    }
    let image = volley::render::Image::load_png(&shot).expect("the last frame was saved");
    assert_eq!((image.width, image.height), (640, 400));
}

#[test]
fn a_script_clicks_the_aim_button_by_its_label_and_each_lane_hits() {
    let test = "a_script_clicks_the_aim_button_by_its_label_and_each_lane_hits";
    let dir = support::scratch_dir(test);
    let script = dir.join("click.script");
    // The button is found by its label among the panel's controls and clicked through egui
    // (a press and a release on two frames), as a user would.
    std::fs::write(
        &script,
        "wait 5\nclick Aim: low arc\nwait 40\nclick Pause\nwait 3\n",
    )
    .unwrap();
    let args = [
        "window",
        "seed",
        "--compare",
        "explicit-euler,rk4",
        "--script",
        script.to_str().unwrap(),
        "--time-scale",
        "4",
        "--exit-after-frames",
        "52",
        "--no-watch",
    ];
    let Some(stdout) = crate::window_smoke::window_stdout(test, &args, "1280x800") else {
        return;
    };
    assert_eq!(stdout.matches("low arc elevation").count(), 2, "{stdout}");
    for lane in stdout.split("lane ").skip(1) {
        assert!(
            number_after(lane, "body 1 passed target 0 at ") < HIT,
            "{lane}"
        );
    }
    // The Pause click took: the ticks stopped growing with the frames after it (the low arc
    // arrives by tick 10; 52 frames at this time scale would be 17 ticks unpaused).
    let tick = number_after(&stdout, "lane explicit-euler: tick ");
    assert!(tick < 17.0, "{stdout}");
}
