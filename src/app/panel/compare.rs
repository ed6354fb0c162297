//! The panel's compare block: compare mode on or off, the integrators picked, equal cost, and
//! the legend: each lane's colour, its own dt and substeps (editable), its cost and its
//! largest error or its divergence.

use egui::{Color32, RichText, Ui};

use super::errors::{max_error, short};
use super::{PanelState, cause, colour};
use crate::app::input::Action;
use crate::app::session::Session;
use crate::integrate::Integrator;

pub(super) fn show(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let mut on = session.is_comparing();
    if ui.checkbox(&mut on, "Compare integrators").changed() {
        out.push(Action::SetCompare(if on {
            state.compare_pick.clone()
        } else {
            Vec::new()
        }));
    }
    ui.horizontal_wrapped(|ui| {
        for i in Integrator::ALL {
            let mut picked = state.compare_pick.contains(&i);
            let text = RichText::new(i.name()).color(colour(crate::render::integrator_colour(i)));
            if ui.checkbox(&mut picked, text).changed() {
                state.compare_pick.retain(|&j| j != i);
                if picked {
                    state.compare_pick.push(i);
                    state.compare_pick.sort();
                }
                if on {
                    out.push(Action::SetCompare(state.compare_pick.clone()));
                }
            }
        }
    });
    if !on {
        return;
    }
    let mut equal = session.is_equal_cost();
    if ui
        .checkbox(&mut equal, "Equal cost")
        .on_hover_text(
            "every lane spends the first lane's force evaluations per simulated second: its dt \
             scaled by its evaluations a tick (RK4 at 4 h beside Euler at h)",
        )
        .changed()
    {
        out.push(Action::SetEqualCost(equal));
    }
    egui::Grid::new("legend").striped(true).show(ui, |ui| {
        ui.strong("integrator");
        ui.strong("dt (ms)");
        ui.strong("substeps");
        ui.strong("evals/s");
        ui.strong("max |dp|");
        ui.end_row();
        let specs = session.compare_lanes();
        for (i, lane) in session.lanes().iter().enumerate() {
            let world = &lane.sim.world;
            ui.colored_label(colour(lane.colour()), world.integrator().name());
            let (mut dt_ms, mut substeps) = (world.dt() * 1e3, world.substeps());
            let derived = session.is_equal_cost() && i > 0;
            let dt_edit = ui.add_enabled(
                !derived,
                egui::DragValue::new(&mut dt_ms)
                    .speed(0.1)
                    .range(0.001..=10_000.0),
            );
            let n_edit = ui.add(
                egui::DragValue::new(&mut substeps)
                    .speed(0.1)
                    .range(1..=1000),
            );
            if (dt_edit.lost_focus()
                || dt_edit.drag_stopped()
                || n_edit.lost_focus()
                || n_edit.drag_stopped())
                && (dt_ms != world.dt() * 1e3 || substeps != world.substeps())
                && specs.get(i).is_some()
            {
                out.push(Action::SetLaneStep {
                    lane: i,
                    dt: Some(dt_ms * 1e-3),
                    substeps: Some(substeps),
                });
            }
            ui.monospace(
                lane.evals_per_second()
                    .map_or("-".into(), |e| format!("{e:.0}")),
            );
            match &lane.stopped {
                Some(d) => {
                    ui.colored_label(Color32::LIGHT_RED, format!("diverged at tick {}", d.tick))
                        .on_hover_text(format!("body {}: {}", d.body, cause(d)));
                }
                None => {
                    let first = (!lane.sim.world.bodies().is_empty())
                        .then(|| lane.history.references.error(&lane.sim.world, 0));
                    // The largest error, or why body 0 has none (its reference ended).
                    ui.monospace(match (max_error(lane), first) {
                        (Some(m), _) => format!("{m:.2e} m"),
                        (None, Some(e)) => short(&e),
                        (None, None) => "-".into(),
                    });
                }
            }
            ui.end_row();
        }
    });
}
