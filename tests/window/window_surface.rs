//! The window's surface: which formats it picks, and that the 3D view still draws in sRGB
//! while egui draws into the plain 8-bit view of the same texture.

use volley::app::surface::pick_formats;
use wgpu::TextureFormat as F;

#[test]
fn the_surface_is_plain_8_bit_for_egui_with_an_srgb_view_for_the_scene_where_allowed() {
    let offered = [F::Bgra8UnormSrgb, F::Bgra8Unorm, F::Rgba16Float];
    assert_eq!(
        pick_formats(&offered, true),
        Some((F::Bgra8Unorm, F::Bgra8UnormSrgb))
    );
    // Without surface view formats: one sRGB format for both, as before.
    assert_eq!(
        pick_formats(&offered, false),
        Some((F::Bgra8UnormSrgb, F::Bgra8UnormSrgb))
    );
    // A format without an sRGB twin is no pair: the sRGB one, or failing that the first.
    assert_eq!(
        pick_formats(&[F::Rgba16Float, F::Rgba8UnormSrgb], true),
        Some((F::Rgba8UnormSrgb, F::Rgba8UnormSrgb))
    );
    assert_eq!(
        pick_formats(&[F::Rgba16Float], true),
        Some((F::Rgba16Float, F::Rgba16Float))
    );
    assert_eq!(pick_formats(&[], true), None);
}

/// The sRGB encoding of a linear channel, in levels of 255.
fn srgb_level(linear: f64) -> f64 {
    let v = if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    };
    v * 255.0
}

#[test]
fn the_3d_view_draws_its_background_srgb_encoded_and_the_panel_its_own_grey() {
    let test = "the_3d_view_draws_its_background_srgb_encoded_and_the_panel_its_own_grey";
    let Some((image, _)) = crate::window_smoke::drawn_under_xvfb(test, 6, &[], &[]) else {
        return;
    };
    // The top right corner of the 3D view is background: the renderer's clear colour (linear)
    // as an sRGB view stores it. Drawn into the plain view it would be about 3, 4 and 6.
    let sky = image.pixel(image.width - 4, 4);
    let c = volley::render::renderer::CLEAR;
    for (k, linear) in [c.r, c.g, c.b].into_iter().enumerate() {
        let want = srgb_level(linear);
        assert!(
            (f64::from(sky[k]) - want).abs() <= 1.0,
            "channel {k}: {} where the sRGB encoding is {want:.1} ({sky:?})",
            sky[k]
        );
    }
    // The panel's background is egui's panel grey, stored as egui gives it (gamma space).
    let fill = egui::Visuals::dark().panel_fill;
    let panel = image.pixel(2, image.height / 2);
    assert_eq!(panel[..3], [fill.r(), fill.g(), fill.b()], "{panel:?}");
}
