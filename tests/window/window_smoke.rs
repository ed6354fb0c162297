//! The window end to end: it opens under a virtual X server, draws, saves its last frame and
//! exits 0, also through a resize, a minimise and a lost surface, and at a HiDPI scale; without
//! any display it exits 4 with one line naming the headless mode.

use crate::support;

use std::process::Command;

use volley::render::Image;

fn volley() -> Command {
    Command::new(env!("CARGO_BIN_EXE_volley"))
}

#[test]
fn the_window_opens_draws_frames_and_exits_0_under_xvfb() {
    let test = "the_window_opens_draws_frames_and_exits_0_under_xvfb";
    // A steady virtual 60 Hz clock: 12 frames are 0.2 s of sim time, one tick of the seed.
    let Some((image, _)) = drawn_under_xvfb(test, 12, &[], &[]) else {
        return;
    };
    // Xvfb reports a scale factor of 1: the frame is the window's logical size.
    assert_eq!((image.width, image.height), (640, 400));
    // The panel is drawn into the same frame: its background differs from the 3D view's.
    assert_ne!(image.pixel(5, 200), image.pixel(630, 5));
}

#[test]
fn without_a_display_the_window_exits_4_naming_the_headless_mode() {
    let output = volley()
        .args(["window", "--exit-after-frames", "1", "--no-watch"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(4));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let ours = support::only_line(&stderr, "error: no");
    assert!(ours.contains("volley headless"), "{stderr}");
}

#[test]
fn without_an_adapter_the_window_exits_4_naming_the_headless_mode() {
    let test = "without_an_adapter_the_window_exits_4_naming_the_headless_mode";
    if !support::has("xvfb-run") {
        return support::unavailable(test, "xvfb-run is not installed (apt-get install xvfb)");
    }
    // A display but no adapter: WebGPU is the browser's backend, absent from native builds.
    let output = Command::new("xvfb-run")
        .arg("-a")
        .arg(env!("CARGO_BIN_EXE_volley"))
        .args(["window", "--exit-after-frames", "1", "--no-watch"])
        .env("WGPU_BACKEND", "webgpu")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(4));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let ours = support::only_line(&stderr, "error:");
    assert!(ours.contains("volley headless"), "{stderr}");
}

/// Runs `volley ARGS --size 640x400 --frame-rate 60` under a virtual X server with `env`
/// set; `None` (after reporting why) where no window can open here. `timeout`: a window that
/// stopped drawing (say, never woke after a minimise) would otherwise wait for its frame limit
/// forever; it exits 124 instead.
fn under_xvfb_with(
    test: &str,
    env: &[(&str, &str)],
    args: &[&str],
) -> Option<std::process::Output> {
    under_xvfb_sized(test, env, args, "640x400")
}

/// [`under_xvfb_with`] at window size `size` (WxH).
pub(crate) fn under_xvfb_sized(
    test: &str,
    env: &[(&str, &str)],
    args: &[&str],
    size: &str,
) -> Option<std::process::Output> {
    under_xvfb_paced(test, env, args, size, &["--frame-rate", "60"])
}

/// [`under_xvfb_sized`] with `pacing` for the frames instead of `--frame-rate 60` (an
/// emulated display's `--display NAME`).
pub(crate) fn under_xvfb_paced(
    test: &str,
    env: &[(&str, &str)],
    args: &[&str],
    size: &str,
    pacing: &[&str],
) -> Option<std::process::Output> {
    if !support::has("xvfb-run") {
        support::unavailable(test, "xvfb-run is not installed (apt-get install xvfb)");
        return None;
    }
    let output = Command::new("timeout")
        .args(["120", "xvfb-run", "-a", "-s", "-screen 0 1600x1200x24"])
        .arg(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .args(["--size", size])
        .args(pacing)
        .envs(env.iter().copied())
        .output()
        .expect("timeout and xvfb-run start");
    if output.status.code() == Some(4) {
        support::unavailable(test, String::from_utf8_lossy(&output.stderr).trim());
        return None;
    }
    Some(output)
}

/// `volley ARGS` at window size `size` under Xvfb at a steady 60 Hz, run in folder `dir` (where
/// the window writes its recordings and saved plots); `None` (after reporting why) where no
/// window can open here.
pub(crate) fn under_xvfb_in(
    test: &str,
    dir: &std::path::Path,
    args: &[&str],
    size: &str,
) -> Option<std::process::Output> {
    if !support::has("xvfb-run") {
        support::unavailable(test, "xvfb-run is not installed (apt-get install xvfb)");
        return None;
    }
    let output = Command::new("timeout")
        .args(["120", "xvfb-run", "-a", "-s", "-screen 0 1600x1200x24"])
        .arg(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .args(["--size", size, "--frame-rate", "60"])
        .current_dir(dir)
        .output()
        .expect("timeout and xvfb-run start");
    if output.status.code() == Some(4) {
        support::unavailable(test, String::from_utf8_lossy(&output.stderr).trim());
        return None;
    }
    Some(output)
}

/// `volley ARGS` at window size `size` under Xvfb, which must exit 0: its stdout; `None` (after
/// reporting why) where no window can open here.
pub(crate) fn window_stdout(test: &str, args: &[&str], size: &str) -> Option<String> {
    let out = under_xvfb_sized(test, &[], args, size)?;
    assert!(
        out.status.success(),
        "exit {:?} (124: timed out): {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    Some(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The number right after the first `label` in `text` (up to a space, a comma or a closing
/// parenthesis); fails naming the text if there is none.
pub(crate) fn number_after(text: &str, label: &str) -> f64 {
    text.split(label)
        .nth(1)
        .and_then(|rest| rest.split([' ', ',', ')']).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no number after `{label}` in:\n{text}"))
}

/// [`under_xvfb_with`] without extra environment.
pub(crate) fn under_xvfb(test: &str, args: &[&str]) -> Option<std::process::Output> {
    under_xvfb_with(test, &[], args)
}

/// `volley window seed` under Xvfb, closing after `frames` frames with a screenshot; it must
/// exit 0. Returns the screenshot and stdout.
pub(crate) fn drawn_under_xvfb(
    test: &str,
    frames: u32,
    env: &[(&str, &str)],
    extra: &[&str],
) -> Option<(Image, String)> {
    let shot = support::scratch_dir(test).join("window.png");
    let frames = frames.to_string();
    let shot_arg = shot.to_str().expect("a UTF-8 temp path");
    let mut args = vec!["window", "seed", "--exit-after-frames", &frames];
    args.extend(["--no-watch", "--screenshot", shot_arg]);
    args.extend_from_slice(extra);
    let output = under_xvfb_with(test, env, &args)?;
    assert!(
        output.status.success(),
        "exit {:?} (124: timed out): {}",
        output.status.code(),
        String::from_utf8_lossy(&output.stderr)
    );
    let image = Image::load_png(&shot).expect("the last frame was saved");
    Some((image, String::from_utf8_lossy(&output.stdout).into_owned()))
}

#[test]
fn a_recording_made_in_the_window_replays_and_verifies_in_the_window() {
    let test = "a_recording_made_in_the_window_replays_and_verifies_in_the_window";
    let file = support::scratch_dir("record-window").join("run.vrec");
    let scene = support::crate_path("tests/data/replay_scene.ron");
    let (file_arg, scene_arg) = (file.to_str().unwrap(), scene.to_str().unwrap());
    // 30 frames of a steady 60 Hz clock are 0.5 s: 50 ticks of 10 ms.
    let record = ["window", scene_arg, "--record", file_arg, "--no-watch"];
    let Some(out) = under_xvfb(
        test,
        &[&record[..], &["--exit-after-frames", "30"]].concat(),
    ) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let expected = format!("recorded ticks 0..=50 of `replay` to {file_arg}: ");
    assert!(stdout.starts_with(&expected), "{stdout}");
    assert!(
        stdout
            .lines()
            .next()
            .unwrap()
            .ends_with("(the window closed)")
    );
    let footer = *volley::replay::Recording::open(&file)
        .unwrap()
        .footer()
        .unwrap();
    assert_eq!(footer.final_tick, 50);

    // At time scale 4, 20 frames are 133 ticks' worth: the replay reaches the end.
    let replay = [
        "replay",
        file_arg,
        "--time-scale",
        "4",
        "--exit-after-frames",
        "20",
    ];
    let Some(out) = under_xvfb(test, &replay) else {
        return;
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let verdict = format!(
        "verified 50 ticks, final hash {} (ticks 0..=50: 51 hashes",
        volley::hash::hex(footer.final_hash)
    );
    assert!(stdout.lines().any(|l| l.starts_with(&verdict)), "{stdout}");
}

#[test]
fn a_window_replay_that_parts_from_its_recording_exits_1_with_the_report() {
    let test = "a_window_replay_that_parts_from_its_recording_exits_1_with_the_report";
    let file = support::scratch_dir("parted-window").join("nudged.vrec");
    let scene = volley::scene::load(&support::crate_path("tests/data/replay_scene.ron")).unwrap();
    let mut sim = volley::SimLoop::new(volley::World::new(&scene));
    let mut source = volley::clock::VirtualClock::Steady(scene.timestep());
    let out = std::fs::File::create(&file).unwrap();
    let options = volley::replay::RecordOptions {
        keyframe_every: 10,
        ..Default::default()
    };
    let mut recorder = volley::replay::Recorder::start(out, &sim.world, options).unwrap();
    sim.run_until(20, &mut source, &mut recorder).unwrap();
    let mut s = sim.world.snapshot();
    s.bodies.mv.z[0] = s.bodies.mv.z[0].next_down();
    sim.world.restore(&s).unwrap();
    sim.run_until(40, &mut source, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap();

    let file_arg = file.to_str().unwrap();
    let args = [
        "replay",
        file_arg,
        "--time-scale",
        "4",
        "--exit-after-frames",
        "20",
    ];
    let Some(out) = under_xvfb(test, &args) else {
        return;
    };
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let first = "first divergence at tick 21: state hash recorded 0x";
    assert!(stdout.lines().any(|l| l.starts_with(first)), "{stdout}");
    assert!(stdout.contains("\n  body 0 mV.z: recorded "), "{stdout}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = format!("error: {file_arg}: the replay parts from the recording at tick 21");
    assert!(stderr.lines().any(|l| l == line), "{stderr}");
}

#[test]
fn the_window_draws_on_through_a_resize_a_minimise_and_a_lost_surface() {
    let test = "the_window_draws_on_through_a_resize_a_minimise_and_a_lost_surface";
    let Some((image, stdout)) = drawn_under_xvfb(test, 24, &[], &["--surface-drill"]) else {
        return;
    };
    assert!(stdout.contains("window: 24 frames"), "{stdout}");
    // 24 frames were presented after the drill's three events (frames 3, 6 and 9), and the last
    // one has the restored size.
    assert_eq!((image.width, image.height), (640, 400));
    assert_ne!(image.pixel(5, 200), image.pixel(630, 5));
}

#[test]
fn at_a_hidpi_scale_the_window_draws_at_its_physical_size() {
    let test = "at_a_hidpi_scale_the_window_draws_at_its_physical_size";
    // winit's X11 backend takes the scale factor from this variable.
    let Some((image, stdout)) = drawn_under_xvfb(test, 24, &[("WINIT_X11_SCALE_FACTOR", "2")], &[])
    else {
        return;
    };
    assert!(stdout.contains("window: 24 frames"), "{stdout}");
    // 640 x 400 logical pixels at scale 2; the panel (egui, in points) is drawn at the same
    // scale, so its background shows at twice the logical distance from the edge.
    assert_eq!((image.width, image.height), (1280, 800));
    assert_ne!(image.pixel(10, 400), image.pixel(1260, 10));
}
