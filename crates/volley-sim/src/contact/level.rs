//! Level geometry as scene surfaces: static triangle meshes and heightfields, each with a
//! transform, a restitution and a name that events report.
//!
//! A mesh is baked into world space and its bounding-volume hierarchy ([`super::bvh`]) built
//! once, when the surface is made (the scene's load or [`crate::SceneBuilder::mesh`]); a
//! heightfield keeps its grid in its own frame with the height range of every block of
//! [`BLOCK`] x [`BLOCK`] cells, and a query walks the blocks and cells under the query's box in
//! that frame. Both are behind an `Arc`: a scene, its worlds and their lanes share one copy.

use std::fmt;
use std::sync::Arc;

use glam::{DMat3, DVec3};

use super::bvh::{Aabb, Bvh};
use super::triangle::is_degenerate;

/// Where a surface sits: a point `x` of its file or grid is at `position + R (scale * x)` in the
/// world, `R = Rz(z) Ry(y) Rx(x)` from `rotation_deg` (degrees about the world's x, then y,
/// then z axes).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Transform {
    /// Translation (m).
    pub position: DVec3,
    /// Rotation about x, then y, then z (degrees).
    pub rotation_deg: DVec3,
    /// Scale along the surface's own axes (dimensionless; each non-zero).
    pub scale: DVec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    /// No translation, no rotation, unit scale.
    pub const IDENTITY: Transform = Transform {
        position: DVec3::ZERO,
        rotation_deg: DVec3::ZERO,
        scale: DVec3::ONE,
    };

    /// A translation alone.
    pub fn at(position: DVec3) -> Transform {
        Transform {
            position,
            ..Transform::IDENTITY
        }
    }

    /// The rotation `Rz Ry Rx` (sines and cosines from libm: the same bits everywhere).
    pub fn rotation(&self) -> DMat3 {
        let r = self.rotation_deg * (std::f64::consts::PI / 180.0);
        let (sx, cx) = (libm::sin(r.x), libm::cos(r.x));
        let (sy, cy) = (libm::sin(r.y), libm::cos(r.y));
        let (sz, cz) = (libm::sin(r.z), libm::cos(r.z));
        let rx = DMat3::from_cols(DVec3::X, DVec3::new(0.0, cx, sx), DVec3::new(0.0, -sx, cx));
        let ry = DMat3::from_cols(DVec3::new(cy, 0.0, -sy), DVec3::Y, DVec3::new(sy, 0.0, cy));
        let rz = DMat3::from_cols(DVec3::new(cz, sz, 0.0), DVec3::new(-sz, cz, 0.0), DVec3::Z);
        rz * ry * rx
    }

    /// The linear part `R diag(scale)`.
    pub fn linear(&self) -> DMat3 {
        self.rotation() * DMat3::from_diagonal(self.scale)
    }
}

/// Where a surface's geometry came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LevelSource {
    /// A file, by the path as the scene wrote it (relative to the scene file).
    File(String),
    /// Written in the scene or built in code.
    Inline,
}

/// A triangle mesh as read, in its own frame (m).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshGeometry {
    /// Vertex positions (m).
    pub vertices: Vec<DVec3>,
    /// Triangles, as indices into `vertices` (counter-clockwise seen from outside; the contact
    /// is two-sided, so the winding only matters to a renderer).
    pub triangles: Vec<[u32; 3]>,
    /// Degenerate triangles the reader dropped (zero area, see
    /// `super::triangle::is_degenerate`); they are not in `triangles`.
    pub degenerate: u32,
}

impl MeshGeometry {
    /// A mesh of these triangles, with the degenerate ones (and any with an index past the
    /// vertices) dropped and counted.
    pub fn new(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> MeshGeometry {
        let n = vertices.len();
        let mut degenerate = 0;
        let triangles = triangles
            .into_iter()
            .filter(|t| {
                let ok = t.iter().all(|&i| (i as usize) < n)
                    && !is_degenerate(
                        vertices[t[0] as usize],
                        vertices[t[1] as usize],
                        vertices[t[2] as usize],
                    );
                degenerate += u32::from(!ok);
                ok
            })
            .collect();
        MeshGeometry {
            vertices,
            triangles,
            degenerate,
        }
    }

    /// A 64-bit content hash of the vertices' and indices' bits (xxh3), for meshes built in code.
    pub fn content_hash(&self) -> u64 {
        let mut bytes = Vec::with_capacity(self.vertices.len() * 24 + self.triangles.len() * 12);
        for v in &self.vertices {
            for x in [v.x, v.y, v.z] {
                bytes.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        }
        for t in &self.triangles {
            for i in t {
                bytes.extend_from_slice(&i.to_le_bytes());
            }
        }
        xxhash_rust::xxh3::xxh3_64(&bytes)
    }
}

/// A static triangle mesh in a scene.
#[derive(Clone)]
pub struct MeshSurface {
    /// Name that events and errors report.
    pub name: String,
    /// The file it was read from, or inline.
    pub source: LevelSource,
    /// xxh3 of the file's bytes (of the geometry for an inline mesh): a recording refuses to
    /// replay against another.
    pub content_hash: u64,
    /// Placement in the world.
    pub transform: Transform,
    /// Coefficient of restitution, 0 to 1.
    pub restitution: f64,
    /// The triangles in the mesh's own frame.
    pub geometry: Arc<MeshGeometry>,
    /// The triangles in world space under their hierarchy, built once.
    pub(crate) bvh: Arc<Bvh>,
}

impl MeshSurface {
    /// A surface of `geometry` placed by `transform`; builds its hierarchy (the one cost of a
    /// mesh, paid here and never per tick).
    pub fn new(
        name: impl Into<String>,
        source: LevelSource,
        content_hash: u64,
        geometry: Arc<MeshGeometry>,
        transform: Transform,
        restitution: f64,
    ) -> MeshSurface {
        let (m, at) = (transform.linear(), transform.position);
        let world: Vec<[DVec3; 3]> = geometry
            .triangles
            .iter()
            .map(|t| t.map(|i| at + m * geometry.vertices[i as usize]))
            .collect();
        let ids: Vec<u32> = (0..world.len() as u32).collect();
        MeshSurface {
            name: name.into(),
            source,
            content_hash,
            transform,
            restitution,
            geometry,
            bvh: Arc::new(Bvh::build(&world, &ids)),
        }
    }

    /// The world-space box around the mesh.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Bytes its hierarchy takes (nodes and world-space triangles).
    pub fn hierarchy_bytes(&self) -> usize {
        self.bvh.memory_bytes()
    }

    /// Triangle `index` (as [`crate::contact::Surface::Mesh`] numbers it) in the world, as
    /// the contact meets it; `None` past the last.
    pub fn triangle(&self, index: u32) -> Option<[DVec3; 3]> {
        let t = self.geometry.triangles.get(index as usize)?;
        let (m, at) = (self.transform.linear(), self.transform.position);
        Some(t.map(|i| at + m * self.geometry.vertices[i as usize]))
    }

    /// Every triangle in the world, in [`MeshSurface::triangle`]'s order.
    pub fn triangles(&self) -> impl Iterator<Item = [DVec3; 3]> + '_ {
        let (m, at) = (self.transform.linear(), self.transform.position);
        let v = &self.geometry.vertices;
        self.geometry
            .triangles
            .iter()
            .map(move |t| t.map(|i| at + m * v[i as usize]))
    }
}

impl PartialEq for MeshSurface {
    fn eq(&self, o: &Self) -> bool {
        // The hierarchy follows from the rest.
        self.name == o.name
            && self.source == o.source
            && self.content_hash == o.content_hash
            && self.transform == o.transform
            && self.restitution == o.restitution
            && self.geometry == o.geometry
    }
}

impl fmt::Debug for MeshSurface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MeshSurface")
            .field("name", &self.name)
            .field("source", &self.source)
            .field("content_hash", &format_args!("{:#018x}", self.content_hash))
            .field("transform", &self.transform)
            .field("restitution", &self.restitution)
            .field("triangles", &self.geometry.triangles.len())
            .finish()
    }
}

/// A grid of heights (m): `columns` samples along x, `rows` along y, row-major (the sample of
/// column `i`, row `j` is `heights[j * columns + i]`). A cell is the square between four
/// samples, split into two triangles along its diagonal from `(i, j)` to `(i + 1, j + 1)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HeightGrid {
    /// Samples along x (>= 2).
    pub columns: u32,
    /// Samples along y (>= 2).
    pub rows: u32,
    /// Heights (m), `columns * rows` of them.
    pub heights: Vec<f64>,
}

impl HeightGrid {
    /// Cells along x and y.
    pub fn cells(&self) -> (u32, u32) {
        (self.columns.saturating_sub(1), self.rows.saturating_sub(1))
    }

    /// The sample at column `i`, row `j` (m).
    #[inline]
    pub fn height(&self, i: u32, j: u32) -> f64 {
        self.heights[j as usize * self.columns as usize + i as usize]
    }

    /// A 64-bit content hash of the grid's bits (xxh3), for grids written in the scene.
    pub fn content_hash(&self) -> u64 {
        let mut bytes = Vec::with_capacity(8 + self.heights.len() * 8);
        bytes.extend_from_slice(&self.columns.to_le_bytes());
        bytes.extend_from_slice(&self.rows.to_le_bytes());
        for h in &self.heights {
            bytes.extend_from_slice(&h.to_bits().to_le_bytes());
        }
        xxhash_rust::xxh3::xxh3_64(&bytes)
    }
}

/// Cells along each side of a heightfield block (the walk's coarse level).
pub const BLOCK: u32 = 8;

/// A heightfield in a scene: a [`HeightGrid`] whose samples are `cell_size` apart, placed by a
/// transform.
#[derive(Clone)]
pub struct HeightfieldSurface {
    /// Name that events and errors report.
    pub name: String,
    /// The PNG it was read from, or inline.
    pub source: LevelSource,
    /// xxh3 of the file's bytes (of the grid for an inline one).
    pub content_hash: u64,
    /// Placement in the world (the grid's sample `(i, j)` is at `(i cell, j cell, h)` before
    /// it).
    pub transform: Transform,
    /// Coefficient of restitution, 0 to 1.
    pub restitution: f64,
    /// Distance between neighbouring samples (m), > 0.
    pub cell_size: f64,
    /// Metres per unit of a PNG's 16-bit sample (1 for a grid written in the scene).
    pub height_scale: f64,
    /// The heights (m), already scaled.
    pub grid: Arc<HeightGrid>,
    pub(crate) index: Arc<super::heightfield::GridIndex>,
}

impl HeightfieldSurface {
    /// A surface of `grid` (heights in metres) with samples `cell_size` apart; computes the
    /// blocks' height ranges and the world box once.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        name: impl Into<String>,
        source: LevelSource,
        content_hash: u64,
        grid: Arc<HeightGrid>,
        cell_size: f64,
        height_scale: f64,
        transform: Transform,
        restitution: f64,
    ) -> HeightfieldSurface {
        let index = super::heightfield::GridIndex::build(&grid, cell_size, &transform);
        HeightfieldSurface {
            name: name.into(),
            source,
            content_hash,
            transform,
            restitution,
            cell_size,
            height_scale,
            grid,
            index: Arc::new(index),
        }
    }

    /// The world-space box around the heightfield.
    pub fn bounds(&self) -> Aabb {
        self.index.bounds
    }

    /// Half `half` (0 below the diagonal, 1 above, as [`crate::contact::Surface::Heightfield`]
    /// numbers them) of cell `cell` in the world, as the contact meets it; `None` past the
    /// last cell or for a half other than 0 and 1.
    pub fn triangle(&self, cell: u32, half: u8) -> Option<[DVec3; 3]> {
        let (cx, cy) = self.grid.cells();
        if cx == 0 || cell >= cx.saturating_mul(cy) || half > 1 {
            return None;
        }
        let (i, j) = (cell % cx, cell / cx);
        Some(self.index.cell_triangles(i, j, self.corners(i, j))[usize::from(half)])
    }

    /// Every triangle in the world, cell by cell (row-major), below the diagonal first.
    pub fn triangles(&self) -> impl Iterator<Item = [DVec3; 3]> + '_ {
        let (cx, cy) = self.grid.cells();
        (0..cy)
            .flat_map(move |j| (0..cx).map(move |i| (i, j)))
            .flat_map(|(i, j)| self.index.cell_triangles(i, j, self.corners(i, j)))
    }

    fn corners(&self, i: u32, j: u32) -> [f64; 4] {
        let g = &self.grid;
        [
            g.height(i, j),
            g.height(i + 1, j),
            g.height(i + 1, j + 1),
            g.height(i, j + 1),
        ]
    }
}

impl PartialEq for HeightfieldSurface {
    fn eq(&self, o: &Self) -> bool {
        self.name == o.name
            && self.source == o.source
            && self.content_hash == o.content_hash
            && self.transform == o.transform
            && self.restitution == o.restitution
            && self.cell_size == o.cell_size
            && self.height_scale == o.height_scale
            && self.grid == o.grid
    }
}

impl fmt::Debug for HeightfieldSurface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HeightfieldSurface")
            .field("name", &self.name)
            .field("source", &self.source)
            .field("content_hash", &format_args!("{:#018x}", self.content_hash))
            .field("transform", &self.transform)
            .field("restitution", &self.restitution)
            .field("cell_size", &self.cell_size)
            .field("columns", &self.grid.columns)
            .field("rows", &self.grid.rows)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a renderer draws (`MeshSurface::triangle` and `triangles`) is what the hierarchy
    /// hands the contact, to the bit, on a moved, turned and scaled mesh.
    #[test]
    fn the_drawn_triangles_are_the_ones_the_hierarchy_holds() {
        let vertices: Vec<DVec3> = (0..40)
            .map(|k| {
                let k = f64::from(k);
                DVec3::new(0.37 * k, (0.61 * k).sin() * 3.0, (0.29 * k).cos())
            })
            .collect();
        let triangles: Vec<[u32; 3]> = (0..38).map(|k| [k, k + 1, k + 2]).collect();
        let geometry = Arc::new(MeshGeometry::new(vertices, triangles));
        let t = Transform {
            position: DVec3::new(12.0, -4.5, 0.3),
            rotation_deg: DVec3::new(-15.0, 40.0, 100.0),
            scale: DVec3::new(2.0, 0.5, 1.25),
        };
        let mesh = MeshSurface::new("strip", LevelSource::Inline, 0, geometry, t, 0.5);
        let mut held = Vec::new();
        let everything = Aabb::of_segment(DVec3::splat(-1e6), DVec3::splat(1e6), 0.0);
        mesh.bvh.any(&everything, |id, tri| {
            held.push((id, *tri));
            false
        });
        held.sort_by_key(|(id, _)| *id);
        assert_eq!(held.len(), mesh.geometry.triangles.len());
        let drawn: Vec<_> = mesh.triangles().collect();
        for (id, tri) in &held {
            assert_eq!(mesh.triangle(*id), Some(*tri), "{id}");
            assert_eq!(drawn[*id as usize], *tri, "{id}");
        }
        assert_eq!(mesh.triangle(held.len() as u32), None);
    }
}
