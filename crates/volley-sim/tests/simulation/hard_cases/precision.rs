//! Hard case 8: far from the origin, f32 freezes a slow body; Volley's f64 physics does not.

use super::{allowed, load, run, with};

#[test]
fn a_slow_body_ten_kilometres_out_moves_as_it_should() {
    let scene = load("hard/far_from_origin");
    let ticks = 600;
    let b = scene.bodies()[0];
    let expected = b.position.x + ticks as f64 * scene.dt() * b.velocity.x;
    for integrator in allowed(&scene) {
        let (_, result, world) = run(&with(&scene, integrator), ticks);
        assert!(result.is_ok(), "{integrator}: {result:?}");
        let p = world.bodies().positions().get(0);
        // Each step rounds to half an ulp of 1e4 m (9.1e-13 m): 600 steps stay below 1e-9 m.
        assert!((p.x - expected).abs() < 1e-9, "{integrator}: x = {}", p.x);
        assert!(
            p.x - b.position.x > 0.19,
            "{integrator} moved {} m",
            p.x - b.position.x
        );
    }
}

#[test]
fn the_same_motion_in_f32_does_not_move_at_all() {
    let scene = load("hard/far_from_origin");
    let b = scene.bodies()[0];
    let step = (b.velocity.x * scene.dt()) as f32; // 3.3e-4 m, under half an f32 ulp at 1e4 m
    let mut x = b.position.x as f32;
    for _ in 0..600 {
        x += step;
    }
    assert_eq!(x, b.position.x as f32);
}
