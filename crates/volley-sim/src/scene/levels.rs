//! Level surfaces in a scene file: `meshes` (OBJ, glTF or inline triangles) and `heightfields`
//! (a 16-bit PNG or an inline grid), read and checked into [`MeshSurface`]s and
//! [`HeightfieldSurface`]s. A file is named by a path relative to the scene file; its bytes'
//! xxh3 is kept on the surface ([`MeshSurface::content_hash`]) so a recording can refuse a
//! changed level.

use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::{
    HeightGrid, HeightfieldSurface, LevelSource, MeshGeometry, MeshSurface, Transform,
};

mod gltf;
mod heightmap;
mod obj;

pub use self::gltf::read_gltf;
pub use heightmap::{read_heightmap_png, write_heightmap_png};
pub use obj::read_obj;

use super::error::{InvalidValue, ValueProblem};
use super::validate::invalid;

/// Most triangles the meshes of one scene may hold together (about 150 MB of hierarchy at
/// this count): far past a game level's collision mesh.
pub const MAX_LEVEL_TRIANGLES: usize = 2_000_000;

/// Most cells one heightfield may have (2048 x 2048; 32 MB of heights).
pub const MAX_HEIGHTFIELD_CELLS: u64 = 1 << 22;

/// Most bytes of a level file (a mesh, its glTF buffers, a heightfield PNG).
pub const MAX_LEVEL_FILE_BYTES: u64 = 128 << 20;

/// A level file that cannot be used: the file and what is wrong, on one line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LevelError {
    /// The file, as the scene named it.
    pub file: String,
    /// What is wrong.
    pub message: String,
}

impl LevelError {
    /// The error `message` about `file`.
    pub fn new(file: &str, message: impl Into<String>) -> LevelError {
        LevelError {
            file: file.to_string(),
            message: message.into(),
        }
    }
}

impl std::fmt::Display for LevelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.file, self.message.replace('\n', " "))
    }
}

impl std::error::Error for LevelError {}

pub(super) fn check_triangles(file: &str, n: usize) -> Result<(), LevelError> {
    if n > MAX_LEVEL_TRIANGLES {
        return Err(LevelError::new(
            file,
            format!("more than {MAX_LEVEL_TRIANGLES} triangles"),
        ));
    }
    Ok(())
}

/// The level files Volley ships (`assets/levels/`), for the bundled scenes: a file a scene names
/// that is not on disk but whose path ends in `levels/NAME` with a name here is read from this
/// list, so a bundled scene steps anywhere.
pub const BUNDLED_LEVELS: &[(&str, &[u8])] = &[
    ("berm.obj", include_bytes!("../../levels/berm.obj")),
    ("corner.obj", include_bytes!("../../levels/corner.obj")),
    ("hill.png", include_bytes!("../../levels/hill.png")),
    ("plate.gltf", include_bytes!("../../levels/plate.gltf")),
    ("plate.bin", include_bytes!("../../levels/plate.bin")),
    ("plate.obj", include_bytes!("../../levels/plate.obj")),
    ("ramp.glb", include_bytes!("../../levels/ramp.glb")),
];

/// Where a scene's level files are: the scene file's folder.
#[derive(Clone, Debug)]
pub(crate) struct LevelFiles {
    pub dir: PathBuf,
}

impl LevelFiles {
    /// Files next to the scene file labelled `file` (its folder; the current one for a label
    /// without one).
    pub(crate) fn beside(file: &str) -> LevelFiles {
        LevelFiles {
            dir: Path::new(file)
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
        }
    }

    /// The bytes of `rel` (as the scene wrote it), at most [`MAX_LEVEL_FILE_BYTES`].
    pub(crate) fn read(&self, rel: &str) -> Result<Vec<u8>, LevelError> {
        let path = normalise(&self.dir.join(rel));
        match read_limited(&path) {
            Ok(bytes) => Ok(bytes),
            // Not found, or no file system at all (a wasm32 build): a shipped level.
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::Unsupported
                ) =>
            {
                let shown = path.to_string_lossy().replace('\\', "/");
                let bundled = BUNDLED_LEVELS.iter().find(|(name, _)| {
                    shown == format!("levels/{name}") || shown.ends_with(&format!("/levels/{name}"))
                });
                match bundled {
                    Some((_, bytes)) => Ok(bytes.to_vec()),
                    None => Err(LevelError::new(rel, format!("cannot read: {e}"))),
                }
            }
            Err(e) => Err(LevelError::new(rel, format!("cannot read: {e}"))),
        }
    }
}

fn read_limited(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let mut bytes = Vec::new();
    let file = std::fs::File::open(path)?;
    // Only regular files: a FIFO or a device (`/dev/stdin`) could block or never end.
    if !file.metadata()?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    file.take(MAX_LEVEL_FILE_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_LEVEL_FILE_BYTES {
        return Err(std::io::Error::other(format!(
            "longer than {} MiB, the most a level file may be",
            MAX_LEVEL_FILE_BYTES >> 20
        )));
    }
    Ok(bytes)
}

/// `a/b/../c` as `a/c`, without touching the disk.
fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir if out.file_name().is_some() => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// A mesh as a scene file writes it: `file` (`.obj`, `.gltf`, `.glb`) or inline `vertices`
/// and `triangles`, with a transform and a restitution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMesh {
    pub(super) name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) file: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) vertices: Vec<DVec3>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) triangles: Vec<(u32, u32, u32)>,
    #[serde(default, skip_serializing_if = "is_identity")]
    pub(super) transform: Transform,
    #[serde(default = "elastic")]
    pub(super) restitution: f64,
}

/// A heightfield as a scene file writes it: a `png` or an inline `grid`, the samples'
/// spacing, the metres per PNG unit, a transform and a restitution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHeightfield {
    pub(super) name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) png: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) grid: Option<RawGrid>,
    pub(super) cell_size: f64,
    #[serde(default = "unit", skip_serializing_if = "is_unit")]
    pub(super) height_scale: f64,
    #[serde(default, skip_serializing_if = "is_identity")]
    pub(super) transform: Transform,
    #[serde(default = "elastic")]
    pub(super) restitution: f64,
}

/// A grid written in the scene: `columns x rows` heights (m), row-major from `y = 0`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGrid {
    pub(super) columns: u32,
    pub(super) rows: u32,
    pub(super) heights: Vec<f64>,
}

fn elastic() -> f64 {
    1.0
}
fn is_identity(t: &Transform) -> bool {
    *t == Transform::IDENTITY
}
fn unit() -> f64 {
    1.0
}
fn is_unit(x: &f64) -> bool {
    *x == 1.0
}

fn level_problem(field: String, e: LevelError) -> InvalidValue {
    invalid(field, ValueProblem::Level(e.to_string()))
}

fn check_transform(field: &str, t: &Transform) -> Result<(), InvalidValue> {
    for (what, v) in [("position", t.position), ("rotation_deg", t.rotation_deg)] {
        if !v.is_finite() {
            return Err(invalid(
                format!("{field}.transform.{what}"),
                ValueProblem::NotFiniteVector(v),
            ));
        }
    }
    if !t.scale.is_finite() || t.scale.abs().min_element() < 1e-9 {
        return Err(invalid(
            format!("{field}.transform.scale"),
            ValueProblem::Level(format!(
                "expected finite, non-zero components (at least 1e-9), got {}",
                t.scale
            )),
        ));
    }
    Ok(())
}

fn check_restitution(field: &str, e: f64) -> Result<(), InvalidValue> {
    if (0.0..=1.0).contains(&e) {
        Ok(())
    } else {
        Err(invalid(
            format!("{field}.restitution"),
            ValueProblem::NotUnitInterval(e),
        ))
    }
}

/// Reads and checks `meshes[i]`.
pub(super) fn validate_mesh(
    i: usize,
    raw: &RawMesh,
    files: &LevelFiles,
) -> Result<MeshSurface, InvalidValue> {
    let field = format!("meshes[{i}]");
    check_transform(&field, &raw.transform)?;
    check_restitution(&field, raw.restitution)?;
    let inline = !raw.vertices.is_empty() || !raw.triangles.is_empty();
    let (source, hash, geometry) = match (&raw.file, inline) {
        (Some(file), false) => {
            let f = format!("{field}.file");
            let bytes = files.read(file).map_err(|e| level_problem(f.clone(), e))?;
            let lower = file.to_ascii_lowercase();
            let mut hasher = xxhash_rust::xxh3::Xxh3::new();
            hasher.update(&bytes);
            let geometry = if lower.ends_with(".obj") {
                read_obj(&bytes, file)
            } else if lower.ends_with(".gltf") || lower.ends_with(".glb") {
                let base = Path::new(file).parent().map(Path::to_path_buf);
                let mut buffer = |uri: &str| {
                    let rel = base.as_ref().map_or(PathBuf::from(uri), |b| b.join(uri));
                    files.read(&rel.to_string_lossy())
                };
                read_gltf(&bytes, file, &mut buffer).map(|(g, external)| {
                    for b in &external {
                        hasher.update(b);
                    }
                    g
                })
            } else {
                Err(LevelError::new(file, "expected a .obj, .gltf or .glb file"))
            }
            .map_err(|e| level_problem(f, e))?;
            (LevelSource::File(file.clone()), hasher.digest(), geometry)
        }
        (None, true) => {
            let n = raw.vertices.len();
            if let Some((k, v)) = raw
                .vertices
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite())
            {
                return Err(invalid(
                    format!("{field}.vertices[{k}]"),
                    ValueProblem::NotFiniteVector(*v),
                ));
            }
            if raw.triangles.len() > MAX_LEVEL_TRIANGLES {
                return Err(level_problem(
                    format!("{field}.triangles"),
                    LevelError::new(
                        &raw.name,
                        format!("more than {MAX_LEVEL_TRIANGLES} triangles"),
                    ),
                ));
            }
            let mut triangles = Vec::with_capacity(raw.triangles.len());
            for (k, &(a, b, c)) in raw.triangles.iter().enumerate() {
                if [a, b, c].iter().any(|&x| x as usize >= n) {
                    return Err(invalid(
                        format!("{field}.triangles[{k}]"),
                        ValueProblem::Level(format!(
                            "expected indices below the {n} vertices, got ({a}, {b}, {c})"
                        )),
                    ));
                }
                triangles.push([a, b, c]);
            }
            let g = MeshGeometry::new(raw.vertices.clone(), triangles);
            if g.triangles.is_empty() {
                return Err(invalid(
                    format!("{field}.triangles"),
                    ValueProblem::Level(
                        "expected at least one triangle that is not degenerate".into(),
                    ),
                ));
            }
            (LevelSource::Inline, g.content_hash(), g)
        }
        _ => {
            return Err(invalid(
                field,
                ValueProblem::Level("expected either `file` or `vertices` and `triangles`".into()),
            ));
        }
    };
    Ok(MeshSurface::new(
        raw.name.clone(),
        source,
        hash,
        Arc::new(geometry),
        raw.transform,
        raw.restitution,
    ))
}

/// Reads and checks `heightfields[i]`.
pub(super) fn validate_heightfield(
    i: usize,
    raw: &RawHeightfield,
    files: &LevelFiles,
) -> Result<HeightfieldSurface, InvalidValue> {
    let field = format!("heightfields[{i}]");
    check_transform(&field, &raw.transform)?;
    check_restitution(&field, raw.restitution)?;
    if !(raw.cell_size.is_finite() && raw.cell_size > 0.0) {
        return Err(invalid(
            format!("{field}.cell_size"),
            ValueProblem::NotPositive(raw.cell_size),
        ));
    }
    if !(raw.height_scale.is_finite() && raw.height_scale >= 0.0) {
        return Err(invalid(
            format!("{field}.height_scale"),
            ValueProblem::NotNonNegative(raw.height_scale),
        ));
    }
    let (source, hash, grid) = match (&raw.png, &raw.grid) {
        (Some(file), None) => {
            let f = format!("{field}.png");
            let bytes = files.read(file).map_err(|e| level_problem(f.clone(), e))?;
            let grid = read_heightmap_png(&bytes, file, raw.height_scale)
                .map_err(|e| level_problem(f, e))?;
            (
                LevelSource::File(file.clone()),
                xxhash_rust::xxh3::xxh3_64(&bytes),
                grid,
            )
        }
        (None, Some(g)) => {
            let f = format!("{field}.grid");
            let (c, r) = (u64::from(g.columns), u64::from(g.rows));
            if c < 2 || r < 2 {
                return Err(invalid(
                    f,
                    ValueProblem::Level(format!("expected at least 2 x 2 samples, got {c} x {r}")),
                ));
            }
            if (c - 1) * (r - 1) > MAX_HEIGHTFIELD_CELLS {
                return Err(invalid(
                    f,
                    ValueProblem::Level(format!("more than {MAX_HEIGHTFIELD_CELLS} cells")),
                ));
            }
            if g.heights.len() as u64 != c * r {
                return Err(invalid(
                    format!("{f}.heights"),
                    ValueProblem::Level(format!(
                        "expected {} heights ({c} x {r}), got {}",
                        c * r,
                        g.heights.len()
                    )),
                ));
            }
            if let Some((k, h)) = g.heights.iter().enumerate().find(|(_, h)| !h.is_finite()) {
                return Err(invalid(
                    format!("{f}.heights[{k}]"),
                    ValueProblem::NotFinite(*h),
                ));
            }
            if raw.height_scale != 1.0 {
                return Err(invalid(
                    format!("{field}.height_scale"),
                    ValueProblem::Level(
                        "applies to a PNG only: a grid's heights are in metres".into(),
                    ),
                ));
            }
            let grid = HeightGrid {
                columns: g.columns,
                rows: g.rows,
                heights: g.heights.clone(),
            };
            (LevelSource::Inline, grid.content_hash(), grid)
        }
        _ => {
            return Err(invalid(
                field,
                ValueProblem::Level("expected either `png` or `grid`".into()),
            ));
        }
    };
    Ok(HeightfieldSurface::new(
        raw.name.clone(),
        source,
        hash,
        Arc::new(grid),
        raw.cell_size,
        raw.height_scale,
        raw.transform,
        raw.restitution,
    ))
}

/// A mesh surface as the scene file writes it back.
pub(super) fn raw_mesh(m: &MeshSurface) -> RawMesh {
    let (file, vertices, triangles) = match &m.source {
        LevelSource::File(f) => (Some(f.clone()), Vec::new(), Vec::new()),
        LevelSource::Inline => (
            None,
            m.geometry.vertices.clone(),
            m.geometry
                .triangles
                .iter()
                .map(|t| (t[0], t[1], t[2]))
                .collect(),
        ),
    };
    RawMesh {
        name: m.name.clone(),
        file,
        vertices,
        triangles,
        transform: m.transform,
        restitution: m.restitution,
    }
}

/// A heightfield as the scene file writes it back.
pub(super) fn raw_heightfield(h: &HeightfieldSurface) -> RawHeightfield {
    let (png, grid) = match &h.source {
        LevelSource::File(f) => (Some(f.clone()), None),
        LevelSource::Inline => (
            None,
            Some(RawGrid {
                columns: h.grid.columns,
                rows: h.grid.rows,
                heights: h.grid.heights.clone(),
            }),
        ),
    };
    RawHeightfield {
        name: h.name.clone(),
        png,
        grid,
        cell_size: h.cell_size,
        height_scale: h.height_scale,
        transform: h.transform,
        restitution: h.restitution,
    }
}
