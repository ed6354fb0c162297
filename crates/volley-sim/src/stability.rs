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
//! | point mass mu | `W += mu / r_p^3`: the orbital frequency at periapsis `r_p` of the body's Kepler orbit (the radial eigenvalue `+2 mu/r^3` is a physical instability every method shares, not a numerical one) | explicitly |
//!
//! Gravity and constant forces shift the equilibrium and add nothing. For each integrator the
//! one-step amplification matrix `M` of the test system at the sub-step `h = dt / substeps` is
//! formed by applying that integrator's update (the same algebra as [`crate::integrate`], on
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

use crate::integrate::{FOREST_RUTH_C1, FOREST_RUTH_C2, Integrator};
use crate::scene::{BodySpec, Scene};
use crate::world::World;

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

    /// The stiffness of a body of mass `m` launched at `v0` from `p0` under the scene's forces.
    pub fn of_body(scene: &Scene, m: f64, p0: DVec3, v0: DVec3) -> Stiffness {
        let f = &scene.forces;
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
        if let Some(pm) = f.point_mass {
            let rp = periapsis(pm.mu, p0 - pm.center, v0);
            if rp > 0.0 {
                s.w2_nl += pm.mu / (rp * rp * rp);
            }
        }
        s
    }
}

/// Periapsis distance (m) of the Kepler orbit through relative position `r` with velocity `v`.
fn periapsis(mu: f64, r: DVec3, v: DVec3) -> f64 {
    let (rn, l2) = (r.length(), r.cross(v).length_squared());
    let energy = 0.5 * v.length_squared() - mu / rn;
    let e = (1.0 + 2.0 * energy * l2 / (mu * mu)).max(0.0).sqrt();
    // r_p = l^2 / (mu (1 + e)) holds for every conic; never above the current distance.
    (l2 / (mu * (1.0 + e))).min(rn)
}

/// The increment `(dx, dv)` of one step of `integrator` on the scalar test system
/// `x'' = -W x - K x'` (mass 1) from `(x, v)`: the same update as the integrator's scheme, with
/// implicit Euler treating only the `_lin` part implicitly. Increments rather than new states,
/// so that the growth `|1 + mu|` of a nearly neutral step is not lost in rounding against 1.
fn linear_increment(
    integrator: Integrator,
    s: &Stiffness,
    h: f64,
    (x, v): (f64, f64),
) -> (f64, f64) {
    let (w2, k) = (s.w2_lin + s.w2_nl, s.k());
    let a = |x: f64, v: f64| -w2 * x - k * v;
    match integrator {
        Integrator::ExplicitEuler => (h * v, h * a(x, v)),
        Integrator::SemiImplicitEuler => {
            let dv = h * a(x, v);
            (h * (v + dv), dv)
        }
        Integrator::VelocityVerlet => {
            let a0 = a(x, v);
            let dv_half = 0.5 * h * a0;
            let dx = h * (v + dv_half);
            // With damping Volley evaluates the end force at the Euler-predicted velocity.
            let v_pred = if k == 0.0 { v + dv_half } else { v + h * a0 };
            (dx, dv_half + 0.5 * h * a(x + dx, v_pred))
        }
        Integrator::Midpoint => {
            let (mx, mv) = (x + 0.5 * h * v, v + 0.5 * h * a(x, v));
            (h * mv, h * a(mx, mv))
        }
        Integrator::Rk4 => {
            let stage = |x: f64, v: f64| (v, a(x, v));
            let k1 = stage(x, v);
            let k2 = stage(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = stage(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = stage(x + h * k3.0, v + h * k3.1);
            (
                h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
                h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
            )
        }
        Integrator::ForestRuth => {
            // Three generalised Verlet steps; the damping is implicit in the first half kick.
            let (c1, c2) = (FOREST_RUTH_C1, FOREST_RUTH_C2);
            let (mut dx, mut dv) = (0.0, 0.0);
            for c in [c1, c2, c1] {
                let (hc, (x, v)) = (c * h, (x + dx, v + dv));
                let dv_half = (0.5 * hc * (-w2 * x) - 0.5 * hc * k * v) / (1.0 + 0.5 * hc * k);
                let step_dx = hc * (v + dv_half);
                let v_half = v + dv_half;
                let step_dv = dv_half + 0.5 * hc * (-w2 * (x + step_dx) - k * v_half);
                (dx, dv) = (dx + step_dx, dv + step_dv);
            }
            (dx, dv)
        }
        Integrator::ImplicitMidpoint => {
            // The `_lin` part by the midpoint rule, the rest at the Euler-predicted midpoint.
            let (mx, mv) = (x + 0.5 * h * v, v + 0.5 * h * a(x, v));
            let a_nl = -s.w2_nl * mx - s.k_nl * mv;
            let damp = 0.5 * h * s.k_lin + 0.25 * h * h * s.w2_lin;
            let dv = (h * (a_nl - s.w2_lin * x) - 2.0 * damp * v) / (1.0 + damp);
            (h * (v + 0.5 * dv), dv)
        }
        // Dormand-Prince never gets here: `growth_per_step` answers for it first.
        Integrator::Dopri5 | Integrator::ImplicitEuler | Integrator::Exact => {
            // v' = (v + h (a_nl - W_lin x)) / (1 + h K_lin + h^2 W_lin), written as v' - v.
            let a_nl = -s.w2_nl * x - s.k_nl * v;
            let den = 1.0 + h * s.k_lin + h * h * s.w2_lin;
            let dv = h * (a_nl - s.w2_lin * x - s.k_lin * v - h * s.w2_lin * v) / den;
            (h * (v + dv), dv)
        }
    }
}

/// Growth of the exact flow over `h`: `e^(h Re(lambda_max))` of the test system.
fn exact_growth(s: &Stiffness, h: f64) -> f64 {
    let (w2, k) = (s.w2_lin + s.w2_nl, s.k());
    let disc = k * k - 4.0 * w2;
    let re = if disc > 0.0 {
        -2.0 * w2 / (k + disc.sqrt())
    } else {
        -0.5 * k
    };
    libm::exp(h * re)
}

/// How one step amplifies the test system.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Growth {
    /// Spectral radius of the amplification matrix (1 = neutral).
    pub rho: f64,
    /// Whether `rho <= 1`, decided on the increments so rounding against 1 cannot flip it.
    pub stable: bool,
}

/// Spectral radius of `integrator`'s amplification matrix on `s` at step `h`, and whether it
/// is at most 1.
pub fn growth_per_step(integrator: Integrator, s: &Stiffness, h: f64) -> Growth {
    // The closed form grows as the flow does; Dormand-Prince's controller shrinks its internal
    // steps until the error estimate (and with it the growth) is bounded, at whatever cost.
    if matches!(integrator, Integrator::Exact | Integrator::Dopri5) {
        return Growth {
            rho: exact_growth(s, h),
            stable: true,
        };
    }
    // Forest-Ruth's backward substep (length c2 h, c2 = -1.70) solves its half kick with the
    // quadratic drag implicitly: `(h c2 / 2) k s^2/|v| + s = |rhs|` has no real root once
    // `2 |c2| h k_nl > 1` (k h > 0.29), and the step turns NaN however the linearisation grows.
    if integrator == Integrator::ForestRuth && 2.0 * FOREST_RUTH_C2.abs() * h * s.k_nl > 1.0 {
        return Growth {
            rho: f64::INFINITY,
            stable: false,
        };
    }
    // M = I + D; the eigenvalues of M are 1 + mu for the eigenvalues mu of D.
    let (a, c) = linear_increment(integrator, s, h, (1.0, 0.0));
    let (b, d) = linear_increment(integrator, s, h, (0.0, 1.0));
    let (tr, det) = (a + d, a * d - b * c);
    let disc = tr * tr - 4.0 * det;
    // Rounding allowance: a few ulps of the increments' own size. Forest-Ruth's increments
    // are sums over three substeps whose own increments are of order 1 (the middle one runs
    // backwards 1.7 h), so `det(M) - 1 = tr + det` carries a few ulps of 1, not of the sum.
    let mut tol = 8.0 * f64::EPSILON * (tr.abs() + det.abs());
    if integrator == Integrator::ForestRuth {
        tol = tol.max(64.0 * f64::EPSILON);
    }
    // The edge at 1 + mu = -1 is excluded: there the two eigenvalues meet at -1 (symplectic
    // Euler and Verlet at w h = 2 exactly) and the matrix is defective, so the state grows
    // linearly (tripling the spring's stretch in the first step). The edge at +1 stays: free
    // flight (k = 0) is a defective +1, and moving at constant velocity is not a divergence.
    if disc < 0.0 {
        // mu = alpha +- i beta: |1 + mu|^2 = 1 + 2 alpha + alpha^2 + beta^2 = 1 + tr + det.
        let excess = tr + det;
        Growth {
            rho: (1.0 + excess).sqrt(),
            stable: excess <= tol && tr > -4.0 + tol,
        }
    } else {
        let root = disc.sqrt();
        let big = if tr >= 0.0 {
            0.5 * (tr + root)
        } else {
            0.5 * (tr - root)
        };
        let small = if big != 0.0 { det / big } else { 0.0 };
        let (hi, lo) = (big.max(small), big.min(small));
        Growth {
            rho: (1.0 + hi).abs().max((1.0 + lo).abs()),
            stable: hi <= tol && lo > -2.0 + tol,
        }
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
    check_at(scene, scene.dt(), scene.substeps, scene.integrator)
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
    let launcher = BodySpec {
        mass: scene.launcher.mass,
        radius: scene.launcher.radius,
        position: scene.launcher.position,
        velocity: scene.launcher.velocity(),
    };
    let bodies: Vec<Stiffness> = scene
        .bodies
        .iter()
        .chain(std::iter::once(&launcher))
        .map(|b| Stiffness::of_body(scene, b.mass, b.position, b.velocity))
        .collect();
    let allowed = Integrator::ALL
        .into_iter()
        .filter(|i| crate::scene::check_integrator(*i, &scene.forces).is_ok());
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
        scene: scene.name.clone(),
        dt,
        substeps,
        chosen,
        body_count: scene.bodies.len(),
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

impl StabilityReport {
    /// The verdict for `integrator`, if the scene allows it.
    pub fn verdict(&self, integrator: Integrator) -> Option<&Verdict> {
        self.verdicts.iter().find(|v| v.integrator == integrator)
    }

    /// Whether the integrator that will run is stable at this step.
    pub fn chosen_is_stable(&self) -> bool {
        self.verdict(self.chosen).is_none_or(|v| v.stable)
    }

    /// The integrators that are unstable at this step.
    pub fn unstable(&self) -> impl Iterator<Item = &Verdict> {
        self.verdicts.iter().filter(|v| !v.stable)
    }

    /// Warning lines (no prefix) for a user about to run: empty when the chosen integrator is
    /// stable. Otherwise: the stiffness, the chosen integrator's growth, how to fix it (substeps,
    /// a smaller dt, a stable integrator), and whether every explicit method diverges.
    pub fn warnings(&self) -> Vec<String> {
        let Some(v) = self.verdict(self.chosen).filter(|v| !v.stable) else {
            return Vec::new();
        };
        let Some((body, s)) = self.stiffest else {
            return Vec::new();
        };
        let h = self.dt / f64::from(self.substeps);
        let mut lines = vec![format!(
            "stability: {} at h = {} s ({} substep{}): the stiffest body ({}) has {}",
            self.scene,
            sig(h),
            self.substeps,
            if self.substeps == 1 { "" } else { "s" },
            self.body_label(body),
            describe(&s, h),
        )];
        // On the edge itself the spectral radius is 1 and the growth is linear, not geometric.
        let growth = if v.growth <= 1.0 + 1e-12 {
            "on its edge, where two eigenvalues meet at -1 and the amplitude grows linearly".into()
        } else {
            format!("amplitude {} per step", growth_text(v.growth))
        };
        lines.push(format!(
            "{} is outside its linear stability region at this step: {growth}{}",
            v.integrator,
            limit_note(v.integrator),
        ));
        lines.push(format!("  fix: {}", self.fixes(v).join(", or ")));
        let explicit: Vec<_> = self
            .verdicts
            .iter()
            .filter(|v| {
                !matches!(
                    v.integrator,
                    Integrator::ImplicitEuler
                        | Integrator::Exact
                        | Integrator::ImplicitMidpoint
                        | Integrator::Dopri5
                )
            })
            .collect();
        if explicit.iter().all(|v| !v.stable) {
            let names: Vec<_> = explicit.iter().map(|v| v.integrator.name()).collect();
            lines.push(format!(
                "every explicit integrator diverges at this step ({})",
                names.join(", ")
            ));
        }
        lines
    }

    fn body_label(&self, index: usize) -> String {
        if index == self.body_count {
            "a launcher projectile".into()
        } else {
            format!("body {index}")
        }
    }

    /// The largest tick length (s), rounded down to three significant digits, at which `v`'s
    /// integrator is stable with the report's substeps; `None` when no step is stable.
    pub fn suggested_dt(&self, v: &Verdict) -> Option<f64> {
        v.max_step.map(|m| floor_sig(m * f64::from(self.substeps)))
    }

    /// Ways to make the step stable for `v`'s integrator: substeps, a smaller dt, another
    /// integrator.
    pub fn fixes(&self, v: &Verdict) -> Vec<String> {
        let mut fixes = Vec::new();
        if let (Some(n), Some((_, s))) = (v.substeps, self.stiffest) {
            let h = self.dt / f64::from(n);
            fixes.push(format!("--substeps {n} ({})", describe_short(&s, h)));
        }
        if let Some(dt) = self.suggested_dt(v) {
            fixes.push(format!("--dt {} or less", sig(dt)));
        }
        let stable: Vec<_> = self
            .verdicts
            .iter()
            .filter(|o| o.stable && o.integrator != Integrator::Exact)
            .map(|o| o.integrator.name())
            .collect();
        if !stable.is_empty() {
            fixes.push(format!(
                "--integrator {} (stable at this step)",
                stable.join(" / ")
            ));
        }
        fixes
    }
}

fn limit_note(integrator: Integrator) -> String {
    let info = integrator.info();
    match info.oscillator_limit {
        None => format!(
            " (never stable on an undamped spring; drag needs k h <= {})",
            sig(info.drag_limit)
        ),
        Some(l) if l.is_finite() => format!(
            " (needs w h < {} and k h <= {})",
            sig(l),
            sig(info.drag_limit)
        ),
        Some(_) => String::new(),
    }
}

fn describe(s: &Stiffness, h: f64) -> String {
    let mut parts = Vec::new();
    if s.w() > 0.0 {
        parts.push(format!(
            "w = {} rad/s (w^2 = {} 1/s^2)",
            sig(s.w()),
            sig(s.w() * s.w())
        ));
    }
    if s.k() > 0.0 {
        parts.push(format!("drag rate k = {} 1/s", sig(s.k())));
    }
    format!("{}; {}", parts.join(", "), describe_short(s, h))
}

fn describe_short(s: &Stiffness, h: f64) -> String {
    let mut parts = Vec::new();
    if s.w() > 0.0 {
        parts.push(format!("w h = {}", sig(s.w() * h)));
    }
    if s.k() > 0.0 {
        parts.push(format!("k h = {}", sig(s.k() * h)));
    }
    parts.join(", ")
}

/// A growth factor per step for people: `x25.7`, or `x(1 + 1.97e-3)` when it is close to 1 and
/// three digits would round it to a misleading `x1.00`.
pub fn growth_text(rho: f64) -> String {
    if (rho - 1.0).abs() < 5e-3 {
        format!(
            "x(1 {} {:.2e})",
            if rho >= 1.0 { "+" } else { "-" },
            (rho - 1.0).abs()
        )
    } else {
        format!("x{}", sig(rho))
    }
}

/// Three significant digits.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    if x.abs() >= 1e5 || x.abs() < 1e-4 {
        format!("{x:.2e}")
    } else {
        format!("{x:.digits$}")
    }
}

/// Rounded down to three significant digits (a suggested bound must itself satisfy the bound).
fn floor_sig(x: f64) -> f64 {
    let scale = 10f64.powi(2 - x.log10().floor() as i32);
    (x * scale).floor() / scale
}

#[cfg(test)]
mod tests;
