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
