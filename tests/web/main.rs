//! The browser build, end to end: `scripts/web` builds the page, `tests/web/open.mjs` serves it
//! on localhost and drives it in Debian's headless Chromium (WebGPU on SwiftShader), and these
//! tests check what it showed: the seed scene drawn and stepping, a key press reaching the
//! window, the window's own screenshot offered as a download, and a bad `?scene=` answered with
//! the command line's one-line error in the page.
//!
//! Needs Debian's rustc-web toolchain (scripts/wasm32 installs it), wasm-bindgen-cli
//! (scripts/web installs it), Chromium and the npm package playwright-core (`.ci/run` installs
//! both: `apt-get install chromium`, `npm ci --prefix tests/web`). Under `CI=true` a missing one
//! fails the tests; elsewhere they say so and pass.

#[path = "../support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use volley::render::Image;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// What a browser test needs that this machine lacks, if anything.
fn missing() -> Option<String> {
    if Command::new("node").arg("--version").output().is_err() {
        return Some("node is not installed".into());
    }
    if !Path::new("/usr/bin/chromium").exists() && std::env::var_os("CHROMIUM").is_none() {
        return Some("Chromium is not installed (apt-get install chromium)".into());
    }
    if !root()
        .join("tests/web/node_modules/playwright-core")
        .is_dir()
    {
        return Some("playwright-core is not installed (npm ci --prefix tests/web)".into());
    }
    None
}

/// The page, built once for every test of this binary (scripts/web, dev profile).
fn page() -> Result<&'static Path, String> {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BUILT
        .get_or_init(|| {
            let out = root().join("target/web-test");
            let build = Command::new(root().join("scripts/web"))
                .arg(&out)
                .current_dir(root())
                .output()
                .map_err(|e| format!("scripts/web: {e}"))?;
            if !build.status.success() {
                let log = String::from_utf8_lossy(&build.stderr);
                let tail: Vec<&str> = log.lines().rev().take(40).collect();
                let tail: Vec<&str> = tail.into_iter().rev().collect();
                panic!("scripts/web failed:\n{}", tail.join("\n"));
            }
            Ok(out)
        })
        .as_ref()
        .map(PathBuf::as_path)
        .map_err(Clone::clone)
}

/// The built page's folder, for a test that puts files beside it; `None` after saying why
/// there is none.
fn page_dir(test: &str) -> Option<&'static Path> {
    let why = match (missing(), page()) {
        (None, Ok(dir)) => return Some(dir),
        (Some(why), _) | (None, Err(why)) => why,
    };
    support::unavailable(test, &why);
    None
}

/// What open.mjs reported, as JSON, and the page's screenshot.
fn open(test: &str, query: &str, frames: u32) -> Option<(serde_json::Value, PathBuf)> {
    open_with(test, query, frames, &[])
}

/// [`open`] with open.mjs's optional steps asked for in its environment: `PICK` (a file picked
/// in the page's file input once the window runs) and `KEYS` (keys pressed in turn).
fn open_with(
    test: &str,
    query: &str,
    frames: u32,
    env: &[(&str, &std::ffi::OsStr)],
) -> Option<(serde_json::Value, PathBuf)> {
    if let Some(why) = missing() {
        support::unavailable(test, &why);
        return None;
    }
    let dir = match page() {
        Ok(dir) => dir,
        Err(why) => {
            support::unavailable(test, &why);
            return None;
        }
    };
    let shot = support::scratch_dir(test).join("page.png");
    let run = Command::new("node")
        .envs(env.iter().copied())
        .arg(root().join("tests/web/open.mjs"))
        .arg(dir)
        .arg(query)
        .arg(&shot)
        .arg(frames.to_string())
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "open.mjs {query} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report = serde_json::from_str(stdout.trim()).expect("open.mjs prints one JSON object");
    Some((report, shot))
}

/// How many pixels of `image` are close to `rgb` (each channel within 40).
fn near(image: &Image, rgb: [u8; 3]) -> usize {
    image
        .rgba
        .chunks_exact(4)
        .filter(|p| (0..3).all(|c| p[c].abs_diff(rgb[c]) <= 40))
        .count()
}

#[test]
fn the_seed_opens_steps_pauses_and_screenshots_in_chromium() {
    let Some((report, shot)) = open("browser_seed", "scene=seed", 60) else {
        return;
    };
    let r = &report;
    assert_eq!(r["error"], serde_json::Value::Null, "{r}");
    assert_eq!(r["scene"], "seed", "{r}");
    assert!(r["frames"].as_u64().unwrap() >= 60, "{r}");
    assert!(
        r["adapter"].as_str().unwrap().contains("BrowserWebGpu"),
        "{r}"
    );
    // The seed steps: 0.2 s ticks on the real clock, so 60 frames run ticks.
    assert!(r["tick"].as_u64().unwrap() > 0, "{r}");
    // Space paused it: ten frames later the tick has not moved.
    assert_eq!(r["tickAtPause"], r["tickAfterPause"], "{r}");
    assert!(
        r["framesAfterPause"].as_u64().unwrap() >= r["frames"].as_u64().unwrap() + 10,
        "{r}"
    );
    // V, V: a recording made in the page, offered as a download, verifies on this machine.
    let recorded = shot.with_file_name("page-recorded.vrec");
    let name = r["recording"].as_str().unwrap_or_default();
    assert!(name.starts_with("seed-") && name.ends_with(".vrec"), "{r}");
    let (code, verdict, err) = volley_in(
        root(),
        &["replay", &recorded.display().to_string(), "--verify"],
    );
    assert_eq!(code, Some(0), "{verdict}{err}");
    assert!(verdict.starts_with("verified "), "{verdict}");
    assert!(err.contains("recorded on wasm32"), "{err}");
    // P: the window's screenshot as a download, named as the desktop names its file.
    let tick = r["tickAtPause"].as_u64().unwrap();
    assert_eq!(r["download"], format!("volley-tick{tick}.png"), "{r}");
    for (file, what) in [
        (shot.clone(), "the page"),
        (
            shot.with_file_name("page-key-p.png"),
            "the window's own screenshot",
        ),
    ] {
        let image = Image::load_png(&file).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!((image.width, image.height), (1280, 800), "{what}");
        // The scene: explicit Euler's trail in its colour (src/palette.rs), the panel's light
        // grey, and the 3D view's dark background, each over a share of the picture no blank
        // or half-drawn page has.
        let [r, g, b, _] = volley::palette::integrator(volley::Integrator::ExplicitEuler);
        let euler = [r, g, b];
        let total = (image.width * image.height) as usize;
        let (trail, panel, dark) = (
            near(&image, euler),
            near(&image, [248, 248, 248]),
            near(&image, [30, 30, 30]),
        );
        assert!(
            trail >= 200,
            "{what}: {trail} trail pixels ({})",
            file.display()
        );
        assert!(
            panel >= total / 10,
            "{what}: {panel} panel pixels ({})",
            file.display()
        );
        assert!(
            dark >= total / 10,
            "{what}: {dark} dark pixels ({})",
            file.display()
        );
    }
}

#[test]
fn an_unknown_scene_shows_the_command_lines_error_in_the_page() {
    let Some((report, _)) = open("browser_unknown_scene", "scene=no_such_scene", 1) else {
        return;
    };
    let cli = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(["headless", "no_such_scene"])
        .output()
        .expect("volley runs");
    assert_eq!(cli.status.code(), Some(2));
    let line = String::from_utf8(cli.stderr).unwrap();
    assert_eq!(report["error"].as_str(), Some(line.trim_end()), "{report}");
}

#[test]
fn an_unknown_integrator_is_refused_in_the_page() {
    let Some((report, _)) = open("browser_unknown_integrator", "integrator=rk5", 1) else {
        return;
    };
    let error = report["error"].as_str().unwrap_or_default();
    assert!(
        error.starts_with("error: ?integrator: unknown `rk5`, expected one of explicit-euler"),
        "{report}"
    );
}

/// Runs the CLI in `dir` and returns (exit code, stdout, stderr).
fn volley_in(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("volley runs");
    let text = |b: Vec<u8>| String::from_utf8(b).expect("UTF-8");
    (out.status.code(), text(out.stdout), text(out.stderr))
}

#[test]
fn a_recording_the_cli_made_verifies_in_the_page() {
    let Some(dir) = page_dir("browser_replay") else {
        return;
    };
    // The replay tests' scene and script: a seeded volley, bounces, a wall, a target, a spring,
    // drag toggled, every kind of command, velocity Verlet's carried force; recorded here by
    // the CLI, replayed by the page in wasm32.
    let file = "browser-replay.vrec";
    let (code, _, err) = volley_in(
        dir,
        &[
            "record",
            &root()
                .join("tests/data/replay_scene.ron")
                .display()
                .to_string(),
            "--commands",
            &root()
                .join("tests/data/replay_commands.txt")
                .display()
                .to_string(),
            "--keyframe-every",
            "50",
            "-o",
            file,
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    let (code, verdict, err) = volley_in(dir, &["replay", file, "--verify"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(verdict.starts_with("verified 300 ticks"), "{verdict}");
    let Some((report, _)) = open("browser_replay", &format!("replay={file}"), 1) else {
        return;
    };
    assert_eq!(report["error"], serde_json::Value::Null, "{report}");
    // The page's verdict is the command line's, hash for hash.
    assert_eq!(
        report["replay"].as_str(),
        Some(verdict.trim_end()),
        "{report}"
    );
}

#[test]
fn a_broken_recording_shows_the_command_lines_error_in_the_page() {
    let Some(dir) = page_dir("browser_broken_replay") else {
        return;
    };
    let file = "browser-broken.vrec";
    std::fs::write(dir.join(file), b"this is not a recording").unwrap();
    let (code, _, err) = volley_in(dir, &["replay", file, "--verify"]);
    assert_eq!(code, Some(2), "{err}");
    let Some((report, _)) = open("browser_broken_replay", &format!("replay={file}"), 1) else {
        return;
    };
    assert_eq!(report["error"].as_str(), Some(err.trim_end()), "{report}");
    // A recording the server does not have: the HTTP status, in the same form.
    let Some((report, _)) = open("browser_missing_replay", "replay=no-such.vrec", 1) else {
        return;
    };
    assert_eq!(
        report["error"].as_str(),
        Some("error: no-such.vrec: HTTP 404 Not Found"),
        "{report}"
    );
}

#[test]
fn webgl2_runs_the_seed_without_trails_and_says_so() {
    let Some((report, shot)) = open("browser_webgl2", "scene=seed&backend=webgl", 30) else {
        return;
    };
    let adapter = report["adapter"].as_str().unwrap_or_default();
    assert!(adapter.contains("(Gl, "), "{report}");
    assert!(adapter.contains("no trails on this adapter"), "{report}");
    assert!(report["tick"].as_u64().unwrap() > 0, "{report}");
    assert_eq!(report["tickAtPause"], report["tickAfterPause"], "{report}");
    let image = Image::load_png(&shot).unwrap();
    let total = (image.width * image.height) as usize;
    // The panel and the 3D view are drawn; the body and its tick markers in explicit Euler's
    // colour (no trail line joins them).
    let [r, g, b, _] = volley::palette::integrator(volley::Integrator::ExplicitEuler);
    assert!(near(&image, [r, g, b]) >= 20, "{}", shot.display());
    assert!(near(&image, [248, 248, 248]) >= total / 10);
    assert!(near(&image, [30, 30, 30]) >= total / 10);
}

#[test]
fn a_recording_picked_in_the_file_input_replays_and_verifies() {
    // tests/data/golden.vrec, made by the CLI (docs/replays.md, "The golden recording").
    let golden = root().join("tests/data/golden.vrec");
    let Some((report, _)) = open_with(
        "browser_pick",
        "scene=bounce",
        20,
        &[("PICK", golden.as_os_str())],
    ) else {
        return;
    };
    let (code, verdict, err) = volley_in(root(), &["replay", "tests/data/golden.vrec", "--verify"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(
        report["picked"].as_str(),
        Some(verdict.trim_end()),
        "{report}"
    );
}

#[test]
fn a_scene_from_a_url_opens_and_a_broken_one_shows_the_command_lines_error() {
    let Some(dir) = page_dir("browser_scene_url") else {
        return;
    };
    std::fs::copy(
        root().join("assets/scenes/drag.ron"),
        dir.join("url-drag.ron"),
    )
    .unwrap();
    let Some((report, _)) = open("browser_scene_url", "scene=url-drag.ron", 10) else {
        return;
    };
    assert_eq!(report["error"], serde_json::Value::Null, "{report}");
    // The file names no scene: it is named after the file, as `volley window FILE` names it.
    assert_eq!(report["scene"], "url-drag", "{report}");
    // A scene with a field missing: the CLI's line, naming the file, line and column.
    std::fs::write(
        dir.join("url-broken.ron"),
        "Scene(\n  name: \"x\",\n  dt: 0.01,\n)\n",
    )
    .unwrap();
    let (code, _, err) = volley_in(dir, &["headless", "url-broken.ron"]);
    assert_eq!(code, Some(2), "{err}");
    let Some((report, _)) = open("browser_broken_scene_url", "scene=url-broken.ron", 1) else {
        return;
    };
    assert_eq!(report["error"].as_str(), Some(err.trim_end()), "{report}");
}

#[test]
fn compare_plots_and_aim_run_in_the_page() {
    // C: compare mode with the panel's default set; a: every lane aims at the seed's target
    // (high arc) and fires its own solution, on the page's one thread. The plots are on from
    // the start.
    let keys = std::ffi::OsStr::new("KeyC KeyA");
    let Some((report, shot)) = open_with("browser_compare", "scene=seed", 30, &[("KEYS", keys)])
    else {
        return;
    };
    let r = &report;
    assert_eq!(r["error"], serde_json::Value::Null, "{r}");
    let lanes: Vec<&str> = r["keys"]["lanes"].as_str().unwrap().split(',').collect();
    let expected: Vec<&str> = volley::app::input::DEFAULT_COMPARE
        .iter()
        .map(|i| i.name())
        .collect();
    assert_eq!(lanes, expected, "{r}");
    // Each lane solved its own aim on its stepped trajectory and fired it.
    assert_eq!(r["keys"]["aims"].as_u64(), Some(lanes.len() as u64), "{r}");
    assert!(r["keys"]["tick"].as_u64().unwrap() > 0, "{r}");
    // The window's screenshot (P) shows every lane's colour, and the plots below the 3D view:
    // the panel's light grey over most of that strip, where the view alone is dark.
    let image = Image::load_png(&shot.with_file_name("page-key-p.png")).unwrap();
    for integrator in volley::app::input::DEFAULT_COMPARE {
        let [red, green, blue, _] = volley::palette::integrator(integrator);
        let n = near(&image, [red, green, blue]);
        assert!(
            n >= 50,
            "{}: {n} pixels ({})",
            integrator.name(),
            shot.display()
        );
    }
    let (x0, y0) = (420, 660);
    let width = image.width as usize;
    let strip = image
        .rgba
        .chunks_exact(4)
        .enumerate()
        .filter(|(i, _)| i % width >= x0 && i / width >= y0);
    let (light, all) = strip.fold((0, 0), |(light, all), (_, p)| {
        (
            light + usize::from(p[..3].iter().all(|&c| c >= 208)),
            all + 1,
        )
    });
    assert!(
        light * 2 >= all,
        "plots: {light} of {all} light pixels ({})",
        shot.display()
    );
}

/// The bundled level scene in the page, through WebGPU and through WebGL2: its hill and berm
/// drawn lit (turf-green and steel-grey pixels in the 3D view), the run stepping.
#[test]
fn the_range_level_scene_draws_its_meshes_and_hill_in_the_page() {
    for (test, query) in [
        ("browser_range", "scene=range"),
        ("browser_range_webgl", "scene=range&backend=webgl"),
    ] {
        let Some((report, shot)) = open(test, query, 60) else {
            return;
        };
        assert!(report["tick"].as_u64().unwrap() > 0, "{query}: {report}");
        let image = Image::load_png(&shot).unwrap();
        let count = |f: &dyn Fn(i32, i32, i32) -> bool| {
            image
                .rgba
                .chunks_exact(4)
                .filter(|p| f(i32::from(p[0]), i32::from(p[1]), i32::from(p[2])))
                .count()
        };
        let turf = count(&|r, g, b| g > 70 && g > r + 20 && g > b + 20);
        let steel = count(&|r, _, b| r > 90 && (5..40).contains(&(b - r)));
        assert!(turf > 1000, "{query}: turf {turf}, {}", shot.display());
        assert!(steel > 500, "{query}: steel {steel}, {}", shot.display());
    }
}
