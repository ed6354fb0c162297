//! The window end to end: it opens under a virtual X server, draws, saves its last frame and
//! exits 0; without any display it exits 4 with one line naming the headless mode.

mod support;

use std::process::Command;

use volley::render::Image;

fn volley() -> Command {
    Command::new(env!("CARGO_BIN_EXE_volley"))
}

fn has(program: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {program}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn the_window_opens_draws_frames_and_exits_0_under_xvfb() {
    let test = "the_window_opens_draws_frames_and_exits_0_under_xvfb";
    if !has("xvfb-run") {
        return support::unavailable(test, "xvfb-run is not installed (apt-get install xvfb)");
    }
    let shot = support::scratch_dir("smoke").join("window.png");
    // A steady virtual 60 Hz clock: 12 frames are 0.2 s of sim time, one tick of the seed.
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_volley"))
        .args([
            "window",
            "seed",
            "--exit-after-frames",
            "12",
            "--frame-rate",
            "60",
        ])
        .args(["--size", "640x400", "--no-watch", "--screenshot"])
        .arg(&shot)
        .output()
        .expect("xvfb-run starts");
    let stderr = String::from_utf8_lossy(&output.stderr);
    if output.status.code() == Some(4) {
        return support::unavailable(test, stderr.trim());
    }
    assert!(
        output.status.success(),
        "exit {:?}: {stderr}",
        output.status.code()
    );
    let image = Image::load_png(&shot).expect("the last frame was saved");
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
    let ours: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: no"))
        .collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    assert!(ours[0].contains("volley headless"), "{stderr}");
}

#[test]
fn without_an_adapter_the_window_exits_4_naming_the_headless_mode() {
    let test = "without_an_adapter_the_window_exits_4_naming_the_headless_mode";
    if !has("xvfb-run") {
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
    let ours: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    assert!(ours[0].contains("volley headless"), "{stderr}");
}
