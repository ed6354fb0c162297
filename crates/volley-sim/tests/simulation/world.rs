//! Bodies: stable ids in spawn order, contiguous storage, ordered despawn; commands at tick
//! boundaries.

use glam::DVec3;
use volley_sim::internals::command::{Command, CommandError, parse_script};
use volley_sim::internals::scene;
use volley_sim::internals::scene::{BodySpec, IntegratorError};
use volley_sim::internals::world::RestoreError;
use volley_sim::{BodyId, ForceKind, Integrator, SimLoop, World};

fn empty_world() -> World {
    let text = r#"Scene(dt: 0.01, integrator: SemiImplicitEuler,
        forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag(0.1)])"#;
    World::new(&scene::parse(text, "inline.ron", "inline").unwrap())
}

fn ball(x: f64) -> BodySpec {
    BodySpec {
        mass: 1.0,
        radius: 0.1,
        position: DVec3::new(x, 0.0, 10.0),
        velocity: DVec3::ZERO,
        spin: Default::default(),
    }
}

#[test]
fn ids_follow_spawn_order_and_despawn_keeps_the_rest_in_order() {
    let mut w = empty_world();
    let ids: Vec<BodyId> = (0..5).map(|i| w.spawn(&ball(i as f64))).collect();
    assert_eq!(ids, (0..5).map(BodyId).collect::<Vec<_>>());
    assert!(w.despawn(BodyId(2)));
    assert!(!w.despawn(BodyId(2)), "gone is gone");
    assert_eq!(
        w.bodies().ids(),
        &[BodyId(0), BodyId(1), BodyId(3), BodyId(4)]
    );
    // Storage follows the ids: body 3's data moved down with it.
    assert_eq!(w.bodies().positions().get(2).x, 3.0);
    // Ids are never reused.
    assert_eq!(w.spawn(&ball(9.0)), BodyId(5));
    assert_eq!(w.bodies().index_of(BodyId(5)), Some(4));
    assert_eq!(w.bodies().index_of(BodyId(2)), None);
}

#[test]
fn commands_apply_at_their_tick_boundary() {
    let mut sim = SimLoop::new(empty_world());
    let script = "0: spawn mass=2 position=0,0,5 velocity=1,0,0\n\
                  3: fire\n\
                  3: launch speed=5 elevation=90\n\
                  3: fire\n\
                  5: despawn 0\n";
    sim.schedule(parse_script(script, "script.txt").unwrap());
    let steady = volley_sim::internals::clock::VirtualClock::Steady(sim.world.scene().timestep());
    sim.run_until(3, &mut steady.clone(), &mut ()).unwrap();
    assert_eq!(sim.world.bodies().len(), 1);
    sim.run_until(4, &mut steady.clone(), &mut ()).unwrap();
    // Two fires at tick 3, in file order: the first with the old launcher, the second straight up.
    assert_eq!(sim.world.bodies().ids(), &[BodyId(0), BodyId(1), BodyId(2)]);
    let v2 = sim.world.velocity(2);
    assert!(v2.x.abs() < 1.0 && v2.z > 4.5, "{v2}");
    sim.run_until(6, &mut steady.clone(), &mut ()).unwrap();
    assert_eq!(sim.world.bodies().ids(), &[BodyId(1), BodyId(2)]);
}

#[test]
fn commands_that_cannot_apply_are_refused_with_a_reason() {
    let mut w = empty_world();
    let err = w.apply(&Command::Despawn(BodyId(7))).unwrap_err();
    assert_eq!(err, CommandError::NoSuchBody(BodyId(7)));
    let err = w
        .apply(&Command::SetForce {
            kind: ForceKind::Spring,
            enabled: true,
        })
        .unwrap_err();
    assert!(
        matches!(&err, CommandError::UndeclaredForce { kind: ForceKind::Spring, declared }
            if declared == &[ForceKind::Gravity, ForceKind::LinearDrag]),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "force: the scene does not declare Spring (declared: Gravity, LinearDrag)"
    );
    // Exact is fine with drag and gravity, but not once the scene's quadratic drag is on; here
    // there is none, so it applies.
    w.apply(&Command::SetIntegrator(Integrator::Exact)).unwrap();
    assert_eq!(w.integrator(), Integrator::Exact);
}

#[test]
fn toggling_a_force_changes_the_motion_and_turning_it_back_restores_it() {
    let mut w = empty_world();
    w.spawn(&ball(0.0));
    w.apply(&Command::SetForce {
        kind: ForceKind::Gravity,
        enabled: false,
    })
    .unwrap();
    w.step().unwrap();
    assert_eq!(
        w.bodies().positions().get(0).z,
        10.0,
        "no force, no motion from rest"
    );
    w.apply(&Command::SetForce {
        kind: ForceKind::Gravity,
        enabled: true,
    })
    .unwrap();
    w.step().unwrap();
    assert!(w.bodies().positions().get(0).z < 10.0);
    assert_eq!(w.forces().gravity, Some(DVec3::new(0.0, 0.0, -9.81)));
}

#[test]
fn reset_restores_the_scene_but_time_keeps_counting() {
    let text = r#"Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0.0, 0.0, -9.81))],
        bodies: [(mass: 1.0, position: (0.0, 0.0, 3.0))])"#;
    let mut w = World::new(&scene::parse(text, "inline.ron", "inline").unwrap());
    for _ in 0..10 {
        w.step().unwrap();
    }
    w.apply(&Command::Fire).unwrap();
    w.apply(&Command::Reset).unwrap();
    assert_eq!(w.tick(), 10);
    assert_eq!(w.bodies().len(), 1);
    assert_eq!(w.bodies().ids(), &[BodyId(2)], "new ids after a reset");
    assert_eq!(w.bodies().positions().get(0), DVec3::new(0.0, 0.0, 3.0));
}

#[test]
fn reset_clears_a_divergence_and_the_world_steps_again() {
    // The reference's stiff spring, k/m = 1e4 at h = 1/60 (w h = 1.667): explicit Euler's
    // energy passes the guard's bound within a few steps.
    let text = r#"Scene(dt: 0.0166666667, integrator: ExplicitEuler,
        forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
        bodies: [(mass: 1, position: (0.1, 0, 0))])"#;
    let scene = scene::parse(text, "inline.ron", "inline").unwrap();
    let mut w = World::new(&scene);
    let d = (0..100)
        .find_map(|_| w.step().err())
        .expect("the run diverges");
    assert_eq!(w.divergence(), Some(d));
    assert_eq!(w.step(), Err(d), "a stopped world stays stopped");
    let tick = w.tick();
    w.apply(&Command::Reset).unwrap();
    assert_eq!(w.divergence(), None);
    assert_eq!(w.tick(), tick, "the tick keeps counting");
    let fresh = World::new(&scene);
    assert_eq!(
        w.bodies().positions().get(0),
        fresh.bodies().positions().get(0)
    );
    assert_eq!(w.bodies().momenta().get(0), fresh.bodies().momenta().get(0));
    assert_eq!(w.step(), Ok(()));
    assert_eq!(w.tick(), tick + 1);
}

#[test]
fn restore_names_the_check_a_snapshot_fails() {
    let text = r#"Scene(dt: 0.01, integrator: Rk4,
        forces: [Gravity((0.0, 0.0, -9.81)), QuadraticDrag(0.1)])"#;
    let mut w = World::new(&scene::parse(text, "inline.ron", "inline").unwrap());
    w.spawn(&ball(0.0));
    w.spawn(&ball(1.0));
    let good = w.snapshot();
    type Spoil = fn(&mut volley_sim::internals::replay::Snapshot);
    let cases: [(Spoil, RestoreError, &str); 10] = [
        (
            |s| s.tick = u64::MAX,
            RestoreError::Counts {
                tick: u64::MAX,
                next_id: 2,
            },
            "tick 18446744073709551615 and next_id 2 must be below 2^62 (4611686018427387904)",
        ),
        (
            |s| s.next_id = volley_sim::internals::world::MAX_COUNT,
            RestoreError::Counts {
                tick: 0,
                next_id: 1 << 62,
            },
            "tick 0 and next_id 4611686018427387904 must be below 2^62 (4611686018427387904)",
        ),
        (
            |s| s.bodies.mass.push(1.0),
            RestoreError::Lengths { ids: 2 },
            "body arrays of different lengths (2 ids)",
        ),
        (
            |s| s.bodies.id.swap(0, 1),
            RestoreError::Ids,
            "body ids must increase and stay below next_id",
        ),
        (
            |s| s.bodies.mass[1] = 0.0,
            RestoreError::Mass {
                body: BodyId(1),
                mass: 0.0,
            },
            "body 1: mass must be > 0, got 0",
        ),
        (
            |s| s.bodies.radius[0] = -1.0,
            RestoreError::Radius {
                body: BodyId(0),
                radius: -1.0,
            },
            "body 0: radius must be >= 0, got -1",
        ),
        (
            |s| s.forces.constant = Some(DVec3::X),
            RestoreError::Forces,
            "active forces are not a subset of the scene's declared terms",
        ),
        (
            |s| s.integrator = Integrator::Exact,
            RestoreError::Integrator(IntegratorError::NoClosedForm(ForceKind::QuadraticDrag)),
            "`exact` needs a closed form, and force term QuadraticDrag has none (exact covers any \
             mix of Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, or a \
             PointMass alone); choose another integrator",
        ),
        (
            |s| s.launcher.speed = -1.0,
            RestoreError::Launcher,
            "launcher: values must be finite, speed and radius >= 0, mass > 0",
        ),
        (
            |s| {
                for c in [&mut s.carry.x, &mut s.carry.y, &mut s.carry.z] {
                    c.resize(2, 0.0);
                }
            },
            RestoreError::Carry,
            "a carried force needs velocity Verlet, forces of position only and one entry per \
             body",
        ),
    ];
    for (spoil, expected, message) in cases {
        let mut s = good.clone();
        spoil(&mut s);
        let err = w.restore(&s).unwrap_err();
        assert_eq!(err, expected);
        assert_eq!(err.to_string(), message);
    }
    w.restore(&good).unwrap();
}

#[test]
fn a_scene_written_by_to_ron_parses_back_to_the_same_scene_and_steps_to_the_same_bits() {
    for (name, _) in volley_sim::internals::scene::BUNDLED {
        let scene = volley_sim::internals::scene::bundled(name).unwrap();
        let scene = scene
            .edit()
            .compare(vec![
                volley_sim::internals::scene::CompareLane::of(scene.integrator()),
                volley_sim::internals::scene::CompareLane {
                    integrator: scene.integrator(),
                    dt: Some(0.05),
                    substeps: Some(3),
                },
            ])
            .build()
            .unwrap();
        let text = scene.to_ron();
        let back = volley_sim::internals::scene::parse(&text, "saved.ron", "saved")
            .unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        // Everything but the source text (and the description's own comment lines) is equal.
        assert_eq!(back.to_ron(), scene.to_ron(), "{name}");
        assert_eq!(back.forces(), scene.forces(), "{name}");
        let (mut a, mut b) = (
            volley_sim::World::new(&scene),
            volley_sim::World::new(&back),
        );
        let ticks = 50.min(scene.ticks_until(scene.start_time() + scene.duration()));
        let (ra, rb) = (a.step_ticks(ticks), b.step_ticks(ticks));
        assert_eq!(ra.is_ok(), rb.is_ok(), "{name}");
        assert_eq!(
            volley_sim::internals::hash::state_hash(&a),
            volley_sim::internals::hash::state_hash(&b),
            "{name}"
        );
    }
}
