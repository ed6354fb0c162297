//! A bounding-volume hierarchy over a mesh's triangles, built once when the scene loads.
//!
//! Median split: each node's triangles are sorted by their centroid along the longest axis of
//! the centroids' box (ties by triangle index, so the order is total and the build is the same
//! on every platform) and split in half, down to leaves of at most [`LEAF_SIZE`]. That gives a
//! balanced tree of depth `ceil(log2(n / LEAF_SIZE)) + 1` whatever the mesh, so a query's stack
//! is bounded (Ericson, *Real-Time Collision Detection*, 6.2.1, "median-cut"). The surface area
//! heuristic would give tighter boxes on very uneven meshes at a slower build; levels here are
//! mostly evenly tessellated, and the depth bound matters more.
//!
//! Triangles are stored in leaf order with their world-space corners, so a leaf's test reads
//! one contiguous run.

use glam::DVec3;

/// Most triangles in a leaf.
pub const LEAF_SIZE: usize = 4;

/// An axis-aligned box (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (the identity of [`Aabb::union`]).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// The box around a segment from `a` to `b`, grown by `margin` on every side.
    #[inline]
    pub fn of_segment(a: DVec3, b: DVec3, margin: f64) -> Aabb {
        Aabb {
            min: a.min(b) - DVec3::splat(margin),
            max: a.max(b) + DVec3::splat(margin),
        }
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// The box grown to hold `p`.
    #[inline]
    pub fn with(self, p: DVec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Whether the two boxes share a point (touching counts).
    #[inline]
    pub fn overlaps(&self, o: &Aabb) -> bool {
        (self.min.x <= o.max.x)
            & (self.max.x >= o.min.x)
            & (self.min.y <= o.max.y)
            & (self.max.y >= o.min.y)
            & (self.min.z <= o.max.z)
            & (self.max.z >= o.min.z)
    }
}

/// One node: its box and either two children (`count == 0`, the left child follows the node and
/// the right one is at `index`) or a leaf of `count` triangles from `index`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    index: u32,
    count: u32,
}

/// The hierarchy and the triangles it holds, in leaf order.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// World-space corners, in leaf order.
    triangles: Vec<[DVec3; 3]>,
    /// Each stored triangle's index in the mesh (what events report).
    ids: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy over `triangles` (world-space corners; `ids[i]` names the i-th).
    pub fn build(triangles: &[[DVec3; 3]], ids: &[u32]) -> Bvh {
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let centroids: Vec<DVec3> = triangles
            .iter()
            .map(|t| (t[0] + t[1] + t[2]) * (1.0 / 3.0))
            .collect();
        let mut nodes = Vec::with_capacity(2 * triangles.len() / LEAF_SIZE + 1);
        if !triangles.is_empty() {
            build_node(&mut nodes, &mut order, 0, triangles, &centroids);
        }
        Bvh {
            nodes,
            triangles: order.iter().map(|&i| triangles[i as usize]).collect(),
            ids: order.iter().map(|&i| ids[i as usize]).collect(),
        }
    }

    /// The box around every triangle ([`Aabb::EMPTY`] for none).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// Triangles held.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether it holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Bytes the nodes and the stored triangles take.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
            + self.triangles.len() * std::mem::size_of::<[DVec3; 3]>()
            + self.ids.len() * 4
    }

    /// Calls `f(id, corners)` for every triangle whose leaf box overlaps `query`, in tree order
    /// (left before right: deterministic), until `f` returns `true`; returns whether it did.
    #[inline]
    pub fn any(&self, query: &Aabb, mut f: impl FnMut(u32, &[DVec3; 3]) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        // The median split bounds the depth by log2 of the triangle count (< 64).
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let i = stack[top] as usize;
            let node = &self.nodes[i];
            if !node.bounds.overlaps(query) {
                continue;
            }
            if node.count > 0 {
                let start = node.index as usize;
                for k in start..start + node.count as usize {
                    if f(self.ids[k], &self.triangles[k]) {
                        return true;
                    }
                }
            } else {
                stack[top] = node.index; // right, visited after the left
                stack[top + 1] = i as u32 + 1;
                top += 2;
            }
        }
        false
    }
}

fn build_node(
    nodes: &mut Vec<Node>,
    order: &mut [u32],
    offset: usize,
    triangles: &[[DVec3; 3]],
    centroids: &[DVec3],
) -> usize {
    let bounds = order.iter().fold(Aabb::EMPTY, |b, &i| {
        let t = &triangles[i as usize];
        b.with(t[0]).with(t[1]).with(t[2])
    });
    let at = nodes.len();
    if order.len() <= LEAF_SIZE {
        nodes.push(Node {
            bounds,
            index: offset as u32,
            count: order.len() as u32,
        });
        return at;
    }
    nodes.push(Node {
        bounds,
        index: 0,
        count: 0,
    });
    let spread = order
        .iter()
        .fold(Aabb::EMPTY, |b, &i| b.with(centroids[i as usize]));
    let extent = spread.max - spread.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    order.sort_unstable_by(|&i, &j| {
        let (a, b) = (centroids[i as usize][axis], centroids[j as usize][axis]);
        a.total_cmp(&b).then(i.cmp(&j))
    });
    let half = order.len() / 2;
    let (left, right) = order.split_at_mut(half);
    build_node(nodes, left, offset, triangles, centroids);
    let r = build_node(nodes, right, offset + half, triangles, centroids);
    nodes[at].index = r as u32;
    at
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<[DVec3; 3]> {
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let p = DVec3::new(i as f64, j as f64, 0.0);
                t.push([p, p + DVec3::X, p + DVec3::Y]);
            }
        }
        t
    }

    #[test]
    fn a_query_finds_exactly_the_triangles_whose_boxes_overlap_it() {
        let tris = grid(20);
        let ids: Vec<u32> = (0..tris.len() as u32).collect();
        let bvh = Bvh::build(&tris, &ids);
        let q = Aabb::of_segment(DVec3::new(3.5, 4.5, -1.0), DVec3::new(5.2, 4.6, 1.0), 0.0);
        let mut found = Vec::new();
        bvh.any(&q, |id, t| {
            let b = Aabb::EMPTY.with(t[0]).with(t[1]).with(t[2]);
            if b.overlaps(&q) {
                found.push(id);
            }
            false
        });
        found.sort_unstable();
        let expected: Vec<u32> = (0..tris.len() as u32)
            .filter(|&i| {
                let t = &tris[i as usize];
                Aabb::EMPTY.with(t[0]).with(t[1]).with(t[2]).overlaps(&q)
            })
            .collect();
        assert_eq!(found, expected);
        // Cells x in [i, i + 1] meet [3.5, 5.2] for i = 3, 4, 5; y in [j, j + 1] meets [4.5, 4.6]
        // for j = 4 only.
        assert_eq!(expected, vec![3 * 20 + 4, 4 * 20 + 4, 5 * 20 + 4]);
    }

    #[test]
    fn the_root_box_holds_every_triangle_and_the_build_is_repeatable() {
        let tris = grid(7);
        let ids: Vec<u32> = (0..tris.len() as u32).collect();
        let (a, b) = (Bvh::build(&tris, &ids), Bvh::build(&tris, &ids));
        assert_eq!(a.bounds().min, DVec3::ZERO);
        assert_eq!(a.bounds().max, DVec3::new(7.0, 7.0, 0.0));
        assert_eq!(a.ids, b.ids);
    }
}
