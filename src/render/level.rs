//! The scene's level surfaces, meshes and heightfields, as lit opaque triangles: every triangle
//! the contact meets ([`crate::contact::MeshSurface::triangles`],
//! [`crate::contact::HeightfieldSurface::triangles`]), with one normal per face, so what is
//! drawn is what a body hits and nothing is smoothed over.
//!
//! Level geometry is static: the renderer builds these vertices once per scene and render
//! origin ([`LevelKey`]) and keeps them on the GPU, instead of rebuilding them every frame as
//! the [`super::DrawList`] is.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::contact::Contacts;
use crate::render::draw::{Rgba, rel};

/// Colour of mesh surfaces (steel).
pub const MESH: Rgba = [150, 158, 172, 255];
/// Colour of heightfields (turf).
pub const TERRAIN: Rgba = [104, 138, 82, 255];

/// A vertex of a lit triangle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LitVertex {
    /// Position (m, relative to the render origin).
    pub position: [f32; 3],
    /// The face's unit normal (world axes; either side, the shader lights the one in view).
    pub normal: [f32; 3],
    /// sRGB colour.
    pub colour: Rgba,
}

/// What the level's vertices were built from: the render origin and, for each surface, its
/// geometry (the shared copy's address and its content hash) and placement. Equal keys give
/// equal vertices, so the renderer rebuilds only when the key changes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LevelKey(Vec<u64>);

impl LevelKey {
    /// The key of `contacts`' level surfaces drawn about `origin`.
    pub fn of(contacts: &Contacts, origin: DVec3) -> LevelKey {
        let mut k =
            Vec::with_capacity(3 + 12 * (contacts.meshes.len() + contacts.heightfields.len()));
        let put = |v: DVec3, k: &mut Vec<u64>| k.extend(v.to_array().map(f64::to_bits));
        put(origin, &mut k);
        for m in &contacts.meshes {
            k.extend([
                m.content_hash,
                std::sync::Arc::as_ptr(&m.geometry) as usize as u64,
            ]);
            let t = m.transform;
            for v in [t.position, t.rotation_deg, t.scale] {
                put(v, &mut k);
            }
        }
        for h in &contacts.heightfields {
            k.extend([
                h.content_hash,
                std::sync::Arc::as_ptr(&h.grid) as usize as u64,
            ]);
            k.extend([h.cell_size.to_bits(), h.height_scale.to_bits()]);
            let t = h.transform;
            for v in [t.position, t.rotation_deg, t.scale] {
                put(v, &mut k);
            }
        }
        LevelKey(k)
    }
}

/// Appends every level triangle of `contacts` to `out`, three vertices each, positions relative
/// to `origin`: meshes in scene order, then heightfields.
pub fn level_vertices(contacts: &Contacts, origin: DVec3, out: &mut Vec<LitVertex>) {
    for m in &contacts.meshes {
        out.extend(m.triangles().flat_map(|t| lit(t, MESH, origin)));
    }
    for h in &contacts.heightfields {
        out.extend(h.triangles().flat_map(|t| lit(t, TERRAIN, origin)));
    }
}

fn lit(t: [DVec3; 3], colour: Rgba, origin: DVec3) -> [LitVertex; 3] {
    // Degenerate triangles never reach a surface (the readers drop them), and a heightfield's
    // cell has positive area, so the normal exists; a zero one still draws, unlit.
    let normal = (t[1] - t[0])
        .cross(t[2] - t[0])
        .normalize_or_zero()
        .as_vec3()
        .to_array();
    t.map(|p| LitVertex {
        position: rel(p, origin),
        normal,
        colour,
    })
}
