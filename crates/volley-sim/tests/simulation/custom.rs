//! A game's own force term (`ForceTerm`): stepped by every integrator that can, at each stage's
//! own time, named in scene files and recordings, refused where it must be.

use glam::DVec3;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::scene;
use volley_sim::internals::world::World;
use volley_sim::state_hash;
use volley_sim::{ForceInput, ForceTerm, ForceTerms, Reads};

/// Quadratic drag written as a game would: `-c |v| v`, the built-in term's own operations.
#[derive(Debug)]
struct GameDrag(f64);

impl ForceTerm for GameDrag {
    fn name(&self) -> &str {
        "test/game-drag"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        -((self.0 * i.v.length()) * i.v)
    }
}

/// A push along x that swings with time, `F = m A cos(w t)`: position-only and time-dependent,
/// with the closed form `x(t) = A (1 - cos(w t)) / w^2` from rest.
#[derive(Debug)]
struct Swing;

const A: f64 = 3.0;
const W: f64 = 2.0;

impl ForceTerm for Swing {
    fn name(&self) -> &str {
        "test/swing"
    }
    fn version(&self) -> u32 {
        2
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        DVec3::new(i.m * A * libm::cos(W * i.t), 0.0, 0.0)
    }
    fn reads(&self) -> Reads {
        Reads::POSITION
    }
}

/// The program's terms, as a game passes them to Volley.
fn terms() -> ForceTerms {
    ForceTerms::new()
        .with(GameDrag(0.02))
        .with(Swing)
        .with(Fuse)
}

fn parse(text: &str, file: &str, name: &str) -> Result<scene::Scene, volley_sim::SceneError> {
    volley_sim::parse_scene_with(text, file, name, &terms())
}

fn scene_with(forces: &str, integrator: Integrator, dt: f64) -> scene::Scene {
    let text = format!(
        "Scene(dt: {dt:?}, integrator: {integrator:?}, forces: [{forces}],
           bodies: [(mass: 1.5, position: (0, 0, 10), launch: Velocity((20, 3, 15))),
                    (mass: 0.4, position: (1, 2, 3), launch: Velocity((-5, 0, 30)))])"
    );
    parse(&text, "custom.ron", "custom").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_games_drag_steps_to_the_bits_of_the_built_in_term_it_equals() {
    let gravity = "Gravity((0, 0, -9.81))";
    for integrator in Integrator::ALL {
        if matches!(integrator, Integrator::Exact | Integrator::ForestRuth) {
            continue; // both refuse it (tested below)
        }
        let run = |forces: String| {
            let mut w = World::new(&scene_with(&forces, integrator, 1.0 / 60.0));
            w.step_ticks(120).unwrap();
            state_hash(&w)
        };
        assert_eq!(
            run(format!("{gravity}, QuadraticDrag(0.02)")),
            run(format!(
                "{gravity}, Custom(name: \"test/game-drag\", version: 1)"
            )),
            "{integrator}"
        );
    }
}

#[test]
fn a_time_dependent_term_is_read_at_each_stages_time() {
    // RK4's error at t = 2 s falls 16-fold per halving of the step only if every stage reads
    // the force at its own time (one stale stage time drops the order to 1).
    let err = |dt: f64| {
        let text = format!(
            "Scene(dt: {dt:?}, integrator: Rk4, forces: [Custom(name: \"test/swing\", version: 2)],
               bodies: [(mass: 2, position: (0, 0, 0))])"
        );
        let mut w = World::new(&parse(&text, "swing.ron", "swing").unwrap());
        let ticks = (2.0 / dt).round() as u64;
        w.step_ticks(ticks).unwrap();
        let t = w.time();
        let exact = A * (1.0 - libm::cos(W * t)) / (W * W);
        (w.bodies().positions().get(0).x - exact).abs()
    };
    let (e1, e2) = (err(0.1), err(0.05));
    let order = (e1 / e2).log2();
    assert!((3.7..4.3).contains(&order), "RK4's observed order {order}");
    // Velocity Verlet (position-only, carried force): order 2.
    let text = |dt: f64| {
        format!(
            "Scene(dt: {dt:?}, integrator: VelocityVerlet, forces: [Custom(name: \"test/swing\", version: 2)],
               bodies: [(mass: 2, position: (0, 0, 0))])"
        )
    };
    let verlet = |dt: f64| {
        let mut w = World::new(&parse(&text(dt), "swing.ron", "swing").unwrap());
        w.step_ticks((2.0 / dt).round() as u64).unwrap();
        let exact = A * (1.0 - libm::cos(W * w.time())) / (W * W);
        (w.bodies().positions().get(0).x - exact).abs()
    };
    let order = (verlet(0.1) / verlet(0.05)).log2();
    assert!(
        (1.8..2.2).contains(&order),
        "velocity Verlet's observed order {order}"
    );
}

#[test]
fn a_batch_and_single_ticks_give_a_time_dependent_term_the_same_bits() {
    let forces = "Gravity((0, 0, -9.81)), Custom(name: \"test/swing\", version: 2)";
    for integrator in [
        Integrator::Rk4,
        Integrator::VelocityVerlet,
        Integrator::Dopri5,
    ] {
        let scene = scene_with(forces, integrator, 0.01);
        let (mut a, mut b) = (World::new(&scene), World::new(&scene));
        a.step_ticks(200).unwrap();
        for _ in 0..200 {
            b.step().unwrap();
        }
        assert_eq!(state_hash(&a), state_hash(&b), "{integrator}");
    }
}

#[test]
fn a_scene_naming_a_term_this_program_lacks_is_refused_in_one_line() {
    let unknown = "Custom(name: \"someone-else/thrust\", version: 1)";
    let err = parse(
        &format!("Scene(dt: 0.01, integrator: Rk4, forces: [{unknown}])"),
        "replay.ron",
        "r",
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("forces[0]"), "{err}");
    let text = err.to_string();
    assert!(
        text.contains("`someone-else/thrust` (version 1) is not in this program's terms"),
        "{text}"
    );
    assert!(!text.contains('\n'));
    let other = "Custom(name: \"test/swing\", version: 1)";
    let err = parse(
        &format!("Scene(dt: 0.01, integrator: Rk4, forces: [{other}])"),
        "replay.ron",
        "r",
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("is version 1 here, and this program has version 2"),
        "{err}"
    );
}

#[test]
fn a_saved_scene_names_the_term_and_its_version() {
    let scene = scene_with(
        "Custom(name: \"test/swing\", version: 2)",
        Integrator::Rk4,
        0.01,
    );
    let text = scene.to_ron();
    let squeezed: String = text.split_whitespace().collect();
    assert!(
        squeezed.contains("Custom(name:\"test/swing\",version:2,)"),
        "{text}"
    );
    let back = parse(&text, "saved.ron", "saved").unwrap();
    assert_eq!(back.forces(), scene.forces());
}

#[test]
fn exact_refuses_any_custom_term_and_forest_ruth_a_velocity_dependent_one() {
    let drag = "Custom(name: \"test/game-drag\", version: 1)";
    let swing = "Custom(name: \"test/swing\", version: 2)";
    let parse = |forces: &str, i: &str| {
        parse(
            &format!("Scene(dt: 0.01, integrator: {i}, forces: [{forces}])"),
            "x.ron",
            "x",
        )
    };
    let err = parse(swing, "Exact").unwrap_err();
    assert!(
        err.to_string().contains("force term Custom has none"),
        "{err}"
    );
    let err = parse(drag, "ForestRuth").unwrap_err();
    assert!(
        err.to_string().contains("force term Custom has none"),
        "{err}"
    );
    // A position-only term is Forest-Ruth's to step: order 4 on the swing.
    parse(swing, "ForestRuth").unwrap();
}

/// A game's own motor that reads each body's own clock: `m a (1 - age / 0.5)` along +x for the
/// first 0.5 s after the body's launch, nothing after (`ForceTerm::force_launched` with the
/// launch, which it says it reads).
#[derive(Debug)]
struct Fuse;

impl ForceTerm for Fuse {
    fn name(&self) -> &str {
        "test/fuse"
    }
    fn version(&self) -> u32 {
        1
    }
    fn reads(&self) -> Reads {
        Reads {
            velocity: false,
            launch: true,
        }
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        let launch = i.launch.expect("a term that reads the launch is given it");
        let age = i.t - launch.time;
        DVec3::new(i.m * 4.0 * (1.0 - age / 0.5).max(0.0), 0.0, 0.0)
    }
}

/// Two bodies launched 0.3 s apart (the scene's at 0, a `fire` at 0.3 s) each get their own
/// 0.5 s of push: 4 m/s^2 falling straight to 0, 1 m/s each, whenever it started. At 0.01 s
/// ticks the push's kink falls on a tick and it is linear in time inside every step, where
/// RK4's stages are Simpson's rule, exact for it (to rounding).
#[test]
fn a_term_that_reads_the_launch_pushes_each_body_on_its_own_clock() {
    let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Custom(name: \"test/fuse\", version: 1)],
                  bodies: [(mass: 2, position: (0, 0, 0))],
                  launcher: (position: (0, 5, 0), speed: 0, elevation_deg: 0, azimuth_deg: 0,
                             mass: 0.5))";
    let scene = parse(text, "fuse.ron", "fuse").unwrap();
    let mut world = World::new(&scene);
    world.step_ticks(30).unwrap();
    world.apply(&volley_sim::Command::Fire).unwrap();
    world.step_ticks(100).unwrap();
    let b = world.bodies();
    assert_eq!(b.launch(1).time, world.time_of(30));
    for i in 0..2 {
        assert!(
            (world.velocity(i).x - 1.0).abs() < 1e-12,
            "body {i}: {}",
            world.velocity(i)
        );
    }
    // Had the term read the world's clock, the second body would have got 0.2 s of the
    // push's tail: 0.16 m/s.
}

/// Several of a game's terms in one scene, evaluated in the order declared: the drag and the
/// swing together step to the bits of the built-in quadratic drag plus the swing, and the same
/// term twice is refused by name.
#[test]
fn a_scene_holds_several_terms_and_each_name_once() {
    let both = "Gravity((0, 0, -9.81)), Custom(name: \"test/game-drag\", version: 1), \
                Custom(name: \"test/swing\", version: 2)";
    let builtin = "Gravity((0, 0, -9.81)), QuadraticDrag(0.02), \
                   Custom(name: \"test/swing\", version: 2)";
    let run = |forces: &str| {
        let mut w = World::new(&scene_with(forces, Integrator::Rk4, 0.01));
        w.step_ticks(100).unwrap();
        state_hash(&w)
    };
    assert_eq!(run(both), run(builtin));
    assert_eq!(
        scene_with(both, Integrator::Rk4, 0.01)
            .forces()
            .custom
            .len(),
        2
    );
    let twice =
        "Custom(name: \"test/swing\", version: 2), Custom(name: \"test/swing\", version: 2)";
    let err = parse(
        &format!("Scene(dt: 0.01, integrator: Rk4, forces: [{twice}])"),
        "x.ron",
        "x",
    )
    .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("forces[1]"), "{err}");
    assert!(
        err.to_string().contains("`test/swing` is declared twice"),
        "{err}"
    );
}

/// A term is a value a world holds: two programs' terms of the same name (here two drags of
/// different strength) live side by side in one process, each scene resolving its own.
#[test]
fn terms_are_values_so_two_worlds_hold_two_terms_of_one_name() {
    let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81)), \
                Custom(name: \"test/game-drag\", version: 1)],
                bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((30, 0, 30)))])";
    let weak = ForceTerms::new().with(GameDrag(0.001));
    let strong = ForceTerms::new().with(GameDrag(0.1));
    let run = |terms: &ForceTerms| {
        let scene = volley_sim::parse_scene_with(text, "d.ron", "d", terms).unwrap();
        let mut w = World::new(&scene);
        w.step_ticks(100).unwrap();
        w.bodies().positions().get(0).x
    };
    let (far, near) = (run(&weak), run(&strong));
    assert!(far > 1.5 * near, "{far} vs {near}");
}

/// A term that does not say it reads the launch is given none, never a launch of zeros.
#[derive(Debug)]
struct Peek;

impl ForceTerm for Peek {
    fn name(&self) -> &str {
        "test/peek"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        assert!(
            i.launch.is_none(),
            "an undeclared launch was given: {:?}",
            i.launch
        );
        DVec3::ZERO
    }
}

#[test]
fn a_term_that_does_not_read_the_launch_is_given_none() {
    // Beside the fuse, which reads it: the launch columns are loaded, and still not handed to
    // the term that did not ask.
    let text =
        "Scene(dt: 0.01, integrator: Rk4, forces: [Custom(name: \"test/fuse\", version: 1), \
                Custom(name: \"test/peek\", version: 1)],
                bodies: [(mass: 2, position: (0, 0, 0))])";
    let terms = terms().with(Peek);
    let scene = volley_sim::parse_scene_with(text, "p.ron", "p", &terms).unwrap();
    let mut world = World::new(&scene);
    world.step_ticks(10).unwrap();
}
