//! The stability pre-check: its verdicts follow the linearised scene, its suggestions work,
//! and the runs it calls unstable do diverge.

#[path = "../../volley-sim/tests/support/mod.rs"]
mod support;

use volley_lab::stability::{self, Stiffness};
use volley_sim::Integrator::{self, *};
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::scene::{self, Scene};
use volley_sim::{Command, SimLoop, World};

fn load(name: &str) -> Scene {
    scene::load(&crate::support::ws(format!("assets/scenes/{name}.ron"))).unwrap()
}

fn parse(text: &str) -> Scene {
    scene::parse(text, "inline.ron", "inline").unwrap_or_else(|e| panic!("{e}"))
}

fn diverges(scene: &Scene, integrator: Integrator, ticks: u64) -> bool {
    let mut s = scene.clone();
    s.set_integrator(integrator).unwrap();
    let mut sim = SimLoop::new(World::new(&s));
    sim.run_until(ticks, &mut VirtualClock::Steady(s.timestep()), &mut ())
        .is_err()
}

#[test]
fn a_scene_without_stiffness_is_stable_for_every_integrator() {
    let report = stability::check(&load("seed"));
    assert!(report.stiffest.is_none());
    assert!(report.verdicts.iter().all(|v| v.stable && v.growth == 1.0));
    assert!(report.warnings().is_empty());
}

#[test]
fn explicit_euler_on_an_undamped_spring_has_no_stable_step() {
    let report = stability::check(&load("hard/stiff_spring"));
    let v = report.verdict(ExplicitEuler).unwrap();
    assert!(!v.stable);
    assert_eq!((v.max_step, v.substeps), (None, None));
    let text = report.warnings().join("\n");
    assert!(
        text.contains("never stable on an undamped spring"),
        "{text}"
    );
    assert!(
        !text.contains("--substeps"),
        "no substep count helps: {text}"
    );
    for name in ["semi-implicit-euler", "verlet", "rk4", "implicit-euler"] {
        assert!(
            text.contains(name),
            "{name} is stable here and must be offered: {text}"
        );
    }
}

#[test]
fn the_suggested_substeps_and_dt_are_the_smallest_that_work() {
    let scene = load("hard/stiff_spring_1e5");
    let report = stability::check(&scene);
    for integrator in [SemiImplicitEuler, VelocityVerlet, Rk4] {
        let v = report.verdict(integrator).unwrap();
        let n = v.substeps.unwrap();
        let at = |substeps: u32| stability::check_at(&scene, scene.dt(), substeps, integrator);
        assert!(
            at(n).verdict(integrator).unwrap().stable,
            "{integrator} at {n}"
        );
        assert!(
            !at(n - 1).verdict(integrator).unwrap().stable,
            "{integrator} at {}",
            n - 1
        );
        let m = v.max_step.unwrap();
        let stable_at = |h: f64| {
            stability::check_at(&scene, h, 1, integrator)
                .verdict(integrator)
                .unwrap()
                .stable
        };
        assert!(
            stable_at(m) && !stable_at(1.01 * m),
            "{integrator}: max step {m}"
        );
    }
}

#[test]
fn a_damped_spring_lets_explicit_euler_be_stable_below_k_over_w_squared() {
    // |1 + h lambda|^2 = 1 - h k + h^2 w^2 for lambda = -k/2 +- i sqrt(w^2 - k^2/4): stable
    // for h <= k / w^2.
    let s = Stiffness {
        w2_lin: 100.0,
        k_lin: 1.0,
        ..Stiffness::default()
    };
    let m = stability::max_stable_step(ExplicitEuler, &s, 1.0).unwrap();
    assert!((m - 0.01).abs() < 1e-6, "{m}");
}

#[test]
fn quadratic_drag_is_linearised_at_c_v_over_m_and_the_verdict_holds() {
    // At speed v the force -c |v| v is linear drag with b = c v: rate c v / m. At 60 Hz, 200 m/s
    // with c = m = 1 is k h = 3.33 (every fixed-step method outside), 60 m/s is k h = 1 (every
    // one inside but Forest-Ruth, whose backward substep has no real solution past
    // k h = 1 / (2 |c2|) = 0.29). Dormand-Prince's controller keeps it stable at both.
    for (speed, stable_fixed) in [(200.0, false), (60.0, true)] {
        let text = format!(
            "Scene(dt: 0.016666667, integrator: SemiImplicitEuler, forces: [QuadraticDrag(1.0)],
             bodies: [(mass: 1.0, position: (0, 0, 0), launch: Velocity(({speed}, 0, 0)))])"
        );
        let scene = parse(&text);
        let report = stability::check(&scene);
        let (_, s) = report.stiffest.unwrap();
        assert_eq!(s.k_nl, speed);
        for v in &report.verdicts {
            let stable = match v.integrator {
                Dopri5 => true,
                ForestRuth => false,
                _ => stable_fixed,
            };
            assert_eq!(v.stable, stable, "{} at {speed} m/s", v.integrator);
            // The one verdict that is conservative: at 200 m/s Forest-Ruth's first substep
            // slows the body from 200 to about 8 m/s (the drag is that strong), so the backward
            // substep finds a root and the run survives; at 60 m/s it slows only to 22 m/s,
            // and 2 |c2| h k = 1.25 > 1 there: NaN at the first tick.
            let runs_fine = if v.integrator == ForestRuth {
                speed > 100.0
            } else {
                stable
            };
            assert_eq!(
                diverges(&scene, v.integrator, 60),
                !runs_fine,
                "{} at {speed}",
                v.integrator
            );
        }
    }
}

#[test]
fn a_point_mass_is_linearised_at_the_orbit_periapsis() {
    // r = 1, v = 0.5, mu = 1: E = -7/8, L = 1/2, e = sqrt(1 + 2 E L^2) = 3/4,
    // r_p = L^2 / (1 + e) = 1/7, so w^2 = mu / r_p^3 = 343.
    let text = "Scene(dt: 0.01, integrator: SemiImplicitEuler,
        forces: [PointMass(center: (0, 0, 0), mu: 1.0)],
        bodies: [(mass: 1.0, position: (1, 0, 0), launch: Velocity((0, 0.5, 0)))])";
    let scene = parse(text);
    let b = scene.bodies()[0];
    let s = Stiffness::of_body(&scene, b.mass, b.position, b.velocity);
    assert!((s.w2_nl - 343.0).abs() < 1e-9, "{}", s.w2_nl);
}

#[test]
fn the_window_can_recheck_after_a_command_switches_the_integrator() {
    let scene = load("hard/stiff_spring");
    let mut world = World::new(&scene);
    assert!(!stability::check_world(&world).chosen_is_stable());
    world
        .apply(&Command::SetIntegrator(VelocityVerlet))
        .unwrap();
    let report = stability::check_world(&world);
    assert_eq!(report.chosen, VelocityVerlet);
    assert!(report.chosen_is_stable() && report.warnings().is_empty());
}

#[test]
fn the_verdict_matches_what_the_runs_do_on_the_hard_scenes() {
    for name in [
        "hard/stiff_spring",
        "hard/stiff_spring_1e5",
        "hard/strong_drag",
    ] {
        let scene = load(name);
        let report = stability::check(&scene);
        for v in &report.verdicts {
            // 120 ticks: every unstable growth factor here is above 1.9 per step.
            assert_eq!(
                diverges(&scene, v.integrator, 120),
                !v.stable,
                "{name}: {}",
                v.integrator
            );
        }
    }
}

#[test]
fn a_step_exactly_on_the_oscillator_limit_is_called_unstable_and_diverges() {
    // w = 20 rad/s at h = 0.1 s: w h = 2, the edge of symplectic Euler's and Verlet's regions,
    // where their two eigenvalues meet at -1 and the matrix is defective: from any state off
    // its one eigenvector (for Verlet, rest; for semi-implicit Euler, v = 20 x) the amplitude
    // grows linearly, and the energy guard stops both.
    let scene = parse(
        "Scene(dt: 0.1, integrator: SemiImplicitEuler,
               forces: [Spring(anchor: (0, 0, 0), stiffness: 400.0)],
               bodies: [(mass: 1, position: (1, 0, 0), launch: Velocity((5, 0, 0)))])",
    );
    let report = stability::check(&scene);
    for integrator in [SemiImplicitEuler, VelocityVerlet] {
        assert!(!report.verdict(integrator).unwrap().stable, "{integrator}");
        assert!(diverges(&scene, integrator, 1000), "{integrator}");
    }
    let warnings = report.warnings().join("\n");
    assert!(warnings.contains("on its edge"), "{warnings}");
    assert!(warnings.contains("fix: --substeps 2"), "{warnings}");
}

/// A spun ball's pre-check counts the spin's drag at its launch spin and the lift model's
/// largest coefficient as more drag: `rho pi d^2 / (8 m) (k omega + 1.120 / 2.333)` on top of
/// the curve's own rate, times the same speed.
#[test]
fn the_pre_check_counts_a_spins_drag_and_lift_as_more_drag() {
    let ball = load("baseball");
    let b = &ball.bodies()[0];
    let still = Stiffness::of_body(&ball, b.mass, b.position, b.velocity);
    let spun = Stiffness::of_spinning(&ball, b.mass, b.position, b.velocity, b.spin.length());
    let d = ball.forces().mach_drag.as_ref().unwrap();
    let sp = d.spin.unwrap();
    let (rho, _) = d.air.at(0.0);
    let extra = std::f64::consts::PI / 8.0
        * 0.07378
        * 0.07378
        * rho
        * (sp.drag_per_spin * b.spin.length() + 1.120 / 2.333)
        / b.mass;
    let speed = b.velocity.length();
    assert!(
        ((spun.k() - still.k()) - extra * speed).abs() <= 1e-12 * spun.k(),
        "{} vs {}",
        spun.k() - still.k(),
        extra * speed
    );
    // The scene's own report uses it: the bundled ball at 60 Hz is stable for RK4.
    let report = stability::check(&ball);
    let rk4 = report
        .verdicts
        .iter()
        .find(|v| v.integrator == Rk4)
        .unwrap();
    assert!(rk4.stable, "{report:?}");
}
