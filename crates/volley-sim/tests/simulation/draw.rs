//! The swept draw: predict's straight path met by the scene's surfaces, and how deep a drawn
//! body sits inside one. Positions are checked against the straight line's own arithmetic: a
//! plane hit at `t = d / v`, reflected with the restitution, to rounding of the metre scale
//! (1e-12 m).

use glam::DVec3;
use volley_sim::internals::scene;
use volley_sim::{DrawMode, World, bundled_scene, swept_position};

fn world(text: &str) -> World {
    World::new(&scene::parse(text, "draw.ron", "draw").unwrap())
}

const GROUND: &str = "Scene(dt: 0.01, integrator: VelocityVerlet, forces: [Gravity((0.0, 0.0, -9.81))], \
    ground: (height: 0.0, restitution: RESTITUTION), walls: [(point: (5.0, 0.0, 0.0), \
    normal: (1.0, 0.0, 0.0), thickness: 0.2, restitution: 1.0)], \
    bodies: [(mass: 1.0, radius: 0.1, position: (0.0, 0.0, 1.0))])";

#[test]
fn a_swept_draw_turns_at_the_ground_and_a_wall_where_the_straight_line_meets_them() {
    let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
    for (e, up) in [(1.0, 1.2), (0.5, 0.65)] {
        let w = world(&GROUND.replace("RESTITUTION", &format!("{e:?}")));
        // Down at 10 m/s from 1 m: the sphere meets the ground at 0.09 s and rises at 10 e m/s
        // for the 0.11 s left.
        let p = swept_position(
            &w,
            0.1,
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, -10.0),
            0.2,
        );
        assert!(close(p, DVec3::new(0.0, 0.0, up)), "e = {e}: {p}");
        assert_eq!(w.contacts().penetration(p, 0.1), 0.0);
        // Predict draws it 0.9 m into the ground.
        let predict = DVec3::new(0.0, 0.0, 1.0) + DVec3::new(0.0, 0.0, -10.0) * 0.2;
        assert!((w.contacts().penetration(predict, 0.1) - 1.1).abs() < 1e-12);
    }
    let w = world(&GROUND.replace("RESTITUTION", "1.0"));
    // At 100 m/s towards the wall 5 m away: it meets the slab's near face (4.9 m) with its
    // surface at 4.8 m after 0.048 s, and comes back for the 0.952 s left.
    let p = swept_position(
        &w,
        0.1,
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(100.0, 0.0, 0.0),
        1.0,
    );
    assert!(close(p, DVec3::new(4.8 - 95.2, 0.0, 1.0)), "{p}");
    // A bounce slower than gravity's gain in a tick (9.81 * 0.01 m/s) rests on the ground.
    let p = swept_position(
        &w,
        0.1,
        DVec3::new(1.0, 0.0, 0.1),
        DVec3::new(2.0, 0.0, -0.05),
        0.1,
    );
    assert!(close(p, DVec3::new(1.2, 0.0, 0.1)), "{p}");
}

#[test]
fn with_no_surface_in_the_way_the_swept_draw_is_predict_bit_for_bit() {
    let w = world(&GROUND.replace("RESTITUTION", "1.0"));
    for (cur, v, tau) in [
        (DVec3::new(0.0, 0.0, 3.0), DVec3::new(1.0, 0.3, 2.0), 0.0213),
        (
            DVec3::new(-7.0, 1.0, 1.0),
            DVec3::new(-30.0, 0.0, -1.0),
            0.05,
        ),
    ] {
        let predict = DrawMode::Predict.position(cur, cur, v, 1.0, tau, 0.0);
        assert_eq!(
            swept_position(&w, 0.1, cur, v, tau).to_array(),
            predict.to_array()
        );
    }
    // And in a scene with no surface at all, whatever the path.
    let orbit = World::new(&bundled_scene("orbit").unwrap());
    let (cur, v) = (DVec3::new(10.0, 0.0, 0.0), DVec3::new(0.0, 10.0, 0.0));
    assert_eq!(swept_position(&orbit, 0.3, cur, v, 0.03), cur + v * 0.03);
}

#[test]
fn a_swept_draw_meets_a_level_mesh_the_straight_line_passes_through() {
    // Hard case 17: a 900 m/s bullet and a 1 cm steel plate 50 m downrange (restitution 0.1).
    // Drawn 0.1 s ahead, predict shows it 40 m beyond the plate; swept stops it at the face and
    // sends it back at a tenth of the speed.
    let w = World::new(&bundled_scene("hard/plate_bullet").unwrap());
    let r = w.bodies().radii()[0];
    let (cur, v) = (DVec3::new(0.0, 0.0, 1.5), DVec3::new(900.0, 0.0, 0.0));
    let p = swept_position(&w, r, cur, v, 0.1);
    let face = 49.995 - r;
    let back = face - 90.0 * (0.1 - face / 900.0);
    assert!((p.x - back).abs() < 1e-9, "{p} vs {back}");
    assert_eq!(w.contacts().penetration(p, r), 0.0);
    // Overlapping the plate's face (a level surface is its triangles), it reads as inside by
    // its overlap: the centre 2 mm past the face at 49.995 m, so r - 2 mm.
    let depth = w.contacts().penetration(DVec3::new(49.997, 0.0, 1.5), r);
    assert!((depth - (r - 0.002)).abs() < 1e-9, "{depth}");
}

#[test]
fn a_wall_is_inside_from_either_side_of_its_slab() {
    let w = world(&GROUND.replace("RESTITUTION", "1.0"));
    let c = w.contacts();
    // The slab spans x in [4.9, 5.1]; a 0.1 m sphere overlaps it from 4.8 to 5.2.
    for (x, depth) in [
        (4.75, 0.0),
        (4.85, 0.05),
        (5.0, 0.2),
        (5.15, 0.05),
        (5.25, 0.0),
    ] {
        let got = c.penetration(DVec3::new(x, 0.0, 3.0), 0.1);
        assert!((got - depth).abs() < 1e-12, "x = {x}: {got}");
    }
    // On the ground to rounding is touching, not inside.
    assert_eq!(c.penetration(DVec3::new(0.0, 0.0, 0.1 - 1e-15), 0.1), 0.0);
}

#[test]
fn a_swept_draw_stops_on_a_moving_target_only_for_a_game_that_removes_shots_there() {
    use volley_sim::{AtTargets, swept_position_at};
    // A target of radius 0.5 m at (10, -2, 1) at tick 0, moving at 2 m/s along y; a 0.1 m shot
    // at 20 m/s along x from (0, 0, 1), drawn 1 s past tick 50 (dt 0.01: 0.5 s since tick 0).
    let mut w = world(
        "Scene(dt: 0.01, integrator: VelocityVerlet, forces: [], \
         targets: [(center: (10.0, -2.0, 1.0), radius: 0.5, velocity: (0.0, 2.0, 0.0))])",
    );
    w.step_ticks(50).unwrap();
    let (cur, v) = (DVec3::new(0.0, 0.0, 1.0), DVec3::new(20.0, 0.0, 0.0));
    // At 0.5 s the target's centre is at (10, -1, 1). The shot closes on it at w = (20, -2, 0)
    // from d = (-10, 1, 0) = -w / 2, head on: the gap is |w| |s - 1/2|, and reaches the 0.6 m
    // of the two radii at s = 1/2 - 0.6 / sqrt(404).
    let s = 0.5 - 0.6 / 404.0f64.sqrt();
    let struck = cur + v * s;
    let expected = struck + DVec3::new(0.0, 2.0, 0.0) * (1.0 - s);
    let p = swept_position_at(&w, AtTargets::Stop, 0.1, (cur, v), 1.0);
    assert!((p - expected).length() < 1e-12, "{p} vs {expected}");
    // It rides on the target's surface: the centre 0.6 m from the target's at 1.5 s.
    let centre = DVec3::new(10.0, -2.0 + 2.0 * 1.5, 1.0);
    assert!(((p - centre).length() - 0.6).abs() < 1e-12);
    // Short of the hit, the straight line; through it by default, as the world's bodies go.
    let short = swept_position_at(&w, AtTargets::Stop, 0.1, (cur, v), 0.2);
    assert_eq!(short.to_array(), (cur + v * 0.2).to_array());
    assert_eq!(
        swept_position(&w, 0.1, cur, v, 1.0).to_array(),
        (cur + v * 1.0).to_array()
    );
}
