//! What the two subcommands that open a window (`volley window`, `volley replay`) share: the
//! window's size, pacing and closing, its errors' exit code, and the report it leaves behind.

use std::path::PathBuf;

use clap::Args;

use volley::app::display::{MODEL_SECONDS, believed_refresh};
use volley::app::{AppError, RunSummary, WindowOptions};
use volley::clock::LoopPolicy;
use volley::pacing::SweepDisplay;
use volley::pacing::{DisplayModel, DrawMode};

use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail};

/// Parses `WxH` (each side 1 to 16384).
pub fn parse_size(flag: &str, text: &str) -> Result<(u32, u32), Failure> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Ok((w, h)),
        _ => Err(fail(
            EXIT_INPUT,
            format!("{flag}: expected WIDTHxHEIGHT, each 1 to 16384, got `{text}`"),
        )),
    }
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
    /// Run this many ticks before the window opens (every lane, with its history, plots and
    /// timeline), so a measurement or a demo starts with a long run behind it.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub warm_up_ticks: u64,
    /// Memory budget of each lane's timeline (MiB): keyframes and commands for rewinding.
    #[arg(long, value_name = "MIB", default_value_t = 64)]
    pub history_budget: u32,
    /// Play this input script (key presses and waits in frames; docs/window.md, "Input
    /// scripts") from the first frame.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Emulate a display: a model (60, 59.94, 120, 144, 165, 240, 60-misses, vrr-144,
    /// 60-hitch, or any rate in Hz) or a PresentMon CSV capture. Its frame deltas drive the
    /// loop (virtual frames, looped) and the pacing view measures at its display times.
    #[arg(long, value_name = "MODEL|FILE.csv", conflicts_with = "frame_rate")]
    pub display: Option<String>,
    /// Start with this loop policy: accumulator, snap, snap-avg, quantise or hysteresis
    /// (default: accumulator, volley::pacing::DEFAULT_POLICY).
    #[arg(long, value_name = "NAME")]
    pub policy: Option<String>,
    /// Start with this draw mode: current, interpolate, extrapolate, predict or swept
    /// (default: swept, volley::pacing::DEFAULT_DRAW).
    #[arg(long, value_name = "MODE")]
    pub draw: Option<String>,
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
            history_budget: 64,
            warm_up_ticks: 0,
            script: None,
            display: None,
            policy: None,
            draw: None,
        }
    }
}

/// Every display model name `--display` takes, for its error line.
fn display_names() -> String {
    let names: Vec<&str> = DisplayModel::bundled().iter().map(|(n, _)| *n).collect();
    names.join(", ")
}

/// `--display`: a display model's name or rate, or a PresentMon CSV capture.
pub fn parse_display(text: &str) -> Result<SweepDisplay, Failure> {
    let path = std::path::Path::new(text);
    let is_file = path.is_file()
        || path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if !is_file {
        return DisplayModel::named(text)
            .map(|m| SweepDisplay::model(text, &m, MODEL_SECONDS))
            .ok_or_else(|| {
                fail(
                    EXIT_INPUT,
                    format!(
                        "--display: expected a display model ({}, or a refresh rate from 1 to \
                         1000 Hz) or a PresentMon CSV file, got `{text}`",
                        display_names()
                    ),
                )
            });
    }
    let body = volley::scene::read_text(path).map_err(|e| {
        fail(
            EXIT_INPUT,
            format!(
                "--display: cannot read `{text}` ({e}); expected a PresentMon CSV file or a \
                 display model ({})",
                display_names()
            ),
        )
    })?;
    let timing = volley::pacing::read_capture(&body, text, None)
        .map_err(|e| fail(EXIT_INPUT, format!("--display: {e}")))?;
    if timing.presents.is_empty() {
        return Err(fail(
            EXIT_INPUT,
            format!("--display: `{text}` holds no presents, expected at least one"),
        ));
    }
    Ok(SweepDisplay::capture(&timing.name.clone(), timing))
}

/// `--policy NAME` with the refresh the game believes in.
pub fn parse_policy(text: &str, refresh: std::time::Duration) -> Result<LoopPolicy, Failure> {
    LoopPolicy::from_name(text, refresh).ok_or_else(|| {
        fail(
            EXIT_INPUT,
            format!(
                "--policy: expected one of {}, got `{text}`",
                LoopPolicy::NAMES.join(", ")
            ),
        )
    })
}

/// `--draw MODE`.
pub fn parse_draw(text: &str) -> Result<DrawMode, Failure> {
    DrawMode::parse(text).ok_or_else(|| {
        let names: Vec<&str> = DrawMode::ALL.iter().map(|m| m.name()).collect();
        fail(
            EXIT_INPUT,
            format!("--draw: expected one of {}, got `{text}`", names.join(", ")),
        )
    })
}

impl DisplayArgs {
    /// Checks the options and makes the window's options of them (compare mode off, no
    /// scenes for the picker, watching off, no recording: the caller fills those in).
    pub fn options(&self) -> Result<WindowOptions, Failure> {
        let size = parse_size("--size", &self.size)?;
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
        let script = match &self.script {
            Some(path) => {
                let text = super::read_input(path)?;
                volley::app::script::parse(&text, &path.display().to_string())
                    .map_err(|e| fail(EXIT_INPUT, e))?
            }
            None => Vec::new(),
        };
        let display = self.display.as_deref().map(parse_display).transpose()?;
        // The refresh the snapping and quantising policies start with (the window takes the
        // monitor's on the real clock, where it reports one).
        let refresh = match (&display, self.frame_rate) {
            (Some(d), _) => d.refresh,
            (None, Some(hz)) => believed_refresh(hz),
            (None, None) => volley::app::display::DEFAULT_REFRESH,
        };
        let policy = match &self.policy {
            Some(name) => parse_policy(name, refresh)?,
            None => volley::pacing::DEFAULT_POLICY.with_refresh(refresh),
        };
        let draw = match &self.draw {
            Some(name) => parse_draw(name)?,
            None => volley::pacing::DEFAULT_DRAW,
        };
        Ok(WindowOptions {
            compare: Vec::new(),
            equal_cost: false,
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
            script,
            history_budget: (self.history_budget as usize) << 20,
            warm_up_ticks: self.warm_up_ticks,
            display,
            policy,
            draw,
        })
    }
}

/// Every window error is the environment's (exit code 4).
pub fn window_failure(e: AppError) -> Failure {
    match e {
        AppError::NoDisplay(_) | AppError::Gpu(_) | AppError::Io(_) | AppError::Recording(_) => {
            fail(EXIT_ENVIRONMENT, e)
        }
    }
}

/// Prints what a window run leaves behind: its recordings, one line each, and with a frame
/// limit each lane's state (tick, bodies, aim, closest passes by targets) and the median frame
/// time.
pub fn report(display: &DisplayArgs, summary: &RunSummary) {
    for r in &summary.recordings {
        println!("{r}");
    }
    if display.exit_after_frames.is_some() {
        for lane in &summary.lanes {
            println!("{lane}");
        }
        if let Some(lines) = &summary.probe {
            println!("probe: {}", lines.join("; "));
        }
        println!("{}", summary.pacing);
        println!("forces: {}", summary.forces.join("; "));
    }
    if let (Some(_), Some(interval), Some(work), Some(ui), Some(triangles)) = (
        display.exit_after_frames,
        summary.interval_ms,
        summary.work_ms,
        summary.ui_ms,
        summary.ui_triangles,
    ) {
        println!(
            "window: {} frames, median frame {interval:.2} ms, of which work {work:.2} ms \
             (UI {ui:.2} ms, {triangles} triangles), on {}",
            summary.frames, summary.adapter
        );
    }
}
