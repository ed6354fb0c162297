//! The orbit camera: a target point, a distance, and two angles, z up.
//!
//! Positions stay `f64` until the last moment: the camera and everything drawn are expressed
//! relative to a render origin (the scene's centre, see [`crate::render::SceneBounds`]) before
//! they become `f32`, so a scene 10 km from the world origin draws as steadily as one at it.
//! Depth is reversed (near plane at depth 1, infinity at 0) for even precision at every range.

use glam::{DVec3, Mat4, Vec2, Vec3};

/// A rectangle of the target in physical pixels, y down from the top-left corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Left edge (px).
    pub x: f32,
    /// Top edge (px).
    pub y: f32,
    /// Width (px).
    pub width: f32,
    /// Height (px).
    pub height: f32,
}

impl Viewport {
    /// The whole of a `width` x `height` target.
    pub fn full(width: u32, height: u32) -> Viewport {
        Viewport {
            x: 0.0,
            y: 0.0,
            width: width as f32,
            height: height as f32,
        }
    }

    /// Width over height (1 for an empty viewport, so a minimised window never divides by 0).
    pub fn aspect(&self) -> f32 {
        if self.width > 0.0 && self.height > 0.0 {
            self.width / self.height
        } else {
            1.0
        }
    }

    /// Whether the viewport covers at least one pixel.
    pub fn is_visible(&self) -> bool {
        self.width >= 1.0 && self.height >= 1.0
    }
}

/// A camera orbiting a target point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at and orbited (m).
    pub target: DVec3,
    /// Distance from the eye to the target (m), > 0.
    pub distance: f64,
    /// Azimuth of the eye around the target (degrees, from +x towards +y).
    pub yaw_deg: f64,
    /// Elevation of the eye above the target's horizontal plane (degrees, -89 to 89).
    pub pitch_deg: f64,
    /// Vertical field of view (degrees).
    pub fov_y_deg: f64,
}

/// Steepest elevation the orbit allows (degrees): keeps "up" defined.
pub const MAX_PITCH_DEG: f64 = 89.0;
/// Degrees of orbit per pixel of mouse drag.
pub const ORBIT_DEG_PER_PX: f64 = 0.3;
/// Distance factor per scroll step (one notch of a wheel zooms in by 10 %).
pub const ZOOM_PER_STEP: f64 = 0.9;

impl OrbitCamera {
    /// A camera looking at `target` from `distance`, from the -y side and 20 degrees up, so a
    /// shot along +x flies left to right with z up on screen.
    pub fn looking_at(target: DVec3, distance: f64) -> OrbitCamera {
        OrbitCamera {
            target,
            distance: distance.max(1e-3),
            yaw_deg: -90.0,
            pitch_deg: 20.0,
            fov_y_deg: 45.0,
        }
    }

    /// Unit vector from the target towards the eye.
    pub fn back(&self) -> DVec3 {
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        DVec3::new(
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            pitch.sin(),
        )
    }

    /// The eye position (m).
    pub fn eye(&self) -> DVec3 {
        self.target + self.distance * self.back()
    }

    /// View matrix for positions given relative to `origin`.
    pub fn view(&self, origin: DVec3) -> Mat4 {
        let eye = (self.eye() - origin).as_vec3();
        let target = (self.target - origin).as_vec3();
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Z)
    }

    /// Near plane (m): a thousandth of the orbit distance, so zooming never clips the target.
    pub fn near(&self) -> f32 {
        (self.distance * 1e-3).max(1e-4) as f32
    }

    /// Reversed-depth infinite perspective projection for `aspect` (width / height).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective_infinite_reverse(
            (self.fov_y_deg as f32).to_radians(),
            aspect,
            self.near(),
        )
    }

    /// Pixel position of world point `p` in `viewport` (x right, y down, the pixel grid's own
    /// coordinates: the centre of the top-left pixel is (0.5, 0.5)), or `None` behind the eye.
    pub fn project(&self, p: DVec3, viewport: &Viewport) -> Option<Vec2> {
        let clip = self.projection(viewport.aspect())
            * self.view(self.target)
            * (p - self.target).as_vec3().extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            viewport.x + (ndc.x + 1.0) * 0.5 * viewport.width,
            viewport.y + (1.0 - ndc.y) * 0.5 * viewport.height,
        ))
    }

    /// The ray through pixel `px` of `viewport` (the inverse of [`OrbitCamera::project`]): its
    /// origin on the near plane and its unit direction, world coordinates.
    pub fn ray(&self, px: Vec2, viewport: &Viewport) -> (DVec3, DVec3) {
        let ndc = Vec2::new(
            (px.x - viewport.x) / viewport.width.max(1.0) * 2.0 - 1.0,
            1.0 - (px.y - viewport.y) / viewport.height.max(1.0) * 2.0,
        );
        let inverse = (self.projection(viewport.aspect()) * self.view(self.target)).inverse();
        // Reversed depth: the near plane is at z = 1, farther points towards 0.
        let at = |z: f32| {
            let p = inverse * ndc.extend(z).extend(1.0);
            self.target + (p.truncate() / p.w).as_dvec3()
        };
        let (near, far) = (at(1.0), at(0.5));
        (near, (far - near).normalize_or(-self.back()))
    }

    /// Turns the eye around the target by a mouse drag of (`dx`, `dy`) pixels.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        self.yaw_deg = (self.yaw_deg - dx * ORBIT_DEG_PER_PX).rem_euclid(360.0);
        self.pitch_deg =
            (self.pitch_deg + dy * ORBIT_DEG_PER_PX).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }

    /// Moves closer (`steps` > 0) or further away, by [`ZOOM_PER_STEP`] per step.
    pub fn zoom(&mut self, steps: f64) {
        self.distance = (self.distance * ZOOM_PER_STEP.powf(steps)).clamp(1e-3, 1e7);
    }

    /// Slides the target across the screen so the point under the cursor follows a drag of
    /// (`dx`, `dy`) pixels in a viewport `height` pixels tall.
    pub fn pan(&mut self, dx: f64, dy: f64, height: f64) {
        let per_px = 2.0 * self.distance * (self.fov_y_deg.to_radians() * 0.5).tan() / height;
        let back = self.back();
        let right = DVec3::Z.cross(back).try_normalize().unwrap_or(DVec3::X);
        let up = back.cross(right);
        self.target += per_px * (-dx * right + dy * up);
    }

    /// A camera that shows all of `bounds` from its angle ([`SceneBounds::yaw_deg`](
    /// crate::render::SceneBounds::yaw_deg), 20 degrees up) in a view of `aspect` (width /
    /// height), with a 10 % margin.
    pub fn framing(bounds: &crate::render::SceneBounds, aspect: f64) -> OrbitCamera {
        let mut camera = OrbitCamera::looking_at(bounds.center(), 1.0);
        camera.yaw_deg = bounds.yaw_deg;
        let tan_v = (camera.fov_y_deg.to_radians() * 0.5).tan() / 1.1;
        let tan_h = tan_v * aspect.max(1e-3);
        let back = camera.back();
        let right = DVec3::Z.cross(back).normalize();
        let up = back.cross(right);
        // A corner at offset q from the target is in view when its sideways and vertical offsets
        // stay within the field of view at its depth `d - q.back`: d >= q.back + |q.right| / tan_h
        // and d >= q.back + |q.up| / tan_v.
        let mut distance: f64 = 1e-3;
        for k in 0..8 {
            let corner = bounds.corner(k);
            let q = corner - camera.target;
            let along = q.dot(back);
            distance = distance
                .max(along + q.dot(right).abs() / tan_h)
                .max(along + q.dot(up).abs() / tan_v);
        }
        camera.distance = distance.max(1.0);
        camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_view_has_z_up_and_x_to_the_right() {
        let camera = OrbitCamera::looking_at(DVec3::ZERO, 10.0);
        let vp = Viewport::full(200, 100);
        let centre = camera.project(DVec3::ZERO, &vp).unwrap();
        let up = camera.project(DVec3::Z, &vp).unwrap();
        let right = camera.project(DVec3::X, &vp).unwrap();
        assert!(
            (centre - Vec2::new(100.0, 50.0)).length() < 1e-3,
            "{centre}"
        );
        assert!(up.y < centre.y, "z is up on screen");
        assert!(right.x > centre.x, "x is to the right");
    }

    #[test]
    fn orbit_never_passes_the_pole() {
        let mut camera = OrbitCamera::looking_at(DVec3::ZERO, 10.0);
        camera.orbit(0.0, 1e6);
        assert_eq!(camera.pitch_deg, MAX_PITCH_DEG);
        camera.orbit(0.0, -1e6);
        assert_eq!(camera.pitch_deg, -MAX_PITCH_DEG);
    }

    #[test]
    fn panning_moves_the_target_across_the_view_not_along_it() {
        let mut camera = OrbitCamera::looking_at(DVec3::ZERO, 10.0);
        camera.pan(30.0, -20.0, 100.0);
        assert!(camera.target.dot(camera.back()).abs() < 1e-12);
    }
}
