//! The panel's clock block: the loop's state this frame (tick, sim time, dt, steps, alpha, the
//! time dropped), pause and single step, the time scale, and the step (dt and substeps) being
//! edited, which restarts the scene when applied.

use egui::Ui;

use super::{PanelState, named_button};
use crate::app::input::Action;
use crate::app::session::Session;

pub(super) fn show(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let world = session.world();
    let last = session.last_frame();
    let lane = &session.lanes()[0];
    egui::Grid::new("clock").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.monospace(v);
            ui.end_row();
        };
        row("tick", world.tick().to_string());
        row("sim time", format!("{:.6} s", world.time()));
        row("dt", format!("{:.6} ms", world.dt() * 1e3));
        row("steps this frame", last.steps.to_string());
        row("alpha", format!("{:.3}", last.alpha));
        row(
            "dropped",
            format!(
                "{:.1} ms this frame, {:.3} s in all",
                last.dropped.as_secs_f64() * 1e3,
                lane.sim.clock.dropped().as_secs_f64()
            ),
        );
        let integrator = if session.is_comparing() {
            format!("{} compared (legend below)", session.lanes().len())
        } else {
            world.integrator().to_string()
        };
        row("integrator", integrator);
        row("bodies", world.bodies().len().to_string());
    });
    ui.horizontal(|ui| {
        let label = if session.is_paused() {
            "Resume"
        } else {
            "Pause"
        };
        if named_button(ui, label).clicked() {
            out.push(Action::TogglePause);
        }
        if named_button(ui, "Step").clicked() {
            out.push(Action::Step);
        }
        let pending = lane.pending();
        if pending > 0 {
            ui.weak(format!("{pending} command(s) wait for the next tick"));
        }
    });
    let mut scale = session.time_scale();
    let slider = egui::Slider::new(&mut scale, 0.01..=100.0)
        .logarithmic(true)
        .text("time scale");
    if ui.add(slider).changed() {
        out.push(Action::SetTimeScale(scale));
    }
    ui.add_enabled_ui(session.replay().is_none(), |ui| {
        ui.horizontal(|ui| {
            ui.add(
                egui::DragValue::new(&mut state.dt_ms)
                    .speed(0.1)
                    .range(0.001..=10_000.0)
                    .suffix(" ms"),
            );
            ui.add(
                egui::DragValue::new(&mut state.substeps)
                    .speed(0.1)
                    .range(1..=crate::scene::MAX_SUBSTEPS)
                    .suffix(" substeps"),
            );
            if named_button(ui, "Apply").clicked() {
                out.push(Action::SetStep {
                    dt: state.dt_ms * 1e-3,
                    substeps: state.substeps,
                });
            }
        });
    });
    ui.weak(
        "Changing dt or substeps restarts the scene at tick 0 with the new step, so sim time \
         stays tick x dt.",
    );
}
