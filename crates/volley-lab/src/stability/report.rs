//! The stability report in words: the verdicts, the limits and the numbers as the CLI and the
//! window print them.

use super::*;

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

    pub(super) fn body_label(&self, index: usize) -> String {
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

pub(super) fn limit_note(integrator: Integrator) -> String {
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

pub(super) fn describe(s: &Stiffness, h: f64) -> String {
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

pub(super) fn describe_short(s: &Stiffness, h: f64) -> String {
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
pub(super) fn sig(x: f64) -> String {
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
pub(super) fn floor_sig(x: f64) -> f64 {
    let scale = 10f64.powi(2 - x.log10().floor() as i32);
    (x * scale).floor() / scale
}
