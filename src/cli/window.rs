//! `volley window` (and `volley` alone): the sandbox window.

use std::path::PathBuf;

use clap::Args;

use volley::app::{self, AppError, WindowOptions};
use volley::integrate::Integrator;

use super::headless::{HeadlessArgs, load_scene, parse_integrator};
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, resolve_scene, scene_dirs};

/// Arguments of `volley window`.
#[derive(Args, Clone, Debug)]
pub struct WindowArgs {
    /// Scene file, or the name of a bundled scene (see `volley scenes`).
    #[arg(default_value = "seed")]
    pub scene: String,
    /// Integrator to start with: explicit-euler, semi-implicit-euler, verlet, midpoint, rk4,
    /// implicit-euler, exact.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Timestep (s), rounded to whole nanoseconds.
    #[arg(long)]
    pub dt: Option<f64>,
    /// Start in compare mode with these integrators (comma-separated names, or `default` for
    /// explicit-euler,semi-implicit-euler,verlet,rk4).
    #[arg(long, value_name = "LIST")]
    pub compare: Option<String>,
    /// Close after drawing this many frames (exit code 0).
    #[arg(long, value_name = "N")]
    pub exit_after_frames: Option<u64>,
    /// Save the last frame, panel included, to this PNG before closing.
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT in logical pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x800")]
    pub size: String,
    /// Feed the loop steady frames of this rate (Hz) instead of the real clock: the same run
    /// on every machine, for screenshots and tests.
    #[arg(long, value_name = "HZ")]
    pub frame_rate: Option<f64>,
    /// Start paused.
    #[arg(long)]
    pub paused: bool,
    /// Sim seconds per real second at start (0 to 100).
    #[arg(long, default_value_t = 1.0)]
    pub time_scale: f64,
    /// Do not reload the scene when its file is saved.
    #[arg(long)]
    pub no_watch: bool,
}

/// `volley` with no arguments: the window on the seed scene.
pub fn default_run() -> Result<(), Failure> {
    run(&WindowArgs {
        scene: "seed".into(),
        integrator: None,
        dt: None,
        compare: None,
        exit_after_frames: None,
        screenshot: None,
        size: "1280x800".into(),
        frame_rate: None,
        paused: false,
        time_scale: 1.0,
        no_watch: false,
    })
}

fn parse_compare(list: &str) -> Result<Vec<Integrator>, Failure> {
    if list == "default" {
        return Ok(app::input::DEFAULT_COMPARE.to_vec());
    }
    list.split(',')
        .map(|name| parse_integrator("--compare", name.trim()))
        .collect()
}

/// The bundled scenes, (name, path), for the picker.
fn bundled_scenes() -> Vec<(String, PathBuf)> {
    let Some(dir) = scene_dirs().into_iter().find(|d| d.is_dir()) else {
        return Vec::new();
    };
    let mut files = Vec::new();
    if super::scenes::collect_ron(&dir, &mut files).is_err() {
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
    let path = resolve_scene(&args.scene)?;
    let scene = load_scene(&HeadlessArgs {
        integrator: args.integrator.clone(),
        dt: args.dt,
        ..HeadlessArgs::for_scene(&args.scene)
    })?;
    let size = super::frames::parse_size("--size", &args.size)?;
    if let Some(hz) = args.frame_rate
        && !(hz.is_finite() && hz > 0.0)
    {
        return Err(fail(
            EXIT_INPUT,
            format!("--frame-rate: expected a rate > 0, got {hz}"),
        ));
    }
    if !(args.time_scale.is_finite() && (0.0..=100.0).contains(&args.time_scale)) {
        return Err(fail(
            EXIT_INPUT,
            "--time-scale: expected a number from 0 to 100",
        ));
    }
    let compare = match &args.compare {
        Some(list) => parse_compare(list)?,
        None => Vec::new(),
    };
    let options = WindowOptions {
        compare,
        exit_after_frames: args.exit_after_frames,
        screenshot: args.screenshot.clone(),
        size,
        frame_rate: args.frame_rate,
        paused: args.paused,
        time_scale: args.time_scale,
        watch: !args.no_watch,
        scenes: bundled_scenes(),
    };
    let summary = app::run(scene, &path, options).map_err(|e| match e {
        AppError::NoDisplay(_) | AppError::Gpu(_) | AppError::Io(_) => fail(EXIT_ENVIRONMENT, e),
    })?;
    if let (Some(_), Some(interval), Some(work)) =
        (args.exit_after_frames, summary.interval_ms, summary.work_ms)
    {
        println!(
            "window: {} frames, median frame {interval:.2} ms, of which work {work:.2} ms, on {}",
            summary.frames, summary.adapter
        );
    }
    Ok(())
}
