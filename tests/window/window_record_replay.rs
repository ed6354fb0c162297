//! The window's record toggle, replays in the window, and the stability pre-check per lane,
//! driven through `Session` as the window drives it, without a window; and `volley replay`
//! falling back to the table where no window can open.

use crate::replay_support;
use crate::support;

use std::path::{Path, PathBuf};
use std::time::Duration;

use volley::app::panel::PanelState;
use volley::app::session::Session;
use volley::clock::VirtualClock;
use volley::hash::state_hash;
use volley::replay::{Recorder, Recording, Replay};
use volley::stability::check_at;
use volley::{Command, Integrator, Scene, SimLoop, World, scene};

/// One frame of a 60 Hz display.
const HZ60: Duration = Duration::from_nanos(16_666_667);

fn coverage_path() -> PathBuf {
    support::crate_path("tests/data/replay_scene.ron")
}

fn coverage() -> Session {
    let path = coverage_path();
    Session::new(scene::load(&path).unwrap(), &path, Vec::new())
}

/// The reference's stiff spring: k/m = 1e4 at h = 1/60 (w h = 1.667).
fn stiff_spring() -> Scene {
    let text = "Scene(dt: 0.0166666667, integrator: ExplicitEuler,
        forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
        bodies: [(mass: 1, position: (0.1, 0, 0))])";
    scene::parse(text, "stiff.ron", "stiff").unwrap()
}

/// Re-simulates a recording file to its end; returns the replay.
fn verify(file: &Path) -> Replay<std::io::BufReader<std::fs::File>> {
    let mut replay = Replay::start(Recording::open(file).unwrap(), None).unwrap();
    replay.run_to(u64::MAX, &mut ()).unwrap();
    replay
}

fn launch(speed: f64) -> Command {
    Command::SetLaunch {
        speed: Some(speed),
        elevation_deg: Some(70.0),
        azimuth_deg: None,
        position: None,
    }
}

#[test]
fn the_record_toggle_records_the_first_lane_from_its_tick_with_every_command_pushed() {
    let file = support::scratch_dir("toggle").join("run.vrec");
    let mut session = coverage();
    for _ in 0..10 {
        session.frame(HZ60);
    }
    // Pushed before the toggle, applied after it: the recording holds it.
    session.push(Command::Fire).unwrap();
    let start = session.world().tick();
    session.start_recording(Some(file.clone())).unwrap();
    for i in 0..60 {
        match i {
            20 => {
                session.push(launch(13.0)).unwrap();
                session.push(Command::Fire).unwrap();
            }
            30 => session.set_paused(true),
            31 => session.push(Command::Reset).unwrap(),
            32 | 33 => session.single_step(),
            34 => session.set_paused(false),
            _ => {}
        }
        session.frame(HZ60);
    }
    let (end, hash) = (session.world().tick(), state_hash(session.world()));
    assert_eq!(session.recording().unwrap().stats().last_tick, end);
    let finished = session.stop_recording("stopped").unwrap().clone();
    assert!(session.recording().is_none());
    let stats = finished.stats.unwrap();
    assert_eq!(
        (stats.start_tick, stats.last_tick, stats.commands),
        (start, end, 4)
    );
    let recording = Recording::open(&file).unwrap();
    assert_eq!(recording.start_tick(), start);
    let commands: Vec<String> = recording
        .commands()
        .iter()
        .map(|c| c.command.to_string())
        .collect();
    assert_eq!(commands[0], "fire");
    assert_eq!(commands[3], "reset");
    assert_eq!(recording.footer().unwrap().final_hash, hash);
    let replay = verify(&file);
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.world().tick(), end);
    assert_eq!(state_hash(replay.world()), hash);
}

#[test]
fn restarts_end_the_recording_with_its_footer_and_say_why() {
    let dir = support::scratch_dir("restart");
    let mut session = coverage();
    type Restart = fn(&mut Session);
    let cases: [(&str, Restart); 3] = [
        ("dt changed", |s| s.set_dt(0.005).unwrap()),
        ("substeps changed", |s| s.set_step(0.005, 2).unwrap()),
        ("the scene file was saved", |s| {
            let path = coverage_path();
            s.restart(
                Some((scene::load(&path).unwrap(), path)),
                "the scene file was saved",
            )
            .unwrap()
        }),
    ];
    for (i, (why, restart)) in cases.into_iter().enumerate() {
        let file = dir.join(format!("{i}.vrec"));
        session.start_recording(Some(file.clone())).unwrap();
        for _ in 0..5 {
            session.frame(HZ60);
        }
        let tick = session.world().tick();
        restart(&mut session);
        assert_eq!(session.world().tick(), 0);
        assert!(session.recording().is_none());
        let last = session.recordings().last().unwrap();
        assert!(last.ended.starts_with(why), "{}", last.ended);
        assert_eq!(last.stats.unwrap().last_tick, tick);
        let recording = Recording::open(&file).unwrap();
        assert_eq!(recording.footer().map(|f| f.final_tick), Some(tick));
        assert!(verify(&file).first_divergence().is_none());
    }
}

#[test]
fn a_divergence_ends_the_recording_and_its_replay_reproduces_it() {
    let file = support::scratch_dir("diverged").join("stiff.vrec");
    let mut session = Session::new(stiff_spring(), Path::new("stiff.ron"), Vec::new());
    session.start_recording(Some(file.clone())).unwrap();
    session.frame(Duration::from_millis(100));
    let d = session.lanes()[0].stopped.expect("explicit Euler diverges");
    assert!(session.recording().is_none());
    assert!(session.recordings()[0].ended.contains("diverged at tick"));
    assert_eq!(
        Recording::open(&file).unwrap().footer().unwrap().diverged,
        Some(d)
    );
    let replay = verify(&file);
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.world().divergence(), Some(d));
}

#[test]
fn in_compare_mode_the_first_lane_is_recorded() {
    let file = support::scratch_dir("compare").join("first.vrec");
    let compared = vec![Integrator::Rk4, Integrator::SemiImplicitEuler];
    let path = coverage_path();
    let mut session = Session::new(scene::load(&path).unwrap(), &path, compared);
    session.start_recording(Some(file.clone())).unwrap();
    for _ in 0..20 {
        session.frame(HZ60);
    }
    let hash = state_hash(&session.lanes()[0].sim.world);
    session.stop_recording("stopped");
    assert_eq!(
        Recording::open(&file).unwrap().header().integrator,
        Integrator::Rk4
    );
    assert_eq!(state_hash(verify(&file).world()), hash);
}

#[test]
fn recording_is_refused_while_recording_diverged_or_replaying() {
    let dir = support::scratch_dir("refused");
    let mut session = coverage();
    session.start_recording(Some(dir.join("a.vrec"))).unwrap();
    let e = session
        .start_recording(Some(dir.join("b.vrec")))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("already recording to"), "{e}");
    session.stop_recording("stopped");
    let mut stiff = Session::new(stiff_spring(), Path::new("stiff.ron"), Vec::new());
    stiff.frame(Duration::from_millis(100));
    let e = stiff
        .start_recording(Some(dir.join("c.vrec")))
        .unwrap_err()
        .to_string();
    assert!(e.ends_with("reset before recording"), "{e}");
    let mut replaying = Session::for_replay(&dir.join("a.vrec"), None).unwrap();
    let e = replaying
        .start_recording(Some(dir.join("d.vrec")))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("replaying"), "{e}");
    assert!(!dir.join("c.vrec").exists() && !dir.join("d.vrec").exists());
}

#[test]
fn the_default_file_is_named_after_the_scene_and_never_overwritten() {
    use volley::app::session::recording::{create_default, default_path};
    let dir = support::scratch_dir("default-name");
    let first = default_path(&dir, "hard/stiff spring", 1700, 1);
    assert_eq!(first, dir.join("recordings/hard_stiff_spring-1700.vrec"));
    std::fs::create_dir_all(first.parent().unwrap()).unwrap();
    std::fs::write(&first, b"taken").unwrap();
    let (second, _) = create_default(&dir, "hard/stiff spring", 1700).unwrap();
    assert_eq!(second, dir.join("recordings/hard_stiff_spring-1700-2.vrec"));
    assert_eq!(std::fs::read(&first).unwrap(), b"taken");
    // The session's own toggle uses the same names, in its recordings folder.
    let mut session = coverage();
    session.set_recordings_dir(dir.clone());
    assert_eq!(session.toggle_recording(), Ok(()));
    let path = session.recording().unwrap().path().to_path_buf();
    assert_eq!(path.parent().unwrap(), dir.join("recordings"));
    session.toggle_recording().unwrap();
    assert!(Recording::open(&path).is_ok());
}

/// `recordings` is a file: the toggle fails at once with the path and the cause in the panel's
/// error line, after a bounded number of file-system calls (it used to probe `-2`, `-3`, ...
/// without end); every name taken fails the same way after `DEFAULT_NAME_TRIES` names.
#[test]
fn a_default_folder_that_cannot_be_used_is_an_error_in_the_panel_not_a_hang() {
    use volley::app::session::recording::{DEFAULT_NAME_TRIES, create_default, default_path};
    let dir = support::scratch_dir("default-blocked");
    std::fs::write(dir.join("recordings"), b"a file, not a folder").unwrap();
    let mut session = coverage();
    session.set_recordings_dir(dir.clone());
    let started = std::time::Instant::now();
    let refused = session.toggle_recording();
    assert!(started.elapsed() < Duration::from_secs(5));
    assert!(session.recording().is_none());
    let e = refused.expect_err("the refusal is shown").to_string();
    assert!(
        e.contains("recordings") && e.contains("cannot create its folder"),
        "{e}"
    );

    let full = support::scratch_dir("default-full");
    std::fs::create_dir_all(full.join("recordings")).unwrap();
    for n in 1..=DEFAULT_NAME_TRIES {
        std::fs::write(default_path(&full, "seed", 9, n), b"taken").unwrap();
    }
    let e = create_default(&full, "seed", 9).unwrap_err().to_string();
    assert!(e.contains("every name is taken"), "{e}");
    let after = default_path(&full, "seed", 9, DEFAULT_NAME_TRIES + 1);
    assert!(!after.exists());
}

#[test]
fn a_session_that_dies_mid_recording_leaves_a_readable_truncated_file() {
    let file = support::scratch_dir("crash").join("cut.vrec");
    let mut session = coverage();
    session.start_recording(Some(file.clone())).unwrap();
    for _ in 0..30 {
        session.frame(HZ60);
    }
    // A crash: no footer, no final flush (the recorder's buffer is lost with the process).
    std::mem::forget(session);
    let recording = Recording::open(&file).unwrap();
    assert!(recording.footer().is_none() && recording.truncated_at().is_some());
    let end = recording.end_tick();
    let replay = verify(&file);
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.world().tick(), end);
}

/// Records `ticks` of the coverage scene with its script headless, as `volley record` does;
/// returns the file, the final hash and the bodies at the end.
fn record_coverage(name: &str, ticks: u64) -> (PathBuf, u64, usize) {
    let file = support::scratch_dir(name).join("coverage.vrec");
    let scene = replay_support::coverage_scene();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(replay_support::coverage_commands());
    let out = std::fs::File::create(&file).unwrap();
    let mut recorder = Recorder::start(out, &sim.world, replay_support::options(1, 50)).unwrap();
    let mut source = VirtualClock::Steady(scene.timestep());
    sim.run_until(ticks, &mut source, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap();
    (file, state_hash(&sim.world), sim.world.bodies().len())
}

#[test]
fn a_replay_in_the_window_runs_the_recorded_commands_and_verifies_every_tick() {
    let (file, hash, bodies) = record_coverage("replay-window", 300);
    let mut session = Session::for_replay(&file, None).unwrap();
    assert!(session.is_embedded());
    assert_eq!(session.scene().name(), "replay");
    session.set_time_scale(2.0).unwrap();
    for _ in 0..400 {
        session.frame(HZ60);
    }
    let verdict = session.replay_verdict().unwrap();
    assert_eq!(verdict.parted, None);
    assert_eq!((verdict.from, verdict.at, verdict.end), (0, 300, 300));
    assert_eq!((verdict.hashes, verdict.keyframes), (301, 7));
    assert_eq!(verdict.final_hash, hash);
    assert_eq!(session.world().bodies().len(), bodies);
    assert!(
        verdict
            .line()
            .starts_with("verified 300 ticks, final hash 0x")
    );
    assert!(!session.is_paused(), "a replay that matches does not alarm");
}

/// The panel's red line keeps the last refusal until another replaces it or a replay opens:
/// a seek in a replay opens it again at the new tick, a seek to the tick it is at does not.
#[test]
fn the_panels_refusal_stays_until_a_replay_opens_again() {
    let (file, _, _) = record_coverage("refusal-line", 60);
    let mut session = Session::for_replay(&file, None).unwrap();
    let mut panel = PanelState::new(&session, Vec::new());
    assert_eq!(panel.refusal(&session), None);
    let fire = session.push(Command::Fire).unwrap_err().to_string();
    panel.refuse(&session, fire.clone());
    assert_eq!(session.frame(HZ60), None);
    assert_eq!(panel.refusal(&session), Some(fire.as_str()));
    session.seek(30).unwrap();
    assert_eq!(panel.refusal(&session), None);
    let reset = session.reset().unwrap_err().to_string();
    assert!(reset.starts_with("replaying: reset is off"), "{reset}");
    panel.refuse(&session, reset.clone());
    session.seek(30).unwrap();
    assert_eq!(panel.refusal(&session), Some(reset.as_str()));
}

#[test]
fn while_replaying_commands_are_refused_and_going_live_takes_over_from_that_tick() {
    let (file, _, _) = record_coverage("go-live", 300);
    let mut session = Session::for_replay(&file, None).unwrap();
    for _ in 0..60 {
        session.frame(HZ60);
    }
    let bodies = session.world().bodies().len();
    let e = session.push(Command::Fire).unwrap_err().to_string();
    assert!(e.starts_with("replaying"), "{e}");
    assert_eq!(session.lanes()[0].pending(), 0);
    assert!(session.set_dt(0.02).is_err());
    assert!(session.reset().is_err());
    assert_eq!(session.world().bodies().len(), bodies);
    let tick = session.world().tick();
    let applied = session.lanes()[0].history.commands_applied();
    assert!(session.go_live());
    assert!(session.replay().is_none());
    for _ in 0..120 {
        session.frame(HZ60);
    }
    assert!(session.world().tick() > 200);
    assert_eq!(
        session.lanes()[0].history.commands_applied(),
        applied,
        "the recording's later commands are not applied"
    );
    session.push(Command::Fire).unwrap();
    session.frame(HZ60);
    assert_eq!(session.lanes()[0].history.commands_applied(), applied + 1);
    let verdict = session.replay_verdict().unwrap();
    assert_eq!((verdict.at, verdict.parted), (tick, None));
}

#[test]
fn a_replay_that_parts_from_its_recording_pauses_and_names_the_tick() {
    let file = support::scratch_dir("parted").join("nudged.vrec");
    let scene = replay_support::coverage_scene();
    let mut sim = SimLoop::new(World::new(&scene));
    let mut source = VirtualClock::Steady(scene.timestep());
    let out = std::fs::File::create(&file).unwrap();
    let mut recorder = Recorder::start(out, &sim.world, replay_support::options(1, 10)).unwrap();
    sim.run_until(20, &mut source, &mut recorder).unwrap();
    let mut s = sim.world.snapshot();
    s.bodies.mv.z[0] = s.bodies.mv.z[0].next_down();
    sim.world.restore(&s).unwrap();
    sim.run_until(40, &mut source, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap();

    let mut session = Session::for_replay(&file, None).unwrap();
    for _ in 0..100 {
        session.frame(HZ60);
    }
    let verdict = session.replay_verdict().unwrap();
    let parted = verdict.parted.clone().expect("the nudge is found");
    assert_eq!((parted.tick, parted.compared_at), (21, Some(30)));
    assert!(parted.fields.iter().any(|f| f.field == "mV.z"));
    assert_eq!(session.world().tick(), 30, "the replay stops at its report");
    assert!(session.is_paused() && session.paused_by_alarm());
    assert_eq!(
        verdict.line(),
        format!(
            "{}: the replay parts from the recording at tick 21",
            file.display()
        )
    );
}

#[test]
fn a_replay_can_start_at_any_tick() {
    let (file, hash, _) = record_coverage("seek", 300);
    let mut session = Session::for_replay(&file, Some(170)).unwrap();
    assert_eq!(session.world().tick(), 170);
    assert_eq!(
        session.replay_verdict().unwrap().from,
        150,
        "the keyframe before it"
    );
    for _ in 0..200 {
        session.frame(HZ60);
    }
    assert_eq!(session.replay_verdict().unwrap().final_hash, hash);
    assert!(Session::for_replay(&file, Some(301)).is_err());
}

#[test]
fn the_pre_check_warns_per_lane_and_follows_integrator_dt_and_substeps() {
    let scene = stiff_spring();
    let expected = |dt: f64, substeps: u32, integrator: Integrator| {
        let mut s = scene.clone();
        s.set_dt(dt).unwrap();
        check_at(&s, s.dt(), substeps, integrator).warnings()
    };
    let mut session = Session::new(scene.clone(), Path::new("stiff.ron"), Vec::new());
    let h = scene.dt();
    let warnings = &session.lanes()[0].warnings;
    assert!(
        !warnings.is_empty(),
        "explicit Euler never holds an undamped spring"
    );
    assert_eq!(warnings, &expected(h, 1, Integrator::ExplicitEuler));
    // A command switches the integrator at the next tick; the warning follows it.
    session
        .push(Command::SetIntegrator(Integrator::SemiImplicitEuler))
        .unwrap();
    session.frame(HZ60);
    assert!(session.lanes()[0].warnings.is_empty(), "w h = 1.667 < 2");
    session.set_dt(0.05).unwrap();
    let warnings = &session.lanes()[0].warnings;
    assert!(!warnings.is_empty(), "w h = 5 > 2");
    assert_eq!(warnings, &expected(0.05, 1, Integrator::SemiImplicitEuler));
    session.set_step(0.05, 3).unwrap();
    assert!(
        session.lanes()[0].warnings.is_empty(),
        "w h / 3 = 1.667 < 2"
    );
    session
        .set_compare(vec![Integrator::ExplicitEuler, Integrator::Rk4])
        .unwrap();
    let lanes = session.lanes();
    assert_eq!(
        lanes[0].warnings,
        expected(0.05, 3, Integrator::ExplicitEuler)
    );
    assert!(lanes[1].warnings.is_empty(), "RK4 holds w h < 2.83");
}

#[test]
fn without_a_display_volley_replay_prints_the_table_after_one_warning() {
    let (file, _, _) = record_coverage("fallback", 50);
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_volley"))
            .arg("replay")
            .arg(&file)
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("WAYLAND_SOCKET")
            .output()
            .unwrap()
    };
    let (windowed, headless) = (run(&[]), run(&["--headless"]));
    assert_eq!(windowed.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&windowed.stderr);
    let ours = support::only_line(&stderr, "warning:");
    assert!(
        ours.contains("printing the replay's table instead"),
        "{stderr}"
    );
    assert!(headless.stderr.is_empty());
    assert_eq!(windowed.stdout, headless.stdout);
    assert!(String::from_utf8_lossy(&headless.stdout).lines().count() > 50);
}
