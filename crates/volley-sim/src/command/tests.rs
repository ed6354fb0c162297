use super::*;

#[test]
fn a_script_of_more_than_the_most_commands_is_refused_at_the_line_past_it() {
    let text = "0: fire\n".repeat(MAX_SCRIPT_COMMANDS + 1);
    let err = parse_script(&text, "big.txt").unwrap_err();
    assert_eq!(err.problem, ScriptProblem::TooManyCommands);
    assert_eq!(err.line, MAX_SCRIPT_COMMANDS + 1);
    assert_eq!(
        parse_script(&"0: fire\n".repeat(MAX_SCRIPT_COMMANDS), "ok.txt").map(|s| s.len()),
        Ok(MAX_SCRIPT_COMMANDS)
    );
}

#[test]
fn fire_and_spawn_are_refused_once_the_world_holds_the_most_bodies() {
    let text = format!(
        "Scene(dt: 0.01, integrator: Rk4, bodies: [(mass: 1, position: (0, 0, 1))], volley: (count: {}))",
        MAX_BODIES - 2
    );
    let scene = crate::scene::parse(&text, "x.ron", "x").unwrap();
    let mut world = World::new(&scene);
    assert_eq!(world.apply(&Command::Fire), Ok(()));
    assert_eq!(world.bodies().len(), MAX_BODIES);
    let spawn = Command::Spawn(scene.bodies[0]);
    for refused in [Command::Fire, spawn] {
        assert_eq!(world.apply(&refused), Err(CommandError::TooManyBodies));
    }
    assert_eq!(world.bodies().len(), MAX_BODIES);
    assert_eq!(world.apply(&Command::Despawn(BodyId(0))), Ok(()));
    assert_eq!(world.apply(&spawn), Ok(()));
}

#[test]
fn every_command_round_trips_through_its_script_form() {
    let commands = [
        Command::Fire,
        Command::Reset,
        Command::Despawn(BodyId(7)),
        Command::SetIntegrator(Integrator::Rk4),
        Command::SetForce {
            kind: ForceKind::LinearDrag,
            enabled: false,
        },
        Command::SetLaunch {
            speed: Some(0.1 + 0.2),
            elevation_deg: None,
            azimuth_deg: Some(-3.5),
            position: Some(DVec3::new(1.0, 2.0, 1e-300)),
        },
        Command::Spawn(BodySpec {
            mass: 2.5,
            radius: 0.0,
            position: DVec3::new(10.0, 0.0, 2.0),
            velocity: DVec3::new(7.681, 0.0, 29.000_04),
            spin: Default::default(),
        }),
        Command::Spawn(BodySpec {
            mass: 0.145,
            radius: 0.037,
            position: DVec3::new(0.0, 0.0, 1.0),
            velocity: DVec3::new(40.0, 0.0, 20.0),
            spin: DVec3::new(0.0, -261.799_387_799_149_4, 0.1),
        }),
    ];
    for c in commands {
        let text = c.to_string();
        assert_eq!(text.parse::<Command>(), Ok(c), "{text}");
    }
}

#[test]
fn script_errors_name_the_line() {
    let e = parse_script("# intro\n0: fire\n5: warp 9\n", "s.txt").unwrap_err();
    assert!(
        matches!(&e, ScriptError { file, line: 3, problem: ScriptProblem::Command(
            CommandParseError::UnknownCommand(_)) } if file == "s.txt"),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("s.txt:3: unknown command"), "{e}");
    let e = parse_script("5: fire\n4: fire\n", "s.txt").unwrap_err();
    assert_eq!((e.line, e.problem), (2, ScriptProblem::TickGoesBack(4)));
}

/// Every variant prints the message it printed when errors were strings.
#[test]
fn error_messages_are_pinned() {
    let parse_err = |text: &str| text.parse::<Command>().unwrap_err();
    let parse = |text: &str| parse_err(text).to_string();
    let apply = |e: CommandError| e.to_string();
    let script = |text: &str| parse_script(text, "s.txt").unwrap_err().to_string();
    let cases: [(String, &str); 19] = [
        (
            apply(CommandError::NoSuchBody(BodyId(7))),
            "despawn: there is no body 7",
        ),
        (
            apply(CommandError::InvalidLaunch),
            "launch: values must be finite and the speed >= 0",
        ),
        (
            apply(CommandError::UndeclaredForce {
                kind: ForceKind::Spring,
                declared: vec![ForceKind::Gravity, ForceKind::LinearDrag],
            }),
            "force: the scene does not declare Spring (declared: Gravity, LinearDrag)",
        ),
        (
            apply(CommandError::Integrator(IntegratorError::NoClosedForm(
                ForceKind::QuadraticDrag,
            ))),
            "`exact` needs a closed form, and force term QuadraticDrag has none (exact covers \
             any mix of Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, \
             or a PointMass alone); choose another integrator",
        ),
        (parse("spawn mass=0"), "spawn: mass must be > 0, got 0"),
        (
            parse("spawn radius=-1"),
            "spawn: radius must be >= 0, got -1",
        ),
        (
            apply(CommandError::SpawnState),
            "spawn: position, velocity and spin must be finite",
        ),
        (parse("spawn mass"), "expected key=value, got `mass`"),
        (parse("despawn"), "despawn: expected a body id"),
        (
            parse("integrator"),
            "integrator: expected an integrator name",
        ),
        (parse("despawn x"), "despawn: expected a body id, got `x`"),
        (
            parse("integrator leapfrog"),
            "integrator: unknown `leapfrog`, expected one of explicit-euler, \
             semi-implicit-euler, verlet, midpoint, rk4, implicit-euler, exact, forest-ruth, \
             dopri5, implicit-midpoint",
        ),
        (
            parse("force Antigravity on"),
            "force: unknown term `Antigravity`, expected one of Gravity, ConstantForce, \
             LinearDrag, QuadraticDrag, Spring, PointMass, MachDrag, Custom, Thrust",
        ),
        (
            parse("force Gravity"),
            "force: expected `force KIND on|off`",
        ),
        (
            parse("launch warp=9"),
            "launch: unknown key `warp`, expected speed, elevation, azimuth or position",
        ),
        (
            parse("spawn warp=9"),
            "spawn: unknown key `warp`, expected mass, radius, position, velocity or spin",
        ),
        (
            parse("launch speed=fast"),
            "speed: expected a finite number, got `fast`",
        ),
        (
            parse("spawn position=1,2"),
            "position: expected x,y,z, got `1,2`",
        ),
        (
            parse("warp 9"),
            "unknown command `warp 9`, expected fire, spawn, despawn, launch, force, \
             integrator or reset",
        ),
    ];
    for (error, message) in cases {
        assert_eq!(error, message);
    }
    assert_eq!(script("fire\n"), "s.txt:1: expected `TICK: COMMAND`");
    assert_eq!(
        script("0: fire\nx: fire"),
        "s.txt:2: expected a tick number, got `x`"
    );
    assert_eq!(
        script("5: fire\n4: fire\n"),
        "s.txt:2: tick 4 comes after a later tick"
    );
    assert_eq!(
        script("0: fire\n3: warp 9"),
        "s.txt:2: unknown command `warp 9`, expected fire, spawn, despawn, launch, force, \
         integrator or reset"
    );
    // A spawn the world would refuse is caught as it is read, as the error applying it gives.
    assert_eq!(
        parse_err("spawn mass=0"),
        CommandParseError::Spawn(CommandError::SpawnMass(0.0))
    );
    assert_eq!(
        parse_err("spawn position=1,2"),
        CommandParseError::InvalidVector {
            key: "position",
            value: "1,2".into(),
        }
    );
}

#[test]
fn every_kind_of_term_switches_off_and_back_on() {
    let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81)),
        MachDrag(curve: Table([(0, 0.3), (1, 0.3)]), diameter: 0.07, spin: ()),
        Thrust(curve: [(0, 1), (1, 0)], propellant: 0.01)],
        bodies: [(mass: 0.1, position: (0, 0, 0))])";
    let scene = crate::scene::parse(text, "x.ron", "x").unwrap();
    let mut world = World::new(&scene);
    for kind in [ForceKind::MachDrag, ForceKind::Thrust, ForceKind::Gravity] {
        world
            .apply(&Command::SetForce {
                kind,
                enabled: false,
            })
            .unwrap();
        assert!(!world.forces().has(kind), "{kind:?} off");
        world
            .apply(&Command::SetForce {
                kind,
                enabled: true,
            })
            .unwrap();
        assert!(world.forces().has(kind), "{kind:?} back on");
    }
    assert_eq!(world.forces(), &scene.forces, "every term back as declared");
}
