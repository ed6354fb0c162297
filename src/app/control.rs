//! Input to actions, actions to commands: the one place the window changes a simulation.

use super::setup_drag::{Grab, Preview, SetupDrag};
use std::path::PathBuf;

use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};

use super::session::SessionError;
use super::{Action, App};
use crate::command::Command;
use crate::replay::ReplayError;

/// Why an action was refused: the session's reason, a recording that cannot be replayed, or the
/// window's own (a script's click on a control not shown, a hover or a drag on nothing in view,
/// going live with nothing replaying). The panel shows it as its `Display` says.
#[derive(Debug)]
pub(super) enum Refusal {
    /// The session refused.
    Session(SessionError),
    /// The recording could not be replayed.
    Replay(ReplayError),
    /// The window refused.
    Window(String),
}

impl From<SessionError> for Refusal {
    fn from(e: SessionError) -> Refusal {
        Refusal::Session(e)
    }
}

impl From<ReplayError> for Refusal {
    fn from(e: ReplayError) -> Refusal {
        Refusal::Replay(e)
    }
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Session(e) => e.fmt(f),
            Refusal::Replay(e) => e.fmt(f),
            Refusal::Window(why) => f.write_str(why),
        }
    }
}

impl App {
    /// Does what `action` asks; a refusal goes to the panel.
    pub(super) fn apply(&mut self, action: Action) {
        if let Err(why) = self.act(action) {
            self.refuse(why);
        }
    }

    /// Shows `why` in the panel as the last refusal.
    pub(super) fn refuse(&mut self, why: impl std::fmt::Display) {
        self.ui.panel.refuse(&self.session, why);
    }

    /// Does what `action` asks, or says why it cannot.
    fn act(&mut self, action: Action) -> Result<(), Refusal> {
        let s = &mut self.session;
        match action {
            Action::TogglePause => s.set_paused(!s.is_paused()),
            Action::Step => s.single_step(),
            Action::SetLaneStep { lane, dt, substeps } => {
                let set = s.set_lane_step(lane, dt, substeps);
                self.ui.panel.sync(&self.session);
                set?;
            }
            Action::SetEqualCost(on) => s.set_equal_cost(on)?,
            Action::Seek(tick) => s.seek(tick)?,
            Action::StepBack => s.step_back()?,
            Action::JumpStart => s.jump_to_start()?,
            Action::JumpEnd => s.jump_to_end()?,
            Action::ToggleReverse => s.toggle_reverse(),
            Action::SetTimeScale(x) => s.set_time_scale(x)?,
            Action::ScaleTime(f) => s.set_time_scale((s.time_scale() * f).clamp(1e-3, 100.0))?,
            Action::SetStep { dt, substeps } => self.set_step(dt, substeps)?,
            Action::ScaleDt(f) => {
                let (dt, substeps) = (s.scene().dt() * f, s.scene().substeps());
                self.set_step(dt, substeps)?;
            }
            Action::SetIntegrator(i) => s.push(Command::SetIntegrator(i))?,
            Action::Launch {
                speed,
                elevation_deg,
                azimuth_deg,
            } => s.push(Command::SetLaunch {
                speed,
                elevation_deg,
                azimuth_deg,
                position: None,
            })?,
            Action::NudgeLaunch(ds, de, da) => {
                let p = &mut self.ui.panel;
                p.speed = (p.speed + ds).max(0.0);
                p.elevation_deg = (p.elevation_deg + de).clamp(-90.0, 90.0);
                p.azimuth_deg += da;
                s.push(Command::SetLaunch {
                    speed: Some(p.speed),
                    elevation_deg: Some(p.elevation_deg),
                    azimuth_deg: Some(p.azimuth_deg),
                    position: None,
                })?;
            }
            Action::Fire => s.push(Command::Fire)?,
            Action::Aim(arc) => s.aim(arc, self.ui.panel.aim_target)?,
            Action::Reset => s.reset()?,
            Action::ToggleRecord => s.toggle_recording()?,
            Action::Replay(path) => self.replay(&path)?,
            Action::GoLive => {
                if !s.go_live() {
                    return Err(Refusal::Window("go live: nothing is replaying".into()));
                }
                self.ui.panel.sync(&self.session);
                self.ui.panel.refused = None;
                self.retitle();
            }
            Action::PickScene(path) => self.load_scene(&path, false),
            Action::SetCompare(list) => s.set_compare(list)?,
            Action::ToggleCompare => {
                let list = if s.is_comparing() {
                    Vec::new()
                } else {
                    self.ui.panel.compare_pick.clone()
                };
                s.set_compare(list)?;
            }
            Action::ToggleTrails => self.ui.toggles.trails = !self.ui.toggles.trails,
            Action::ToggleGhosts => self.ui.toggles.ghosts = !self.ui.toggles.ghosts,
            Action::TogglePanel => self.ui.toggles.panel = !self.ui.toggles.panel,
            Action::TogglePlots => self.ui.toggles.plots = !self.ui.toggles.plots,
            Action::ToggleMarkers => self.ui.toggles.markers = !self.ui.toggles.markers,
            Action::ToggleVectors => self.ui.toggles.vectors = !self.ui.toggles.vectors,
            Action::SetPolicy(name) => s.set_policy_named(&name)?,
            Action::SetDrawMode(mode) => s.set_draw_mode(mode),
            Action::TogglePacing => self.ui.toggles.pacing = !self.ui.toggles.pacing,
            Action::ToggleJudder => self.ui.toggles.judder = !self.ui.toggles.judder,
            Action::SetPacingBody(i) => s.set_pacing_body(i),
            Action::HoverBody(n) => {
                let at = super::pick::body_on_screen(s, &self.view.camera, &self.view.viewport, n);
                self.hover_script(at, format!("hover body {n}"))?;
            }
            Action::HoverMarker(kind) => {
                let at =
                    super::pick::marker_on_screen(s, &self.view.camera, &self.view.viewport, kind);
                let name = super::pick::marker_name(kind);
                self.hover_script(at, format!("hover marker ({name})"))?;
            }
            Action::PinProbe => {
                self.ui.probe_pinned = self.ui.probe.is_some() && !self.ui.probe_pinned
            }
            Action::Drag(grab, dx, dy) => self.scripted_drag(grab, dx, dy)?,
            Action::Click(at) => self.scripted_click(&at)?,
            Action::SaveSetup => {
                let dir = s.recordings_dir().to_path_buf();
                self.ui.panel.saved_note = Some(match s.save_setup(&dir) {
                    Ok(path) => format!("saved the setup to {}", path.display()),
                    Err(e) => format!("could not save the setup: {e}"),
                });
            }
            Action::SavePlots => {
                let dir = s.recordings_dir().to_path_buf();
                self.ui.panel.saved_note = Some(match super::panel::plots::write(&dir, s) {
                    Ok((csv, png)) => format!("saved {} and {}", csv.display(), png.display()),
                    Err(e) => format!("could not save the plots: {e}"),
                });
            }
            Action::FrameScene => self.view.needs_framing = true,
            Action::Screenshot => {
                let tick = s.world().tick();
                self.screenshot = Some(PathBuf::from(format!("volley-tick{tick}.png")));
            }
            Action::Quit => self.quit(),
        }
        Ok(())
    }

    /// Changes the step; the panel's step fields follow unless it is refused.
    fn set_step(&mut self, dt: f64, substeps: u32) -> Result<(), SessionError> {
        self.session.set_step(dt, substeps)?;
        self.ui.panel.sync(&self.session);
        Ok(())
    }

    /// Replays `path` in the window; a file that cannot be replayed leaves the session alone.
    fn replay(&mut self, path: &std::path::Path) -> Result<(), ReplayError> {
        self.replay_from(super::session::replaying::ReplaySource::File(
            path.to_path_buf(),
        ))
    }

    /// Replays a recording from `source` (a file, or a browser's bytes); one that cannot be
    /// replayed leaves the session alone.
    pub(super) fn replay_from(
        &mut self,
        source: super::session::replaying::ReplaySource,
    ) -> Result<(), ReplayError> {
        self.session.start_replay_from(source, None)?;
        self.ui.panel.sync(&self.session);
        self.rewatch();
        self.retitle();
        self.view.needs_framing = true;
        Ok(())
    }

    /// A script's click: on the 3D view it pins the probe there (what a real click does); on
    /// the panel it is a press and a release fed to egui over two frames, so the button under
    /// it acts as if clicked. Refused for a control the panel does not show.
    fn scripted_click(&mut self, at: &super::input::ClickAt) -> Result<(), Refusal> {
        use super::input::ClickAt;
        let point = match at {
            ClickAt::Point(x, y) => egui::pos2(*x, *y),
            ClickAt::Control(label) => match self.ui.controls.0.iter().find(|(l, _)| l == label) {
                Some((_, rect)) => rect.center(),
                None => {
                    return Err(Refusal::Window(format!(
                        "click {label}: no such control shown"
                    )));
                }
            },
        };
        let ppp = self.host.egui.pixels_per_point();
        let (px, py) = (point.x * ppp, point.y * ppp);
        let v = &self.view.viewport;
        let on_view = matches!(at, ClickAt::Point(..))
            && px >= v.x
            && px < v.x + v.width
            && py >= v.y
            && py < v.y + v.height;
        if on_view {
            self.ui.pointer.position = Some((f64::from(px), f64::from(py)));
            self.ui.probe = super::pick::pick(
                &self.session,
                &self.view.camera,
                &self.view.viewport,
                (px, py),
                super::pick::PICK_RADIUS * ppp,
            );
            return self.act(Action::PinProbe);
        }
        let button = |pressed| egui::Event::PointerButton {
            pos: point,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        self.script
            .queue_input(vec![egui::Event::PointerMoved(point), button(true)]);
        self.script.queue_input(vec![button(false)]);
        Ok(())
    }

    /// Where `grab` is drawn now (physical px).
    fn grab_position(&self, grab: Grab) -> Option<glam::Vec2> {
        let world = self.session.world();
        let l = world.launcher();
        let p = match grab {
            Grab::Launcher => l.position,
            Grab::Handle => super::setup_drag::handle_tip(l, self.session.bounds().radius()),
            Grab::Target(i) => world
                .contacts()
                .targets
                .get(i)?
                .center_at(world.tick() as f64 * world.dt()),
        };
        self.view.camera.project(p, &self.view.viewport)
    }

    /// A script's drag: press on `grab`, move by (dx, dy), release; refused for what is not in
    /// view.
    fn scripted_drag(&mut self, grab: Grab, dx: f32, dy: f32) -> Result<(), Refusal> {
        let Some(start) = self.grab_position(grab) else {
            return Err(Refusal::Window(format!("drag {grab:?}: it is not in view")));
        };
        let world = self.session.world();
        let mut drag = SetupDrag::begin(grab, start, *world.launcher(), &world.contacts().targets);
        drag.update(
            &self.view.camera,
            &self.view.viewport,
            start + glam::Vec2::new(dx, dy),
        );
        self.ui.setup_drag = Some(drag);
        Ok(self.end_setup_drag()?)
    }

    /// Ends a drag: the launcher's change as a `launch` command, a target's as a setup change;
    /// returns why the session refused it.
    fn end_setup_drag(&mut self) -> Result<(), SessionError> {
        let Some(drag) = self.ui.setup_drag.take() else {
            return Ok(());
        };
        match drag.preview {
            Preview::Target(i, at) => {
                let moved = self.session.move_target(i, at);
                self.ui.panel.sync(&self.session);
                moved
            }
            Preview::Launcher(_) => match drag.command() {
                Some(command) => self.session.push(command),
                None => Ok(()),
            },
        }
    }

    /// The drag's preview of the launcher, for drawing.
    pub(super) fn dragged_launcher(&self) -> Option<crate::scene::Launcher> {
        match self.ui.setup_drag?.preview {
            Preview::Launcher(l) => Some(l),
            Preview::Target(..) => None,
        }
    }

    /// The drag's preview of a target's place, for drawing.
    pub(super) fn dragged_target(&self) -> Option<glam::DVec3> {
        match self.ui.setup_drag?.preview {
            Preview::Target(_, at) => Some(at),
            Preview::Launcher(_) => None,
        }
    }

    /// What a press at the pointer would grab (live runs only).
    fn grab_under_pointer(&self) -> Option<Grab> {
        let (x, y) = self.ui.pointer.position?;
        if self.session.replay().is_some() {
            return None;
        }
        let world = self.session.world();
        super::setup_drag::grab_at(
            &self.view.camera,
            &self.view.viewport,
            glam::Vec2::new(x as f32, y as f32),
            world.launcher(),
            &world.contacts().targets,
            self.session.bounds().radius(),
            world.tick() as f64 * world.dt(),
        )
    }

    /// A script's hover: the pointer goes to `at`, or it says it could not.
    fn hover_script(&mut self, at: Option<(f32, f32)>, what: String) -> Result<(), Refusal> {
        let (x, y) =
            at.ok_or_else(|| Refusal::Window(format!("{what}: nothing there to hover")))?;
        self.ui.pointer.position = Some((f64::from(x), f64::from(y)));
        Ok(())
    }

    pub(super) fn on_pointer(&mut self, event: &WindowEvent, over_ui: bool) {
        match *event {
            WindowEvent::ModifiersChanged(m) => self.ui.pointer.shift = m.state().shift_key(),
            WindowEvent::MouseInput { state, button, .. }
                if button == MouseButton::Left
                    && state == ElementState::Released
                    && self.ui.setup_drag.is_some() =>
            {
                if let Err(why) = self.end_setup_drag() {
                    self.refuse(why);
                }
                self.ui.pointer.dragging = None;
            }
            WindowEvent::MouseInput { state, button, .. }
                if button == MouseButton::Left
                    && state == ElementState::Pressed
                    && !over_ui
                    && !self.ui.pointer.shift
                    && self.grab_under_pointer().is_some() =>
            {
                if let (Some(grab), Some((x, y))) =
                    (self.grab_under_pointer(), self.ui.pointer.position)
                {
                    let world = self.session.world();
                    let start = glam::Vec2::new(x as f32, y as f32);
                    let targets = &world.contacts().targets;
                    self.ui.setup_drag =
                        Some(SetupDrag::begin(grab, start, *world.launcher(), targets));
                }
            }
            WindowEvent::CursorMoved { position, .. } if self.ui.setup_drag.is_some() => {
                let px = glam::Vec2::new(position.x as f32, position.y as f32);
                let (camera, viewport) = (self.view.camera, self.view.viewport);
                if let Some(drag) = self.ui.setup_drag.as_mut() {
                    drag.update(&camera, &viewport, px);
                }
                self.ui.pointer.position = Some((position.x, position.y));
            }
            WindowEvent::MouseInput { state, button, .. } => {
                // A left click that did not drag pins (or unpins) the probe.
                if state == ElementState::Released
                    && button == MouseButton::Left
                    && !self.ui.pointer.moved
                    && self.ui.pointer.dragging.is_some()
                {
                    self.apply(Action::PinProbe);
                }
                self.ui.pointer.dragging = match state {
                    ElementState::Pressed if !over_ui => Some(button),
                    _ => None,
                };
                self.ui.pointer.moved = false;
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (Some(button), Some(last)) =
                    (self.ui.pointer.dragging, self.ui.pointer.position)
                {
                    let (dx, dy) = (now.0 - last.0, now.1 - last.1);
                    self.ui.pointer.moved |= dx.abs() + dy.abs() > 2.0;
                    let orbit = button == MouseButton::Left && !self.ui.pointer.shift;
                    if orbit {
                        // Degrees per logical pixel, the same feel at any HiDPI scale.
                        let scale = self.timing.stats.scale.max(1.0);
                        self.view.camera.orbit(dx / scale, dy / scale);
                    } else {
                        let h = f64::from(self.view.viewport.height.max(1.0));
                        self.view.camera.pan(dx, dy, h);
                    }
                }
                self.ui.pointer.position = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } if !over_ui => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.view.camera.zoom(steps);
            }
            _ => {}
        }
    }
}
