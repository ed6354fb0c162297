//! A grid mesh for the level benchmarks (`crates/volley-sim/benches/levels.rs`,
//! `benches/levels_peer.rs`, both including this file by path).

use glam::DVec3;
use volley_sim::MeshGeometry;

/// A grid mesh of `n x n` quads (2 n^2 triangles) over `size` metres centred on the origin,
/// heights `z(x, y)`.
pub fn grid(n: usize, size: f64, z: impl Fn(f64, f64) -> f64) -> MeshGeometry {
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

/// The wavy terrain both benchmarks use: 0.3 m bumps, 12.6 m by 15.7 m apart.
pub fn wavy(x: f64, y: f64) -> f64 {
    0.3 * libm::sin(0.5 * x) * libm::cos(0.4 * y)
}
