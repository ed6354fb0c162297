//! The stability pre-check: before a run, is each integrator's step inside its linear stability
//! region for this scene, and if not, what step, substep count or integrator would be?
//!
//! Every body sees, near its state, the linear test system `x'' = -W x - K x'` (per axis, mass
//! folded in), built from the scene's declared terms:
//!
//! | term | contributes | treated by implicit Euler |
//! |---|---|---|
//! | spring, rest length 0 | `W += k/m` (exact: the force is linear) | implicitly |
//! | spring, rest length L > 0 | `W += k/m` (the radial stiffness; the tangential one, `k (1 - L/r)`, is smaller for `r > L/2`) | explicitly |
//! | spring damping c | `K += c/m` | implicitly |
//! | linear drag b | `K += b/m` (exact) | implicitly |
//! | quadratic drag c | `K += c v_max / m`: at speed `|v|` the force `-c |v| v` is linear drag with `b = c |v|`, so the speed itself grows under a step exactly when that drag would (explicit Euler: `|v'| = |v| |1 - h c |v| / m|`); `v_max` is the larger of the launch speed and the terminal speed in the uniform field. (The Jacobian's rate `2 c |v|` governs how nearby paths separate, not whether the speed blows up.) | explicitly |
//! | Mach drag | as quadratic drag with `c/m = rho(0) Cd_max Cd_body A / (2 Cd m)`: the curve's largest coefficient at the ground's density, a bound on the real rate; `v_max` is the larger of the speed through the air at launch and the terminal speed with that coefficient | explicitly |
//! | point mass mu | `W += mu / r_p^3`: the orbital frequency at periapsis `r_p` of the body's Kepler orbit (the radial eigenvalue `+2 mu/r^3` is a physical instability every method shares, not a numerical one) | explicitly |
//!
//! Gravity and constant forces shift the equilibrium and add nothing. For each integrator the
//! one-step amplification matrix `M` of the test system at the sub-step `h = dt / substeps` is
//! formed by applying that integrator's update (the same algebra as [`volley_sim::internals::integrate`], on
//! scalars; a unit test checks the two agree) to the basis states, and the step is stable when
//! the spectral radius `rho(M) <= 1`. For the pure cases this reproduces the limits of
//! [`Integrator::info`]: `w h < 2` for symplectic Euler and Verlet, `2.828` for RK4, never for
//! explicit Euler and midpoint on an undamped spring, `k h <= 2` (RK4: 2.785) on drag.
//!
//! The window calls [`check`] (or [`check_world`] after a command changed the integrator) and
//! shows [`StabilityReport::warnings`]; headless runs print the same lines to stderr before the
//! table.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use volley_sim::internals::integrate::{FOREST_RUTH_C1, FOREST_RUTH_C2, Integrator};
use volley_sim::internals::scene::Scene;
use volley_sim::internals::world::World;

mod growth;
mod report;

use growth::*;
pub use growth::{Growth, growth_per_step};
pub use report::growth_text;

/// The linear test system one body sees: `x'' = -(w2_lin + w2_nl) x - (k_lin + k_nl) x'`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stiffness {
    /// Squared frequency (1/s^2) of terms implicit Euler treats implicitly (zero-rest spring).
    pub w2_lin: f64,
    /// Damping rate (1/s) of terms implicit Euler treats implicitly (linear drag, spring damping).
    pub k_lin: f64,
    /// Squared frequency (1/s^2) of terms treated explicitly everywhere (spring with rest
    /// length, point mass).
    pub w2_nl: f64,
    /// Damping rate (1/s) of terms treated explicitly everywhere (quadratic drag).
    pub k_nl: f64,
}

impl Stiffness {
    /// Angular frequency w (rad/s) of the undamped part.
    pub fn w(&self) -> f64 {
        (self.w2_lin + self.w2_nl).sqrt()
    }

    /// Damping rate k (1/s).
    pub fn k(&self) -> f64 {
        self.k_lin + self.k_nl
    }

    /// Whether the body sees no stiffness at all (then every integrator is stable).
    pub fn is_zero(&self) -> bool {
        self.w2_lin + self.w2_nl == 0.0 && self.k() == 0.0
    }

    /// The stiffness of a body of mass `m` launched at `v0` from `p0` under the scene's forces,
    /// without spin.
    pub fn of_body(scene: &Scene, m: f64, p0: DVec3, v0: DVec3) -> Stiffness {
        Stiffness::of_spinning(scene, m, p0, v0, 0.0)
    }

    /// [`Stiffness::of_body`] for a body spinning at `spin` rad/s at launch: a spun Mach drag
    /// counts the spin's drag at that rate and the largest lift coefficient its model reaches
    /// (as S grows without bound) as more drag coefficient, an upper bound on both. A motor is
    /// left out: it judges the launch state, and a motor that speeds the body up and burns its
    /// mass away raises the drag's rate past it (for a rocket the verdict is a lower bound).
    pub fn of_spinning(scene: &Scene, m: f64, p0: DVec3, v0: DVec3, spin: f64) -> Stiffness {
        let f = &scene.forces();
        let mut s = Stiffness {
            k_lin: f.drag_rate(m),
            ..Stiffness::default()
        };
        if let Some(spring) = f.spring {
            s.k_lin += spring.damping / m;
            if spring.rest_length == 0.0 {
                s.w2_lin += spring.stiffness / m;
            } else {
                s.w2_nl += spring.stiffness / m;
            }
        }
        if let Some(c) = f.quadratic_drag {
            let uniform = f.gravity.unwrap_or(DVec3::ZERO) + f.constant.unwrap_or(DVec3::ZERO) / m;
            let terminal = if c > 0.0 {
                (m * uniform.length() / c).sqrt()
            } else {
                0.0
            };
            s.k_nl += c * v0.length().max(terminal) / m;
        }
        if let Some(d) = &f.mach_drag {
            // As quadratic drag with the curve's largest coefficient at the ground's density,
            // at the larger of the speed through the air at launch and the terminal speed.
            let mut q = d.worst_quadratic_rate(m);
            if let (Some(sp), volley_sim::internals::forces::DragSize::Diameter { diameter, .. }) =
                (d.spin, d.size)
            {
                let (density, _) = d.air.at(0.0);
                let lift = if spin > 0.0 {
                    sp.lift.max_coefficient()
                } else {
                    0.0
                };
                let extra = sp.drag_per_spin * spin + lift;
                q += (std::f64::consts::PI / 8.0) * diameter * diameter * density * extra / m;
            }
            let g = f.gravity.unwrap_or(DVec3::ZERO).length();
            let terminal = if q > 0.0 { (g / q).sqrt() } else { 0.0 };
            let air_speed = (v0 - d.wind_at(p0.z)).length();
            s.k_nl += q * air_speed.max(terminal);
        }
        if let Some(pm) = f.point_mass {
            let rp = periapsis(pm.mu, p0 - pm.center, v0);
            if rp > 0.0 {
                s.w2_nl += pm.mu / (rp * rp * rp);
            }
        }
        s
    }
}

/// How far below the current step the search for a stable one goes: `2^-30`, a step a billion
/// times smaller is no practical suggestion.
const MIN_STEP_HALVINGS: i32 = 30;

/// Largest stable step (s) of `integrator` on `s`, searching below `h`: `None` if even
/// `h / 2^30` grows (unstable at every practical step), `Some(h)` if `h` itself is stable.
pub fn max_stable_step(integrator: Integrator, s: &Stiffness, h: f64) -> Option<f64> {
    let stable = |h: f64| growth_per_step(integrator, s, h).stable;
    if stable(h) {
        return Some(h);
    }
    // Undamped, a method with no oscillator limit grows at every step, however small (for
    // midpoint by (w h)^4 / 4 per step, below rounding long before the search would end).
    if s.k() == 0.0 && integrator.info().oscillator_limit.is_none() {
        return None;
    }
    let mut lo = (1..=MIN_STEP_HALVINGS)
        .map(|j| h * 0.5f64.powi(j))
        .find(|&x| stable(x))?;
    let mut hi = 2.0 * lo;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) { lo = mid } else { hi = mid }
    }
    Some(lo)
}

/// What the pre-check says about one integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The integrator.
    pub integrator: Integrator,
    /// Spectral radius of its step on the stiffest body (1 = neutral; above 1 it diverges).
    pub growth: f64,
    /// Whether the step is inside its linear stability region for every body.
    pub stable: bool,
    /// Largest stable sub-step (s); `None` when no step is stable (explicit Euler on an
    /// undamped spring).
    pub max_step: Option<f64>,
    /// Fewest substeps per tick that make the tick stable, if any number does.
    pub substeps: Option<u32>,
}

/// The pre-check of one scene at one timestep and substep count.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityReport {
    /// The scene's name.
    pub scene: String,
    /// Tick length (s).
    pub dt: f64,
    /// Integrator steps per tick.
    pub substeps: u32,
    /// The integrator that will run.
    pub chosen: Integrator,
    /// Bodies the scene declares; index `body_count` in [`StabilityReport::stiffest`] stands for
    /// a projectile fired from the launcher.
    pub body_count: usize,
    /// The stiffest body (index into the scene's bodies, or `body_count` for the launcher's
    /// projectiles) and its stiffness; `None` when no body sees any stiffness.
    pub stiffest: Option<(usize, Stiffness)>,
    /// One verdict per integrator the scene allows, in [`Integrator::ALL`] order.
    pub verdicts: Vec<Verdict>,
}

/// Checks `scene` at its own timestep, substeps and integrator.
pub fn check(scene: &Scene) -> StabilityReport {
    check_at(scene, scene.dt(), scene.substeps(), scene.integrator())
}

/// Checks a running world (its integrator may have been switched by a command).
pub fn check_world(world: &World) -> StabilityReport {
    check_at(
        world.scene(),
        world.dt(),
        world.substeps(),
        world.integrator(),
    )
}

/// Checks `scene` at tick length `dt` (s) with `substeps` per tick, `chosen` being the
/// integrator that will run.
pub fn check_at(scene: &Scene, dt: f64, substeps: u32, chosen: Integrator) -> StabilityReport {
    let substeps = substeps.max(1);
    let h = dt / f64::from(substeps);
    let launcher = scene.launcher().body();
    let bodies: Vec<Stiffness> = scene
        .bodies()
        .iter()
        .chain(std::iter::once(&launcher))
        .map(|b| Stiffness::of_spinning(scene, b.mass, b.position, b.velocity, b.spin.length()))
        .collect();
    let allowed = Integrator::ALL
        .into_iter()
        .filter(|i| volley_sim::internals::scene::check_integrator(*i, scene.forces()).is_ok());
    let verdicts = allowed
        .map(|integrator| verdict(integrator, &bodies, h, dt))
        .collect();
    // The first body of the largest severity (so a launcher identical to body 0 does not win).
    let stiffest = bodies
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, s)| !s.is_zero())
        .fold(None::<(usize, Stiffness)>, |best, (i, s)| match best {
            Some((_, b)) if severity(&b, h) >= severity(&s, h) => best,
            _ => Some((i, s)),
        });
    StabilityReport {
        scene: scene.name().to_string(),
        dt,
        substeps,
        chosen,
        body_count: scene.bodies().len(),
        stiffest,
        verdicts,
    }
}

/// How hard a body is to integrate at step `h`: the larger of `w h` and `k h`.
fn severity(s: &Stiffness, h: f64) -> f64 {
    (s.w() * h).max(s.k() * h)
}

fn verdict(integrator: Integrator, bodies: &[Stiffness], h: f64, dt: f64) -> Verdict {
    let stiff: Vec<&Stiffness> = bodies.iter().filter(|s| !s.is_zero()).collect();
    let growth_at = |h: f64| {
        stiff
            .iter()
            .map(|s| growth_per_step(integrator, s, h))
            .fold(
                Growth {
                    rho: 1.0,
                    stable: true,
                },
                |a, b| Growth {
                    rho: a.rho.max(b.rho),
                    stable: a.stable && b.stable,
                },
            )
    };
    let Growth {
        rho: growth,
        stable,
    } = growth_at(h);
    let max_step = stiff.iter().try_fold(h, |m, s| {
        max_stable_step(integrator, s, h).map(|b| m.min(b))
    });
    let substeps = max_step.and_then(|m| {
        if stable {
            return Some(1);
        }
        // The first whole count strictly past dt / m, checked on every body (and a few more in
        // case the stable set is not an interval).
        let first = (dt / m).floor() + 1.0;
        (0..4).map(|extra| first + f64::from(extra)).find_map(|n| {
            let ok = n <= f64::from(u32::MAX) && growth_at(dt / n).stable;
            ok.then_some(n as u32)
        })
    });
    Verdict {
        integrator,
        growth,
        stable,
        max_step,
        substeps,
    }
}

#[cfg(test)]
mod tests;
