//! The panel's error block: each of the first bodies' error against its reference (the closed
//! form, or the numerical reference where there is none), the largest over the first
//! [`ERROR_SCAN`], and why a body has none.

use egui::Ui;

use crate::app::session::Session;
use crate::render::BodyError;
use crate::render::reference::ReferenceEnd;

/// Bodies listed in the error table.
const ERROR_ROWS: usize = 8;
/// Bodies the "largest error" line looks at (the first ones, so the cost stays bounded).
const ERROR_SCAN: usize = 4096;

/// Largest position error over the first bodies of a lane, if any body has one.
pub(super) fn max_error(lane: &crate::app::session::Lane) -> Option<f64> {
    let world = &lane.sim.world;
    (0..world.bodies().len().min(ERROR_SCAN))
        .filter_map(|i| match lane.history.references.error(world, i) {
            BodyError::Measured { position, .. } => Some(position),
            _ => None,
        })
        .reduce(f64::max)
}

pub(super) fn short(e: &BodyError) -> String {
    match e {
        BodyError::Measured { position, .. } => format!("{position:.3e} m"),
        BodyError::NoClosedForm => "no closed form".into(),
        BodyError::Ended(ReferenceEnd::Contact { time, .. }) => format!("contact at {time:.3} s"),
        BodyError::Ended(ReferenceEnd::ForcesChanged { tick }) => {
            format!("forces changed at tick {tick}")
        }
        BodyError::Unknown => "-".into(),
    }
}

pub(super) fn show(ui: &mut Ui, session: &Session) {
    let lane = &session.lanes()[0];
    let world = &lane.sim.world;
    ui.strong("Error against the reference");
    if let Some(r) = world
        .bodies()
        .ids()
        .first()
        .and_then(|id| lane.history.references.get(*id))
    {
        let (kind, estimate) = r.kind();
        ui.weak(match estimate {
            Some(e) => format!("body 0 against: {kind}, its own error about {e:.1e}"),
            None => format!("body 0 against: {kind}"),
        });
    }
    egui::Grid::new("errors").striped(true).show(ui, |ui| {
        ui.strong("body");
        ui.strong("|p - p_exact|");
        ui.strong("|v - v_exact|");
        ui.end_row();
        for i in 0..world.bodies().len().min(ERROR_ROWS) {
            ui.monospace(world.bodies().ids()[i].to_string());
            match lane.history.references.error(world, i) {
                BodyError::Measured { position, velocity } => {
                    ui.monospace(format!("{position:.4e} m"));
                    ui.monospace(format!("{velocity:.4e} m/s"));
                }
                other => {
                    ui.weak(short(&other));
                    ui.label("");
                }
            }
            ui.end_row();
        }
    });
    let n = world.bodies().len();
    if n > ERROR_ROWS {
        let scanned = n.min(ERROR_SCAN);
        let max = max_error(lane).map_or("-".into(), |m| format!("{m:.4e} m"));
        ui.weak(format!(
            "largest |p - p_exact| over the first {scanned} of {n} bodies: {max}"
        ));
    }
    ui.weak("References have no contacts: a body's reference ends at its first impact.");
}
