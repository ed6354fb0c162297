//! The heightfield's walk: which cells lie under a query, found in the grid's own frame.
//!
//! A query (a sphere around a piece of a body's path) is carried into the grid's frame, where
//! its box covers a rectangle of cells. The walk visits the blocks of [`BLOCK`] x [`BLOCK`]
//! cells under that rectangle, skips a block whose height range misses the box's, then the cells
//! of the block, skipping a cell whose four samples miss it, and hands each remaining cell's two
//! triangles (in world space) to the caller. Rows and columns go in increasing order, so the
//! visit order is fixed. The root search ([`super::roots`]) only asks about short pieces of the
//! path, whose rectangles are a few cells wide, so this is a walk along the path's ground track
//! like Amanatides and Woo's ("A Fast Voxel Traversal Algorithm", Eurographics 1987), done on
//! the subdivided path's pieces instead of one ray.

use glam::{DMat3, DVec3};

use super::bvh::Aabb;
use super::level::{BLOCK, HeightGrid, Transform};

/// What a heightfield keeps besides its grid: the world transform and its inverse, the blocks'
/// height ranges and the world box.
#[derive(Clone, Debug)]
pub struct GridIndex {
    pub(crate) bounds: Aabb,
    linear: DMat3,
    inverse: DMat3,
    position: DVec3,
    /// The largest factor by which the inverse transform stretches a length.
    inverse_stretch: f64,
    cell: f64,
    blocks_x: u32,
    /// `(lowest, highest)` sample of each block, row-major.
    ranges: Vec<(f64, f64)>,
}

impl GridIndex {
    pub(crate) fn build(grid: &HeightGrid, cell: f64, transform: &Transform) -> GridIndex {
        let (cx, cy) = grid.cells();
        let blocks_x = cx.div_ceil(BLOCK);
        let blocks_y = cy.div_ceil(BLOCK);
        let mut ranges = Vec::with_capacity(blocks_x as usize * blocks_y as usize);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for by in 0..blocks_y {
            for bx in 0..blocks_x {
                let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
                for j in by * BLOCK..=((by + 1) * BLOCK).min(cy) {
                    for i in bx * BLOCK..=((bx + 1) * BLOCK).min(cx) {
                        let h = grid.height(i, j);
                        a = a.min(h);
                        b = b.max(h);
                    }
                }
                ranges.push((a, b));
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        let linear = transform.linear();
        let position = transform.position;
        let mut bounds = Aabb::EMPTY;
        for k in 0..8 {
            let local = DVec3::new(
                if k & 1 == 0 {
                    0.0
                } else {
                    f64::from(cx) * cell
                },
                if k & 2 == 0 {
                    0.0
                } else {
                    f64::from(cy) * cell
                },
                if k & 4 == 0 { lo } else { hi },
            );
            bounds = bounds.with(position + linear * local);
        }
        let s = transform.scale.abs();
        GridIndex {
            bounds,
            linear,
            inverse: linear.inverse(),
            position,
            inverse_stretch: 1.0 / s.x.min(s.y).min(s.z),
            cell,
            blocks_x,
            ranges,
        }
    }

    /// The two triangles of cell `(i, j)` in the world, from its corner samples' heights `h`
    /// (at `(i, j)`, `(i + 1, j)`, `(i + 1, j + 1)`, `(i, j + 1)`): below the diagonal
    /// `(p00, p10, p11)`, above it `(p00, p11, p01)`. The one place a cell's corners are
    /// placed, so a renderer draws the triangles the contact meets, to the bit.
    pub(crate) fn cell_triangles(&self, i: u32, j: u32, h: [f64; 4]) -> [[DVec3; 3]; 2] {
        let (x0, y0) = (f64::from(i) * self.cell, f64::from(j) * self.cell);
        let (x1, y1) = (f64::from(i + 1) * self.cell, f64::from(j + 1) * self.cell);
        let w = |x: f64, y: f64, z: f64| self.position + self.linear * DVec3::new(x, y, z);
        let (p00, p10, p11, p01) = (
            w(x0, y0, h[0]),
            w(x1, y0, h[1]),
            w(x1, y1, h[2]),
            w(x0, y1, h[3]),
        );
        [[p00, p10, p11], [p00, p11, p01]]
    }

    /// Calls `f(2 cell + half, corners)` for each triangle of the cells whose samples' range
    /// meets the box of the sphere `(center, radius)` in the grid's frame, until `f` returns
    /// `true`; returns whether it did.
    pub(crate) fn any(
        &self,
        grid: &HeightGrid,
        center: DVec3,
        radius: f64,
        mut f: impl FnMut(u32, &[DVec3; 3]) -> bool,
    ) -> bool {
        let (cx, cy) = grid.cells();
        if cx == 0 || cy == 0 {
            return false;
        }
        let local = self.inverse * (center - self.position);
        let reach = radius * self.inverse_stretch;
        let (zlo, zhi) = (local.z - reach, local.z + reach);
        let span = |lo: f64, hi: f64, n: u32| -> Option<(u32, u32)> {
            let (a, b) = ((lo / self.cell).floor(), (hi / self.cell).floor());
            // NaN fails both comparisons and is skipped too.
            if !(b >= 0.0 && a < f64::from(n)) {
                return None;
            }
            Some((a.max(0.0) as u32, b.min(f64::from(n - 1)) as u32))
        };
        let Some((i0, i1)) = span(local.x - reach, local.x + reach, cx) else {
            return false;
        };
        let Some((j0, j1)) = span(local.y - reach, local.y + reach, cy) else {
            return false;
        };
        for by in j0 / BLOCK..=j1 / BLOCK {
            for bx in i0 / BLOCK..=i1 / BLOCK {
                let (a, b) = self.ranges[(by * self.blocks_x + bx) as usize];
                if b < zlo || a > zhi {
                    continue;
                }
                let (ja, jb) = ((by * BLOCK).max(j0), ((by + 1) * BLOCK - 1).min(j1));
                let (ia, ib) = ((bx * BLOCK).max(i0), ((bx + 1) * BLOCK - 1).min(i1));
                for j in ja..=jb {
                    for i in ia..=ib {
                        let h = [
                            grid.height(i, j),
                            grid.height(i + 1, j),
                            grid.height(i + 1, j + 1),
                            grid.height(i, j + 1),
                        ];
                        let (lo, hi) = (
                            h[0].min(h[1]).min(h[2]).min(h[3]),
                            h[0].max(h[1]).max(h[2]).max(h[3]),
                        );
                        if hi < zlo || lo > zhi {
                            continue;
                        }
                        let [lower, upper] = self.cell_triangles(i, j, h);
                        let id = 2 * (j * cx + i);
                        if f(id, &lower) || f(id + 1, &upper) {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hill() -> HeightGrid {
        // 21 x 21 samples, 20 x 20 cells: heights i + j (m).
        let heights = (0..21)
            .flat_map(|j| (0..21).map(move |i| f64::from(i + j)))
            .collect();
        HeightGrid {
            columns: 21,
            rows: 21,
            heights,
        }
    }

    #[test]
    fn the_walk_visits_only_the_cells_under_the_query() {
        let g = hill();
        let t = Transform::IDENTITY;
        let idx = GridIndex::build(&g, 1.0, &t);
        assert_eq!(idx.bounds.min, DVec3::ZERO);
        assert_eq!(idx.bounds.max, DVec3::new(20.0, 20.0, 40.0));
        let mut seen = Vec::new();
        // A ball of 0.4 m at (10.5, 3.5) at the height of that cell's centre: one cell.
        idx.any(&g, DVec3::new(10.5, 3.5, 14.0), 0.4, |id, _| {
            seen.push(id);
            false
        });
        assert_eq!(seen, vec![2 * (3 * 20 + 10), 2 * (3 * 20 + 10) + 1]);
        // Far above the hill: no cell.
        assert!(!idx.any(&g, DVec3::new(10.5, 3.5, 100.0), 0.4, |_, _| true));
    }

    #[test]
    fn a_moved_grid_is_queried_in_its_own_frame() {
        let g = hill();
        let t = Transform {
            position: DVec3::new(100.0, 0.0, 0.0),
            rotation_deg: DVec3::new(0.0, 0.0, 90.0),
            scale: DVec3::ONE,
        };
        let idx = GridIndex::build(&g, 1.0, &t);
        // Local (10.5, 3.5) is world (100 - 3.5, 10.5).
        let mut seen = Vec::new();
        idx.any(&g, DVec3::new(96.5, 10.5, 14.0), 0.4, |id, _| {
            seen.push(id);
            false
        });
        assert_eq!(seen, vec![2 * (3 * 20 + 10), 2 * (3 * 20 + 10) + 1]);
    }

    /// What a renderer draws (`HeightfieldSurface::triangle` and `triangles`) is what the
    /// walk hands the contact, to the bit, on a moved, turned and scaled grid.
    #[test]
    fn the_drawn_triangles_are_the_ones_the_walk_meets() {
        let g = std::sync::Arc::new(hill());
        let t = Transform {
            position: DVec3::new(-3.25, 7.5, 0.125),
            rotation_deg: DVec3::new(10.0, -20.0, 35.0),
            scale: DVec3::new(0.5, 1.5, 0.75),
        };
        let surface = crate::contact::HeightfieldSurface::new(
            "hill",
            crate::contact::LevelSource::Inline,
            0,
            g.clone(),
            1.0,
            1.0,
            t,
            0.5,
        );
        let mut walked = Vec::new();
        surface.index.any(&g, DVec3::ZERO, 1e6, |id, tri| {
            walked.push((id, *tri));
            false
        });
        assert_eq!(walked.len(), 800);
        for (id, tri) in &walked {
            assert_eq!(surface.triangle(id / 2, (id % 2) as u8), Some(*tri), "{id}");
        }
        walked.sort_by_key(|(id, _)| *id);
        let walked: Vec<_> = walked.into_iter().map(|(_, t)| t).collect();
        let drawn: Vec<_> = surface.triangles().collect();
        assert_eq!(drawn, walked);
        assert_eq!(surface.triangle(400, 0), None);
        assert_eq!(surface.triangle(0, 2), None);
    }
}
