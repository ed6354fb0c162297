//! What a firing solution can fail with, and the words for what blocks a shot.

use super::*;

/// Why no firing solution was found.
#[derive(Clone, Debug, PartialEq)]
pub enum FiringError {
    /// An input is not usable; names it.
    Invalid(String),
    /// The target's centre is below the ground plane.
    BelowGround {
        /// Height of the target's centre (m).
        target_z: f64,
        /// Height of the ground (m).
        ground: f64,
    },
    /// No launch at this speed reaches the target within the maximum flight time.
    OutOfReach {
        /// The speed asked for (m/s).
        speed: f64,
        /// The slowest launch that reaches the target (m/s), if one was found.
        min_speed: Option<f64>,
        /// Closest the stepped shot gets at the speed asked for (m), over elevations.
        best_miss: f64,
        /// The elevation of that closest shot (degrees).
        best_elevation_deg: f64,
    },
    /// No arrival time gives this elevation (below the line of sight, or vertical with the
    /// target off to the side); gives the range of elevations that do reach it.
    NoArcAtElevation {
        /// Elevation asked for (degrees).
        elevation_deg: f64,
        /// The lowest elevation that reaches the target (degrees): the line of sight.
        lowest_deg: f64,
        /// The highest elevation reached within the maximum flight time (degrees).
        highest_deg: f64,
    },
    /// The target is straight above or below the launch point: any speed above the minimum
    /// reaches it vertically, so an elevation does not pick one.
    VerticalNeedsSpeed {
        /// The slowest vertical launch that reaches it (m/s).
        min_speed: f64,
    },
    /// The only solutions are blocked by the ground, a wall or a level surface.
    Blocked(Vec<(ShotKind, Blocked)>),
    /// Newton's method did not converge for an arrival time the answer needs.
    Stalled {
        /// The arrival time being solved for (s after launch).
        flight_time: f64,
        /// The tick that arrival falls in.
        tick: u64,
        /// Iterations done.
        iterations: u32,
        /// Distance left between the stepped shot and the target's centre (m).
        residual: f64,
    },
    /// The stepped shot stopped being finite, or the world's divergence guard stopped it (the
    /// integrator is unstable at this step).
    Diverged {
        /// Arrival time being solved for (s).
        flight_time: f64,
        /// The tick the world stopped at, when the check in a world found it.
        tick: Option<u64>,
    },
    /// The shot fired in a world never came closest to the target: the solution is not
    /// trusted.
    Unverified {
        /// Arrival time of the solution (s).
        flight_time: f64,
    },
}

impl std::fmt::Display for FiringError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FiringError::Invalid(what) => f.write_str(what),
            FiringError::BelowGround { target_z, ground } => write!(
                f,
                "the target's centre (z = {target_z} m) is below the ground (z = {ground} m)"
            ),
            FiringError::OutOfReach {
                speed,
                min_speed,
                best_miss,
                best_elevation_deg,
            } => {
                write!(
                    f,
                    "out of reach at {speed} m/s: the closest shot (elevation \
                     {best_elevation_deg:.4} deg) passes {best_miss:.4} m from the target's centre"
                )?;
                match min_speed {
                    Some(v) => write!(f, "; it needs at least {v:.4} m/s"),
                    None => f.write_str("; no speed reaches it within the maximum flight time"),
                }
            }
            FiringError::NoArcAtElevation {
                elevation_deg,
                lowest_deg,
                highest_deg,
            } => write!(
                f,
                "no arc at elevation {elevation_deg} deg: elevations from {lowest_deg:.4} deg (the \
                 line of sight) to {highest_deg:.4} deg reach the target"
            ),
            FiringError::VerticalNeedsSpeed { min_speed } => write!(
                f,
                "the target is straight above or below: every vertical launch from {min_speed:.4} \
                 m/s reaches it, so give a speed, not an elevation"
            ),
            FiringError::Blocked(shots) => {
                f.write_str("every solution is blocked:")?;
                for (kind, b) in shots {
                    write!(f, " the {} {}", kind.label(), blocked_text(b))?;
                }
                Ok(())
            }
            FiringError::Stalled {
                flight_time,
                tick,
                iterations,
                residual,
            } => write!(
                f,
                "the solver stalled solving for arrival at {flight_time} s (tick {tick}): \
                 {residual:e} m from the target after {iterations} Newton iterations"
            ),
            FiringError::Diverged { flight_time, tick } => {
                write!(f, "the shot for arrival at {flight_time} s diverges")?;
                if let Some(tick) = tick {
                    write!(f, " at tick {tick}")?;
                }
                f.write_str(": the integrator is unstable at this step")
            }
            FiringError::Unverified { flight_time } => write!(
                f,
                "the solution for arrival at {flight_time} s never passed the target when fired \
                 in a world"
            ),
        }
    }
}

impl std::error::Error for FiringError {}

/// "hits the ground at 1.2 s (tick 6)".
pub fn blocked_text(b: &Blocked) -> String {
    let surface = match b.surface {
        Surface::Ground => "the ground".to_string(),
        s => s.to_string(),
    };
    format!("hits {surface} at {:.4} s (tick {})", b.time, b.tick)
}
