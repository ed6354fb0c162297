//! glTF 2.0, read with the gltf crate: `.glb` with its binary chunk, or `.gltf` JSON with its
//! buffers in `.bin` files beside it. The default scene's nodes (or every mesh once, when the
//! file has no scene) are placed by their node transforms; triangle primitives only (points,
//! lines and strips are skipped). glTF is y-up and Volley is z-up: a glTF point `(x, y, z)`
//! becomes `(x, -z, y)`. Buffers given as data URIs are refused (no base64 decoder is linked).

use glam::{DMat4, DVec3, DVec4};

use super::{LevelError, check_triangles};
use crate::contact::MeshGeometry;

/// Most nodes visited in one file's scene hierarchy, and the deepest nesting followed: a
/// hostile file cannot make the walk run long.
const MAX_NODE_VISITS: usize = 1 << 20;
const MAX_NODE_DEPTH: usize = 64;

/// Reads a glTF or GLB file's bytes; `buffer(uri)` reads an external buffer (relative to the
/// file). Returns the mesh and the bytes of every external buffer read, in buffer order (for
/// the content hash).
pub fn read_gltf(
    bytes: &[u8],
    file: &str,
    buffer: &mut dyn FnMut(&str) -> Result<Vec<u8>, LevelError>,
) -> Result<(MeshGeometry, Vec<Vec<u8>>), LevelError> {
    // The gltf crate subtracts the 12-byte header from a GLB's declared length unchecked (an
    // overflow panic in debug builds, found by fuzzing): check it first.
    if bytes.starts_with(b"glTF") && bytes.len() >= 12 {
        let declared = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if declared < 12 {
            return Err(LevelError::new(
                file,
                format!(
                    "not a readable glTF file: a GLB length of {declared} bytes, less than its 12-byte header"
                ),
            ));
        }
    }
    let unreadable =
        |e: gltf::Error| LevelError::new(file, format!("not a readable glTF file: {e}"));
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(unreadable)?;
    // gltf-json's validation indexes the accessors by a primitive's POSITION before checking
    // the index (a panic, found by fuzzing): check it here first, then validate.
    let json = raw.document.into_json();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for p in &mesh.primitives {
            let position = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
            if let Some(i) = p.attributes.get(&position)
                && i.value() >= json.accessors.len()
            {
                return Err(LevelError::new(
                    file,
                    format!(
                        "mesh {m}'s POSITION names accessor {}, past the file's {}",
                        i.value(),
                        json.accessors.len()
                    ),
                ));
            }
        }
    }
    let gltf = gltf::Gltf {
        document: gltf::Document::from_json(json).map_err(unreadable)?,
        blob: raw.blob,
    };
    let mut data: Vec<Vec<u8>> = Vec::new();
    let mut external = Vec::new();
    for b in gltf.document.buffers() {
        let bytes = match b.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                LevelError::new(file, "a buffer refers to a binary chunk the file lacks")
            })?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                return Err(LevelError::new(
                    file,
                    "buffers as data URIs are not read (export the .bin beside the .gltf, or a .glb)",
                ));
            }
            gltf::buffer::Source::Uri(uri) => {
                let bytes = buffer(uri)?;
                external.push(bytes.clone());
                bytes
            }
        };
        if bytes.len() < b.length() {
            return Err(LevelError::new(
                file,
                format!(
                    "buffer {} holds {} bytes, fewer than the {} it declares",
                    b.index(),
                    bytes.len(),
                    b.length()
                ),
            ));
        }
        data.push(bytes);
    }
    let mut out = Collect {
        file,
        data: &data,
        vertices: Vec::new(),
        triangles: Vec::new(),
        visits: 0,
    };
    match gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next())
    {
        Some(scene) => {
            for node in scene.nodes() {
                out.node(&node, DMat4::IDENTITY, 0)?;
            }
        }
        None => {
            for mesh in gltf.document.meshes() {
                out.mesh(&mesh, DMat4::IDENTITY)?;
            }
        }
    }
    if out.triangles.is_empty() {
        return Err(LevelError::new(file, "no triangles in the file's meshes"));
    }
    Ok((MeshGeometry::new(out.vertices, out.triangles), external))
}

struct Collect<'a> {
    file: &'a str,
    data: &'a [Vec<u8>],
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    visits: usize,
}

impl Collect<'_> {
    fn node(&mut self, node: &gltf::Node, parent: DMat4, depth: usize) -> Result<(), LevelError> {
        self.visits += 1;
        if depth > MAX_NODE_DEPTH || self.visits > MAX_NODE_VISITS {
            return Err(LevelError::new(
                self.file,
                format!(
                    "the node hierarchy is deeper than {MAX_NODE_DEPTH} or has more than {MAX_NODE_VISITS} node visits"
                ),
            ));
        }
        let m = node.transform().matrix();
        let local = DMat4::from_cols_array_2d(&m.map(|c| c.map(f64::from)));
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            self.mesh(&mesh, world)?;
        }
        for child in node.children() {
            self.node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn mesh(&mut self, mesh: &gltf::Mesh, world: DMat4) -> Result<(), LevelError> {
        for prim in mesh.primitives() {
            if prim.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            // The gltf crate's accessor reader trusts counts, strides and offsets (debug
            // assertions and unchecked arithmetic, found by fuzzing): check every accessor it
            // will read against its view and buffer first.
            let bad =
                |what: String| LevelError::new(self.file, format!("mesh {}: {what}", mesh.index()));
            if let Some(a) = prim.get(&gltf::Semantic::Positions) {
                check_accessor(&a, self.data, &[gltf::accessor::DataType::F32], 12)
                    .map_err(|e| bad(format!("POSITION {e}")))?;
            }
            if let Some(a) = prim.indices() {
                use gltf::accessor::DataType::{U8, U16, U32};
                let size = a.data_type().size();
                check_accessor(&a, self.data, &[U8, U16, U32], size)
                    .map_err(|e| bad(format!("indices {e}")))?;
            }
            let reader = prim.reader(|b| self.data.get(b.index()).map(Vec::as_slice));
            let Some(positions) = reader.read_positions() else {
                return Err(LevelError::new(
                    self.file,
                    format!("mesh {} has a primitive without positions", mesh.index()),
                ));
            };
            let base = self.vertices.len();
            for p in positions {
                let v = world * DVec4::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]), 1.0);
                let v = DVec3::new(v.x, -v.z, v.y); // y-up to z-up
                if !v.is_finite() {
                    return Err(LevelError::new(
                        self.file,
                        format!("mesh {} has a vertex that is not finite", mesh.index()),
                    ));
                }
                self.vertices.push(v);
            }
            let n = self.vertices.len() - base;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(ix) => ix.into_u32().collect(),
                None => (0..n as u32).collect(),
            };
            check_triangles(self.file, self.triangles.len() + indices.len() / 3)?;
            for t in indices.chunks_exact(3) {
                if t.iter().any(|&i| i as usize >= n) {
                    return Err(LevelError::new(
                        self.file,
                        format!("mesh {} has an index past its vertices", mesh.index()),
                    ));
                }
                self.triangles
                    .push([t[0], t[1], t[2]].map(|i| (base + i as usize) as u32));
            }
        }
        Ok(())
    }
}

/// Checks that accessor `a` is what the reader expects (one of `types`, elements of `size`
/// bytes, no sparse storage) and that every element lies inside its view and buffer, with
/// checked arithmetic.
fn check_accessor(
    a: &gltf::Accessor,
    data: &[Vec<u8>],
    types: &[gltf::accessor::DataType],
    size: usize,
) -> Result<(), String> {
    let i = a.index();
    if a.sparse().is_some() {
        return Err(format!("accessor {i} is sparse, which is not read"));
    }
    if !types.contains(&a.data_type()) || a.size() != size {
        return Err(format!(
            "accessor {i} has {:?} x {:?}, not what it names",
            a.data_type(),
            a.dimensions()
        ));
    }
    let Some(view) = a.view() else {
        return Err(format!("accessor {i} has no buffer view"));
    };
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "accessor {i}'s stride {stride} is below its element size {size}"
        ));
    }
    let buffer = data.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    let end = (a.count() as u64)
        .checked_sub(1)
        .and_then(|n| n.checked_mul(stride as u64))
        .and_then(|n| n.checked_add(a.offset() as u64))
        .and_then(|n| n.checked_add(size as u64));
    match (view_end, end) {
        (Some(v), Some(e)) if v <= buffer && e <= view.length() as u64 => Ok(()),
        (_, None) if a.count() == 0 => Err(format!("accessor {i} has no elements")),
        _ => Err(format!(
            "accessor {i} reaches past its buffer view or buffer ({} elements from byte {})",
            a.count(),
            a.offset()
        )),
    }
}
