//! The panel's recording and replay block: the record toggle with the file and the ticks
//! recorded, the recordings made so far (each can be replayed), and while replaying: where the
//! replay is, what it compared, and where it parted from its recording, field by field.

use super::named_button;
use egui::{Color32, RichText, Ui};

use crate::app::input::Action;
use crate::app::session::Session;
use crate::app::session::replaying::SessionReplay;
use crate::hash::hex;

/// Differing fields listed in the panel (the command line lists them all).
const FIELD_ROWS: usize = 8;

/// The block.
pub fn show(ui: &mut Ui, session: &Session, out: &mut Vec<Action>) {
    match session.replay() {
        Some(replay) => replaying(ui, session, replay, out),
        None => recording(ui, session, out),
    }
}

fn recording(ui: &mut Ui, session: &Session, out: &mut Vec<Action>) {
    let first = session.lanes()[0].sim.world.integrator().name();
    ui.horizontal(|ui| match session.recording() {
        Some(_) => {
            if named_button(ui, "Stop recording").clicked() {
                out.push(Action::ToggleRecord);
            }
            ui.colored_label(
                Color32::from_rgb(255, 80, 80),
                RichText::new("REC").strong(),
            );
        }
        None => {
            if named_button(ui, "Record").clicked() {
                out.push(Action::ToggleRecord);
            }
            if session.is_comparing() {
                ui.weak(format!("records the first lane ({first})"));
            }
        }
    });
    if let Some(r) = session.recording() {
        let s = r.stats();
        ui.monospace(r.path().display().to_string());
        ui.label(format!(
            "{} ticks recorded (from tick {}), {} commands, {} bytes{}",
            s.last_tick - s.start_tick,
            s.start_tick,
            s.commands,
            s.bytes,
            if session.is_comparing() {
                format!(", lane {first}")
            } else {
                String::new()
            }
        ));
        ui.weak("A restart (dt, substeps, scene, compare mode) or a divergence ends it.");
    }
    if let Some(last) = session.recordings().last() {
        let ok = last.error.is_none();
        let c = if ok {
            Color32::LIGHT_GREEN
        } else {
            Color32::LIGHT_RED
        };
        ui.colored_label(c, last.to_string());
        // A page keeps no file to replay: the recording was downloaded (open it again with
        // the page's file input).
        if crate::platform::WRITES_FILES && named_button(ui, "Replay it").clicked() {
            out.push(Action::Replay(last.path.clone()));
        }
    }
    if let Some(v) = session.replay_verdict() {
        ui.weak(format!("last replay: {}", v.line()));
    }
}

fn replaying(ui: &mut Ui, session: &Session, replay: &SessionReplay, out: &mut Vec<Action>) {
    let world = session.world();
    let v = replay.verifier();
    let (from, end, tick) = (v.started_at(), replay.end_tick(), world.tick());
    ui.strong(format!(
        "replaying {}, tick {tick} of {end}",
        replay.file().display()
    ));
    let done = (tick - from) as f32 / (end - from).max(1) as f32;
    ui.add(egui::ProgressBar::new(done).desired_height(6.0));
    for w in replay.warnings() {
        ui.colored_label(Color32::YELLOW, w);
    }
    let compared = format!(
        "{} hashes and {} keyframes compared",
        v.hashes_checked(),
        v.keyframes_checked()
    );
    if let Some(e) = replay.error() {
        ui.colored_label(Color32::LIGHT_RED, format!("stopped: {e}"));
    } else if let Some(p) = v.parted() {
        ui.colored_label(Color32::LIGHT_RED, p.report(Some(FIELD_ROWS)));
        if p.compared_at.is_none() {
            ui.weak("the fields follow at the next keyframe");
        }
    } else if replay.is_over(world) {
        let mut text = format!(
            "verified {} ticks, final hash {} ({compared})",
            tick - from,
            hex(crate::hash::state_hash(world))
        );
        if let Some(d) = world.divergence() {
            text += &format!("; the recorded divergence reproduced at tick {}", d.tick);
        }
        ui.colored_label(Color32::LIGHT_GREEN, text);
    } else {
        ui.colored_label(Color32::LIGHT_GREEN, format!("equal so far: {compared}"));
    }
    if let Some((t, f)) = v.force_evals_differ() {
        ui.colored_label(
            Color32::YELLOW,
            format!("{f} at tick {t} (a cost counter, not state)"),
        );
    }
    if named_button(ui, "Go live").clicked() {
        out.push(Action::GoLive);
    }
    ui.weak("Commands are off while replaying; going live keeps this state and runs on from it.");
}
