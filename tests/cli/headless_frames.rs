//! `volley headless --frames`: PNG frames of a headless run, no window.

use crate::support;

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

#[test]
fn without_an_adapter_frames_exit_4_with_one_line_naming_the_way_without_a_gpu() {
    let dir = support::scratch_dir("noadapter");
    // WebGPU is the browser's backend: no native build has it, so this finds no adapter on
    // any machine.
    let output = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(["headless", "seed", "--ticks", "2", "--no-table", "--frames"])
        .arg(&dir)
        .env("WGPU_BACKEND", "webgpu")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(4));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let ours = support::only_line(&stderr, "error:");
    assert!(ours.contains("no GPU adapter"), "{stderr}");
    assert!(ours.contains("run without --frames"), "{stderr}");
}
