//! The 3D view: its camera, the rectangle of the surface it fills, and whether it still has to
//! frame the scene.

use crate::render::{OrbitCamera, SceneBounds, Viewport};

/// The camera the scene is drawn with and where on the surface it is drawn.
pub(super) struct SceneView {
    /// The orbiting camera the pointer drives.
    pub(super) camera: OrbitCamera,
    /// What the panels leave of the surface (physical px).
    pub(super) viewport: Viewport,
    /// The camera frames the scene as soon as the view has a size (at start, after a new
    /// scene or replay, on the key).
    pub(super) needs_framing: bool,
}

impl SceneView {
    /// A camera framing `bounds` at 16:9 until the view has its size, and framed again then.
    pub(super) fn new(bounds: &SceneBounds) -> SceneView {
        SceneView {
            camera: OrbitCamera::framing(bounds, 16.0 / 9.0),
            viewport: Viewport::full(1, 1),
            needs_framing: true,
        }
    }

    /// Frames `bounds` if asked to and the view is visible.
    pub(super) fn frame_if_asked(&mut self, bounds: &SceneBounds) {
        if self.needs_framing && self.viewport.is_visible() {
            let aspect = f64::from(self.viewport.aspect());
            self.camera = OrbitCamera::framing(bounds, aspect);
            self.needs_framing = false;
        }
    }
}

/// The 3D viewport in physical pixels: egui's remaining rectangle (points) times the scale,
/// clamped to the surface.
pub(super) fn viewport_of(rest: egui::Rect, ppp: f32, size: (u32, u32)) -> Viewport {
    let (w, h) = (size.0 as f32, size.1 as f32);
    if !rest.is_positive() {
        return Viewport::full(size.0, size.1);
    }
    let x = (rest.min.x * ppp).clamp(0.0, w).round();
    let y = (rest.min.y * ppp).clamp(0.0, h).round();
    Viewport {
        x,
        y,
        width: ((rest.max.x * ppp).clamp(0.0, w).round() - x).max(0.0),
        height: ((rest.max.y * ppp).clamp(0.0, h).round() - y).max(0.0),
    }
}
