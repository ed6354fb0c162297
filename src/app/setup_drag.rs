//! Setting a shot up with the mouse: drag the launcher over the ground, drag its aim handle
//! (the barrel's tip) to turn it, drag a target.
//!
//! The launcher moves in the horizontal plane at its height, under the pointer; the handle
//! turns it half a degree of azimuth per pixel sideways and half a degree of elevation per pixel
//! up or down; a target moves in the horizontal plane at its height. While dragging, the
//! launcher (and its predicted shot) or a ring at the target's new place show the change; on
//! release the launcher's change becomes a `launch` command (so recordings, replays and the
//! timeline see it) and a target's move edits the setup and restarts the scene at tick 0 with it,
//! like a dt change (targets are part of the scene, not of the state a recording keeps).

use glam::{DVec3, Vec2};

use crate::command::Command;
use crate::render::{OrbitCamera, Viewport};
use crate::scene::Launcher;

/// What a drag holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Grab {
    /// The launcher: moves over the ground.
    Launcher,
    /// Its aim handle: turns it.
    Handle,
    /// The scene's target with this index.
    Target(usize),
}

/// What the drag would set, shown while it lasts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Preview {
    /// The launcher as it would be.
    Launcher(Launcher),
    /// Where the target would be.
    Target(usize, DVec3),
}

/// A drag under way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetupDrag {
    /// What is held.
    pub grab: Grab,
    /// Where the pointer pressed (physical px).
    pub start: Vec2,
    /// The launcher when the drag began.
    pub launcher: Launcher,
    /// What it would set now.
    pub preview: Preview,
}

/// Degrees of azimuth or elevation per pixel of handle drag.
pub const DEGREES_PER_PIXEL: f64 = 0.5;
/// How near (physical px) the pointer must press to a handle, the launcher or a small target.
pub const GRAB_RADIUS: f32 = 12.0;

/// The aim handle's tip: the launcher's barrel end, as the renderer draws it.
pub fn handle_tip(l: &Launcher, scale: f64) -> DVec3 {
    let dir = l.velocity().try_normalize().unwrap_or(DVec3::Z);
    l.position + 0.06 * scale * dir
}

/// Where the ray through `px` meets the horizontal plane at height `z`, if in front.
fn on_plane(camera: &OrbitCamera, viewport: &Viewport, px: Vec2, z: f64) -> Option<DVec3> {
    let (o, d) = camera.ray(px, viewport);
    if d.z.abs() < 1e-9 {
        return None;
    }
    let t = (z - o.z) / d.z;
    (t > 0.0).then(|| DVec3::new(o.x + t * d.x, o.y + t * d.y, z))
}

/// The thing under `px` a drag can hold: the handle first, then the launcher, then targets.
pub fn grab_at(
    camera: &OrbitCamera,
    viewport: &Viewport,
    px: Vec2,
    launcher: &Launcher,
    targets: &[crate::contact::Target],
    scale: f64,
    since_start: f64,
) -> Option<Grab> {
    let near = |p: DVec3, r: f32| {
        camera
            .project(p, viewport)
            .is_some_and(|s| s.distance(px) <= r)
    };
    if near(handle_tip(launcher, scale), GRAB_RADIUS) {
        return Some(Grab::Handle);
    }
    if near(launcher.position, GRAB_RADIUS) {
        return Some(Grab::Launcher);
    }
    targets
        .iter()
        .position(|t| near(t.center_at(since_start), GRAB_RADIUS))
        .map(Grab::Target)
}

impl SetupDrag {
    /// A drag of `grab` beginning at `start`.
    pub fn begin(
        grab: Grab,
        start: Vec2,
        launcher: Launcher,
        targets: &[crate::contact::Target],
    ) -> SetupDrag {
        let preview = match grab {
            Grab::Target(i) => Preview::Target(i, targets[i].center),
            _ => Preview::Launcher(launcher),
        };
        SetupDrag {
            grab,
            start,
            launcher,
            preview,
        }
    }

    /// Follows the pointer to `px`.
    pub fn update(&mut self, camera: &OrbitCamera, viewport: &Viewport, px: Vec2) {
        let l = self.launcher;
        self.preview = match self.grab {
            Grab::Launcher => {
                let at = on_plane(camera, viewport, px, l.position.z).unwrap_or(l.position);
                Preview::Launcher(Launcher { position: at, ..l })
            }
            Grab::Handle => {
                let d = px - self.start;
                let azimuth = l.azimuth_deg - DEGREES_PER_PIXEL * f64::from(d.x);
                let elevation =
                    (l.elevation_deg - DEGREES_PER_PIXEL * f64::from(d.y)).clamp(-90.0, 90.0);
                Preview::Launcher(Launcher {
                    azimuth_deg: (azimuth + 180.0).rem_euclid(360.0) - 180.0,
                    elevation_deg: elevation,
                    ..l
                })
            }
            Grab::Target(i) => {
                let Preview::Target(_, c) = self.preview else {
                    return;
                };
                let at = on_plane(camera, viewport, px, c.z).unwrap_or(c);
                Preview::Target(i, at)
            }
        };
    }

    /// The command a launcher drag ends in (`None` for a target, or when nothing changed).
    pub fn command(&self) -> Option<Command> {
        let Preview::Launcher(l) = self.preview else {
            return None;
        };
        let before = self.launcher;
        (l != before).then_some(match self.grab {
            Grab::Launcher => Command::SetLaunch {
                speed: None,
                elevation_deg: None,
                azimuth_deg: None,
                position: Some(l.position),
            },
            _ => Command::SetLaunch {
                speed: None,
                elevation_deg: Some(l.elevation_deg),
                azimuth_deg: Some(l.azimuth_deg),
                position: None,
            },
        })
    }
}
