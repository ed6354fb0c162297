//! `--surface-drill`: what a desktop does to a window, for the smoke tests to see it survive.

use winit::window::Window;

use super::surface::WindowGpu;

/// The drill's progress: once each, three frames apart, a resize; a minimise (a 0 x 0 size, as
/// Windows reports it) with the restore after it; a lost surface, rebuilt. The window has to
/// draw on after each.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SurfaceDrill {
    /// Steps done.
    step: u8,
}

impl SurfaceDrill {
    /// After the `frames`-th frame was presented: the next step if it is due. `size` is the
    /// window's initial inner size (logical px).
    pub(super) fn after_frame(
        &mut self,
        frames: u64,
        size: (u32, u32),
        window: &Window,
        gfx: &mut WindowGpu,
    ) {
        if frames < 3 * (u64::from(self.step) + 1) {
            return;
        }
        let (w, h) = size;
        let request = |gfx: &mut WindowGpu, w: u32, h: u32| {
            // Applied at once on some platforms; on others a `Resized` event follows.
            if let Some(size) = window.request_inner_size(winit::dpi::LogicalSize::new(w, h)) {
                gfx.resize(size.width, size.height);
            }
        };
        match self.step {
            0 => request(gfx, w + 160, h + 100),
            1 => {
                gfx.resize(0, 0);
                request(gfx, w, h);
            }
            2 => gfx.rebuild_surface(),
            _ => return,
        }
        self.step += 1;
    }
}
