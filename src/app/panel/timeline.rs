//! The panel's timeline: the scrub bar over the ticks held and Box2D's `|< < play > >|`, with
//! playing backwards, the timeline's memory, and the note when a new command dropped the
//! recorded future.

use egui::Ui;

use super::{future_dropped_note, named_button};
use crate::app::input::Action;
use crate::app::session::Session;

/// The scrub bar over the ticks held and Box2D's `|< < play > >|`, with playing backwards.
pub(super) fn show(ui: &mut Ui, session: &Session, out: &mut Vec<Action>) {
    let Some((start, end)) = session.history_range() else {
        ui.weak(format!(
            "timeline off: a keyframe of this world is over an eighth of the {} MiB budget",
            session.history_budget() >> 20
        ));
        return;
    };
    let now = session.world().tick();
    let mut tick = now;
    ui.spacing_mut().slider_width = 200.0;
    let slider = egui::Slider::new(&mut tick, start..=end.max(start + 1))
        .text("timeline")
        .integer();
    if ui.add_enabled(end > start, slider).changed() && tick != now {
        out.push(Action::Seek(tick));
    }
    ui.horizontal(|ui| {
        let button =
            |ui: &mut Ui, text: &str, hover: &str| named_button(ui, text).on_hover_text(hover);
        if button(ui, "|<", "jump to the first tick held (Backspace)").clicked() {
            out.push(Action::JumpStart);
        }
        if button(ui, "<", "step back one tick (,)").clicked() {
            out.push(Action::StepBack);
        }
        let back = if session.is_reversing() { "stop" } else { "<<" };
        if button(ui, back, "play backwards (B)").clicked() {
            out.push(Action::ToggleReverse);
        }
        let play = if session.is_paused() && !session.is_reversing() {
            ">>"
        } else {
            "||"
        };
        if button(ui, play, "play / pause (Space)").clicked() {
            out.push(if session.is_reversing() {
                Action::ToggleReverse
            } else {
                Action::TogglePause
            });
        }
        if button(ui, ">", "step forward one tick (N)").clicked() {
            out.push(Action::Step);
        }
        if button(ui, ">|", "jump to the last tick run (End)").clicked() {
            out.push(Action::JumpEnd);
        }
    });
    if session.replay().is_none()
        && let Some(t) = session.lanes()[0].history.timeline.as_ref()
    {
        ui.weak(format!(
            "ticks {start} to {end}: {} keyframes every {} ticks, {:.1} of {} MiB a lane",
            t.keyframes(),
            t.every(),
            t.bytes() as f64 / f64::from(1 << 20),
            t.budget() >> 20
        ));
    }
    if let Some(tick) = session.future_dropped_at() {
        ui.weak(future_dropped_note(tick));
    }
}
