//! `volley aim`: both launch solutions, or a clear "out of reach".

use std::io::Write;

use clap::Args;
use glam::DVec3;

use super::{EXIT_ENVIRONMENT, EXIT_INPUT, Failure, fail, parse_vec3};

/// Arguments of `volley aim`.
#[derive(Args)]
pub struct AimArgs {
    /// Launch point X,Y,Z (m).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    from: DVec3,
    /// Target X,Y,Z (m).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    to: DVec3,
    /// Launch speed (m/s).
    #[arg(long)]
    speed: f64,
    /// Gravitational acceleration (m/s^2), pointing down -z.
    #[arg(long, default_value_t = 9.81)]
    gravity: f64,
}

/// Prints the high and the low arc.
pub fn run(args: &AimArgs) -> Result<(), Failure> {
    let [high, low] = volley::exact::aim(args.from, args.to, args.speed, args.gravity)
        .map_err(|e| fail(EXIT_INPUT, e))?;
    let mut out = std::io::stdout().lock();
    for (name, s) in [("high", high), ("low", low)] {
        writeln!(
            out,
            "{name:<4} arc: elevation {:.4} deg, azimuth {:.4} deg, flight time {:.4} s, \
             velocity ({:.4}, {:.4}, {:.4}) m/s",
            s.elevation_deg, s.azimuth_deg, s.flight_time, s.velocity.x, s.velocity.y, s.velocity.z
        )
        .map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    }
    Ok(())
}
