//! Level contact's cost (issue 38's goal: at most 3x today's plane contact per body-tick, at
//! 1e4 bodies against a 1e5-triangle mesh), and the hierarchy's build time and memory.
//!
//! ```text
//! cargo bench -p volley-sim --bench levels
//! ```
//!
//! Three worlds of the same 10 000 balls (seeded: dropped from 0.5 to 5 m with up to 3 m/s
//! across, restitution 0.5, Verlet at 60 Hz), stepped 600 ticks (10 s: flights, bounces, then
//! rest and sliding): on the ground plane z = 0; on a flat 1e5-triangle mesh at z = 0 (the same
//! physics, so the same work but for the contact test); on a wavy 1e5-triangle mesh. Prints
//! nanoseconds per body-tick and the ratios. A timing, not a test: it asserts nothing.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use volley_sim::{
    BodySpec, Ground, Integrator, LevelSource, MeshGeometry, MeshSurface, Scene, Transform, World,
};

/// A grid mesh of `n x n` quads (2 n^2 triangles) over `size` metres, heights `z(x, y)`.
fn grid(n: usize, size: f64, z: impl Fn(f64, f64) -> f64) -> MeshGeometry {
    let mut v = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                size * (i as f64 / n as f64 - 0.5),
                size * (j as f64 / n as f64 - 0.5),
            );
            v.push(DVec3::new(x, y, z(x, y)));
        }
    }
    let mut t = Vec::with_capacity(2 * n * n);
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    MeshGeometry::new(v, t)
}

fn balls(n: usize) -> Vec<BodySpec> {
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| BodySpec {
            mass: 1.0,
            radius: 0.1,
            position: DVec3::new(
                80.0 * next() - 40.0,
                80.0 * next() - 40.0,
                0.5 + 4.5 * next(),
            ),
            velocity: DVec3::new(6.0 * next() - 3.0, 6.0 * next() - 3.0, 0.0),
            spin: DVec3::ZERO,
        })
        .collect()
}

fn base() -> Scene {
    Scene::builder("levels bench", 1.0 / 60.0)
        .integrator(Integrator::VelocityVerlet)
        .gravity(DVec3::new(0.0, 0.0, -9.81))
        .build()
        .expect("the bench's scene is valid")
        .edit()
        .bodies(balls(10_000))
        .build()
        .expect("the bench's scene is valid")
}

/// Nanoseconds per body-tick of `ticks` ticks, best of three runs.
fn time(scene: &Scene, ticks: u64) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let mut w = World::new(scene);
        let start = Instant::now();
        w.step_ticks(ticks).expect("the bench's worlds stay finite");
        let ns = start.elapsed().as_nanos() as f64;
        best = best.min(ns / (ticks as f64 * scene.bodies().len() as f64));
    }
    best
}

fn mesh_scene(geometry: MeshGeometry) -> (Scene, f64, usize) {
    let shared = Arc::new(geometry.clone());
    let start = Instant::now();
    let mesh = MeshSurface::new(
        "grid",
        LevelSource::Inline,
        shared.content_hash(),
        shared,
        Transform::IDENTITY,
        0.5,
    );
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let bytes = mesh.hierarchy_bytes();
    // The scene through the builder, which checks it as a file: the mesh goes into its text.
    let s = base()
        .edit()
        .mesh("grid", geometry, Transform::IDENTITY, 0.5)
        .build()
        .expect("the bench's mesh scene is valid");
    (s, build_ms, bytes)
}

fn main() {
    let ticks = 600;
    let free = time(&base(), ticks);
    let plane = base()
        .edit()
        .ground(Ground {
            height: 0.0,
            restitution: 0.5,
        })
        .build()
        .expect("the bench's scene is valid");
    let plane_ns = time(&plane, ticks);
    // 224 x 224 x 2 = 100 352 triangles over 100 m: cells of 0.45 m.
    let (flat, build_ms, bytes) = mesh_scene(grid(224, 100.0, |_, _| 0.0));
    let tris = flat.meshes()[0].geometry.triangles.len();
    let flat_ns = time(&flat, ticks);
    let (wavy, _, _) = mesh_scene(grid(224, 100.0, |x, y| {
        0.3 * libm::sin(0.5 * x) * libm::cos(0.4 * y)
    }));
    let wavy_ns = time(&wavy, ticks);
    println!("10 000 balls, 600 ticks at 60 Hz, Verlet (ns per body-tick, best of 3)");
    println!("  no contacts          {free:8.1}");
    println!("  ground plane         {plane_ns:8.1}");
    println!(
        "  flat mesh ({tris} tris) {flat_ns:8.1}   {:.2}x the plane",
        flat_ns / plane_ns
    );
    println!(
        "  wavy mesh ({tris} tris) {wavy_ns:8.1}   {:.2}x the plane",
        wavy_ns / plane_ns
    );
    println!(
        "hierarchy of {tris} triangles: built in {build_ms:.1} ms, {:.1} MB ({:.0} bytes a triangle)",
        bytes as f64 / 1e6,
        bytes as f64 / tris as f64
    );
}
