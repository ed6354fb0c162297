//! `volley range`: a scene's range table, the launcher's shot read at chosen distances
//! downrange by declared `Downrange` events (docs/aiming.md, "The range table").

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use volley::firing::{self, RangeTable};
use volley::scene::Scene;

use super::aim::ranges_of;
use super::args::{Overrides, load_scene};
use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail};

/// Arguments of `volley range`.
#[derive(Args)]
pub struct RangeArgs {
    /// Scene file or bundled scene name: its launcher (or first body), forces, integrator, dt
    /// and substeps.
    pub scene: String,
    /// The scene's settings replaced for this table.
    #[command(flatten)]
    pub overrides: Overrides,
    /// The ranges FROM:TO:STEP (m) downrange of the muzzle.
    #[arg(long, value_name = "FROM:TO:STEP", default_value = "100:1000:100")]
    pub ranges: String,
    /// Also write the table as CSV (full precision) to this file.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Longest flight (s).
    #[arg(long, default_value_t = firing::DEFAULT_MAX_FLIGHT_TIME)]
    pub max_flight_time: f64,
}

/// The CSV's columns, in order (units in the names).
const COLUMNS: [&str; 8] = [
    "range_m",
    "time_s",
    "height_m",
    "drop_m",
    "windage_m",
    "speed_mps",
    "mach",
    "energy_j",
];

pub fn run(args: &RangeArgs) -> Result<(), Failure> {
    let ranges = ranges_of("--ranges", &args.ranges)?;
    let scene = load_scene(&args.scene, &args.overrides)?.1;
    let table = firing::range_table(&scene, &ranges, args.max_flight_time)
        .map_err(|e| fail(EXIT_INPUT, e))?;
    if let Some(path) = &args.csv {
        // The file first: a table that printed but was not written would look like success.
        std::fs::write(path, csv(&table))
            .map_err(|e| fail(EXIT_ENVIRONMENT, format!("{}: {e}", path.display())))?;
    }
    std::io::stdout()
        .lock()
        .write_all(text(&scene, &table).as_bytes())
        .map_err(|e| fail(EXIT_ENVIRONMENT, e))
}

/// The table as printed: a header naming the shot, a row per range, the ranges not reached.
pub fn text(scene: &Scene, table: &RangeTable) -> String {
    let l = scene.launcher();
    let mut out = format!(
        "{} at dt {} s x{} substep(s) on {}; {:.3} m/s at elevation {:.4} deg, azimuth {:.4} \
         deg, {} kg from ({}, {}, {}); contacts off\n",
        scene.integrator().name(),
        scene.dt(),
        scene.substeps(),
        scene.name(),
        l.speed,
        l.elevation_deg,
        l.azimuth_deg,
        l.mass,
        l.position.x,
        l.position.y,
        l.position.z,
    );
    out += &format!(
        "{:>8} {:>8} {:>10} {:>10} {:>10} {:>9} {:>6} {:>10}\n",
        "range_m", "time_s", "height_m", "drop_m", "windage_m", "speed_mps", "mach", "energy_j"
    );
    for r in &table.rows {
        let mach = r
            .mach
            .map_or_else(|| "-".to_string(), |m| format!("{m:.3}"));
        out += &format!(
            "{:>8} {:>8.4} {:>10.4} {:>10.4} {:>10.4} {:>9.2} {:>6} {:>10.1}\n",
            r.range, r.time, r.height, r.drop, r.windage, r.speed, mach, r.energy
        );
    }
    if !table.unreached.is_empty() {
        let list: Vec<String> = table.unreached.iter().map(f64::to_string).collect();
        out += &format!("not reached: {} m\n", list.join(", "));
    }
    out
}

/// The table as CSV: a header, then each row at full precision (shortest round-trip digits);
/// `mach` empty without a Mach drag.
pub fn csv(table: &RangeTable) -> String {
    let mut out = COLUMNS.join(",") + "\n";
    for r in &table.rows {
        let mach = r.mach.map_or_else(String::new, |m| m.to_string());
        out += &format!(
            "{},{},{},{},{},{},{},{}\n",
            r.range, r.time, r.height, r.drop, r.windage, r.speed, mach, r.energy
        );
    }
    out
}
