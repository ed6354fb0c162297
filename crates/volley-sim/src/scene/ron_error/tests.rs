use super::*;
use crate::scene::parse;
use crate::scene::raw::RawScene;

/// A scene with `Nope` where each enum of the format names a variant, by the enum's Rust name.
const MISSPELT: &[(&str, &str)] = &[
    ("ForceTerm", "forces: [Nope(1)]"),
    ("RawCurve", "forces: [MachDrag(curve: Nope, bc: 0.3)]"),
    (
        "RawAir",
        "forces: [MachDrag(curve: G1, bc: 0.3, air: Nope)]",
    ),
    (
        "RawThrustDirection",
        "forces: [Thrust(curve: [(0, 1), (1, 0)], direction: Nope)]",
    ),
    (
        "Interpolation",
        "forces: [MachDrag(curve: G1, bc: 0.3, interpolation: Nope)]",
    ),
    (
        "LiftModel",
        "forces: [MachDrag(curve: G1, bc: 0.3, spin: (lift: Nope))]",
    ),
    (
        "SpinDecay",
        "forces: [MachDrag(curve: G1, bc: 0.3, spin: (decay: Nope))]",
    ),
    (
        "Launch",
        "bodies: [(mass: 1, position: (0, 0, 1), launch: Nope)]",
    ),
    (
        "Arc",
        "bodies: [(mass: 1, position: (0, 0, 1), launch: Aim(target: (1, 0, 0), speed: 10, arc: Nope))]",
    ),
    ("Integrator", "bodies: []"),
    ("Detection", "detection: Nope"),
    ("EventCondition", "events: [(when: Nope)]"),
    ("EventDirection", "events: [(when: Apex, direction: Nope)]"),
    ("EventStop", "events: [(when: Apex, stop: Nope)]"),
];

fn scene_with(part: &str, rust: &str) -> String {
    let integrator = if rust == "Integrator" { "Nope" } else { "Rk4" };
    format!("Scene(\n  dt: 0.01,\n  integrator: {integrator},\n  {part},\n)")
}

#[test]
fn every_enum_of_the_format_is_listed_once_and_misspelt_in_a_test() {
    let mut listed: Vec<&str> = ENUMS.iter().map(|e| e.rust).collect();
    let mut tested: Vec<&str> = MISSPELT.iter().map(|(r, _)| *r).collect();
    listed.sort_unstable();
    tested.sort_unstable();
    assert_eq!(listed, tested);
}

#[test]
fn a_misspelt_variant_lists_every_variant_as_the_file_writes_it_with_line_and_column() {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    for (rust, part) in MISSPELT {
        let text = scene_with(part, rust);
        // serde's own list of the variants: the table must name the same ones, in order.
        let code = options.from_str::<RawScene>(&text).unwrap_err().code;
        let ron::Error::NoSuchEnumVariant { expected, .. } = code else {
            panic!("{rust}: {code:?}");
        };
        let e = ENUMS.iter().find(|e| e.rust == *rust).unwrap();
        let names: Vec<&str> = e.variants.iter().map(|v| variant_name(v)).collect();
        assert_eq!(names, expected, "{rust}");

        let err = parse(&text, "x.ron", "x").unwrap_err();
        let line = if *rust == "Integrator" { 3 } else { 4 };
        assert_eq!(err.position.map(|p| p.0), Some(line), "{err}");
        let expected = match e.variants {
            [one] => format!("expected {one}"),
            all => format!("expected one of {}", all.join(", ")),
        };
        assert_eq!(
            err.message,
            format!("unknown {} `Nope`: {expected}", e.words)
        );
    }
}

#[test]
fn the_drag_curve_error_reads_as_the_issue_asks() {
    let text = scene_with("forces: [MachDrag(curve: G8, bc: 0.3)]", "RawCurve");
    let err = parse(&text, "rifle.ron", "x").unwrap_err();
    // Line 4, column 28: the `G` of `G8` after "  forces: [MachDrag(curve: " (27 characters).
    assert_eq!(
        err.to_string(),
        "rifle.ron:4:28: unknown drag curve `G8`: expected one of G1, G7, Sphere, \
         Table([(mach, cd), ...])"
    );
}

#[test]
fn field_and_type_errors_name_no_rust_type() {
    let cases = [
        "bodies: [(mas: 1, position: (0, 0, 1))]",
        "bodies: [(position: (0, 0, 1))]",
        "bodies: [5]",
        "forces: [MachDrag(curve: G1, bcc: 0.3)]",
        "forces: [MachDrag(curve: G1, bc: 0.3, wind: (velocity: (1, 0, 0), speed: 2))]",
        "ground: (restitution: 0.5, height: 0, height: 1)",
        "walls: [(point: (0, 0, 0))]",
        "launcher: (speed: 1)",
        "volley: (count: -1)",
        "guard: (every: 1.5)",
        "compare: [(integrator: Rk4, dt: \"a\")]",
        "forces: [Gravity(1)]",
        "forces: [Thrust(curve: 5)]",
    ];
    for part in cases {
        let err = parse(&scene_with(part, "-"), "x.ron", "x").unwrap_err();
        let text = err.to_string();
        assert!(err.position.is_some(), "{text}");
        for rust in ENUMS
            .iter()
            .map(|e| e.rust)
            .chain(STRUCTS.iter().map(|s| s.0))
        {
            assert!(
                !text.contains(rust)
                    || ENUMS
                        .iter()
                        .any(|e| e.variants.iter().any(|v| variant_name(v) == rust)),
                "{part}: `{text}` names {rust}"
            );
        }
        assert!(!text.contains("Raw"), "{part}: {text}");
    }
}

/// A scene with an unknown field `zzz` inside each struct of the format (and each struct-like
/// variant), named as the error names it.
const STRUCT_PLACES: &[&str] = &[
    "zzz: 1",
    "bodies: [(mass: 1, position: (0, 0, 1), zzz: 1)]",
    "ground: (restitution: 1, zzz: 1)",
    "walls: [(point: (0, 0, 0), normal: (1, 0, 0), thickness: 1, zzz: 1)]",
    "targets: [(center: (0, 0, 0), radius: 1, zzz: 1)]",
    "launcher: (position: (0, 0, 0), speed: 1, elevation_deg: 1, azimuth_deg: 0, zzz: 1)",
    "volley: (count: 1, zzz: 1)",
    "guard: (zzz: 1)",
    "compare: [(integrator: Rk4, zzz: 1)]",
    "forces: [Spring(anchor: (0, 0, 0), stiffness: 1, zzz: 1)]",
    "forces: [PointMass(center: (0, 0, 0), mu: 1, zzz: 1)]",
    "forces: [MachDrag(curve: G1, zzz: 1)]",
    "forces: [MachDrag(curve: G1, bc: 0.3, wind: (velocity: (0, 0, 0), zzz: 1))]",
    "forces: [MachDrag(curve: G1, bc: 0.3, spin: (zzz: 1))]",
    "forces: [MachDrag(curve: G1, bc: 0.3, air: Standard(zzz: 1))]",
    "forces: [MachDrag(curve: G1, bc: 0.3, air: Uniform(zzz: 1))]",
    "forces: [Custom(name: \"a\", version: 1, zzz: 1)]",
    "forces: [Thrust(curve: [(0, 1), (1, 0)], zzz: 1)]",
    "forces: [Thrust(curve: [(0, 1), (1, 0)], direction: Velocity(zzz: 1))]",
    "bodies: [(mass: 1, position: (0, 0, 1), launch: Angles(zzz: 1))]",
    "bodies: [(mass: 1, position: (0, 0, 1), launch: Aim(zzz: 1))]",
    "events: [(when: Apex, zzz: 1)]",
    "events: [(when: Plane(point: (0, 0, 0), normal: (1, 0, 0), zzz: 1))]",
    "events: [(when: Closest(point: (0, 0, 0), zzz: 1))]",
];

/// Every keyword the scene reader accepts: each enum's variants and each struct's fields, as
/// serde lists them when one is misspelt.
fn keywords() -> Vec<&'static str> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let mut words = Vec::new();
    for (rust, part) in MISSPELT {
        if let Err(e) = options.from_str::<RawScene>(&scene_with(part, rust))
            && let ron::Error::NoSuchEnumVariant { expected, .. } = e.code
        {
            words.extend_from_slice(expected);
        }
    }
    for part in STRUCT_PLACES {
        match options.from_str::<RawScene>(&scene_with(part, "-")) {
            Err(e) => match e.code {
                ron::Error::NoSuchStructField { expected, .. } => words.extend_from_slice(expected),
                other => panic!("{part}: {other:?}"),
            },
            Ok(_) => panic!("{part}: the unknown field was accepted"),
        }
    }
    words.sort_unstable();
    words.dedup();
    words
}

/// docs/scenes.md is the manual of the format: every keyword the reader accepts is in it, as a
/// word of its own. (Checked by hand: deleting `ForestRuth` or `rail_exit_speed` from the page
/// fails this test, naming the word.)
#[test]
fn the_manual_names_every_keyword_the_scene_reader_accepts() {
    let page =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/scenes.md"))
            .unwrap();
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let on_page = |word: &str| {
        page.match_indices(word).any(|(i, _)| {
            let before = page[..i].chars().next_back().is_none_or(|c| !is_word(c));
            let after = page[i + word.len()..]
                .chars()
                .next()
                .is_none_or(|c| !is_word(c));
            before && after
        })
    };
    let words = keywords();
    assert!(words.len() > 80, "{words:?}");
    let missing: Vec<&str> = words.into_iter().filter(|w| !on_page(w)).collect();
    assert!(missing.is_empty(), "docs/scenes.md never names {missing:?}");
}
