//! What the user can ask for, from the keyboard or the panel, and the keyboard shortcuts.
//!
//! Keys and panel widgets both produce [`Action`]s; the window applies them in one place
//! ([`crate::app`]), where the ones that change a simulation become [`crate::Command`]s.

use std::path::PathBuf;

use winit::keyboard::{Key, NamedKey};

use crate::integrate::Integrator;

/// One request from the user.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Pause if running, resume if paused.
    TogglePause,
    /// Pause and run exactly one tick.
    Step,
    /// Set the time scale (sim seconds per real second).
    SetTimeScale(f64),
    /// Multiply the time scale.
    ScaleTime(f64),
    /// Set the timestep (s) and the integrator steps per tick: restarts at tick 0.
    SetStep {
        /// Timestep (s).
        dt: f64,
        /// Integrator steps per tick.
        substeps: u32,
    },
    /// Multiply the timestep: restarts at tick 0.
    ScaleDt(f64),
    /// Switch the integrator (outside compare mode).
    SetIntegrator(Integrator),
    /// Change the launcher; `None` keeps a value.
    Launch {
        /// Speed (m/s).
        speed: Option<f64>,
        /// Elevation (degrees).
        elevation_deg: Option<f64>,
        /// Azimuth (degrees).
        azimuth_deg: Option<f64>,
    },
    /// Change the launcher by these amounts (m/s, degrees, degrees).
    NudgeLaunch(f64, f64, f64),
    /// Fire a projectile from the launcher.
    Fire,
    /// Every lane aims at the selected target on this arc (its own solve) and fires.
    Aim(crate::exact::Arc),
    /// Move every lane to this tick on the timeline (paused or not, as it was).
    Seek(u64),
    /// Pause and go back one tick.
    StepBack,
    /// Go to the first tick held, paused.
    JumpStart,
    /// Go to the last tick run, paused.
    JumpEnd,
    /// Play backwards, or stop doing so.
    ToggleReverse,
    /// Put the bodies back: a `Reset` command (in compare mode after a divergence, a restart
    /// at tick 0).
    Reset,
    /// Start or stop recording the first lane.
    ToggleRecord,
    /// Replay a recording in the window.
    Replay(PathBuf),
    /// End the replay and run on live from its state.
    GoLive,
    /// Load another scene file.
    PickScene(PathBuf),
    /// Compare mode with these integrators (empty: off).
    SetCompare(Vec<Integrator>),
    /// A compare lane's own dt (s) and substeps: restarts at tick 0.
    SetLaneStep {
        /// Which lane.
        lane: usize,
        /// Its dt (s).
        dt: Option<f64>,
        /// Its substeps.
        substeps: Option<u32>,
    },
    /// Equal cost on or off: restarts at tick 0.
    SetEqualCost(bool),
    /// Compare mode on (with the default set) or off.
    ToggleCompare,
    /// Show or hide trails.
    ToggleTrails,
    /// Show or hide the closed-form ghosts.
    ToggleGhosts,
    /// Show or hide the panel.
    TogglePanel,
    /// Show or hide the live plots.
    TogglePlots,
    /// Show or hide the markers (0.1 s, 1 s, apex, impacts, declared events) on the first
    /// bodies' paths.
    ToggleMarkers,
    /// Show or hide the velocity and force arrows on the first bodies.
    ToggleVectors,
    /// Every lane's loop policy, by name ([`crate::clock::LoopPolicy::NAMES`]), from the next
    /// frame.
    SetPolicy(String),
    /// How every lane is drawn, from the next frame.
    SetDrawMode(crate::pacing::DrawMode),
    /// Show or hide the pacing view beside the plots.
    TogglePacing,
    /// Show or hide the judder ghosts.
    ToggleJudder,
    /// Measure this body (storage index in the first lane) in the pacing view.
    SetPacingBody(usize),
    /// Put the pointer on lane 0's body N (input scripts: `hover body N`).
    HoverBody(usize),
    /// Put the pointer on lane 0's body 0's last marker of a kind (`hover marker KIND`).
    HoverMarker(crate::render::probe::MarkerKind),
    /// Pin the probe where it is, or unpin it (a click on the 3D view; `pin`).
    PinProbe,
    /// Click at a position (logical points) or on a named control of the panel (a button's
    /// label): input scripts' `click X Y` and `click LABEL`.
    Click(ClickAt),
    /// Drag the launcher, its aim handle or a target by (dx, dy) physical pixels from where
    /// it is drawn (input scripts: `drag launcher DX DY` and so on).
    Drag(crate::app::setup_drag::Grab, f32, f32),
    /// Write the live plots' series (CSV) and picture (PNG).
    SavePlots,
    /// Write the setup (scene, launcher, targets, integrator, step, compare lanes) as a scene
    /// file.
    SaveSetup,
    /// Point the camera at the whole scene again.
    FrameScene,
    /// Save the window's next frame as a PNG in the working directory.
    Screenshot,
    /// Close the window.
    Quit,
}

/// Where a scripted click lands.
#[derive(Clone, Debug, PartialEq)]
pub enum ClickAt {
    /// A position in logical points from the window's top left.
    Point(f32, f32),
    /// The centre of the panel's button with this label.
    Control(String),
}

/// The integrators compare mode starts with: the engines' choice, its second-order sibling, the
/// textbook baseline and the high-order one.
pub const DEFAULT_COMPARE: [Integrator; 4] = [
    Integrator::ExplicitEuler,
    Integrator::SemiImplicitEuler,
    Integrator::VelocityVerlet,
    Integrator::Rk4,
];

/// Every keyboard shortcut, as (keys, what they do): listed in the panel and the README.
pub const SHORTCUTS: [(&str, &str); 24] = [
    ("Space", "pause / resume"),
    ("N or .", "single step (pauses)"),
    (",", "step back one tick (pauses)"),
    ("B", "play backwards on / off"),
    ("Backspace / End", "jump to the first / the last tick held"),
    ("F", "fire"),
    (
        "A / Shift+A",
        "aim at the target on the high / low arc and fire (each lane solves its own shot)",
    ),
    (
        "R",
        "reset (a Reset command, also after a divergence; compare mode then restarts at tick 0)",
    ),
    (
        "V",
        "record on / off (the first lane, to recordings/SCENE-TIME.vrec)",
    ),
    ("L", "go live: end a replay and run on from its state"),
    (
        "1 to 9, 0",
        "integrator: explicit Euler, semi-implicit Euler, Verlet, midpoint, RK4, implicit Euler, \
         exact, Forest-Ruth, Dormand-Prince, implicit midpoint",
    ),
    ("[ and ]", "time scale / 2, x 2"),
    ("- and =", "dt / 2, x 2 (restarts at tick 0)"),
    ("Up / Down", "elevation +- 1 degree"),
    ("Left / Right", "azimuth +- 1 degree"),
    ("PgUp / PgDn", "launch speed +- 1 m/s"),
    ("C", "compare mode on / off"),
    ("T and G", "trails, ghosts on / off"),
    ("H or F1", "panel on / off"),
    ("K", "live plots on / off"),
    ("M", "markers (0.1 s, 1 s, apex, impacts, events) on / off"),
    ("Y", "velocity and force arrows on / off"),
    ("Home", "frame the scene"),
    ("P / Esc", "screenshot to ./volley-tickN.png / quit"),
];

/// Mouse controls, listed with the shortcuts.
pub const MOUSE: [(&str, &str); 3] = [
    ("left drag", "orbit"),
    ("right or middle drag, shift + left drag", "pan"),
    ("wheel", "zoom"),
];

/// The action a key press asks for, if any.
pub fn action_for_key(key: &Key) -> Option<Action> {
    use Action as A;
    Some(match key {
        Key::Named(named) => match named {
            NamedKey::Space => A::TogglePause,
            NamedKey::ArrowUp => A::NudgeLaunch(0.0, 1.0, 0.0),
            NamedKey::ArrowDown => A::NudgeLaunch(0.0, -1.0, 0.0),
            NamedKey::ArrowLeft => A::NudgeLaunch(0.0, 0.0, 1.0),
            NamedKey::ArrowRight => A::NudgeLaunch(0.0, 0.0, -1.0),
            NamedKey::PageUp => A::NudgeLaunch(1.0, 0.0, 0.0),
            NamedKey::PageDown => A::NudgeLaunch(-1.0, 0.0, 0.0),
            NamedKey::Home => A::FrameScene,
            NamedKey::Backspace => A::JumpStart,
            NamedKey::End => A::JumpEnd,
            NamedKey::F1 => A::TogglePanel,
            NamedKey::Escape => A::Quit,
            _ => return None,
        },
        Key::Character(text) if text.as_str() == "A" => A::Aim(crate::exact::Arc::Low),
        Key::Character(text) => match text.to_lowercase().as_str() {
            "a" => A::Aim(crate::exact::Arc::High),
            "n" | "." => A::Step,
            "," => A::StepBack,
            "b" => A::ToggleReverse,
            "f" => A::Fire,
            "r" => A::Reset,
            "v" => A::ToggleRecord,
            "l" => A::GoLive,
            "[" => A::ScaleTime(0.5),
            "]" => A::ScaleTime(2.0),
            "-" => A::ScaleDt(0.5),
            "=" | "+" => A::ScaleDt(2.0),
            "c" => A::ToggleCompare,
            "t" => A::ToggleTrails,
            "g" => A::ToggleGhosts,
            "h" => A::TogglePanel,
            "k" => A::TogglePlots,
            "m" => A::ToggleMarkers,
            "y" => A::ToggleVectors,
            "p" => A::Screenshot,
            digit => {
                // 1 to 9, then 0 for the tenth, as on the keyboard row.
                let k = digit.parse::<usize>().ok()?;
                A::SetIntegrator(*Integrator::ALL.get(if k == 0 { 9 } else { k - 1 })?)
            }
        },
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digit_keys_pick_integrators_in_table_order() {
        let key = |s: &str| Key::Character(s.into());
        assert_eq!(
            action_for_key(&key("1")),
            Some(Action::SetIntegrator(Integrator::ExplicitEuler))
        );
        assert_eq!(
            action_for_key(&key("7")),
            Some(Action::SetIntegrator(Integrator::Exact))
        );
        assert_eq!(
            action_for_key(&key("8")),
            Some(Action::SetIntegrator(Integrator::ForestRuth))
        );
        assert_eq!(
            action_for_key(&key("0")),
            Some(Action::SetIntegrator(Integrator::ImplicitMidpoint))
        );
        assert_eq!(action_for_key(&key("11")), None);
    }
}
