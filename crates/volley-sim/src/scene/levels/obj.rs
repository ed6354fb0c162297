//! Wavefront OBJ, read with tobj: every object's faces, polygons split into triangle fans;
//! points, lines, normals, texture coordinates and materials are ignored.

use glam::DVec3;

use super::{LevelError, check_triangles};
use crate::contact::MeshGeometry;

/// Reads an OBJ file's bytes. `file` labels errors. tobj reports what is wrong but not the line.
pub fn read_obj(bytes: &[u8], file: &str) -> Result<MeshGeometry, LevelError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        // Materials are not read: no file beside the OBJ is opened.
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| LevelError::new(file, format!("not a readable OBJ file: {e}")))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let base = vertices.len();
        if mesh.positions.len() % 3 != 0 {
            return Err(LevelError::new(
                file,
                "a vertex with fewer than 3 coordinates",
            ));
        }
        let faces = mesh.indices.len() / 3;
        check_triangles(file, triangles.len() + faces)?;
        for p in mesh.positions.chunks_exact(3) {
            let v = DVec3::new(p[0], p[1], p[2]);
            if !v.is_finite() {
                return Err(LevelError::new(
                    file,
                    format!("vertex {} is not finite ({v})", vertices.len() + 1),
                ));
            }
            vertices.push(v);
        }
        let n = vertices.len() - base;
        for t in mesh.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= n) {
                return Err(LevelError::new(
                    file,
                    "a face names a vertex it does not have",
                ));
            }
            triangles.push([t[0], t[1], t[2]].map(|i| (base + i as usize) as u32));
        }
    }
    if triangles.is_empty() {
        return Err(LevelError::new(
            file,
            "no triangles (an OBJ needs `f` lines)",
        ));
    }
    Ok(MeshGeometry::new(vertices, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_becomes_two_triangles_and_a_sliver_is_dropped_and_counted() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 1 2 5\n";
        let m = read_obj(obj, "quad.obj").unwrap();
        assert_eq!(m.vertices.len(), 5);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.degenerate, 1);
    }

    #[test]
    fn bad_files_are_one_line_naming_the_file() {
        let e = read_obj(b"v 0 0 0\nv 1 0 0\nf 1 2 9\n", "bad.obj").unwrap_err();
        assert_eq!(e.to_string().lines().count(), 1);
        assert!(e.to_string().starts_with("bad.obj: "), "{e}");
        let e = read_obj(b"v 0 0 0\n", "empty.obj").unwrap_err();
        assert_eq!(
            e.to_string(),
            "empty.obj: no triangles (an OBJ needs `f` lines)"
        );
        let e = read_obj(b"v 0 0 x\nf 1 1 1\n", "nan.obj").unwrap_err();
        assert!(e.to_string().starts_with("nan.obj: "), "{e}");
    }
}
