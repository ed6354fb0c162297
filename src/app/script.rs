//! Input scripts (`--script FILE`): key presses and waits, applied frame by frame, so tests and
//! demos drive the real window the way a user does.
//!
//! One step per line; `#` starts a comment; blank lines are skipped.
//!
//! ```text
//! wait 10          # draw 10 frames first
//! key a            # as if A were pressed: aim on the high arc
//! key shift+a      # Shift+A: the low arc
//! key space        # named keys: space, up, down, left, right, pageup, pagedown, home, end,
//!                  # backspace, f1, escape
//! hover body 0     # the pointer on lane 0's body 0: the probe reads it
//! hover marker apex  # on body 0's last marker of a kind: tenth, second, apex, impact, event
//! pin              # pin the probe there (a click on the 3D view)
//! drag launcher 40 0   # press on the launcher, move 40 px right, release: it moves on the ground
//! drag handle 0 -20    # the aim handle 20 px up: 10 degrees more elevation
//! drag target 0 -30 0  # target 0 moved 30 px left (the scene restarts with it)
//! click Aim: high arc  # click the panel's button with this label (its centre)
//! click 700 300        # click at a position (logical points): on the 3D view it pins the probe
//! policy snap          # the loop policy (accumulator, snap, snap-avg, quantise, hysteresis)
//! draw interpolate     # the draw mode (current, interpolate, extrapolate, predict, swept)
//! ```
//!
//! A key goes through the same mapping as a real key press ([`input::action_for_key`]), so a
//! script does what the keyboard does. Steps run at the start of a frame, before the loop
//! advances: every step up to the next `wait` runs in the same frame.

use std::collections::VecDeque;

use winit::keyboard::{Key, NamedKey};

use crate::app::input::{self, Action, ClickAt};
use crate::clock::LoopPolicy;
use crate::pacing::DrawMode;

/// One step of a script.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Let this many frames be drawn.
    Wait(u64),
    /// What a key press asks for, and the key as written (for messages).
    Key(Action, String),
}

/// A script line that cannot be read: the file, line and column, and what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptError {
    /// The file as named.
    pub file: String,
    /// Line (from 1).
    pub line: usize,
    /// Column (from 1) of the word that is wrong.
    pub column: usize,
    /// What was expected.
    pub message: String,
}

impl std::fmt::Display for ScriptError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.column, self.message
        )
    }
}

impl std::error::Error for ScriptError {}

/// Most frames one `wait` may ask for (a day at 60 Hz): a typo should be an error.
pub const MAX_WAIT: u64 = 5_184_000;

/// Most steps one script may hold: a demo is hundreds; a generated file gone wrong is an error.
pub const MAX_STEPS: usize = 100_000;

const NAMED: [(&str, NamedKey); 12] = [
    ("space", NamedKey::Space),
    ("up", NamedKey::ArrowUp),
    ("down", NamedKey::ArrowDown),
    ("left", NamedKey::ArrowLeft),
    ("right", NamedKey::ArrowRight),
    ("pageup", NamedKey::PageUp),
    ("pagedown", NamedKey::PageDown),
    ("home", NamedKey::Home),
    ("f1", NamedKey::F1),
    ("escape", NamedKey::Escape),
    ("backspace", NamedKey::Backspace),
    ("end", NamedKey::End),
];

/// The key a script names: a named key, one character, or `shift+` and a letter.
fn key_of(name: &str) -> Option<Key> {
    let lower = name.to_ascii_lowercase();
    if let Some((_, k)) = NAMED.iter().find(|(n, _)| *n == lower) {
        return Some(Key::Named(*k));
    }
    let (shift, rest) = match lower.strip_prefix("shift+") {
        Some(rest) => (true, rest),
        None => (false, lower.as_str()),
    };
    let mut chars = rest.chars();
    let c = chars.next()?;
    if chars.next().is_some() {
        return None;
    }
    let text = if shift { c.to_ascii_uppercase() } else { c };
    Some(Key::Character(text.to_string().into()))
}

/// Reads a script; `file` names it in errors.
pub fn parse(text: &str, file: &str) -> Result<Vec<Step>, ScriptError> {
    let mut steps = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let code = raw.split('#').next().unwrap_or("");
        let mut words = code.split_whitespace();
        let Some(verb) = words.next() else {
            continue;
        };
        let column = |word: &str| word.as_ptr() as usize - raw.as_ptr() as usize + 1;
        let error = |word: &str, message: String| ScriptError {
            file: file.to_string(),
            line: n + 1,
            column: column(word),
            message,
        };
        if steps.len() == MAX_STEPS {
            return Err(error(
                verb,
                format!("expected at most {MAX_STEPS} steps in a script"),
            ));
        }
        if verb == "hover" {
            steps.push(hover_step(words.next(), words.next(), verb, &error)?);
            continue;
        }
        if verb == "drag" {
            let rest: Vec<&str> = words.by_ref().collect();
            steps.push(drag_step(&rest, verb, &error)?);
            continue;
        }
        if verb == "click" {
            let rest: Vec<&str> = words.by_ref().collect();
            let at = match rest.as_slice() {
                [x, y] if x.parse::<f32>().is_ok() && y.parse::<f32>().is_ok() => {
                    ClickAt::Point(x.parse().unwrap_or(0.0), y.parse().unwrap_or(0.0))
                }
                [] => {
                    return Err(error(
                        verb,
                        "`click` needs `X Y` (points) or a control's label".into(),
                    ));
                }
                label => ClickAt::Control(label.join(" ").trim_matches('"').to_string()),
            };
            steps.push(Step::Key(Action::Click(at), "click".into()));
            continue;
        }
        if verb == "pin" {
            if let Some(extra) = words.next() {
                return Err(error(extra, "`pin` takes no argument".into()));
            }
            steps.push(Step::Key(Action::PinProbe, "pin".into()));
            continue;
        }
        let arg = words.next();
        if let Some(extra) = words.next() {
            return Err(error(extra, format!("`{verb}` takes one argument")));
        }
        let step = match (verb, arg) {
            ("wait", Some(count)) => match count.parse::<u64>() {
                Ok(frames) if (1..=MAX_WAIT).contains(&frames) => Step::Wait(frames),
                _ => {
                    return Err(error(
                        count,
                        format!(
                            "wait: expected a number of frames from 1 to {MAX_WAIT}, got `{count}`"
                        ),
                    ));
                }
            },
            ("key", Some(name)) => {
                let action = key_of(name).and_then(|k| input::action_for_key(&k));
                match action {
                    Some(action) => Step::Key(action, name.to_string()),
                    None => {
                        return Err(error(
                            name,
                            format!(
                                "key: `{name}` is not a key the window acts on (see the shortcuts in docs/window.md)"
                            ),
                        ));
                    }
                }
            }
            ("policy", Some(name)) => match LoopPolicy::NAMES.iter().find(|n| **n == name) {
                Some(n) => Step::Key(Action::SetPolicy((*n).to_string()), format!("policy {n}")),
                None => {
                    return Err(error(
                        name,
                        format!(
                            "policy: expected one of {}, got `{name}`",
                            LoopPolicy::NAMES.join(", ")
                        ),
                    ));
                }
            },
            ("draw", Some(name)) => match DrawMode::parse(name) {
                Some(m) => Step::Key(Action::SetDrawMode(m), format!("draw {name}")),
                None => {
                    let names: Vec<&str> = DrawMode::ALL.iter().map(|m| m.name()).collect();
                    return Err(error(
                        name,
                        format!("draw: expected one of {}, got `{name}`", names.join(", ")),
                    ));
                }
            },
            ("wait" | "key" | "policy" | "draw", None) => {
                return Err(error(verb, format!("`{verb}` needs an argument")));
            }
            _ => {
                return Err(error(
                    verb,
                    format!(
                        "expected `wait N`, `key NAME`, `hover body N`, `hover marker KIND`, \
                         `pin`, `drag ...`, `click ...`, `policy NAME` or `draw MODE`, got \
                         `{verb}`"
                    ),
                ));
            }
        };
        steps.push(step);
    }
    Ok(steps)
}

/// `drag launcher DX DY`, `drag handle DX DY` or `drag target N DX DY` (physical pixels).
fn drag_step(
    rest: &[&str],
    verb: &str,
    error: &dyn Fn(&str, String) -> ScriptError,
) -> Result<Step, ScriptError> {
    use crate::app::setup_drag::Grab;
    let expected = "expected `drag launcher DX DY`, `drag handle DX DY` or `drag target N DX DY`";
    let (grab, offsets) = match rest {
        ["launcher", d @ ..] => (Grab::Launcher, d),
        ["handle", d @ ..] => (Grab::Handle, d),
        ["target", n, d @ ..] => {
            let n = n.parse::<usize>().map_err(|_| {
                error(
                    n,
                    format!("drag target: expected a target index, got `{n}`"),
                )
            })?;
            (Grab::Target(n), d)
        }
        [w, ..] => return Err(error(w, format!("{expected}, got `{w}`"))),
        [] => return Err(error(verb, expected.to_string())),
    };
    let [dx, dy] = offsets else {
        let at = offsets.get(2).copied().unwrap_or(verb);
        return Err(error(at, format!("{expected}: two offsets in pixels")));
    };
    let px = |w: &str| {
        w.parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| error(w, format!("drag: expected an offset in pixels, got `{w}`")))
    };
    let (x, y) = (px(dx)?, px(dy)?);
    Ok(Step::Key(
        Action::Drag(grab, x, y),
        format!("drag {grab:?} {x} {y}"),
    ))
}

/// `hover body N` or `hover marker KIND`.
fn hover_step(
    what: Option<&str>,
    arg: Option<&str>,
    verb: &str,
    error: &dyn Fn(&str, String) -> ScriptError,
) -> Result<Step, ScriptError> {
    use crate::render::probe::MarkerKind as K;
    let expected = "expected `hover body N` or `hover marker tenth|second|apex|impact|rest|event`";
    match (what, arg) {
        (Some("body"), Some(n)) => n
            .parse::<usize>()
            .map(|n| Step::Key(Action::HoverBody(n), format!("hover body {n}")))
            .map_err(|_| error(n, format!("hover body: expected a body index, got `{n}`"))),
        (Some("marker"), Some(kind)) => {
            let kind_of = match kind {
                "tenth" => K::Tenth,
                "second" => K::Second,
                "apex" => K::Apex,
                // Any impact or rest: the surface is not matched, as no event index is.
                "impact" => K::Impact(crate::contact::Surface::Ground),
                "rest" => K::Rest(crate::contact::Surface::Ground),
                "event" => K::Declared(0),
                _ => return Err(error(kind, format!("{expected}, got `{kind}`"))),
            };
            Ok(Step::Key(
                Action::HoverMarker(kind_of),
                format!("hover marker {kind}"),
            ))
        }
        (Some(w), _) => Err(error(w, format!("{expected}, got `{w}`"))),
        (None, _) => Err(error(verb, expected.to_string())),
    }
}

/// A script being played: where it is, how many frames it still waits, and the egui input its
/// clicks queued for the frames to come.
#[derive(Clone, Debug, Default)]
pub struct Player {
    steps: Vec<Step>,
    next: usize,
    waiting: u64,
    /// Synthetic egui input of scripted clicks, a batch a frame.
    synthetic: VecDeque<Vec<egui::Event>>,
}

impl Player {
    /// Plays `steps` from the first.
    pub fn new(steps: Vec<Step>) -> Player {
        Player {
            steps,
            next: 0,
            waiting: 0,
            synthetic: VecDeque::new(),
        }
    }

    /// Queues `events` for egui, after the batches queued before them, one batch a frame.
    pub fn queue_input(&mut self, events: Vec<egui::Event>) {
        self.synthetic.push_back(events);
    }

    /// The next frame's batch of queued egui input, if any.
    pub fn next_input(&mut self) -> Option<Vec<egui::Event>> {
        self.synthetic.pop_front()
    }

    /// The actions due this frame: every step up to the next wait (which then counts down one
    /// frame at a time).
    pub fn due(&mut self) -> Vec<Action> {
        let mut out = Vec::new();
        if self.waiting > 0 {
            self.waiting -= 1;
            return out;
        }
        while let Some(step) = self.steps.get(self.next) {
            self.next += 1;
            match step {
                Step::Wait(frames) => {
                    self.waiting = frames - 1;
                    break;
                }
                Step::Key(action, _) => out.push(action.clone()),
            }
        }
        out
    }

    /// Whether every step has run.
    pub fn finished(&self) -> bool {
        self.next >= self.steps.len() && self.waiting == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_run_up_to_each_wait_and_waits_count_frames() {
        let steps = parse("key f\nwait 2\nkey a\nkey shift+a # both arcs\n", "s").unwrap();
        let mut p = Player::new(steps);
        assert_eq!(p.due(), vec![Action::Fire]);
        assert_eq!(p.due(), vec![]);
        assert_eq!(
            p.due(),
            vec![
                Action::Aim(crate::exact::Arc::High),
                Action::Aim(crate::exact::Arc::Low)
            ]
        );
        assert!(p.finished());
    }

    #[test]
    fn a_script_of_more_than_the_most_steps_is_refused_at_the_line_past_it() {
        assert_eq!(
            parse(&"wait 1\n".repeat(MAX_STEPS), "s").map(|s| s.len()),
            Ok(MAX_STEPS)
        );
        let e = parse(&"wait 1\n".repeat(MAX_STEPS + 1), "big.txt").unwrap_err();
        assert_eq!((e.line, e.column), (MAX_STEPS + 1, 1), "{e}");
        assert!(e.message.contains("at most 100000 steps"), "{e}");
    }

    #[test]
    fn errors_name_the_line_and_column_and_what_was_expected() {
        let e = parse("wait 1\n  key q\n", "demo.txt").unwrap_err();
        assert_eq!((e.line, e.column), (2, 7), "{e}");
        assert!(e.to_string().starts_with("demo.txt:2:7: key: `q`"), "{e}");
        let e = parse("wait 0", "s").unwrap_err();
        assert_eq!(e.column, 6);
        assert!(
            parse("jump 3", "s")
                .unwrap_err()
                .message
                .contains("expected `wait N`")
        );
        assert!(
            parse("key a b", "s")
                .unwrap_err()
                .message
                .contains("one argument")
        );
        assert!(
            parse("wait", "s")
                .unwrap_err()
                .message
                .contains("needs an argument")
        );
        assert!(
            parse("click", "s")
                .unwrap_err()
                .message
                .contains("needs `X Y`")
        );
        let e = parse("wait 1\npolicy fastest\n", "s").unwrap_err();
        assert_eq!((e.line, e.column), (2, 8), "{e}");
        assert!(
            e.message
                .starts_with("policy: expected one of accumulator, snap"),
            "{e}"
        );
        let e = parse("draw sideways", "s").unwrap_err();
        assert_eq!(e.column, 6, "{e}");
        assert!(
            e.message
                .contains("current, interpolate, extrapolate, predict, swept"),
            "{e}"
        );
        assert_eq!(
            parse("policy snap-avg\ndraw current", "s").unwrap(),
            [
                Step::Key(
                    Action::SetPolicy("snap-avg".into()),
                    "policy snap-avg".into()
                ),
                Step::Key(
                    Action::SetDrawMode(DrawMode::Current),
                    "draw current".into()
                ),
            ]
        );
        let steps = parse("click Aim: high arc\nclick 10 20.5\n", "s").unwrap();
        let click = |at| Step::Key(Action::Click(at), "click".into());
        assert_eq!(steps[0], click(ClickAt::Control("Aim: high arc".into())));
        assert_eq!(steps[1], click(ClickAt::Point(10.0, 20.5)));
    }
}
