//! Closed-form solutions: the exact references every integrator is measured against.
//!
//! Which force sets have one ([`closed_form`], [`Forces::without_closed_form`]):
//! - **every linear scene**: any mix of gravity, constant force, linear drag and a
//!   zero-rest-length spring with any damping, `x'' = a0 - kd x' - w2 (x - anchor)`, under-,
//!   critically or over-damped ([`linear_flow`], derived in its module docs); without a spring
//!   this is the drag flow [`linear_drag_flow`];
//! - **a lone point mass**: Kepler's problem in universal variables, elliptic, parabolic and
//!   hyperbolic ([`KeplerOrbit`]), except past the collision of a radial orbit with the centre.
//!
//! Quadratic drag, a spring with a rest length, and a point mass together with any other term
//! have none.
//!
//! Transcendental functions come from the `libm` crate (a port of musl's libm), not the platform's
//! C library, so a closed form gives the same bits on every target.

use glam::DVec3;

use crate::body::BodyState;
use crate::forces::{ForceModel, Forces};

mod compensated;
mod extrapolation;
mod kepler;
mod linear;
mod series;

pub use extrapolation::{ExtrapolationError, extrapolate, extrapolate_from};
pub use kepler::{
    Anomaly, KeplerError, KeplerOrbit, MAX_ITERATIONS, RADIAL_PERIAPSIS, kepler_flow,
    kepler_flow_momentum,
};
pub use linear::{LinearKernel, linear_flow, linear_flow_momentum};
pub use series::{stumpff_c2, stumpff_c3};

/// `(1 - e^-x) / x`, with its limit 1 at 0.
#[inline]
fn phi1(x: f64) -> f64 {
    if x == 0.0 { 1.0 } else { -libm::expm1(-x) / x }
}

/// `(x - 1 + e^-x) / x^2`, with its limit 1/2 at 0; a series where the formula cancels.
fn phi2(x: f64) -> f64 {
    if x.abs() < 1e-2 {
        phi2_series(x)
    } else {
        (x + libm::expm1(-x)) / (x * x)
    }
}

/// Taylor series of [`phi2`]: 1/2 - x/6 + x^2/24 - x^3/120 + x^4/720 - x^5/5040; the first
/// omitted term is below 2.5e-17 for |x| <= 1e-2, under half an ulp of the sum.
fn phi2_series(x: f64) -> f64 {
    let terms = [
        1.0 / 2.0,
        -1.0 / 6.0,
        1.0 / 24.0,
        -1.0 / 120.0,
        1.0 / 720.0,
        -1.0 / 5040.0,
    ];
    terms.iter().rev().fold(0.0, |acc, c| acc * x + c)
}

/// Exact flow of `a = a0 - k v` over time `t`: returns (p, v).
///
/// With `vT = a0 / k` the solution is `v = vT + (v0 - vT) e^-kt`,
/// `p = p0 + vT t + (v0 - vT)(1 - e^-kt) / k`; written as
/// `v = v0 e^-kt + a0 t phi1(kt)` and `p = p0 + v0 t phi1(kt) + a0 t^2 phi2(kt)` it has no
/// cancellation for small `k t` and reduces to constant acceleration at `k = 0`.
///
/// Always inlined: it is the `exact` step of every scene without a spring or a point mass, and
/// out of line (LLVM's choice once the closed forms grew) it cost the loop a call per body:
/// 25 times the step on `bench/gravity` at 1e3 bodies, where `k` is the constant 0, and +18 %
/// instructions a body-step on `bench/drag` (callgrind).
#[inline(always)]
pub fn linear_drag_flow(p0: DVec3, v0: DVec3, a0: DVec3, k: f64, t: f64) -> (DVec3, DVec3) {
    if k == 0.0 {
        return constant_accel(p0, v0, a0, t);
    }
    let x = k * t;
    let (f1, f2) = (phi1(x), phi2(x));
    let v = libm::exp(-x) * v0 + (t * f1) * a0;
    let p = p0 + (t * f1) * v0 + (t * t * f2) * a0;
    (p, v)
}

/// Constant acceleration: `p = p0 + v0 t + a t^2 / 2`, `v = v0 + a t`.
#[inline(always)]
pub fn constant_accel(p0: DVec3, v0: DVec3, a: DVec3, t: f64) -> (DVec3, DVec3) {
    (p0 + t * v0 + (0.5 * t * t) * a, v0 + t * a)
}

/// Undamped oscillator `x'' = -w^2 x` (x measured from the equilibrium): returns (x, v).
///
/// The textbook form, for reference; [`closed_form`] and the `exact` integrator use
/// [`linear_flow`], which covers it with damping and without dividing by `w`.
pub fn oscillator(x0: DVec3, v0: DVec3, w: f64, t: f64) -> (DVec3, DVec3) {
    let (s, c) = (libm::sin(w * t), libm::cos(w * t));
    (c * x0 + (s / w) * v0, (-w * s) * x0 + c * v0)
}

/// The state of a body at time `t` after `s0`, from the closed form of `forces`, if one exists.
///
/// Covers every linear scene (gravity, constant force, linear drag and a zero-rest-length
/// spring with any damping, in any combination: [`linear_flow`]) and a lone point mass
/// ([`kepler_flow`]; `None` at and after a radial orbit's collision with the centre, see
/// [`KeplerError::Collision`]). `None` for the force sets [`Forces::without_closed_form`]
/// refuses. Contacts are not included. This is the flow the `exact` integrator applies per
/// step, evaluated once over `t`.
pub fn closed_form(forces: &Forces, s0: BodyState, m: f64, t: f64) -> Option<BodyState> {
    if forces.without_closed_form().is_some() {
        return None;
    }
    let v0 = s0.mv / m;
    let (p, v) = match forces.lone_point_mass() {
        Some(pm) => kepler_flow(s0.p, v0, &pm, t).ok()?,
        None => linear_flow(s0.p, v0, &forces.linear_part(m), t),
    };
    Some(BodyState { p, mv: m * v })
}

/// Time (s) for a body at height `z0` rising at `vz` under gravity of magnitude `g` (> 0) to
/// come down to height `zg`: the larger root of `z0 + vz t - g t^2 / 2 = zg`, i.e.
/// `t* = (vz + sqrt(vz^2 + 2 g (z0 - zg))) / g`. `None` if it never gets there.
pub fn ground_impact_time(z0: f64, vz: f64, g: f64, zg: f64) -> Option<f64> {
    let disc = vz * vz + 2.0 * g * (z0 - zg);
    if g.is_nan() || g <= 0.0 || disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    // Both forms are the same root; pick the one without cancellation.
    let t = if vz >= 0.0 {
        (vz + root) / g
    } else {
        2.0 * (z0 - zg) / (root - vz)
    };
    (t >= 0.0).then_some(t)
}

/// One way to launch from a point to hit another under gravity along -z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaunchSolution {
    /// Elevation above the horizontal (degrees), -90 to 90.
    pub elevation_deg: f64,
    /// Azimuth from +x towards +y (degrees), -180 to 180.
    pub azimuth_deg: f64,
    /// Time of flight to the target (s).
    pub flight_time: f64,
    /// Launch velocity (m/s).
    pub velocity: DVec3,
}

/// Which of the two launch solutions to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Arc {
    /// The steeper, slower arc (the seed's "slow arrival").
    High,
    /// The flatter, faster arc.
    Low,
}

/// Why no launch solution exists.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AimError {
    /// The target cannot be reached at this speed; the slowest launch that reaches it is given.
    OutOfReach {
        /// Minimum launch speed (m/s) that reaches the target.
        min_speed: f64,
    },
    /// Launch and target are the same point.
    SamePoint,
    /// Speed or gravity is not a positive finite number.
    InvalidInput,
}

impl std::fmt::Display for AimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AimError::OutOfReach { min_speed } => write!(
                f,
                "out of reach: the target needs a launch speed of at least {min_speed:.4} m/s"
            ),
            AimError::SamePoint => f.write_str("launch point and target are the same point"),
            AimError::InvalidInput => f.write_str("speed and gravity must be positive and finite"),
        }
    }
}

impl std::error::Error for AimError {}

/// Both launch solutions (high arc, low arc) from `from` to `to` at `speed` under gravity `g`
/// (m/s^2, magnitude, along -z).
///
/// `tan(theta) = (v^2 +- sqrt(v^4 - g (g dx^2 + 2 dz v^2))) / (g dx)`, the low root computed as
/// the product of roots over the high one to avoid cancellation. Directly above or below
/// (dx = 0) the answers are vertical launches and no division by dx happens: the low solution
/// is the earlier arrival.
///
/// ```
/// use volley_sim::internals::exact::aim;
/// use glam::DVec3;
/// let [high, low] = aim(DVec3::new(10.0, 0.0, 2.0), DVec3::new(50.0, 0.0, 20.0), 30.0, 9.81).unwrap();
/// assert_eq!(format!("{:.2} {:.2}", high.elevation_deg, low.elevation_deg), "75.17 39.06");
/// ```
pub fn aim(from: DVec3, to: DVec3, speed: f64, g: f64) -> Result<[LaunchSolution; 2], AimError> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(speed) || !positive(g) || !from.is_finite() || !to.is_finite() {
        return Err(AimError::InvalidInput);
    }
    let d = to - from;
    let dx = (d.x * d.x + d.y * d.y).sqrt();
    let dz = d.z;
    let v2 = speed * speed;
    if dx == 0.0 {
        return aim_vertical(dz, speed, g);
    }
    let disc = v2 * v2 - g * (g * dx * dx + 2.0 * dz * v2);
    if disc < 0.0 {
        let min_speed = (g * (dz + (dx * dx + dz * dz).sqrt())).sqrt();
        return Err(AimError::OutOfReach { min_speed });
    }
    let tan_high = (v2 + disc.sqrt()) / (g * dx);
    let tan_low = (g * dx * dx + 2.0 * dz * v2) / (g * dx * dx * tan_high);
    let (ux, uy) = (d.x / dx, d.y / dx);
    let azimuth_deg = libm::atan2(d.y, d.x).to_degrees();
    let solve = |tan: f64| {
        let cos = 1.0 / (1.0 + tan * tan).sqrt();
        let sin = tan * cos;
        LaunchSolution {
            elevation_deg: libm::atan(tan).to_degrees(),
            azimuth_deg,
            flight_time: dx / (speed * cos),
            velocity: speed * DVec3::new(cos * ux, cos * uy, sin),
        }
    };
    Ok([solve(tan_high), solve(tan_low)])
}

fn aim_vertical(dz: f64, speed: f64, g: f64) -> Result<[LaunchSolution; 2], AimError> {
    if dz == 0.0 {
        return Err(AimError::SamePoint);
    }
    let v2 = speed * speed;
    let up_disc = v2 - 2.0 * g * dz;
    if up_disc < 0.0 {
        return Err(AimError::OutOfReach {
            min_speed: (2.0 * g * dz).sqrt(),
        });
    }
    let root = up_disc.sqrt();
    let vertical = |elevation_deg: f64, flight_time: f64| LaunchSolution {
        elevation_deg,
        azimuth_deg: 0.0,
        flight_time,
        velocity: DVec3::new(0.0, 0.0, speed * elevation_deg.signum()),
    };
    // Fired up: passes height dz at (v -+ root) / g; the rising pass exists only above.
    let up_late = vertical(90.0, (speed + root) / g);
    if dz > 0.0 {
        // (v - root) / g rewritten without cancellation.
        let up_early = vertical(90.0, 2.0 * dz / (speed + root));
        Ok([up_late, up_early])
    } else {
        // Fired down: -dz = v t + g t^2 / 2.
        let down = vertical(-90.0, -2.0 * dz / (speed + root));
        Ok([up_late, down])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phi2_series_and_formula_agree_at_the_switch() {
        // (x - 1 + e^-x) / x^2 at x = 0.01, to 17 digits (50-digit decimal arithmetic).
        let truth = 0.498_337_491_680_535_74;
        let (series, formula) = (phi2_series(0.01), phi2(0.01));
        // The series is good to an ulp; the formula loses about log10(2 / x) = 2.3 digits to
        // cancellation at the switch, so allow 1e-13 relative there.
        assert!(
            (series - truth).abs() <= 2.0 * f64::EPSILON * truth,
            "{series}"
        );
        assert!((formula - truth).abs() <= 1e-13 * truth, "{formula}");
    }

    #[test]
    fn drag_flow_matches_the_reference_form() {
        let (p0, v0, g, k, t) = (
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(5.0, 0.0, 20.0),
            DVec3::new(0.0, 0.0, -9.81),
            0.7,
            2.3,
        );
        let vt = g / k;
        let e = (-k * t).exp();
        let p_ref = p0 + vt * t + (v0 - vt) * (1.0 - e) / k;
        let v_ref = vt + (v0 - vt) * e;
        let (p, v) = linear_drag_flow(p0, v0, g, k, t);
        // Both are within a few ulps of the true value; 1e-12 relative leaves room for the
        // reference form's cancellation (|vT t| is about 23 m here).
        assert!(
            (p - p_ref).length() < 1e-12 * p_ref.length(),
            "{p} vs {p_ref}"
        );
        assert!(
            (v - v_ref).length() < 1e-12 * v_ref.length(),
            "{v} vs {v_ref}"
        );
    }

    #[test]
    fn vertical_aim_needs_no_horizontal_distance() {
        let [high, low] = aim(DVec3::ZERO, DVec3::new(0.0, 0.0, 10.0), 20.0, 9.81).unwrap();
        assert_eq!((high.elevation_deg, low.elevation_deg), (90.0, 90.0));
        assert!(low.flight_time < high.flight_time);
        let [up, down] = aim(DVec3::ZERO, DVec3::new(0.0, 0.0, -10.0), 5.0, 9.81).unwrap();
        assert_eq!((up.elevation_deg, down.elevation_deg), (90.0, -90.0));
        assert_eq!(
            aim(DVec3::ZERO, DVec3::new(0.0, 0.0, 100.0), 5.0, 9.81),
            Err(AimError::OutOfReach {
                min_speed: (2.0f64 * 9.81 * 100.0).sqrt()
            })
        );
    }
}
