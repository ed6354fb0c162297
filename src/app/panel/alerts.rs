//! What must not be missed: a divergence (tick, body, cause), a replay that parted from its
//! recording, and the stability pre-check's warnings with one-click fixes. Shown at the top of
//! the panel, and the first two also over the 3D view, so hiding the panel hides none of them.

use egui::{Align2, Color32, RichText, Ui};

use super::colour;
use crate::app::input::Action;
use crate::app::session::{Lane, Session};
use crate::integrate::Integrator;
use crate::world::{Divergence, DivergenceCause, World};

/// Background of an alarm (divergence, mismatch).
const ALARM: Color32 = Color32::from_rgb(110, 22, 22);
/// Background of a warning (the pre-check).
const WARNING: Color32 = Color32::from_rgb(92, 70, 12);

fn boxed(ui: &mut Ui, fill: Color32, add: impl FnOnce(&mut Ui)) {
    egui::Frame::new()
        .fill(fill)
        .inner_margin(6.0)
        .corner_radius(4.0)
        .show(ui, |ui| {
            ui.set_width(ui.available_width());
            add(ui)
        });
}

/// `x` to three significant digits (the pre-check's suggestions are rounded so).
fn three_digits(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// The cause of a divergence in words.
pub fn cause(d: &Divergence) -> String {
    match d.cause {
        DivergenceCause::NonFinite => "its state is no longer finite (NaN or infinite)".into(),
        DivergenceCause::EnergyGrowth { energy, bound } => format!(
            "its energy {energy:.4e} J passed the guard's bound {bound:.4e} J although no force \
             adds energy: a numerical instability"
        ),
    }
}

/// "DIVERGED at tick N (t = T s), body K", with the lane's integrator in compare mode.
fn headline(d: &Divergence, world: &World, comparing: bool) -> String {
    let lane = if comparing {
        format!("{}: ", world.integrator().name())
    } else {
        String::new()
    };
    format!(
        "{lane}DIVERGED at tick {} (t = {:.6} s), body {}",
        d.tick,
        world.time_of(d.tick),
        d.body
    )
}

/// The alarms and warnings block of the panel.
pub fn show(ui: &mut Ui, session: &Session, out: &mut Vec<Action>) {
    let comparing = session.is_comparing();
    for lane in session.lanes() {
        if let Some(d) = lane.sim.world.divergence() {
            divergence(ui, session, lane, &d, comparing);
        }
    }
    if let Some(r) = session.replay()
        && let Some(p) = r.verifier().parted()
    {
        boxed(ui, ALARM, |ui| {
            ui.label(RichText::new(format!("REPLAY PARTED at tick {}", p.tick)).strong());
            ui.label(p.mismatch.to_string());
            ui.label("see Replay below for the fields");
        });
    }
    for lane in session.lanes() {
        if !lane.warnings.is_empty() {
            stability(ui, session, lane, out);
        }
    }
}

fn divergence(ui: &mut Ui, session: &Session, lane: &Lane, d: &Divergence, comparing: bool) {
    boxed(ui, ALARM, |ui| {
        let world = &lane.sim.world;
        ui.label(RichText::new(headline(d, world, comparing)).strong());
        ui.label(cause(d));
        let next = if lane.stopped.is_none() {
            "A reset waits for the next tick (Space resumes)."
        } else if session.replay().is_some() {
            "The replay stops here."
        } else if comparing {
            "The other lanes run on when resumed; R restarts every lane at tick 0."
        } else {
            "R resets the bodies (the tick keeps counting) and resumes."
        };
        if session.paused_by_alarm() {
            ui.label(format!("Paused. {next}"));
        } else {
            ui.label(next);
        }
    });
}

fn stability(ui: &mut Ui, session: &Session, lane: &Lane, out: &mut Vec<Action>) {
    let report = &lane.stability;
    let Some(verdict) = report.verdict(report.chosen) else {
        return;
    };
    boxed(ui, WARNING, |ui| {
        let title = match session.is_comparing() {
            true => format!("Stability pre-check: {}", report.chosen.name()),
            false => "Stability pre-check".to_string(),
        };
        ui.label(RichText::new(title).strong());
        // The fixes line names command-line flags; here the fixes are buttons instead.
        let text = lane.warnings.iter();
        for line in text.filter(|l| !l.trim_start().starts_with("fix:")) {
            ui.label(line);
        }
        let stable: Vec<Integrator> = report
            .verdicts
            .iter()
            .filter(|v| v.stable && v.integrator != Integrator::Exact)
            .map(|v| v.integrator)
            .collect();
        if session.replay().is_some() || session.is_comparing() {
            let names: Vec<&str> = stable.iter().map(|i| i.name()).collect();
            if !names.is_empty() {
                ui.label(format!("stable at this step: {}", names.join(", ")));
            }
        }
        let step_fix = verdict.substeps.is_some() || verdict.max_step.is_some();
        if session.replay().is_some() || (session.is_comparing() && !step_fix) {
            return;
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("fix:");
            let dt = session.scene().dt();
            if let Some(n) = verdict.substeps
                && ui.button(format!("{n} substeps")).clicked()
            {
                out.push(Action::SetStep { dt, substeps: n });
            }
            if let Some(dt) = report.suggested_dt(verdict)
                && ui
                    .button(format!("dt {} ms", three_digits(dt * 1e3)))
                    .clicked()
            {
                let substeps = report.substeps;
                out.push(Action::SetStep { dt, substeps });
            }
            if session.is_comparing() {
                return;
            }
            for i in stable {
                let text =
                    RichText::new(i.name()).color(colour(crate::render::integrator_colour(i)));
                if ui.button(text).clicked() {
                    out.push(Action::SetIntegrator(i));
                }
            }
        });
    });
}

/// Status over the 3D view, whether or not the panel shows: recording, replaying, diverged.
pub fn overlay(ctx: &egui::Context, view: egui::Rect, session: &Session) {
    let mut lines: Vec<(Color32, String)> = Vec::new();
    if let Some(r) = session.recording() {
        let s = r.stats();
        lines.push((
            Color32::from_rgb(255, 80, 80),
            format!("REC {} ticks", s.last_tick - s.start_tick),
        ));
    }
    if let Some(r) = session.replay() {
        let tick = session.world().tick();
        let text = match r.verifier().parted() {
            Some(p) => format!("REPLAY parted at tick {} (now {tick})", p.tick),
            None => format!("REPLAY tick {tick} of {}", r.end_tick()),
        };
        let c = match r.verifier().parted() {
            Some(_) => Color32::from_rgb(255, 80, 80),
            None => Color32::from_rgb(120, 200, 255),
        };
        lines.push((c, text));
    }
    let comparing = session.is_comparing();
    for lane in session.lanes() {
        if let Some(d) = lane.sim.world.divergence() {
            let text = headline(&d, &lane.sim.world, comparing);
            lines.push((Color32::from_rgb(255, 80, 80), text));
        }
    }
    if lines.is_empty() || !view.is_positive() {
        return;
    }
    egui::Area::new(egui::Id::unique("volley status overlay"))
        .fixed_pos(view.left_top() + egui::vec2(8.0, 8.0))
        .pivot(Align2::LEFT_TOP)
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::new()
                .fill(Color32::from_black_alpha(170))
                .inner_margin(6.0)
                .corner_radius(4.0)
                .show(ui, |ui| {
                    for (c, text) in lines {
                        ui.add(
                            egui::Label::new(RichText::new(text).color(c).strong().size(16.0))
                                .extend(),
                        );
                    }
                });
        });
}
