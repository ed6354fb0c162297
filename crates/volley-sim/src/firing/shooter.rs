//! Shooters: the launch velocity that arrives at the target at a given time, on the stepped
//! path (Newton on the integrator's own flow) or on the discrete closed form.

use super::*;

/// A shooter: the launch velocity for an arrival time, one way or another.
pub(super) trait Shooter {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError>;
}

/// Shooting on the stepped trajectory.
pub(super) struct Stepped<'a> {
    pub(super) range: &'a Range,
    pub(super) integrator: Integrator,
    pub(super) forces: Forces,
    pub(super) tolerance: f64,
    /// The shot's mass; its spin follows the launch's azimuth ([`Stepped::mass_for`]).
    pub(super) w: Mass,
    pub(super) hs: f64,
    /// The launch on the world's clock: 0, as the world check ([`flight_world`]) flies the
    /// shot from a scene started at 0, so a term that reads the clock sees the same times in
    /// both.
    pub(super) t0: f64,
}

impl<'a> Stepped<'a> {
    pub(super) fn new(range: &'a Range) -> Stepped<'a> {
        Stepped {
            range,
            integrator: range.scene.integrator,
            forces: range.scene.forces.clone(),
            tolerance: range.scene.tolerance,
            w: Mass::new(range.mass),
            hs: range.sub_step(),
            t0: 0.0,
        }
    }

    /// The shot's mass with its launch: at `t0`, spinning as the scene's launcher spins a shot
    /// fired along `v0` (the spin's axis turns with the azimuth), as the world check fires it.
    pub(super) fn mass_for(&self, v0: DVec3) -> Mass {
        let azimuth = libm::atan2(v0.y, v0.x).to_degrees();
        Mass::launched(
            self.w.m,
            crate::body::Launch {
                time: self.t0,
                mass: self.w.m,
                spin: self.range.scene.launcher.spin_at(azimuth),
            },
        )
    }

    pub(super) fn launch_state(&self, v0: DVec3) -> BodyState {
        BodyState {
            p: self.range.from,
            mv: self.range.mass * v0,
        }
    }

    pub(super) fn samples(&self, v0: DVec3, count: u64) -> Vec<(BodyState, DVec3)> {
        let samples = Samples {
            s0: self.launch_state(v0),
            t0: self.t0,
            w: self.mass_for(v0),
            hs: self.hs,
            count,
        };
        visit(self.integrator, &self.forces, self.tolerance, samples)
    }

    pub(super) fn position(&self, v0: DVec3, t: f64) -> DVec3 {
        let (steps, tau) = split_time(t, self.hs);
        let at = At {
            s0: self.launch_state(v0),
            t0: self.t0,
            w: self.mass_for(v0),
            hs: self.hs,
            steps,
            tau,
        };
        visit(self.integrator, &self.forces, self.tolerance, at).p
    }

    /// The textbook guess: constant acceleration, no drag.
    pub(super) fn guess(&self, t: f64) -> DVec3 {
        let a = self.forces.linear_part(self.range.mass).a0;
        (self.range.target_at(t) - self.range.from - (0.5 * t * t) * a) / t
    }
}

impl Shooter for Stepped<'_> {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError> {
        let goal = self.range.target_at(t);
        let tolerance = RESIDUAL_TOLERANCE * self.range.scale();
        // What rounding alone leaves: each of the `n` steps rounds the position by up to half
        // an ulp of its size, so `p(T)` is only defined to about `n ulp(|p|)`; far from the
        // origin over a long flight that exceeds the tolerance, and no Newton step helps.
        let steps = split_time(t, self.hs).0 as f64 + 1.0;
        let size = goal
            .abs()
            .max_element()
            .max(self.range.from.abs().max_element());
        let floor = rounding_floor(steps, size);
        let residual = |v: DVec3| self.position(v, t) - goal;
        let jacobian = |v: DVec3, r: DVec3| {
            let delta = 1e-5 * v.length().max(1.0);
            let column = |e: DVec3| (residual(v + delta * e) - r) / delta;
            DMat3::from_cols(column(DVec3::X), column(DVec3::Y), column(DVec3::Z))
        };
        let tick = split_time(t, self.range.scene.dt()).0 + 1;
        let stalled = |iterations, residual: f64| FiringError::Stalled {
            flight_time: t,
            tick,
            iterations,
            residual,
        };
        let mut v = self.guess(t);
        let mut r = residual(v);
        if !r.is_finite() {
            return Err(FiringError::Diverged {
                flight_time: t,
                tick: None,
            });
        }
        let mut inverse = jacobian(v, r).inverse();
        let mut last = r.length();
        let iterations = self.range.newton_iterations;
        for iteration in 1..=iterations {
            if last <= tolerance {
                return Ok(v);
            }
            if !inverse.is_finite() {
                return Err(stalled(iteration, last));
            }
            let next = v - inverse * r;
            let r_next = residual(next);
            let size = r_next.length();
            if !size.is_finite() {
                return Err(FiringError::Diverged {
                    flight_time: t,
                    tick: None,
                });
            }
            if size > 0.5 * last {
                // Slow: the Jacobian is stale (a nonlinear force); take it afresh.
                inverse = jacobian(next, r_next).inverse();
            }
            if size >= last && last <= tolerance + floor {
                // At the rounding floor: no iteration makes it smaller.
                return Ok(v);
            }
            (v, r, last) = (next, r_next, size);
        }
        if last <= tolerance {
            Ok(v)
        } else {
            Err(stalled(iterations, last))
        }
    }
}

/// The closed form of explicit and semi-implicit Euler under a constant acceleration `a`, from
/// `p0` with velocity `v0`, at `t` after launch with step `hs`: after `k` steps,
/// `v_k = v0 + k hs a` and `p_k = p0 + k hs v0 + hs^2 a k (k -+ 1) / 2` (the sum of the
/// velocities before each step for explicit Euler, after it for semi-implicit), then the
/// partial step `tau` as the integrator takes it: `p_k + tau v_k` (explicit) or
/// `p_k + tau v_k + tau^2 a` (semi-implicit). `None` for other integrators.
pub fn discrete_position(
    integrator: Integrator,
    (p0, v0, a): (DVec3, DVec3, DVec3),
    hs: f64,
    t: f64,
) -> Option<DVec3> {
    let (k, tau) = split_time(t, hs);
    let k = k as f64;
    let vk = v0 + (k * hs) * a;
    match integrator {
        Integrator::ExplicitEuler => {
            let pk = p0 + (k * hs) * v0 + (hs * hs * k * (k - 1.0) * 0.5) * a;
            Some(pk + tau * vk)
        }
        Integrator::SemiImplicitEuler => {
            let pk = p0 + (k * hs) * v0 + (hs * hs * k * (k + 1.0) * 0.5) * a;
            Some(pk + tau * vk + (tau * tau) * a)
        }
        _ => None,
    }
}

/// Aiming with the discrete closed form: `p(T)` is affine in `v0`, so `v(T)` is one division.
pub(super) struct Discrete<'a> {
    pub(super) range: &'a Range,
    pub(super) a: DVec3,
    pub(super) hs: f64,
}

impl Shooter for Discrete<'_> {
    fn launch_for(&self, t: f64) -> Result<DVec3, FiringError> {
        let r = self.range;
        let integrator = r.scene.integrator;
        let base = discrete_position(integrator, (r.from, DVec3::ZERO, self.a), self.hs, t)
            .ok_or_else(|| {
                FiringError::Invalid(format!(
                    "{} has no discrete closed form here",
                    integrator.name()
                ))
            })?;
        Ok((r.target_at(t) - base) / t)
    }
}
