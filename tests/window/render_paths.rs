//! The drawn trajectories (the launcher's predicted shot, the closed-form ghosts) follow their
//! paths: at the default camera no chord leaves its path by more than a pixel, on every bundled
//! scene. An orbit's 62.8 s drawn in 128 even samples once cut across the circle by metres,
//! white spikes around it in the window's picture.

use glam::{DVec3, Vec2};
use volley::render::draw::{horizon, launcher_shot, path_tolerance};
use volley::render::{DrawOptions, OrbitCamera, Reference, SceneBounds, TickHistory, Viewport};
use volley::scene::BUNDLED;
use volley::{World, parse_scene};

/// Distance (px) from `p` to the segment `a`-`b`.
fn to_segment(p: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + t * ab)).length()
}

/// The largest distance (px) between `r`'s drawn chords and its path (7 points inside each
/// chord), at `camera` in `viewport`; and the number of chords.
fn worst_chord(
    r: &Reference,
    world: &World,
    options: &DrawOptions,
    camera: &OrbitCamera,
    viewport: &Viewport,
) -> (f32, usize) {
    let floor = world.contacts().ground.map(|g| g.height);
    let mut points = Vec::new();
    r.trajectory(
        horizon(world),
        world.dt(),
        floor,
        path_tolerance(options),
        &mut points,
    );
    let mut worst = 0.0f32;
    for pair in points.windows(2) {
        let ((t0, p0), (t1, p1)) = (pair[0], pair[1]);
        let (Some(a), Some(b)) = (camera.project(p0, viewport), camera.project(p1, viewport))
        else {
            continue;
        };
        for k in 1..8 {
            let t = t0 + (t1 - t0) * f64::from(k) / 8.0;
            let p: DVec3 = r.exact_at(t).unwrap().p;
            if let Some(q) = camera.project(p, viewport) {
                worst = worst.max(to_segment(q, a, b));
            }
        }
    }
    (worst, points.len().saturating_sub(1))
}

#[test]
fn no_drawn_chord_leaves_its_path_by_more_than_a_pixel_at_the_default_camera() {
    // The whole 1280 x 800 window as the view: the window's own 3D view (right of the panel,
    // above the plots) is smaller, so its pixels are larger in the world and the bound looser.
    let viewport = Viewport::full(1280, 800);
    let (mut checked, mut failures) = (0, Vec::new());
    for (name, text) in BUNDLED {
        let scene = parse_scene(text, name, name).unwrap();
        let world = World::new(&scene);
        let bounds = SceneBounds::of_scene(&scene);
        let camera = OrbitCamera::framing(&bounds, f64::from(viewport.aspect()));
        let options = DrawOptions::picture(bounds.center(), bounds.radius());
        let history = TickHistory::new(&world, bounds.center());
        let mut paths = vec![(
            "launcher".to_string(),
            launcher_shot(&world, world.launcher()),
        )];
        for (i, r) in history.references.all().iter().enumerate().take(16) {
            if r.has_closed_form {
                paths.push((format!("body {i}"), r.clone()));
            }
        }
        for (what, r) in &paths {
            if r.exact_at(0.0).is_none() {
                continue; // no closed form: nothing is drawn
            }
            let (worst, chords) = worst_chord(r, &world, &options, &camera, &viewport);
            if worst > 1.0 {
                failures.push(format!("{name}, {what}: a chord {worst} px off its path"));
            }
            checked += usize::from(chords > 0);
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(checked >= 20, "{checked} paths checked");
}
