//! A motor's thrust against the body's own time since launch, with its mass falling as the
//! propellant burns: the term [`super::Forces::thrust`] holds.
//!
//! # The model
//! The curve is a table of `(time since launch s, thrust N)` points, straight lines between them
//! and nothing outside them: the form of a RASP `.eng` file, the format model rocket motors are
//! published in (thrustcurve.org). It starts at the first point (ignition), ends at the last
//! (burnout), whose thrust must be 0. The delivered impulse `I(tau)` is the exact integral of
//! those lines, and the propellant mass `m_p` burns in proportion to it, the RASP convention
//! (and OpenRocket's and RocketPy's): `m(tau) = m_0 - m_p I(tau) / I_total`, `m_0` the mass at
//! launch.
//!
//! # Momentum and mass together
//! The seed's state is `S = <mV, p>` with `dS/dt = <F, V>` for a body of fixed mass. A rocket
//! is the body less the gas it has thrown out: with the thrust `T` the force the gas exerts on
//! what remains, `m dV/dt = F + T` (Tsiolkovsky, and McCoy's "Modern Exterior Ballistics",
//! ch. 13), so the remaining body's momentum changes by `d(mV)/dt = F + T + (dm/dt) V`, the last
//! term the momentum the burnt mass carries off at the body's own speed.
//!
//! Volley keeps the seed's state at every step boundary, `mV` the true momentum of the mass
//! `m` the mass column holds, and steps within a step at the mass it started with: each force
//! evaluation at stage time `t` returns `(m_n / m(t)) (F + T)`, evaluated at the mass `m(t)`,
//! so `d(m_n V)/dt = m_n (F + T) / m(t)` is exactly `m_n dV/dt`, and every integrator keeps its
//! order. After the step the mass column takes `m(t_{n+1})` and the momentum
//! `m(t_{n+1}) V_{n+1}`: the momentum that left with the gas is dropped there, in one place.

use std::sync::Arc;

use glam::DVec3;

/// A thrust curve: `(time since launch s, thrust N)` points, straight lines between them.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrustCurve {
    /// The points, times strictly increasing from >= 0, thrusts >= 0, the last 0.
    points: Vec<(f64, f64)>,
    /// Impulse delivered up to each point (N s), by the trapezoid rule, which is exact for
    /// straight lines.
    impulse: Vec<f64>,
}

/// Why a thrust curve was refused: the point (from 0) and what it should have been.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrustCurveError {
    /// Index of the offending point.
    pub index: usize,
    /// What was expected.
    pub expected: &'static str,
}

impl std::fmt::Display for ThrustCurveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "point {} (counted from 0): {}",
            self.index, self.expected
        )
    }
}

impl std::error::Error for ThrustCurveError {}

impl ThrustCurve {
    /// A curve from its points, checked: at least two, times finite, >= 0 and strictly
    /// increasing (no repeated or backward time), thrusts finite and >= 0, the last 0 (burnout).
    pub fn new(points: Vec<(f64, f64)>) -> Result<ThrustCurve, ThrustCurveError> {
        let err = |index, expected| Err(ThrustCurveError { index, expected });
        if points.len() < 2 {
            return err(points.len(), "a thrust curve needs at least two points");
        }
        for (i, &(t, f)) in points.iter().enumerate() {
            if !(t.is_finite() && t >= 0.0) {
                return err(i, "time must be a finite number >= 0 s");
            }
            if i > 0 && t <= points[i - 1].0 {
                return err(
                    i,
                    "times must increase strictly (no repeated or earlier time)",
                );
            }
            if !(f.is_finite() && f >= 0.0) {
                return err(i, "thrust must be a finite number >= 0 N");
            }
        }
        if points[points.len() - 1].1 != 0.0 {
            return err(
                points.len() - 1,
                "the last point is burnout: its thrust must be 0",
            );
        }
        let mut impulse = Vec::with_capacity(points.len());
        let mut total = 0.0;
        impulse.push(0.0);
        for w in points.windows(2) {
            total += 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0);
            impulse.push(total);
        }
        if total <= 0.0 {
            return err(0, "the curve must deliver some impulse");
        }
        Ok(ThrustCurve { points, impulse })
    }

    /// The points.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The segment holding time `tau`: the index `i` with `t_i <= tau < t_{i+1}`, or `None`
    /// before ignition and from burnout on.
    #[inline]
    fn segment(&self, tau: f64) -> Option<usize> {
        let last = self.points.len() - 1;
        if !(tau >= self.points[0].0 && tau < self.points[last].0) {
            return None;
        }
        // The number of points at or before tau, less one; tables are short (tens of points).
        Some(self.points.partition_point(|p| p.0 <= tau) - 1)
    }

    /// Thrust (N) at `tau` s after launch: 0 before ignition and after burnout.
    #[inline]
    pub fn thrust(&self, tau: f64) -> f64 {
        self.segment(tau).map_or(0.0, |i| {
            let ((t0, f0), (t1, f1)) = (self.points[i], self.points[i + 1]);
            f0 + (f1 - f0) * ((tau - t0) / (t1 - t0))
        })
    }

    /// Impulse (N s) delivered by `tau` s after launch: the exact integral of the lines.
    #[inline]
    pub fn impulse(&self, tau: f64) -> f64 {
        match self.segment(tau) {
            Some(i) => {
                let (t0, f0) = self.points[i];
                let d = tau - t0;
                self.impulse[i] + d * (f0 + 0.5 * d * self.slope(i))
            }
            None if tau < self.points[0].0 => 0.0,
            None => self.total_impulse(),
        }
    }

    #[inline]
    fn slope(&self, i: usize) -> f64 {
        let ((t0, f0), (t1, f1)) = (self.points[i], self.points[i + 1]);
        (f1 - f0) / (t1 - t0)
    }

    /// The whole curve's impulse (N s).
    pub fn total_impulse(&self) -> f64 {
        self.impulse[self.impulse.len() - 1]
    }

    /// Burnout: the last point's time (s since launch).
    pub fn burnout(&self) -> f64 {
        self.points[self.points.len() - 1].0
    }
}

/// Which way a motor pushes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThrustDirection {
    /// Along a fixed unit vector (world axes).
    Fixed(DVec3),
    /// Along the launch rail `along` (a unit vector) until the body's speed reaches
    /// `rail_exit_speed` (m/s), and along its velocity from then on: a rocket held to its rail
    /// while it gathers speed (so it leaves the pad along it whatever the ground does to its
    /// velocity first), turning with its flight path afterwards (a gravity turn).
    Velocity {
        /// The rail's direction (unit vector, world axes).
        along: DVec3,
        /// The speed (m/s) at which the body leaves the rail.
        rail_exit_speed: f64,
    },
}

/// A motor: its thrust curve, the propellant it burns and which way it pushes.
#[derive(Clone, Debug, PartialEq)]
pub struct Thrust {
    /// The curve, against each body's time since its launch.
    pub curve: Arc<ThrustCurve>,
    /// Propellant mass (kg) burnt over the whole curve, in proportion to the impulse delivered.
    pub propellant: f64,
    /// Which way it pushes.
    pub direction: ThrustDirection,
}

impl Thrust {
    /// A motor from its curve's `(s since launch, N)` points (checked: [`ThrustCurve::new`]),
    /// the propellant it burns (kg) and which way it pushes.
    ///
    /// ```
    /// use glam::DVec3;
    /// use volley_sim::{Thrust, ThrustDirection};
    ///
    /// let motor = Thrust::new(
    ///     vec![(0.0, 0.0), (0.2, 14.0), (1.86, 0.0)],
    ///     0.0108,
    ///     ThrustDirection::Fixed(DVec3::Z),
    /// )?;
    /// assert_eq!(motor.curve.burnout(), 1.86);
    /// # Ok::<(), volley_sim::ThrustCurveError>(())
    /// ```
    pub fn new(
        points: Vec<(f64, f64)>,
        propellant: f64,
        direction: ThrustDirection,
    ) -> Result<Thrust, ThrustCurveError> {
        Ok(Thrust {
            curve: Arc::new(ThrustCurve::new(points)?),
            propellant,
            direction,
        })
    }

    /// The mass (kg) at `tau` s after launch of a body launched with `launch_mass` kg.
    #[inline]
    pub fn mass_at(&self, tau: f64, launch_mass: f64) -> f64 {
        if self.propellant == 0.0 {
            return launch_mass;
        }
        launch_mass - self.propellant * (self.curve.impulse(tau) / self.curve.total_impulse())
    }

    /// The thrust force (N) at `tau` s after launch on a body moving at `v`.
    #[inline]
    pub fn force(&self, tau: f64, v: DVec3) -> DVec3 {
        let f = self.curve.thrust(tau);
        if f == 0.0 {
            return DVec3::ZERO;
        }
        let d = match self.direction {
            ThrustDirection::Fixed(d) => d,
            ThrustDirection::Velocity {
                along,
                rail_exit_speed,
            } => {
                let speed = v.length();
                if speed > 0.0 && speed >= rail_exit_speed {
                    v / speed
                } else {
                    along
                }
            }
        };
        f * d
    }
}
