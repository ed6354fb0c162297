//! `volley aim`: the launch that hits the target in the simulation, solved by shooting on the
//! stepped trajectory of the scene's (or the chosen) integrator at its tick, beside the
//! textbook aim and its miss. See docs/aiming.md.

use std::io::Write;

use clap::Args;
use glam::DVec3;

use volley::contact::Target;
use volley::firing::{self, Mode, Range, Shot};
use volley::scene::{self, Scene};

use super::args::{Overrides, apply_overrides, load_scene};
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, parse_vec3};

/// Arguments of `volley aim`.
#[derive(Args)]
pub struct AimArgs {
    /// Scene file or bundled scene name: its forces, dt, substeps, integrator, ground, walls,
    /// level surfaces, launcher and targets. Without one: gravity alone (`--gravity`), the closed form
    /// (`exact`) at 60 Hz, no ground.
    pub scene: Option<String>,
    /// The scene's settings replaced for this solve.
    #[command(flatten)]
    pub overrides: Overrides,
    /// Launch point X,Y,Z (m); default: the scene's launcher.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub from: Option<DVec3>,
    /// Target centre X,Y,Z (m) at launch; default: the scene's target `--target`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub to: Option<DVec3>,
    /// Which of the scene's targets (0 is the first).
    #[arg(long, default_value_t = 0, conflicts_with = "to")]
    pub target: usize,
    /// Target velocity X,Y,Z (m/s): a moving target, intercepted with its lead.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target_velocity: Option<DVec3>,
    /// Launch speed (m/s): solve the elevation and azimuth, both arcs where both exist.
    /// Default with a scene: its launcher's speed.
    #[arg(long)]
    pub speed: Option<f64>,
    /// Launch elevation (degrees): solve the speed and azimuth.
    #[arg(long, conflicts_with_all = ["speed", "min_speed"], allow_hyphen_values = true)]
    pub elevation: Option<f64>,
    /// Solve the slowest launch that reaches the target.
    #[arg(long, conflicts_with = "speed")]
    pub min_speed: bool,
    /// Gravitational acceleration (m/s^2, down -z) when no scene is given.
    #[arg(long)]
    pub gravity: Option<f64>,
    /// Mass of the shot (kg); default: the scene's launcher's (drag divides by it).
    #[arg(long)]
    pub mass: Option<f64>,
    /// Whether the scene's ground, walls and level surfaces can block the shot.
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    pub contacts: String,
    /// Longest flight (s) a solution may take.
    #[arg(long, default_value_t = firing::DEFAULT_MAX_FLIGHT_TIME)]
    pub max_flight_time: f64,
    /// A holdover table instead, at the ranges FROM:TO:STEP (m) along a level line of sight
    /// from the launcher (e.g. 100:1000:100), against the zero `--zero`.
    #[arg(long, value_name = "FROM:TO:STEP", conflicts_with_all = ["to", "elevation", "min_speed", "speed"])]
    pub holdover: Option<String>,
    /// The holdover table's zero range (m); default: its first range.
    #[arg(long, requires = "holdover")]
    pub zero: Option<f64>,
    /// The sight's height above the bore (m) for the holdover table.
    #[arg(long, default_value_t = 0.0381, requires = "holdover")]
    pub sight_height: f64,
}

/// `FROM:TO:STEP` as the ranges it lists, or the line saying what was expected, naming
/// `flag`.
pub(super) fn ranges_of(flag: &str, text: &str) -> Result<Vec<f64>, Failure> {
    let bad = || {
        fail(
            EXIT_INPUT,
            format!(
                "{flag}: expected FROM:TO:STEP in m with 0 < FROM <= TO and STEP > 0, \
                 at most 1000 ranges, got `{text}`"
            ),
        )
    };
    let parts: Vec<f64> = text
        .split(':')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let [from, to, step] = parts[..] else {
        return Err(bad());
    };
    if !(from > 0.0 && to >= from && step > 0.0 && to.is_finite()) || (to - from) / step > 999.0 {
        return Err(bad());
    }
    // Each range from the index, never a running sum.
    let n = ((to - from) / step + 1e-9).floor() as u32;
    Ok((0..=n).map(|k| from + f64::from(k) * step).collect())
}

/// Prints the holdover table for `args.holdover`.
fn run_holdover(args: &AimArgs, spec: &str) -> Result<(), Failure> {
    let ranges = ranges_of("--holdover", spec)?;
    let scene = match &args.scene {
        Some(name) => load_scene(name, &args.overrides)?.1,
        None => return Err(fail(EXIT_INPUT, "--holdover: needs a scene")),
    };
    let zero = args.zero.unwrap_or(ranges[0]);
    let table = firing::holdover(&scene, args.sight_height, zero, &ranges)
        .map_err(|e| fail(EXIT_INPUT, e))?;
    let mut text = format!(
        "{} at dt {} s x{} substep(s) on {}; {} m/s, sight {} m above the bore, zero {} m at \
         elevation {:.4} deg\n",
        scene.integrator().name(),
        scene.dt(),
        scene.substeps(),
        scene.name(),
        scene.launcher().speed,
        args.sight_height,
        table.zero.0,
        table.zero.1
    );
    text += &format!(
        "{:>8} {:>10} {:>9} {:>8} {:>9} {:>7} {:>10} {:>12} {:>9}\n",
        "range_m",
        "elev_deg",
        "hold_mrad",
        "hold_moa",
        "hold_m",
        "time_s",
        "miss_m",
        "textbook_m",
        "path_mrad"
    );
    for r in &table.rows {
        let textbook = r
            .shot
            .textbook
            .map_or_else(|| "-".to_string(), |t| format!("{:.4}", t.miss));
        text += &format!(
            "{:>8} {:>10.4} {:>9.3} {:>8.2} {:>9.4} {:>7.3} {:>10.1e} {:>12} {:>9.3}\n",
            r.range,
            r.shot.elevation_deg,
            r.hold_mrad,
            r.hold_moa,
            r.hold_at_target,
            r.shot.flight_time,
            r.shot.miss,
            textbook,
            r.path_hold_mrad
        );
    }
    std::io::stdout()
        .lock()
        .write_all(text.as_bytes())
        .map_err(|e| fail(EXIT_ENVIRONMENT, e))
}

/// The scene when none is given: gravity alone, the closed form, 60 Hz.
fn free_flight(g: f64) -> Result<Scene, Failure> {
    if !(g.is_finite() && g >= 0.0) {
        return Err(fail(
            EXIT_INPUT,
            format!("--gravity: expected a non-negative number of m/s^2, got {g}"),
        ));
    }
    let text = format!(
        "Scene(name: \"free flight\", dt: 0.016666666666666666, integrator: Exact, \
         forces: [Gravity((0.0, 0.0, {}))])",
        -g
    );
    scene::parse(&text, "--gravity", "free flight").map_err(|e| fail(EXIT_INPUT, e))
}

fn range_of(args: &AimArgs) -> Result<(Range, Mode), Failure> {
    let scene = match &args.scene {
        Some(name) => {
            if args.gravity.is_some() {
                return Err(fail(
                    EXIT_INPUT,
                    "--gravity: only without a scene (a scene declares its own forces)",
                ));
            }
            load_scene(name, &args.overrides)?.1
        }
        None => {
            let mut scene = free_flight(args.gravity.unwrap_or(9.81))?;
            apply_overrides(&mut scene, &args.overrides)?;
            scene
        }
    };
    let target = match args.to {
        Some(center) => Target {
            center,
            radius: 0.5,
            velocity: DVec3::ZERO,
        },
        None => *scene.targets().get(args.target).ok_or_else(|| {
            fail(
                EXIT_INPUT,
                format!(
                    "--target {}: the scene has {} target(s); give --to X,Y,Z",
                    args.target,
                    scene.targets().len()
                ),
            )
        })?,
    };
    let mut range = Range::new(&scene, target);
    if let Some(from) = args.from {
        range.from = from;
    } else if args.scene.is_none() {
        return Err(fail(EXIT_INPUT, "--from: required without a scene"));
    }
    if let Some(u) = args.target_velocity {
        range.target.velocity = u;
    }
    if let Some(m) = args.mass {
        range.mass = m;
    }
    range.contacts = args.contacts == "on";
    range.max_flight_time = args.max_flight_time;
    let mode = match (args.speed, args.elevation, args.min_speed) {
        (Some(v), _, _) => Mode::Speed(v),
        (None, Some(e), _) => Mode::Elevation(e),
        (None, None, true) => Mode::MinSpeed,
        (None, None, false) if args.scene.is_some() => Mode::Speed(scene.launcher().speed),
        (None, None, false) => {
            return Err(fail(
                EXIT_INPUT,
                "--speed, --elevation or --min-speed: one is needed without a scene",
            ));
        }
    };
    Ok((range, mode))
}

/// Prints every solution with its check and the textbook's miss.
pub fn run(args: &AimArgs) -> Result<(), Failure> {
    if let Some(spec) = &args.holdover {
        return run_holdover(args, spec);
    }
    let (range, mode) = range_of(args)?;
    let shots = firing::solve(&range, mode).map_err(|e| fail(EXIT_INPUT, e))?;
    let s = &range.scene;
    let mut text = format!(
        "{} at dt {} s x{} substep(s) on {}; from ({}) to ({})",
        s.integrator().name(),
        s.dt(),
        s.substeps(),
        s.name(),
        vec3(range.from),
        vec3(range.target.center)
    );
    if range.target.velocity != DVec3::ZERO {
        text += &format!(" moving at ({}) m/s", vec3(range.target.velocity));
    }
    text.push('\n');
    for shot in &shots {
        text += &describe(shot);
    }
    std::io::stdout()
        .lock()
        .write_all(text.as_bytes())
        .map_err(|e| fail(EXIT_ENVIRONMENT, e))
}

fn vec3(v: DVec3) -> String {
    format!("{:.4}, {:.4}, {:.4}", v.x, v.y, v.z)
}

fn describe(shot: &Shot) -> String {
    let mut out = format!(
        "{:<9}: elevation {:.4} deg, azimuth {:.4} deg, speed {:.4} m/s, velocity ({}) m/s\n",
        shot.kind.label(),
        shot.elevation_deg,
        shot.azimuth_deg,
        shot.speed,
        vec3(shot.velocity)
    );
    out += &format!(
        "           arrives {:.4} s after launch, in tick {}; ",
        shot.flight_time, shot.arrival_tick
    );
    match shot.blocked {
        Some(b) => out += &format!("blocked: {}\n", firing::blocked_text(&b)),
        None => out += &format!("passes the centre within {:.1e} m\n", shot.miss),
    }
    match shot.textbook {
        Some(t) => {
            let (e, _) = firing::angles_of(t.velocity);
            out += &format!(
                "           textbook aim (elevation {e:.4} deg, {:.4} m/s) misses by {:.4} m\n",
                t.velocity.length(),
                t.miss
            );
        }
        None => out += "           textbook aim: none under gravity alone\n",
    }
    out
}
