//! The panel's simulation block: the integrator, the launch sliders, fire, reset and save
//! setup, and the aim buttons with what each lane's own solve fired.

use egui::Ui;

use super::{PanelState, colour, named_button};
use crate::app::input::Action;
use crate::app::session::Session;
use crate::integrate::Integrator;

pub(super) fn show(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let world = session.world();
    let current = world.integrator();
    ui.add_enabled_ui(!session.is_comparing(), |ui| {
        egui::ComboBox::from_label("integrator")
            .selected_text(current.name())
            .show_ui(ui, |ui| {
                for i in Integrator::ALL {
                    let allowed = crate::scene::check_integrator(i, world.forces()).is_ok();
                    let clicked = ui
                        .add_enabled(allowed, egui::Button::selectable(i == current, i.name()))
                        .clicked();
                    if clicked {
                        out.push(Action::SetIntegrator(i));
                    }
                }
            });
    });
    let info = current.info();
    ui.weak(format!(
        "order {}, {}",
        if info.order == u32::MAX {
            "exact".to_string()
        } else {
            info.order.to_string()
        },
        if info.symplectic {
            "symplectic"
        } else {
            "not symplectic"
        }
    ));
    let launch = |ui: &mut Ui, value: &mut f64, range, text: &str, suffix: &str| {
        let slider = egui::Slider::new(value, range).text(text).suffix(suffix);
        ui.add(slider).changed()
    };
    // Up to 200 m/s for a thrown or kicked ball; a bullet's scene (the rifle's 838 m/s) gets a
    // range to 1200 m/s, so the slider shows its speed instead of clamping it.
    let top = if state.speed > 200.0 { 1200.0 } else { 200.0 };
    let s = launch(ui, &mut state.speed, 0.0..=top, "speed", " m/s");
    let e = launch(
        ui,
        &mut state.elevation_deg,
        -90.0..=90.0,
        "elevation",
        " deg",
    );
    let a = launch(
        ui,
        &mut state.azimuth_deg,
        -180.0..=180.0,
        "azimuth",
        " deg",
    );
    if s || e || a {
        out.push(Action::Launch {
            speed: s.then_some(state.speed),
            elevation_deg: e.then_some(state.elevation_deg),
            azimuth_deg: a.then_some(state.azimuth_deg),
        });
    }
    ui.horizontal(|ui| {
        if named_button(ui, "Fire").clicked() {
            out.push(Action::Fire);
        }
        if named_button(ui, "Reset").clicked() {
            out.push(Action::Reset);
        }
        if named_button(ui, "Save setup")
            .on_hover_text("the scene with this launcher, integrator, step and compare lanes")
            .clicked()
        {
            out.push(Action::SaveSetup);
        }
    });
    ui.horizontal(|ui| {
        if let Some(note) = &state.saved_note {
            ui.weak(note);
        }
    });
    aim(ui, state, session, out);
}

/// The aim buttons and, per lane, what its own solve fired and how the textbook would miss.
fn aim(ui: &mut Ui, state: &mut PanelState, session: &Session, out: &mut Vec<Action>) {
    let targets = session.world().contacts().targets.len();
    if targets == 0 {
        return;
    }
    state.aim_target = state.aim_target.min(targets - 1);
    ui.horizontal(|ui| {
        if targets > 1 {
            egui::ComboBox::from_id_salt("aim target")
                .selected_text(format!("target {}", state.aim_target))
                .show_ui(ui, |ui| {
                    for k in 0..targets {
                        ui.selectable_value(&mut state.aim_target, k, format!("target {k}"));
                    }
                });
        }
        if named_button(ui, "Aim: high arc").clicked() {
            out.push(Action::Aim(crate::exact::Arc::High));
        }
        if named_button(ui, "Aim: low arc").clicked() {
            out.push(Action::Aim(crate::exact::Arc::Low));
        }
    });
    for lane in session.lanes() {
        let Some(note) = &lane.aim else {
            continue;
        };
        let name = lane.sim.world.integrator().name();
        let (first, second) = match &note.outcome {
            Ok(shot) => {
                let mut first = format!(
                    "{name}: {} {:.2} deg, {:.2} m/s, {:.3} s",
                    shot.kind.label(),
                    shot.elevation_deg,
                    shot.speed,
                    shot.flight_time
                );
                if let Some(tb) = shot.textbook {
                    let (e, _) = crate::firing::angles_of(tb.velocity);
                    first += &format!("; textbook {e:.2} deg misses by {:.3} m", tb.miss);
                }
                let second = match aimed_pass(lane, note, shot) {
                    Some(p) => format!("  passed at {:.1e} m, t = {:.3} s", p.distance, p.time),
                    None => "  in flight".to_string(),
                };
                (first, second)
            }
            Err(why) => (format!("{name}: no shot: {why}"), String::new()),
        };
        ui.colored_label(colour(lane.colour()), first);
        if !second.is_empty() {
            ui.monospace(second);
        }
    }
}

/// The aimed shot's pass by the aimed target, once it has come (within half a tick of when it
/// was due).
pub fn aimed_pass<'a>(
    lane: &'a crate::app::session::Lane,
    note: &crate::app::session::AimNote,
    shot: &crate::firing::Shot,
) -> Option<&'a crate::render::history::Pass> {
    let world = &lane.sim.world;
    let due = world.time_of(note.tick) + shot.flight_time;
    lane.history
        .passes
        .all()
        .iter()
        .filter(|p| p.body == note.body && p.target as usize == note.target)
        .find(|p| (p.time - due).abs() < 0.5 * world.dt())
}
