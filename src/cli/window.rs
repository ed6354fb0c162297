//! `volley window` (and `volley` alone): the sandbox window.

use std::path::PathBuf;

use clap::Args;

use volley::app::session::compare_refusals;
use volley::app::{self, AppError, RunSummary, WindowOptions};
use volley::scene::{CompareLane, Scene};

use super::args::{Overrides, load_scene, parse_integrator};
use super::display::{DisplayArgs, report, window_failure};
use super::{EXIT_INPUT, Failure, fail, scene_dirs};

/// Arguments of `volley window`.
#[derive(Args, Clone, Debug)]
pub struct WindowArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    #[arg(default_value = "seed")]
    pub scene: String,
    /// The scene's settings replaced at start.
    #[command(flatten)]
    pub overrides: Overrides,
    /// Start in compare mode with these lanes: comma-separated integrator names, each with its
    /// own dt and substeps if wanted as `NAME@DT` or `NAME@DTxSUBSTEPS` (`rk4@0.2,
    /// explicit-euler@0.05x2`), or `default` for explicit-euler,semi-implicit-euler,verlet,rk4.
    /// Repeating the flag adds lanes.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub compare: Option<Vec<String>>,
    /// Compare lanes after the first get the first one's force evaluations per simulated
    /// second (their dt scaled by their cost per step: RK4 at 4 h beside Euler at h).
    #[arg(long)]
    pub equal_cost: bool,
    /// How the window shows and paces frames.
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Do not reload the scene when its file is saved.
    #[arg(long)]
    pub no_watch: bool,
    /// Record the first lane from tick 0 to this file (the record toggle then shows it
    /// running; toggled off and on again, later recordings go to recordings/).
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
}

/// `volley` with no arguments: the window on the seed scene, or, where there is no display to
/// open it on, the same job without a window ([`super::first_run`]), which exits 0.
/// `volley window` keeps its exit 4 and one line there: it was asked for a window.
pub fn default_run() -> Result<(), Failure> {
    if let Some(why) = no_display() {
        return super::first_run::run(&why);
    }
    let args = WindowArgs {
        scene: "seed".into(),
        overrides: Overrides::default(),
        compare: None,
        equal_cost: false,
        display: DisplayArgs::default(),
        no_watch: false,
        record: None,
    };
    match open(&args)? {
        Err(AppError::NoDisplay(why)) => super::first_run::run(&why),
        outcome => finish(&args, outcome),
    }
}

/// Why no window can open here, when the environment says so before trying: on the Unix
/// desktops winit supports, neither `DISPLAY` (X11) nor `WAYLAND_DISPLAY` is set. Elsewhere
/// (Windows, macOS) a window is assumed possible, and a failure to open one is caught as it
/// happens.
fn no_display() -> Option<String> {
    let unix_desktop = cfg!(all(unix, not(target_os = "macos"), not(target_os = "ios")));
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    (unix_desktop && !set("DISPLAY") && !set("WAYLAND_DISPLAY"))
        .then(|| "neither DISPLAY nor WAYLAND_DISPLAY is set".to_string())
}

/// `--compare`: `NAME`, `NAME@DT` or `NAME@DTxSUBSTEPS`, comma-separated; `default` stands
/// for the default lanes wherever it appears.
pub fn parse_compare(list: &str) -> Result<Vec<CompareLane>, Failure> {
    let default = app::input::DEFAULT_COMPARE.map(|i| i.name()).join(",");
    let list = list
        .split(',')
        .map(|item| {
            if item.trim() == "default" {
                default.as_str()
            } else {
                item
            }
        })
        .collect::<Vec<_>>()
        .join(",");
    let lanes = list.split(',').count();
    if lanes > volley::scene::MAX_COMPARE_LANES {
        return Err(fail(
            EXIT_INPUT,
            format!(
                "--compare: expected at most {} lanes, got {lanes}",
                volley::scene::MAX_COMPARE_LANES
            ),
        ));
    }
    list.split(',')
        .map(|item| {
            let item = item.trim();
            let (name, step) = match item.split_once('@') {
                Some((n, s)) => (n, Some(s)),
                None => (item, None),
            };
            let integrator = parse_integrator("--compare", name.trim())?;
            let bad = |what: &str| {
                fail(
                    EXIT_INPUT,
                    format!("--compare: `{item}`: expected NAME@DT or NAME@DTxSUBSTEPS, {what}"),
                )
            };
            let (dt, substeps) = match step {
                None => (None, None),
                Some(s) => {
                    let (dt, n) = match s.split_once('x') {
                        Some((dt, n)) => (dt, Some(n)),
                        None => (s, None),
                    };
                    let dt = dt
                        .parse::<f64>()
                        .ok()
                        .filter(|d| d.is_finite() && *d > 0.0)
                        .ok_or_else(|| {
                            bad(&format!(
                                "the dt `{dt}` is not a positive number of seconds"
                            ))
                        })?;
                    let n = match n {
                        Some(n) => {
                            Some(n.parse::<u32>().ok().filter(|n| *n >= 1).ok_or_else(|| {
                                bad(&format!(
                                    "the substeps `{n}` are not a whole number of at least 1"
                                ))
                            })?)
                        }
                        None => None,
                    };
                    (Some(dt), n)
                }
            };
            Ok(CompareLane {
                integrator,
                dt,
                substeps,
            })
        })
        .collect()
}

/// `--compare`'s lanes, refused in one line if the scene can run none of them (the window
/// would fall back to one lane of the scene's own integrator); a lane it cannot run is left out
/// in the window, as the panel's picks are, with a warning naming it and the scene's reason.
fn runnable(lanes: Vec<CompareLane>, scene: &Scene) -> Result<Vec<CompareLane>, Failure> {
    let Some(reasons) = compare_refusals(&lanes, scene) else {
        return Ok(lanes);
    };
    if lanes.iter().any(|l| l.apply(scene).is_ok()) {
        eprintln!("warning: --compare: the window leaves out {reasons}");
        return Ok(lanes);
    }
    Err(fail(
        EXIT_INPUT,
        format!("--compare: none of the compared integrators can run this scene ({reasons})"),
    ))
}

/// The bundled scenes, (name, path), for the picker.
fn bundled_scenes() -> Vec<(String, PathBuf)> {
    let Some(dir) = scene_dirs().into_iter().find(|d| d.is_dir()) else {
        return Vec::new();
    };
    let mut files = Vec::new();
    if super::collect_ron(&dir, &mut files).is_err() {
        return Vec::new();
    }
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let name = path
                .strip_prefix(&dir)
                .unwrap_or(&path)
                .with_extension("")
                .display()
                .to_string();
            (name, path)
        })
        .collect()
}

/// Opens the window and runs it until it closes.
pub fn run(args: &WindowArgs) -> Result<(), Failure> {
    let outcome = open(args)?;
    finish(args, outcome)
}

/// Prints what the window left behind, or turns its error into the CLI's.
fn finish(args: &WindowArgs, outcome: Result<RunSummary, AppError>) -> Result<(), Failure> {
    let summary = outcome.map_err(window_failure)?;
    report(&args.display, &summary);
    Ok(())
}

/// Checks the arguments and runs the window; the window's own error is returned as it is.
fn open(args: &WindowArgs) -> Result<Result<RunSummary, AppError>, Failure> {
    let (path, scene) = load_scene(&args.scene, &args.overrides)?;
    let compare = match &args.compare {
        Some(list) => runnable(parse_compare(&list.join(","))?, &scene)?,
        // A saved setup opens in its own compare lanes (the scene file checked them).
        None => scene.compare().to_vec(),
    };
    let options = WindowOptions {
        compare,
        equal_cost: args.equal_cost,
        watch: !args.no_watch,
        scenes: bundled_scenes(),
        record: args.record.clone(),
        ..args.display.options()?
    };
    Ok(app::run(scene, &path, options))
}
