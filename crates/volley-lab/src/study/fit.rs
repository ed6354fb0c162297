//! The observed order of accuracy, and the cheapest setting that meets a tolerance.

use volley_sim::internals::integrate::Integrator;

use super::reference::Reference;
use super::{Outcome, StudyPoint};

/// The slope of log(error) against log(dt) for one integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OrderFit {
    /// Least-squares slope over `points` runs (at least 2 distinct dts).
    Fitted {
        /// The observed order.
        order: f64,
        /// Runs used.
        points: usize,
    },
    /// Every completed run's error is at the rounding floor: the method is exact here (Verlet,
    /// midpoint and RK4 under constant force, for example).
    AtRoundingFloor,
    /// Fewer than two usable runs (diverged, or a single dt).
    TooFewPoints,
}

impl std::fmt::Display for OrderFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OrderFit::Fitted { order, points } => write!(f, "{order:.2} ({points} dts)"),
            OrderFit::AtRoundingFloor => f.write_str(
                "exact here (every error below the rounding floor, 1e-10 of the extent)",
            ),
            OrderFit::TooFewPoints => f.write_str("n/a (fewer than 2 usable dts)"),
        }
    }
}

/// Error (m) below which a run counts as exact: the reference's own error estimate times 10, or
/// 1e-10 of the largest reference position (a few thousand ulps of accumulated rounding),
/// whichever is larger.
pub fn rounding_floor(reference: &Reference) -> f64 {
    (10.0 * reference.error_estimate()).max(1e-10 * reference.extent)
}

/// Least-squares slope of ln(max position error) on ln(dt) over `integrator`'s completed runs
/// whose error is above the floor of their reference.
pub fn observed_order(
    points: &[StudyPoint],
    integrator: Integrator,
    references: &[Reference],
) -> OrderFit {
    let floor_of = |dt: f64| {
        references
            .iter()
            .find(|r| r.dt == dt)
            .map_or(0.0, rounding_floor)
    };
    let mine: Vec<&StudyPoint> = points
        .iter()
        .filter(|p| p.integrator == integrator && p.outcome == Outcome::Completed)
        .collect();
    let usable: Vec<(f64, f64)> = mine
        .iter()
        .filter_map(|p| {
            let e = p.errors?.max_position;
            (e > floor_of(p.dt)).then(|| (p.dt.ln(), e.ln()))
        })
        .collect();
    if usable.len() < 2 {
        return if !mine.is_empty() && usable.is_empty() {
            OrderFit::AtRoundingFloor
        } else {
            OrderFit::TooFewPoints
        };
    }
    let n = usable.len() as f64;
    let (mx, my) = usable
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = usable.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    if sxx == 0.0 {
        return OrderFit::TooFewPoints;
    }
    OrderFit::Fitted {
        order: sxy / sxx,
        points: usable.len(),
    }
}

/// Index of the completed point with the fewest force evaluations per simulated second whose
/// largest trajectory error is at most `tolerance` (m); ties go to the larger dt.
pub fn cheapest(points: &[StudyPoint], tolerance: f64) -> Option<usize> {
    points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.errors.is_some_and(|e| e.max_position <= tolerance))
        .min_by(|(_, a), (_, b)| {
            a.evals_per_second
                .total_cmp(&b.evals_per_second)
                .then(b.dt.total_cmp(&a.dt))
        })
        .map(|(i, _)| i)
}
