//! A flat mesh is the ground plane's physics: balls dropped with a sideways speed onto a
//! finely tessellated flat mesh bounce, come to rest and slide across hundreds of triangle
//! edges exactly as they do on the plane z = 0. Found by the levels bench (BENCHMARKS.md,
//! "Level contact"): a body resting on a face a few micrometres from a neighbour's edge took
//! that edge's tilted normal as its resting plane and bounced off the next triangle's edge,
//! losing speed along its track (up to 1.1 m of position over the bench's 10 s).

use glam::DVec3;
use volley_sim::{BodySpec, Ground, Integrator, MeshGeometry, Scene, Transform, World};

/// `n x n` quads over `size` metres at z = 0, centred on the origin.
fn flat(n: usize, size: f64) -> MeshGeometry {
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            v.push(DVec3::new(size * x, size * y, 0.0));
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    MeshGeometry::new(v, t)
}

#[test]
fn balls_sliding_across_a_flat_mesh_end_where_they_end_on_the_plane() {
    // 200 balls on a 20 m square of 0.2 m cells (2 x 10 000 triangles), from 0.5 to 2 m up at
    // up to 1 m/s across: 300 ticks at 60 Hz carry each over a few dozen edges and diagonals.
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let bodies: Vec<BodySpec> = (0..200)
        .map(|_| BodySpec {
            mass: 1.0,
            radius: 0.1,
            position: DVec3::new(8.0 * next() - 4.0, 8.0 * next() - 4.0, 0.5 + 1.5 * next()),
            velocity: DVec3::new(2.0 * next() - 1.0, 2.0 * next() - 1.0, 0.0),
            spin: DVec3::ZERO,
        })
        .collect();
    let base = Scene::builder("flat mesh", 1.0 / 60.0)
        .integrator(Integrator::VelocityVerlet)
        .gravity(DVec3::new(0.0, 0.0, -9.81))
        .build()
        .unwrap()
        .edit()
        .bodies(bodies)
        .build()
        .unwrap();
    let plane = base
        .edit()
        .ground(Ground {
            height: 0.0,
            restitution: 0.5,
        })
        .build()
        .unwrap();
    let mesh = base
        .edit()
        .mesh("flat", flat(100, 20.0), Transform::IDENTITY, 0.5)
        .build()
        .unwrap();
    let (mut a, mut b) = (World::new(&plane), World::new(&mesh));
    a.step_ticks(300).unwrap();
    b.step_ticks(300).unwrap();
    // The same flights and bounces (the mesh's roots are the plane's to rounding); every body
    // stays inside the 20 m square (at most 4 m out and 5 m of sliding).
    let worst = (0..a.bodies().len())
        .map(|i| (a.bodies().positions().get(i) - b.bodies().positions().get(i)).length())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst} m apart");
    for i in 0..b.bodies().len() {
        let p = b.bodies().positions().get(i);
        assert!(p.x.abs().max(p.y.abs()) < 9.9, "{p}");
        assert!((p.z - 0.1).abs() < 1e-9, "{p}");
    }
}
