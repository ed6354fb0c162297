//! The panel's "Forces" section: every declared term in one line with its numbers (the air,
//! the curve, a spin's lift and decay, a motor's impulse and burn), greyed when switched off.

use egui::{RichText, Ui};
use glam::DVec3;

use crate::app::session::Session;
use crate::forces::{AirModel, DragSize, Forces, KG_M2_PER_LB_IN2, SpinDecay, ThrustDirection};
use crate::scene::Launcher;

/// One line per declared term of `declared`, in evaluation order, and whether it is active in
/// `active` (a `force KIND off` command switches it off). What the panel shows and the window's
/// exit report prints.
pub fn lines(declared: &Forces, active: &Forces, launcher: &Launcher) -> Vec<(String, bool)> {
    declared
        .kinds()
        .map(|kind| {
            let text = match kind {
                crate::ForceKind::Gravity => format!("Gravity {}", vec3(declared.gravity)),
                crate::ForceKind::ConstantForce => {
                    format!("ConstantForce {} N", vec3(declared.constant))
                }
                crate::ForceKind::LinearDrag => {
                    format!("LinearDrag {} kg/s", declared.linear_drag.unwrap_or(0.0))
                }
                crate::ForceKind::QuadraticDrag => {
                    format!(
                        "QuadraticDrag {} kg/m",
                        declared.quadratic_drag.unwrap_or(0.0)
                    )
                }
                crate::ForceKind::Spring => "Spring".to_string(),
                crate::ForceKind::PointMass => "PointMass".to_string(),
                crate::ForceKind::MachDrag => mach_drag(declared, launcher),
                crate::ForceKind::Custom => declared
                    .custom
                    .iter()
                    .map(|c| format!("Custom {} v{}", c.name(), c.version()))
                    .collect::<Vec<_>>()
                    .join(", "),
                crate::ForceKind::Thrust => thrust(declared),
            };
            (text, active.has(kind))
        })
        .collect()
}

fn vec3(v: Option<DVec3>) -> String {
    let v = v.unwrap_or(DVec3::ZERO);
    format!("({}, {}, {})", v.x, v.y, v.z)
}

fn mach_drag(forces: &Forces, launcher: &Launcher) -> String {
    let Some(d) = &forces.mach_drag else {
        return String::new();
    };
    let size = match d.size {
        DragSize::Ballistic(bc) => format!("BC {:.3} lb/in^2", bc / KG_M2_PER_LB_IN2),
        DragSize::Diameter {
            diameter,
            form_factor,
        } => format!("d {:.1} mm, i {form_factor}", diameter * 1e3),
    };
    let air = match &d.air {
        AirModel::Uniform(a) => format!("uniform air {:.1} K, {:.0} Pa", a.temperature, a.pressure),
        AirModel::Standard { ground, .. } => format!("ICAO air from {ground} m"),
    };
    let wind = d
        .wind
        .map(|w| format!(", wind {} m/s", vec3(Some(w.velocity))))
        .unwrap_or_default();
    let spin = d
        .spin
        .map(|s| {
            let decay = match s.decay {
                SpinDecay::None => "no decay".to_string(),
                SpinDecay::Time(tau) => format!("decay {tau} s"),
                SpinDecay::Nathan(tau) => format!("Nathan decay {tau} s"),
            };
            let per_krpm = s.drag_per_spin * 1000.0 * crate::forces::RAD_S_PER_RPM;
            format!(
                "; spin: {:?} lift, {decay}, Cd +{per_krpm:.4}/1000 rpm; launcher {} rpm back, {} rpm side",
                s.lift, launcher.backspin, launcher.sidespin
            )
        })
        .unwrap_or_default();
    format!(
        "MachDrag {} ({:?}), {size}, {air}{wind}{spin}",
        d.curve.name(),
        d.interpolation
    )
}

fn thrust(forces: &Forces) -> String {
    let Some(t) = &forces.thrust else {
        return String::new();
    };
    let direction = match t.direction {
        ThrustDirection::Fixed(d) => format!("along ({:.3}, {:.3}, {:.3})", d.x, d.y, d.z),
        ThrustDirection::Velocity {
            along,
            rail_exit_speed,
        } => format!(
            "along the rail ({:.3}, {:.3}, {:.3}) to {rail_exit_speed} m/s, then the velocity",
            along.x, along.y, along.z
        ),
    };
    format!(
        "Thrust {:.3} N s over {} s, {} g of propellant, {direction}",
        t.curve.total_impulse(),
        t.curve.burnout(),
        t.propellant * 1e3
    )
}

/// The section: a heading and the lines, inactive ones greyed.
pub fn show(ui: &mut Ui, session: &Session) {
    let world = session.world();
    egui::CollapsingHeader::new("Forces")
        .default_open(true)
        .show(ui, |ui| {
            for (line, on) in lines(&world.params().declared, world.forces(), world.launcher()) {
                let text = RichText::new(if on { line } else { format!("{line} (off)") });
                ui.label(if on { text } else { text.weak() });
            }
        });
}
