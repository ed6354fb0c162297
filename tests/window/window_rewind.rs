//! Rewinding the window's session: every lane seeks on its timeline to a state bit-identical
//! to the one first computed there; playing forward replays the recorded future; a new
//! command drops it; a recording ends when the timeline moves; playing backwards; seeking in a
//! replay; and the real window driven by a script under Xvfb.

use crate::support;

use std::time::Duration;

use volley::app::session::Session;
use volley::hash::state_hash;
use volley::{Command, Integrator, scene};

const FRAME: Duration = Duration::from_millis(20);

fn session(name: &str, compare: Vec<Integrator>) -> Session {
    let path = support::crate_path(&format!("assets/scenes/{name}.ron"));
    Session::new(scene::load(&path).unwrap(), &path, compare)
}

/// Each lane's hash at every tick from 0 to `ticks`, running frames with a command or two.
fn run_recording_hashes(s: &mut Session, ticks: u64) -> Vec<Vec<u64>> {
    let mut hashes: Vec<Vec<u64>> = s
        .lanes()
        .iter()
        .map(|l| vec![state_hash(&l.sim.world)])
        .collect();
    while s.world().tick() < ticks {
        let tick = s.world().tick();
        if tick == 7 || tick == 23 {
            s.push(Command::Fire).unwrap();
        }
        s.single_step();
        s.frame(FRAME);
        for (h, l) in hashes.iter_mut().zip(s.lanes()) {
            assert_eq!(l.sim.world.tick() as usize, h.len());
            h.push(state_hash(&l.sim.world));
        }
    }
    hashes
}

#[test]
fn seeking_back_and_playing_forward_gives_every_lane_the_states_it_first_computed() {
    let lanes = vec![
        Integrator::ExplicitEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
    ];
    let mut s = session("drag", lanes);
    let hashes = run_recording_hashes(&mut s, 120);
    for tick in [0, 3, 7, 8, 16, 17, 23, 64, 99, 120, 50] {
        s.seek(tick).unwrap();
        for (h, l) in hashes.iter().zip(s.lanes()) {
            assert_eq!(l.sim.world.tick(), tick);
            assert_eq!(state_hash(&l.sim.world), h[tick as usize], "tick {tick}");
        }
    }
    // From 50, play forward through the recorded future: the same states, fires included,
    // and nothing is dropped.
    for tick in 51..=120 {
        s.single_step();
        s.frame(FRAME);
        for (h, l) in hashes.iter().zip(s.lanes()) {
            assert_eq!(state_hash(&l.sim.world), h[tick], "replayed tick {tick}");
        }
    }
    assert_eq!(s.future_dropped_at(), None);
    let t = s.lanes()[0].history.timeline.as_ref().unwrap();
    assert_eq!((t.end(), t.dropped_future()), (120, 0));
}

#[test]
fn a_new_command_after_a_seek_back_drops_the_future_and_says_so() {
    let mut s = session("drag", Vec::new());
    run_recording_hashes(&mut s, 60);
    s.seek(30).unwrap();
    s.push(Command::Fire).unwrap();
    s.single_step();
    s.frame(FRAME);
    assert_eq!(s.future_dropped_at(), Some(30));
    let note = volley::app::panel::future_dropped_note(30);
    assert!(note.contains("tick 30"), "{note}");
    let t = s.lanes()[0].history.timeline.as_ref().unwrap();
    assert_eq!(t.end(), 31);
    assert_eq!(t.dropped_future(), 30);
    // The fire at 23 is kept (two bodies before), the one just pushed is applied.
    assert_eq!(s.world().bodies().len(), 4);
    assert_eq!(s.lanes()[0].pending(), 0);
}

#[test]
fn moving_the_timeline_ends_a_running_recording_at_its_last_tick() {
    let dir = support::scratch_dir("moving_the_timeline_ends_a_running_recording");
    let mut s = session("drag", Vec::new());
    s.set_recordings_dir(dir.clone());
    s.start_recording(Some(dir.join("run.vrec"))).unwrap();
    run_recording_hashes(&mut s, 40);
    s.seek(10).unwrap();
    let done = s.recordings().last().expect("the recording ended");
    assert!(
        done.ended.contains("timeline moved to tick 10"),
        "{}",
        done.ended
    );
    assert_eq!(done.stats.as_ref().unwrap().last_tick, 40);
}

#[test]
fn playing_backwards_goes_back_at_the_time_scale_and_stops_at_the_start() {
    let mut s = session("drag", Vec::new());
    run_recording_hashes(&mut s, 90);
    s.toggle_reverse();
    assert!(s.is_reversing() && s.is_paused());
    // 0.5 s of frames: the whole ticks of the scene's step in it (16 666 667 ns: 29, not 30).
    for _ in 0..25 {
        s.frame(FRAME);
    }
    let back = (500_000_000 / s.scene().timestep().as_nanos()) as u64;
    assert_eq!(s.world().tick(), 90 - back);
    s.set_time_scale(10.0).unwrap();
    for _ in 0..100 {
        s.frame(FRAME);
    }
    assert_eq!(s.world().tick(), 0);
    assert!(!s.is_reversing(), "stops at the first tick held");
}

#[test]
fn a_replay_seeks_in_its_recording() {
    let dir = support::scratch_dir("a_replay_seeks_in_its_recording");
    let mut s = session("drag", Vec::new());
    let file = dir.join("run.vrec");
    s.start_recording(Some(file.clone())).unwrap();
    let hashes = run_recording_hashes(&mut s, 80);
    s.stop_recording("stopped");
    s.start_replay(&file, None).unwrap();
    assert_eq!(s.history_range(), Some((0, 80)));
    for tick in [60, 5, 33] {
        s.seek(tick).unwrap();
        assert_eq!(s.world().tick(), tick);
        assert_eq!(
            state_hash(s.world()),
            hashes[0][tick as usize],
            "tick {tick}"
        );
        assert!(s.replay().is_some());
    }
}

#[test]
fn a_script_drives_the_real_window_back_and_forth_on_its_timeline() {
    let test = "a_script_drives_the_real_window_back_and_forth_on_its_timeline";
    let dir = support::scratch_dir(test);
    let script = dir.join("rewind.script");
    // 60 frames forward (tick 60), three ticks back, then 20 frames of playing backwards.
    std::fs::write(
        &script,
        "wait 60\nkey ,\nkey ,\nkey ,\nwait 2\nkey b\nwait 20\nkey b\n",
    )
    .unwrap();
    let shot = dir.join("rewind.png");
    let args = [
        "window",
        "drag",
        "--script",
        script.to_str().unwrap(),
        "--exit-after-frames",
        "90",
        "--no-watch",
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    let Some(stdout) = crate::window_smoke::window_stdout(test, &args, "640x400") else {
        return;
    };
    // Frame 61 steps back to 57; two frames later playing backwards starts and runs 20
    // frames at one tick a frame (60 Hz frames, h = 1/60 s), then stops: tick 37 (give or take
    // the frame the key lands in), and it stays there, paused.
    let tick = crate::window_smoke::number_after(&stdout, "lane semi-implicit-euler: tick ");
    assert!((35.0..=39.0).contains(&tick), "{stdout}");
    assert!(volley::render::Image::load_png(&shot).is_ok());
}
