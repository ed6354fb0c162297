//! The study as a markdown report and as CSV.

use std::fmt::Write;

use super::{Outcome, StudyPoint, StudyReport};
use volley_sim::internals::integrate::Integrator;

/// A float in 3 significant digits, scientific where that is shorter.
pub fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&x.abs()) {
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

fn wall(p: &StudyPoint) -> String {
    p.wall_per_tick
        .map_or("-".into(), |w| sci(w.as_secs_f64() * 1e6))
}

fn outcome(p: &StudyPoint) -> String {
    match p.outcome {
        Outcome::Completed => "ok".into(),
        Outcome::Diverged(d) => format!("diverged at tick {} (body {})", d.tick, d.body),
    }
}

fn precheck(p: &StudyPoint) -> String {
    if p.precheck.stable {
        "stable".into()
    } else {
        format!(
            "unstable ({}/step)",
            crate::stability::growth_text(p.precheck.rho)
        )
    }
}

fn events(p: &StudyPoint) -> String {
    let e = &p.events;
    if e.reference == 0 {
        return "-".into();
    }
    let mut s = format!("{}/{}", e.matched, e.reference);
    if e.hit_mismatches > 0 {
        write!(s, ", {} hit/miss flipped", e.hit_mismatches).ok();
    }
    s
}

/// The markdown report: what was run, the table, the observed orders, the energy drift per
/// window (conservative scenes), and the cheapest setting meeting the tolerance.
pub fn markdown(r: &StudyReport) -> String {
    let mut s = String::new();
    let build = if r.release {
        "release build"
    } else {
        "DEBUG build: wall times are not representative, use `cargo run --release`"
    };
    writeln!(s, "# Study: {}\n", r.scene).ok();
    writeln!(
        s,
        "Runs from t = {} s to the first tick at or after t = {} s; {build}.",
        r.start_time, r.until
    )
    .ok();
    let mut described: Vec<String> = r.references.iter().map(|x| x.describe()).collect();
    described.dedup();
    if described.len() == 1 {
        writeln!(s, "Reference: {}.\n", described[0]).ok();
    } else {
        writeln!(s, "References:").ok();
        for (x, dt) in r.references.iter().zip(r.references.iter().map(|x| x.dt)) {
            writeln!(s, "- dt = {}: {}", sci(dt), x.describe()).ok();
        }
        writeln!(s).ok();
    }
    writeln!(
        s,
        "Cost: force evaluations per simulated second (every stage and contact root search) and \
         the median wall time per tick. Errors: body position (m) against the reference at the \
         final tick, the largest over the trajectory and the RMS; event dt is the largest impact \
         or target-hit time error (s).\n"
    )
    .ok();
    let energy = r.points.iter().any(|p| p.energy.is_some());
    let mut header = "| integrator | dt (s) | ticks | evals/s | wall/tick (us) | pre-check | err final (m) | err max (m) | err RMS (m) | event dt (s) | events |".to_string();
    if energy {
        header.push_str(" energy drift first / last window |");
    }
    header.push_str(" outcome |");
    writeln!(s, "{header}").ok();
    let columns = header.matches('|').count() - 1;
    writeln!(s, "|{}", "---|".repeat(columns)).ok();
    for p in &r.points {
        let (ef, em, er) = p.errors.map_or(("-".into(), "-".into(), "-".into()), |e| {
            (
                sci(e.final_position),
                sci(e.max_position),
                sci(e.rms_position),
            )
        });
        let ev = p.events.max_time_error.map_or("-".into(), sci);
        write!(
            s,
            "| {} | {} | {} | {} | {} | {} | {ef} | {em} | {er} | {ev} | {} |",
            p.integrator,
            sci(p.dt),
            p.ticks,
            sci(p.evals_per_second),
            wall(p),
            precheck(p),
            events(p)
        )
        .ok();
        if energy {
            let d = p.energy.as_ref();
            let text = match (d, p.outcome) {
                (Some(d), Outcome::Completed) => format!("{} / {}", sci(d.first()), sci(d.last())),
                _ => "-".into(),
            };
            write!(s, " {text} |").ok();
        }
        writeln!(s, " {} |", outcome(p)).ok();
    }
    writeln!(
        s,
        "\n## Observed order (slope of log max error on log dt)\n"
    )
    .ok();
    writeln!(
        s,
        "| integrator | documented order | observed |\n|---|---|---|"
    )
    .ok();
    for (i, fit) in &r.orders {
        // An adaptive method's error follows its tolerance once it splits ticks, not dt: its
        // slope says how much of the sweep it took whole ticks.
        let note = if *i == Integrator::Dopri5 {
            " (adaptive: the error follows the tolerance once ticks are split, not dt)"
        } else {
            ""
        };
        writeln!(s, "| {i} | {}{note} | {fit} |", i.info().order).ok();
    }
    if energy {
        energy_windows(&mut s, r);
    }
    if let Some((tol, best)) = r.cheapest {
        writeln!(
            s,
            "\n## Tolerance {} m (largest trajectory error)\n",
            sci(tol)
        )
        .ok();
        match best.map(|i| &r.points[i]) {
            Some(p) => writeln!(
                s,
                "Cheapest setting that meets it: **{} at dt = {} s** ({} force evaluations per \
                 simulated second, error {} m).",
                p.integrator,
                sci(p.dt),
                sci(p.evals_per_second),
                sci(p.errors.map_or(0.0, |e| e.max_position))
            ),
            None => writeln!(s, "No studied setting meets it: study smaller steps."),
        }
        .ok();
    }
    if !r.warnings.is_empty() {
        writeln!(s, "\n## Stability pre-check\n\n```").ok();
        for w in &r.warnings {
            writeln!(s, "{w}").ok();
        }
        writeln!(s, "```").ok();
    }
    s
}

fn energy_windows(s: &mut String, r: &StudyReport) {
    writeln!(
        s,
        "\n## Energy drift per window (max |E - E0| / scale in each tenth of the run)\n"
    )
    .ok();
    for p in r.points.iter().filter(|p| p.outcome == Outcome::Completed) {
        if let Some(d) = &p.energy {
            let list: Vec<String> = d.windows.iter().map(|x| sci(*x)).collect();
            writeln!(
                s,
                "- {} at dt = {}: {}",
                p.integrator,
                sci(p.dt),
                list.join(", ")
            )
            .ok();
        }
    }
}

/// One CSV row per point, full precision (shortest round-trip floats); empty cells where a
/// value does not exist. Energy windows are `;`-separated in one column.
pub fn csv(r: &StudyReport) -> String {
    let mut s = String::from(
        "scene,integrator,dt,substeps,ticks,force_evals,evals_per_sim_second,wall_per_tick_s,\
         wall_per_sim_second_s,repeats,release,precheck_growth,precheck_stable,outcome,\
         diverged_tick,diverged_body,err_final_m,err_max_m,err_rms_m,vel_err_final_m_per_s,\
         events_reference,events_matched,event_time_err_max_s,hit_mismatches,\
         energy_drift_windows,reference,reference_error_m\n",
    );
    for p in &r.points {
        let reference = r.references.iter().find(|x| x.dt == p.dt);
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:?}"));
        let (dtick, dbody) = match p.outcome {
            Outcome::Diverged(d) => (d.tick.to_string(), d.body.to_string()),
            Outcome::Completed => (String::new(), String::new()),
        };
        let e = p.errors;
        let fields = [
            r.scene.clone(),
            p.integrator.to_string(),
            format!("{:?}", p.dt),
            p.substeps.to_string(),
            p.ticks.to_string(),
            p.force_evals.to_string(),
            format!("{:?}", p.evals_per_second),
            opt(p.wall_per_tick.map(|w| w.as_secs_f64())),
            opt(p.wall_per_sim_second()),
            p.repeats.to_string(),
            r.release.to_string(),
            format!("{:?}", p.precheck.rho),
            p.precheck.stable.to_string(),
            if p.outcome == Outcome::Completed {
                "ok"
            } else {
                "diverged"
            }
            .into(),
            dtick,
            dbody,
            opt(e.map(|e| e.final_position)),
            opt(e.map(|e| e.max_position)),
            opt(e.map(|e| e.rms_position)),
            opt(e.map(|e| e.final_velocity)),
            p.events.reference.to_string(),
            p.events.matched.to_string(),
            opt(p.events.max_time_error),
            p.events.hit_mismatches.to_string(),
            p.energy.as_ref().map_or(String::new(), |d| {
                d.windows
                    .iter()
                    .map(|x| format!("{x:?}"))
                    .collect::<Vec<_>>()
                    .join(";")
            }),
            quote(&reference.map_or(String::new(), |x| x.describe())),
            format!("{:?}", reference.map_or(0.0, |x| x.error_estimate())),
        ];
        writeln!(s, "{}", fields.join(",")).ok();
    }
    s
}

fn quote(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\""))
}
