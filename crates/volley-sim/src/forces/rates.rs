//! How fast a body's acceleration can change along a short piece of its path: the bounds the
//! event search takes its curvature margins from (docs/physics.md, "Declared events").
//!
//! Along a path, `a' = (da/dp) V + (da/dV) a + da/dt`. A piece's [`Reach`] says where the path
//! can be (a box, the speeds, the times); [`Rates`] bound the three parts' norms over it:
//! `|da/dp| <= p`, `|da/dV| <= v`, `|da/dt| <= t`. Gravity and a constant force give zeros
//! (so under them the search's bounds are exact), a linear term its coefficient; the
//! non-linear terms a bound over the reach (quadratic and Mach drag by their steepest growth
//! with speed, a point mass at the nearest the piece can come to it). A game's own term cannot
//! be looked into: it is taken to change by up to its own size across a piece.

use glam::DVec3;

use super::{Forces, ThrustDirection};
use crate::body::Mass;

/// Where a piece of a body's path can be, over `duration` seconds from time `t0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// The low corner of a box the piece stays in (m).
    pub lo: DVec3,
    /// Its high corner (m).
    pub hi: DVec3,
    /// The largest speed along the piece (m/s).
    pub vmax: f64,
    /// The smallest (m/s), 0 if it may stop.
    pub vmin: f64,
    /// The mean acceleration over the piece: the change of velocity over its length (m/s^2).
    pub mean_accel: DVec3,
    /// Sim time at its start (s).
    pub t0: f64,
    /// Its length (s).
    pub duration: f64,
}

impl Reach {
    /// The distance from `c` to the box (0 inside it).
    pub fn distance_to(&self, c: DVec3) -> f64 {
        (self.lo - c).max(c - self.hi).max(DVec3::ZERO).length()
    }
}

/// Bounds on the parts of the acceleration's rate of change along a piece: `|da/dp| <= p`
/// (1/s^2), `|da/dV| <= v` (1/s), `|da/dt| <= t` (m/s^3). Infinite where nothing can be said
/// (a piece passing through a point mass's centre).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rates {
    /// Against the position (1/s^2).
    pub p: f64,
    /// Against the velocity (1/s).
    pub v: f64,
    /// Against the time (m/s^3).
    pub t: f64,
}

/// How much faster than its coefficient a velocity-dependent motor or a game's own term is
/// taken to change.
const UNKNOWN_RATE: f64 = 2.0;

/// A density scale height of the standard atmosphere's lowest layer, shortened (m): the
/// density falls by at most 1/8000 of itself per metre up to 11 km (about 1/9500 near sea
/// level).
const DENSITY_SCALE: f64 = 8000.0;

impl Forces {
    /// The rates of every declared term over `r` for a body of mass `w`.
    pub(crate) fn rates_over(&self, r: &Reach, w: Mass) -> Rates {
        let m = w.m;
        let mut out = Rates::default();
        if let Some(b) = self.linear_drag {
            out.v += b / m;
        }
        if let Some(c) = self.quadratic_drag {
            out.v += 2.0 * c * r.vmax / m;
        }
        if let Some(s) = self.spring {
            let k = s.stiffness / m;
            out.p += if s.rest_length == 0.0 {
                k
            } else {
                // The gradient of k (|d| - L) d/|d| has eigenvalues k and k (1 - L/|d|).
                let d = r.distance_to(s.anchor);
                k * (s.rest_length / d - 1.0).abs().max(1.0)
            };
            out.v += s.damping / m;
        }
        if let Some(pm) = self.point_mass {
            let d = r.distance_to(pm.center);
            out.p += 2.0 * pm.mu / (d * d * d);
        }
        if let Some(d) = &self.mach_drag {
            // The densest air is the lowest; the wind is fastest at the top of a profile.
            let (density, _) = d.air.at(r.lo.z);
            let wind = d.wind_at(r.lo.z).length().max(d.wind_at(r.hi.z).length());
            let umax = r.vmax + wind;
            let spin_rate = w.launch.spin.length();
            let spin_cd = d.spin.map_or(0.0, |s| s.drag_per_spin * spin_rate);
            let q = d.size.half_area(m) * density / m;
            let grow = d.curve.table().rate_bound() + 2.0 * spin_cd;
            out.v += q * umax * grow;
            // Height: the density's fall and the wind's shear.
            let shear = d.wind.map_or(0.0, |w| {
                if w.exponent == 0.0 {
                    0.0
                } else {
                    let z = r.lo.z.max(1e-3 * w.reference_height);
                    w.velocity.length() * w.exponent * libm::pow(z / w.reference_height, w.exponent)
                        / z
                }
            });
            out.p += q * umax * (umax * grow / DENSITY_SCALE + grow * shear);
            if let (Some(s), crate::forces::DragSize::Diameter { diameter, .. }) = (d.spin, d.size)
            {
                // The lift, `(rho/2) C_L(S) A |u| (w_hat x u)`: at most 3 C_L,max |u| per unit
                // of velocity (S C_L' <= C_L for Nathan's fit), and its decay in time.
                let half_area = (std::f64::consts::PI / 8.0) * diameter * diameter;
                let ql = half_area * density / m * s.lift.max_coefficient();
                out.v += 3.0 * ql * umax;
                let decay = match s.decay {
                    crate::forces::SpinDecay::None => 0.0,
                    crate::forces::SpinDecay::Time(tau) => 1.0 / tau,
                    crate::forces::SpinDecay::Nathan(tau) => {
                        umax / (tau * crate::forces::NATHAN_DECAY_SPEED)
                    }
                };
                out.t += ql * umax * umax * decay;
            }
        }
        if let Some(t) = &self.thrust {
            let points = t.curve.points();
            let (mut slope, mut most) = (0.0f64, 0.0f64);
            for w in points.windows(2) {
                slope = slope.max(((w[1].1 - w[0].1) / (w[1].0 - w[0].0)).abs());
                most = most.max(w[1].1).max(w[0].1);
            }
            let burnt = (w.launch.mass - t.propellant).max(f64::MIN_POSITIVE).min(m);
            out.t += slope / burnt;
            if let ThrustDirection::Velocity {
                rail_exit_speed, ..
            } = t.direction
            {
                // Along the velocity: it turns as the velocity does, `|T| / (m |V|)` per unit.
                let speed = r.vmin.max(rail_exit_speed).max(1e-3 * r.vmax);
                out.v += UNKNOWN_RATE * most / (burnt * speed);
            }
        }
        if !self.custom.is_empty() {
            // Cannot be looked into: the mean acceleration's size changing by up to itself
            // across the piece, whatever it depends on.
            if r.duration > 0.0 {
                out.t += UNKNOWN_RATE * r.mean_accel.length() / r.duration;
            }
        }
        out
    }
}
