//! `volley headless --frames`: PNG frames of a headless run, no window.

mod support;

use std::process::Command;

use volley::render::Image;

#[test]
fn frames_are_written_at_tick_0_and_every_k_ticks_at_the_requested_size() {
    let test = "frames_are_written_at_tick_0_and_every_k_ticks_at_the_requested_size";
    let dir = support::scratch_dir("frames");
    let output = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args([
            "headless",
            "seed",
            "--ticks",
            "5",
            "--no-table",
            "--frame-every",
            "2",
        ])
        .args(["--size", "96x54", "--frames"])
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    if output.status.code() == Some(4) {
        return support::unavailable(test, stderr.trim());
    }
    assert!(
        output.status.success(),
        "exit {:?}: {stderr}",
        output.status.code()
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["tick_000000.png", "tick_000002.png", "tick_000004.png"]
    );
    for name in names {
        let image = Image::load_png(&dir.join(&name)).unwrap();
        assert_eq!((image.width, image.height), (96, 54), "{name}");
    }
    // The table and summary are unchanged by drawing: the same hash as without --frames.
    let plain = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(["headless", "seed", "--ticks", "5", "--no-table"])
        .output()
        .unwrap();
    assert_eq!(output.stdout, plain.stdout);
}

#[test]
fn a_bad_frame_size_is_refused_as_bad_input() {
    let dir = support::scratch_dir("badsize");
    let output = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args([
            "headless", "seed", "--ticks", "1", "--size", "12by7", "--frames",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--size"), "{stderr}");
}
