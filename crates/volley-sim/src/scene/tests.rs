use super::*;

const MINIMAL: &str =
    r#"Scene(dt: 0.01, integrator: Rk4, bodies: [(mass: 1, position: (0, 0, 1))])"#;

#[test]
fn a_minimal_scene_parses_with_defaults() {
    let scene = parse(MINIMAL, "mem.ron", "mem").unwrap();
    assert_eq!(scene.timestep, Duration::from_millis(10));
    assert_eq!(scene.integrator, Integrator::Rk4);
    assert_eq!(scene.bodies[0].radius, 0.1);
    assert_eq!(scene.name, "mem");
}

#[test]
fn syntax_errors_carry_line_and_column() {
    let err = parse(
        "Scene(\n  dt: 0.1,\n  integrator: Rk4\n  bodies: [],\n)",
        "x.ron",
        "x",
    )
    .unwrap_err();
    assert_eq!(err.file, "x.ron");
    assert_eq!(err.position.map(|p| p.0), Some(4), "{err}");
}

#[test]
fn value_errors_name_the_field() {
    let text = MINIMAL.replace("mass: 1", "mass: -1");
    let err = parse(&text, "x.ron", "x").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("bodies[0].mass"), "{err}");
    let err = parse(&MINIMAL.replace("0.01", "NaN"), "x.ron", "x").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("dt"), "{err}");
}

#[test]
fn exact_is_refused_with_the_force_that_has_no_closed_form() {
    let text =
        r#"Scene(dt: 0.01, integrator: Exact, forces: [Gravity((0,0,-9.81)), QuadraticDrag(0.1)])"#;
    let err = parse(text, "x.ron", "x").unwrap_err();
    assert!(err.message.contains("QuadraticDrag"), "{err}");
}

#[test]
fn overrides_refuse_with_the_field_and_the_problem() {
    let mut scene = parse(MINIMAL, "mem.ron", "mem").unwrap();
    let e = scene.set_dt(-1.0).unwrap_err();
    assert_eq!(e.field, "dt");
    assert_eq!(e.problem, ValueProblem::NotPositive(-1.0));
    assert!(matches!(
        scene.set_dt(1e-12),
        Err(InvalidValue {
            problem: ValueProblem::Step(_),
            ..
        })
    ));
    assert_eq!(
        scene.set_substeps(0).unwrap_err().problem,
        ValueProblem::Substeps(0)
    );
    scene.forces.quadratic_drag = Some(0.1);
    assert_eq!(
        scene.set_integrator(Integrator::Exact),
        Err(IntegratorError::NoClosedForm(ForceKind::QuadraticDrag))
    );
}

/// A text file past the limit is refused after reading just past it, saying so; one at the
/// limit is read (and then fails to parse, as zeros do).
#[test]
fn a_text_file_longer_than_the_limit_is_refused() {
    let dir = std::env::temp_dir().join(format!("volley-text-limit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge.ron");
    let file = std::fs::File::create(&path).unwrap();
    // Sparse: no disk is written for the zeros.
    file.set_len(MAX_TEXT_BYTES + 1).unwrap();
    let err = load(&path).unwrap_err();
    assert!(err.message.contains("longer than 256 MiB"), "{err}");
    file.set_len(MAX_TEXT_BYTES).unwrap();
    assert_eq!(read_text(&path).unwrap().len() as u64, MAX_TEXT_BYTES);
    drop(file);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A wall normal is normalised once: the normal a saved setup writes reads back to the
/// same bits (a second normalisation moved the last bit of (1, 0, 1)'s; found by fuzzing).
#[test]
fn a_normalised_wall_normal_is_kept_bit_for_bit() {
    for n in [
        (1.0, 0.0, 1.0),
        (1.0, 2.0, 3.0),
        (0.3, -0.7, 0.1),
        (0.0, 0.0, -5.0),
    ] {
        let wall = Wall {
            point: DVec3::ZERO,
            normal: DVec3::from(n),
            thickness: 0.1,
            restitution: 0.5,
        };
        let once = validate_wall(0, &wall).unwrap();
        let twice = validate_wall(0, &once).unwrap();
        assert_eq!(
            once.normal.to_array().map(f64::to_bits),
            twice.normal.to_array().map(f64::to_bits)
        );
        assert!((once.normal.length() - 1.0).abs() < 1e-15);
    }
}

/// What a small file could ask for beyond reason is refused, naming the field (the limits
/// of docs/limits.md).
#[test]
fn limits_on_bodies_work_and_lanes_name_the_field() {
    let field = |text: &str| parse(text, "x.ron", "x").unwrap_err().field.unwrap();
    let volley = |n: u64| MINIMAL.replace("])", &format!("], volley: (count: {n}))"));
    assert!(parse(&volley(MAX_BODIES as u64 - 1), "x.ron", "x").is_ok());
    // One listed body and a volley of the maximum is one body too many.
    let err = parse(&volley(MAX_BODIES as u64), "x.ron", "x").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("volley.count"), "{err}");
    assert!(err.message.contains("got 1000001"), "{err}");
    assert_eq!(field(&volley(20_000_000)), "volley.count");
    let substeps = |n: u32, count: u64| {
        volley(count).replace(
            "integrator: Rk4",
            &format!("integrator: Rk4, substeps: {n}"),
        )
    };
    assert!(parse(&substeps(100, 999_999), "x.ron", "x").is_ok());
    let err = parse(&substeps(101, 999_999), "x.ron", "x").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("substeps"), "{err}");
    assert!(
        err.message.contains("101 substeps for 1000000 bodies"),
        "{err}"
    );
    let lanes = |n: usize| {
        let lane = "(integrator: Rk4, substeps: 200)";
        MINIMAL.replace("])", &format!("], compare: [{}])", vec![lane; n].join(",")))
    };
    assert!(parse(&lanes(MAX_COMPARE_LANES), "x.ron", "x").is_ok());
    assert_eq!(field(&lanes(MAX_COMPARE_LANES + 1)), "compare");
    let heavy_lane = MINIMAL.replace(
        "])",
        "], volley: (count: 999999), compare: [(integrator: Rk4, substeps: 200)])",
    );
    assert_eq!(field(&heavy_lane), "compare[0].substeps");
    let mut scene = parse(&volley(999_999), "x.ron", "x").unwrap();
    assert!(matches!(
        scene.set_substeps(1000).unwrap_err().problem,
        ValueProblem::TickWork {
            bodies: 1_000_000,
            substeps: 1000
        }
    ));
}

/// Every problem prints the message it printed when these errors were strings.
#[test]
fn error_messages_are_pinned() {
    let at = |field: &str, problem| InvalidValue {
        field: field.into(),
        problem,
    };
    let no_closed_form = IntegratorError::NoClosedForm(ForceKind::Spring);
    let cases: [(InvalidValue, &str); 14] = [
        (
            at("start_time", ValueProblem::NotFinite(f64::NAN)),
            "start_time: expected a finite number, got NaN",
        ),
        (
            at("bodies[0].mass", ValueProblem::NotPositive(-1.0)),
            "bodies[0].mass: expected a finite number > 0, got -1",
        ),
        (
            at("duration", ValueProblem::NotNonNegative(-0.5)),
            "duration: expected a finite number >= 0, got -0.5",
        ),
        (
            at("ground.restitution", ValueProblem::NotUnitInterval(1.5)),
            "ground.restitution: expected a number from 0 to 1, got 1.5",
        ),
        (
            at(
                "walls[0].point",
                ValueProblem::NotFiniteVector(DVec3::new(1.0, f64::INFINITY, 0.0)),
            ),
            "walls[0].point: expected finite components, got [1, inf, 0]",
        ),
        (
            at("walls[1].normal", ValueProblem::ZeroVector),
            "walls[1].normal: expected a non-zero vector",
        ),
        (
            timestep_from_secs("dt", 1e-12).unwrap_err(),
            "dt: expected a step from 1 ns to 1000 s, got 0.000000000001 s",
        ),
        (
            at("substeps", ValueProblem::Substeps(0)),
            "substeps: expected 1 to 10000, got 0",
        ),
        (
            at("volley.count", ValueProblem::VolleyCount(20_000_000)),
            "volley.count: expected at most 1000000 bodies, got 20000000",
        ),
        (
            at("guard.energy_factor", ValueProblem::EnergyFactor(1.0)),
            "guard.energy_factor: expected a finite number > 1, got 1",
        ),
        (
            at(
                "forces[1]",
                ValueProblem::DuplicateForce(ForceKind::Gravity),
            ),
            "forces[1]: Gravity is declared twice; declare each term once",
        ),
        (
            at("bodies[0].launch", ValueProblem::AimNeedsGravity),
            "bodies[0].launch: Aim needs a Gravity term pointing along -z",
        ),
        (
            at(
                "bodies[0].launch",
                ValueProblem::CannotAim(AimError::SamePoint),
            ),
            "bodies[0].launch: cannot aim: launch point and target are the same point",
        ),
        (
            at("integrator", ValueProblem::Integrator(no_closed_form)),
            "integrator: `exact` needs a closed form, and force term Spring has none with a \
             rest length (exact covers any mix of Gravity, ConstantForce, LinearDrag and a \
             Spring with rest length 0, or a PointMass alone); choose another integrator",
        ),
    ];
    for (error, message) in cases {
        assert_eq!(error.to_string(), message, "{error:?}");
    }
    // A scene file's value error is the same text after the file name.
    let err = parse(&MINIMAL.replace("0.01", "0"), "x.ron", "x").unwrap_err();
    assert_eq!(
        err.to_string(),
        "x.ron: dt: expected a finite number > 0, got 0"
    );
}

/// A scene with one Mach drag term written as `term`.
fn mach_scene(term: &str, integrator: &str) -> String {
    format!(
        "Scene(dt: 0.001, integrator: {integrator}, forces: [Gravity((0, 0, -9.81)), {term}],
           bodies: [(mass: 0.01, position: (0, 0, 1), launch: Velocity((800, 0, 0)))])"
    )
}

#[test]
fn mach_drag_terms_parse_and_write_back_to_the_same_scene() {
    for term in [
        "MachDrag(curve: G7, bc: 0.223)",
        "MachDrag(curve: G1, interpolation: Linear, bc: 0.5, \
         air: Uniform(temperature: 298.15, pressure: 101325), wind: (velocity: (0, 5, 0)))",
        "MachDrag(curve: Sphere, diameter: 0.073, form_factor: 1.1, \
         air: Standard(ground: 1600, temperature: 300), \
         wind: (velocity: (-3, 1, 0), reference_height: 10, exponent: 0.143))",
        "MachDrag(curve: Table([(0, 0.3), (0.9, 0.35), (1.1, 0.6), (3, 0.4)]), diameter: 0.01)",
    ] {
        let scene = parse(&mach_scene(term, "Rk4"), "x.ron", "x").unwrap();
        assert!(scene.forces.mach_drag.is_some(), "{term}");
        let again = parse(&scene.to_ron(), "saved.ron", "x").unwrap();
        assert_eq!(again.forces, scene.forces, "{term}\n{}", scene.to_ron());
    }
}

#[test]
fn bad_mach_drag_values_name_the_field() {
    for (term, field, says) in [
        ("MachDrag(curve: G7, bc: 0)", "forces[1].bc", "> 0"),
        ("MachDrag(curve: G7, bc: -0.2)", "forces[1].bc", "> 0"),
        ("MachDrag(curve: G7)", "forces[1]", "either `bc`"),
        (
            "MachDrag(curve: G7, bc: 0.2, diameter: 0.01)",
            "forces[1]",
            "either `bc`",
        ),
        (
            "MachDrag(curve: G7, diameter: 0.01, form_factor: 0)",
            "forces[1].form_factor",
            "> 0",
        ),
        (
            "MachDrag(curve: Table([(0, 0.3), (0.5, 0.3), (0.5, 0.4)]), bc: 0.2)",
            "forces[1].curve",
            "point 2 (counted from 0)",
        ),
        (
            "MachDrag(curve: Table([(0, 0.3), (1, -0.1)]), bc: 0.2)",
            "forces[1].curve",
            "point 1 (counted from 0)",
        ),
        (
            "MachDrag(curve: G1, bc: 0.2, air: Uniform(temperature: 0, pressure: 1e5))",
            "forces[1].air.temperature",
            "> 0",
        ),
        (
            "MachDrag(curve: G1, bc: 0.2, air: Standard(ground: -6.3e6))",
            "forces[1].air.ground",
            "from -1000 m to 20000 m",
        ),
        (
            "MachDrag(curve: G1, bc: 0.2, wind: (velocity: (1, 0, 0), reference_height: 0))",
            "forces[1].wind.reference_height",
            "> 0",
        ),
    ] {
        let err = parse(&mach_scene(term, "Rk4"), "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{term}: {err}");
        assert!(err.to_string().contains(says), "{term}: {err}");
        assert!(!err.to_string().contains('\n'), "one line: {err}");
    }
}

#[test]
fn exact_and_forest_ruth_refuse_mach_drag_and_say_why() {
    let term = "MachDrag(curve: G7, bc: 0.223)";
    let err = parse(&mach_scene(term, "Exact"), "x.ron", "x").unwrap_err();
    assert!(err.to_string().contains("MachDrag has none"), "{err}");
    let err = parse(&mach_scene(term, "ForestRuth"), "x.ron", "x").unwrap_err();
    assert!(
        err.to_string().contains("force term MachDrag has none"),
        "{err}"
    );
    // Implicit Euler and the implicit midpoint rule treat it explicitly, like quadratic drag.
    for i in [
        "ImplicitEuler",
        "ImplicitMidpoint",
        "Dopri5",
        "VelocityVerlet",
    ] {
        parse(&mach_scene(term, i), "x.ron", "x").unwrap();
    }
}

/// A scene with a spun ball and a motor (the C6's first points), written as `extra` changes.
fn spin_thrust_scene(spin: &str, thrust: &str, mass: f64) -> String {
    format!(
        "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81)),
           MachDrag(curve: Table([(0, 0.3), (1, 0.3)]), diameter: 0.074{spin}){thrust}],
           bodies: [(mass: {mass:?}, position: (0, 0, 1), launch: Velocity((40, 0, 10)),
                     spin: (0, -260, 0))],
           launcher: (position: (0, 0, 1), speed: 40, elevation_deg: 10, azimuth_deg: 30,
                      mass: {mass:?}, radius: 0.037, backspin: 2000, sidespin: -500))"
    )
}

const C6_START: &str = ", Thrust(curve: [(0, 0), (0.031, 0.946), (0.092, 4.826), (1.86, 0)], \
                        propellant: 0.0108, direction: Velocity(along: (0, 0, 1), \
                        rail_exit_speed: 12))";

#[test]
fn spin_and_thrust_terms_parse_and_write_back_to_the_same_scene() {
    for (spin, thrust) in [
        (
            ", spin: (lift: Nathan, decay: Nathan(30), drag_per_1000_rpm: 0.0292)",
            "",
        ),
        (", spin: (decay: Time(25))", C6_START),
        (
            "",
            ", Thrust(curve: [(0.1, 3), (0.5, 0)], direction: Fixed((1, 0, 1)))",
        ),
    ] {
        let text = spin_thrust_scene(spin, thrust, 0.057);
        let scene = parse(&text, "x.ron", "x").unwrap();
        let again = parse(&scene.to_ron(), "saved.ron", "x").unwrap();
        assert_eq!(again.forces, scene.forces, "{text}\n{}", scene.to_ron());
        assert_eq!(again.bodies, scene.bodies);
        assert_eq!(again.launcher, scene.launcher);
    }
    // A fixed direction is kept as a unit vector.
    let scene = parse(
        &spin_thrust_scene(
            "",
            ", Thrust(curve: [(0, 3), (1, 0)], direction: Fixed((3, 0, 4)))",
            0.1,
        ),
        "x.ron",
        "x",
    )
    .unwrap();
    let crate::forces::ThrustDirection::Fixed(d) = scene.forces.thrust.unwrap().direction else {
        panic!("a fixed direction");
    };
    assert!(
        (d - DVec3::new(0.6, 0.0, 0.8)).length() <= 2.0 * f64::EPSILON,
        "{d}"
    );
}

#[test]
fn bad_spin_and_thrust_values_name_the_field() {
    let spun = ", spin: (decay: Time(30))";
    for (spin, thrust, mass, field, says) in [
        (
            ", spin: (decay: Time(0))",
            "",
            0.1,
            "forces[1].spin.decay",
            "> 0",
        ),
        (
            ", spin: (drag_per_1000_rpm: -1)",
            "",
            0.1,
            "forces[1].spin.drag_per_1000_rpm",
            ">= 0",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1), (0.5, 2), (0.5, 0)])",
            0.1,
            "forces[2].curve",
            "point 2 (counted from 0): times must increase",
        ),
        (
            spun,
            ", Thrust(curve: [(-0.1, 1), (0.5, 0)])",
            0.1,
            "forces[2].curve",
            "point 0 (counted from 0): time must be",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1), (0.5, -2), (1, 0)])",
            0.1,
            "forces[2].curve",
            "point 1 (counted from 0): thrust",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1), (0.5, 2)])",
            0.1,
            "forces[2].curve",
            "burnout",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1)])",
            0.1,
            "forces[2].curve",
            "at least two",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1), (1, 0)], propellant: -1)",
            0.1,
            "forces[2].propellant",
            ">= 0",
        ),
        (
            spun,
            ", Thrust(curve: [(0, 1), (1, 0)], direction: Fixed((0, 0, 0)))",
            0.1,
            "forces[2].direction",
            "zero",
        ),
        (
            spun,
            C6_START,
            0.01,
            "bodies[0].mass",
            "0.0108 kg of propellant",
        ),
    ] {
        let err = parse(&spin_thrust_scene(spin, thrust, mass), "x.ron", "x").unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{thrust}: {err}");
        assert!(err.to_string().contains(says), "{thrust}: {err}");
        assert!(!err.to_string().contains('\n'), "one line: {err}");
    }
    // A spin's lift needs a diameter, not a ballistic coefficient.
    let text = "Scene(dt: 0.01, integrator: Rk4, forces: [MachDrag(curve: G7, bc: 0.2, spin: ())])";
    let err = parse(text, "x.ron", "x").unwrap_err();
    assert_eq!(err.field.as_deref(), Some("forces[0].spin"), "{err}");
    assert!(err.to_string().contains("diameter"), "{err}");
}

#[test]
fn exact_and_forest_ruth_refuse_thrust_and_say_why() {
    let text = |integrator: &str| {
        spin_thrust_scene("", C6_START, 0.057)
            .replace("integrator: Rk4", &format!("integrator: {integrator}"))
    };
    let err = parse(&text("Exact"), "x.ron", "x").unwrap_err();
    assert!(err.to_string().contains("has none"), "{err}");
    let err = parse(&text("ForestRuth"), "x.ron", "x").unwrap_err();
    assert!(err.to_string().contains("force term"), "{err}");
    for i in [
        "ImplicitEuler",
        "ImplicitMidpoint",
        "Dopri5",
        "VelocityVerlet",
    ] {
        parse(&text(i), "x.ron", "x").unwrap();
    }
}
