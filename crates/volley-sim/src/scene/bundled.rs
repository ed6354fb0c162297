//! The bundled scenes (`assets/scenes/`), compiled into the crate so that a game or a test can
//! step one without knowing where the repository is.

use super::{Scene, SceneError, parse};

/// Every bundled scene as `(name, RON text)`, by name (`seed`, `hard/stiff_spring`, ...), in the
/// order of their paths under `assets/scenes/`.
pub const BUNDLED: &[(&str, &str)] = &[
    ("baseball", include_str!("../../scenes/baseball.ron")),
    ("bench/drag", include_str!("../../scenes/bench/drag.ron")),
    (
        "bench/gravity",
        include_str!("../../scenes/bench/gravity.ron"),
    ),
    ("bounce", include_str!("../../scenes/bounce.ron")),
    ("drag", include_str!("../../scenes/drag.ron")),
    ("drag_masses", include_str!("../../scenes/drag_masses.ron")),
    ("hard/bounce", include_str!("../../scenes/hard/bounce.ron")),
    (
        "hard/critical_spring",
        include_str!("../../scenes/hard/critical_spring.ron"),
    ),
    (
        "hard/eccentric_orbit",
        include_str!("../../scenes/hard/eccentric_orbit.ron"),
    ),
    (
        "hard/edge_vertex",
        include_str!("../../scenes/hard/edge_vertex.ron"),
    ),
    (
        "hard/far_from_origin",
        include_str!("../../scenes/hard/far_from_origin.ron"),
    ),
    (
        "hard/grazing",
        include_str!("../../scenes/hard/grazing.ron"),
    ),
    (
        "hard/grenade_corner",
        include_str!("../../scenes/hard/grenade_corner.ron"),
    ),
    (
        "hard/ground_impact",
        include_str!("../../scenes/hard/ground_impact.ron"),
    ),
    ("hard/hill", include_str!("../../scenes/hard/hill.ron")),
    ("hard/hitch", include_str!("../../scenes/hard/hitch.ron")),
    (
        "hard/kepler_time",
        include_str!("../../scenes/hard/kepler_time.ron"),
    ),
    (
        "hard/long_orbit",
        include_str!("../../scenes/hard/long_orbit.ron"),
    ),
    (
        "hard/one_hour",
        include_str!("../../scenes/hard/one_hour.ron"),
    ),
    (
        "hard/plate_bullet",
        include_str!("../../scenes/hard/plate_bullet.ron"),
    ),
    (
        "hard/quadratic_throw",
        include_str!("../../scenes/hard/quadratic_throw.ron"),
    ),
    ("hard/slope", include_str!("../../scenes/hard/slope.ron")),
    (
        "hard/stiff_spring",
        include_str!("../../scenes/hard/stiff_spring.ron"),
    ),
    (
        "hard/stiff_spring_1e5",
        include_str!("../../scenes/hard/stiff_spring_1e5.ron"),
    ),
    (
        "hard/strong_drag",
        include_str!("../../scenes/hard/strong_drag.ron"),
    ),
    (
        "hard/tick_boundary",
        include_str!("../../scenes/hard/tick_boundary.ron"),
    ),
    (
        "hard/tunnelling",
        include_str!("../../scenes/hard/tunnelling.ron"),
    ),
    (
        "model_rocket",
        include_str!("../../scenes/model_rocket.ron"),
    ),
    ("orbit", include_str!("../../scenes/orbit.ron")),
    ("range", include_str!("../../scenes/range.ron")),
    ("rifle", include_str!("../../scenes/rifle.ron")),
    ("seed", include_str!("../../scenes/seed.ron")),
    ("spring", include_str!("../../scenes/spring.ron")),
    ("volley", include_str!("../../scenes/volley.ron")),
    ("wind", include_str!("../../scenes/wind.ron")),
];

/// The bundled scene `name` (`seed`, `hard/stiff_spring`), parsed and validated. A name no
/// bundled scene has is an error naming it and listing the bundled scenes (its `file` is the
/// name, and it has no position or field).
///
/// ```
/// let scene = volley_sim::bundled_scene("seed").unwrap();
/// assert_eq!(scene.name(), "seed");
/// let unknown = volley_sim::bundled_scene("no_such_scene").unwrap_err();
/// assert!(unknown.to_string().starts_with(
///     "no_such_scene: no bundled scene of that name (bundled: baseball, bench/drag,"
/// ));
/// ```
pub fn bundled(name: &str) -> Result<Scene, SceneError> {
    let Some((_, text)) = BUNDLED.iter().find(|(n, _)| *n == name) else {
        let names: Vec<&str> = BUNDLED.iter().map(|(n, _)| *n).collect();
        return Err(SceneError {
            file: name.to_string(),
            position: None,
            field: None,
            message: format!(
                "no bundled scene of that name (bundled: {})",
                names.join(", ")
            ),
        });
    };
    let stem = name.rsplit('/').next().unwrap_or(name);
    parse(text, &format!("assets/scenes/{name}.ron"), stem)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    /// The list is the folder: a scene added to `assets/scenes/` without a line here fails.
    #[test]
    fn every_scene_file_is_bundled_and_parses() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        let mut on_disk = Vec::new();
        let mut dirs = vec![root.clone()];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    dirs.push(path);
                } else if path.extension().is_some_and(|e| e == "ron") {
                    let rel = path.strip_prefix(&root).unwrap().with_extension("");
                    on_disk.push(rel.to_string_lossy().replace('\\', "/"));
                }
            }
        }
        on_disk.sort();
        let unknown = super::bundled("no/such_scene").unwrap_err();
        assert_eq!(
            unknown.to_string(),
            format!(
                "no/such_scene: no bundled scene of that name (bundled: {})",
                on_disk.join(", ")
            )
        );
        let listed: Vec<String> = super::BUNDLED.iter().map(|(n, _)| n.to_string()).collect();
        assert_eq!(listed, on_disk);
        for (name, text) in super::BUNDLED {
            let from_disk = std::fs::read_to_string(root.join(format!("{name}.ron"))).unwrap();
            assert_eq!(*text, from_disk, "{name}");
            let scene = super::bundled(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            let loaded = super::super::load(&root.join(format!("{name}.ron"))).unwrap();
            assert_eq!(scene.name, loaded.name, "{name}");
        }
    }
}
