//! The rendered examples under a virtual X server: each opens Bevy's window on a software
//! adapter, draws its scene for 60 frames, saves a screenshot and exits 0; the screenshot holds
//! the bodies (the examples' orange) and, on the seed, its target (red).
//!
//! `cargo test` builds the examples beside this test (target/<profile>/examples). Outside CI a
//! machine without Xvfb or a Vulkan driver skips with the reason; with `CI=true` (whose
//! `.ci/run` installs both: Mesa's lavapipe) it fails instead.

#[path = "../../../tests/support/ci.rs"]
mod ci;

use std::path::{Path, PathBuf};
use std::process::Command;

use ci::{has, unavailable};

/// A Vulkan driver's manifest, as the loader finds them: Mesa's lavapipe is the software one.
fn vulkan_driver() -> bool {
    ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"]
        .iter()
        .filter_map(|d| std::fs::read_dir(d).ok())
        .flatten()
        .flatten()
        .any(|e| e.path().extension().is_some_and(|x| x == "json"))
}

/// The example binary `name`, built by `cargo test` next to this test's own folder.
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    let profile = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>/deps");
    profile.join("examples").join(name)
}

/// RGB pixels of a PNG file.
fn pixels(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let px = buf[..info.buffer_size()]
        .chunks(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, px)
}

/// Runs example `name` under Xvfb to a screenshot; its pixels, or `None` after saying why not.
fn screenshot(test: &str, name: &str) -> Option<(u32, u32, Vec<[u8; 3]>)> {
    if !has("xvfb-run") {
        unavailable(test, "xvfb-run is not installed (apt-get install xvfb)");
        return None;
    }
    if !vulkan_driver() {
        unavailable(
            test,
            "no Vulkan driver (apt-get install mesa-vulkan-drivers libvulkan1)",
        );
        return None;
    }
    let dir = std::env::temp_dir().join(format!("volley-bevy-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("shot.png");
    // `timeout`: a window that stopped drawing would otherwise run for ever.
    let out = Command::new("timeout")
        .args(["600", "xvfb-run", "-a", "-s", "-screen 0 1280x800x24"])
        .arg(example(name))
        .env("VOLLEY_BEVY_SCREENSHOT", &shot)
        .env("VOLLEY_BEVY_FRAMES", "60")
        // winit's keyboard setup asks for it; Xvfb sessions have none.
        .env("XDG_RUNTIME_DIR", &dir)
        .output()
        .expect("timeout and xvfb-run run");
    assert!(
        out.status.success(),
        "{name} exited {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    let px = pixels(&shot);
    // Kept for a person to look at (CI's log names it).
    eprintln!("{name}: screenshot {}", shot.display());
    Some(px)
}

/// Pixels within 40 of `rgb` in every channel.
fn count(px: &[[u8; 3]], rgb: [u8; 3]) -> usize {
    px.iter()
        .filter(|p| (0..3).all(|c| p[c].abs_diff(rgb[c]) <= 40))
        .count()
}

/// The examples' body colour, unlit, with no tonemapping: sRGB (1, 0.45, 0).
const ORANGE: [u8; 3] = [255, 115, 0];

#[test]
fn the_seed_example_draws_its_shot_and_target_in_a_window() {
    let Some((w, h, px)) = screenshot(
        "the_seed_example_draws_its_shot_and_target_in_a_window",
        "seed",
    ) else {
        return;
    };
    assert_eq!((w, h), (960, 600));
    let body = count(&px, ORANGE);
    // The target: lit red, darker than its base colour (0.85, 0.15, 0.2) on the shaded side.
    let target = px
        .iter()
        .filter(|p| p[0] > 120 && p[1] < 70 && p[2] < 90 && p[0] > 2 * p[2])
        .count();
    assert!(body >= 12, "{body} body pixels");
    assert!(target >= 12, "{target} target pixels");
}

#[test]
fn the_bounce_example_draws_its_three_balls_in_a_window() {
    let Some((_, _, px)) = screenshot(
        "the_bounce_example_draws_its_three_balls_in_a_window",
        "bounce",
    ) else {
        return;
    };
    assert!(
        count(&px, ORANGE) >= 3 * 12,
        "{} body pixels",
        count(&px, ORANGE)
    );
}
