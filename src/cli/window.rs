//! `volley window` (and `volley` alone): the sandbox window.

use std::path::PathBuf;

use clap::Args;

use volley::app::{self, AppError, RunSummary, WindowOptions};
use volley::integrate::Integrator;

use super::headless::{RunArgs, load_scene, parse_integrator};
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

/// The window options `volley window` and `volley replay` share: size, pacing, closing.
#[derive(Args, Clone, Debug)]
pub struct DisplayArgs {
    /// Close after drawing this many frames (exit code 0, or 1 for a replay that parted).
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
    /// For tests: resize the window, minimise and restore it, and lose its surface, three
    /// frames apart, drawing on after each.
    #[arg(long)]
    pub surface_drill: bool,
}

impl Default for DisplayArgs {
    /// The command line's defaults.
    fn default() -> Self {
        DisplayArgs {
            exit_after_frames: None,
            screenshot: None,
            size: "1280x800".into(),
            frame_rate: None,
            paused: false,
            time_scale: 1.0,
            surface_drill: false,
        }
    }
}

impl DisplayArgs {
    /// Checks the options and makes the window's options of them (compare mode off, no
    /// scenes for the picker, watching off, no recording: the caller fills those in).
    pub fn options(&self) -> Result<WindowOptions, Failure> {
        let size = super::frames::parse_size("--size", &self.size)?;
        if let Some(hz) = self.frame_rate
            && !(hz.is_finite() && hz > 0.0)
        {
            return Err(fail(
                EXIT_INPUT,
                format!("--frame-rate: expected a rate > 0, got {hz}"),
            ));
        }
        if !(self.time_scale.is_finite() && (0.0..=100.0).contains(&self.time_scale)) {
            return Err(fail(
                EXIT_INPUT,
                "--time-scale: expected a number from 0 to 100",
            ));
        }
        Ok(WindowOptions {
            compare: Vec::new(),
            exit_after_frames: self.exit_after_frames,
            screenshot: self.screenshot.clone(),
            size,
            frame_rate: self.frame_rate,
            paused: self.paused,
            time_scale: self.time_scale,
            watch: false,
            scenes: Vec::new(),
            record: None,
            surface_drill: self.surface_drill,
        })
    }
}

/// `volley` with no arguments: the window on the seed scene.
pub fn default_run() -> Result<(), Failure> {
    run(&WindowArgs {
        scene: "seed".into(),
        integrator: None,
        dt: None,
        compare: None,
        display: DisplayArgs::default(),
        no_watch: false,
        record: None,
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
    let scene = load_scene(&RunArgs {
        integrator: args.integrator.clone(),
        dt: args.dt,
        ..RunArgs::for_scene(&args.scene)
    })?;
    let compare = match &args.compare {
        Some(list) => parse_compare(list)?,
        None => Vec::new(),
    };
    let options = WindowOptions {
        compare,
        watch: !args.no_watch,
        scenes: bundled_scenes(),
        record: args.record.clone(),
        ..args.display.options()?
    };
    let summary = app::run(scene, &path, options).map_err(window_failure)?;
    report(&args.display, &summary);
    Ok(())
}

/// Every window error is the environment's (exit code 4).
pub fn window_failure(e: AppError) -> Failure {
    match e {
        AppError::NoDisplay(_) | AppError::Gpu(_) | AppError::Io(_) => fail(EXIT_ENVIRONMENT, e),
    }
}

/// Prints what a window run leaves behind: its recordings, one line each, and with a frame
/// limit the median frame time.
pub fn report(display: &DisplayArgs, summary: &RunSummary) {
    for r in &summary.recordings {
        println!("{r}");
    }
    if let (Some(_), Some(interval), Some(work)) = (
        display.exit_after_frames,
        summary.interval_ms,
        summary.work_ms,
    ) {
        println!(
            "window: {} frames, median frame {interval:.2} ms, of which work {work:.2} ms, on {}",
            summary.frames, summary.adapter
        );
    }
}
