//! Observed order of convergence: halve dt, measure the error against the closed form.
//!
//! For a method of order p the global error at a fixed time scales as C h^p, so
//! log2(e(h) / e(h/2)) -> p as h -> 0. The runs go through `World::step`, the real stepping
//! path, on scenes with no contacts so nothing but the integrator contributes.

use volley_sim::internals::exact::closed_form;
use volley_sim::internals::integrate::BodyState;
use volley_sim::internals::scene;
use volley_sim::{Integrator, World};

/// Gravity plus linear drag: k = b / m = 0.25 1/s, a closed form exists (exact.rs).
const DRAG: &str = r#"Scene(
    dt: 0.05, integrator: ExplicitEuler,
    forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag(0.5)],
    bodies: [(mass: 2.0, position: (0.0, 0.0, 0.0), launch: Velocity((10.0, 2.0, 15.0)))],
    guard: (every: 0),
)"#;

/// An undamped zero-rest-length spring under gravity, w = sqrt(k/m) = 2 rad/s: a force that
/// depends on position only, where velocity Verlet is its textbook self.
const SPRING: &str = r#"Scene(
    dt: 0.05, integrator: VelocityVerlet,
    forces: [Gravity((0.0, 0.0, -9.81)), Spring(anchor: (0.0, 0.0, 5.0), stiffness: 8.0)],
    bodies: [(mass: 2.0, position: (1.0, 0.0, 3.0), launch: Velocity((0.0, 1.5, 0.0)))],
    guard: (every: 0),
)"#;

/// Position error at t = `duration` after `steps` steps of `integrator`.
fn final_error(text: &str, integrator: Integrator, duration: f64, steps: u64) -> f64 {
    let mut scene = scene::parse(text, "inline.ron", "inline").unwrap();
    scene.set_integrator(integrator).unwrap();
    scene.set_dt(duration / steps as f64).unwrap();
    stepped_error(&scene, steps).0
}

/// Body 0's position error against the closed form after `steps` steps of `scene`, and the
/// force evaluations they cost.
fn stepped_error(scene: &scene::Scene, steps: u64) -> (f64, u64) {
    let spec = scene.bodies()[0];
    let mut world = World::new(scene);
    for _ in 0..steps {
        world.step().unwrap();
    }
    let start = BodyState {
        p: spec.position,
        mv: spec.mass * spec.velocity,
    };
    let exact = closed_form(scene.forces(), start, spec.mass, world.time()).unwrap();
    let e = (world.bodies().positions().get(0) - exact.p).length();
    (e, world.force_evals())
}

/// Observed orders from successive halvings of dt, starting at `duration / first_steps`.
fn observed_orders(text: &str, integrator: Integrator, first_steps: u64) -> Vec<f64> {
    let errors: Vec<f64> = (0..4)
        .map(|k| final_error(text, integrator, 2.0, first_steps << k))
        .collect();
    errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect()
}

/// The observed order at the finest pair is within 0.1 of the theoretical one. The next term
/// of the error expansion is O(h) relative to the leading one; at these steps (k h <= 0.0125,
/// w h <= 0.05 at the finest pair) it moves the observed order by a few hundredths.
fn assert_order(text: &str, integrator: Integrator, first_steps: u64, expected: f64) {
    let orders = observed_orders(text, integrator, first_steps);
    let finest = *orders.last().unwrap();
    println!("{integrator}: observed orders {orders:?}");
    assert!(
        (finest - expected).abs() < 0.1,
        "{integrator}: observed orders {orders:?}, expected {expected}"
    );
}

#[test]
fn explicit_euler_is_first_order_on_drag() {
    assert_order(DRAG, Integrator::ExplicitEuler, 40, 1.0);
}

#[test]
fn semi_implicit_euler_is_first_order_on_drag() {
    assert_order(DRAG, Integrator::SemiImplicitEuler, 40, 1.0);
}

#[test]
fn implicit_euler_is_first_order_on_drag() {
    assert_order(DRAG, Integrator::ImplicitEuler, 40, 1.0);
}

#[test]
fn midpoint_is_second_order_on_drag() {
    assert_order(DRAG, Integrator::Midpoint, 40, 2.0);
}

#[test]
fn rk4_is_fourth_order_on_drag() {
    // Coarser start: at 320 steps RK4's error (~1e-11 m) would approach rounding noise.
    assert_order(DRAG, Integrator::Rk4, 10, 4.0);
}

#[test]
fn velocity_verlet_is_second_order_on_a_spring() {
    assert_order(SPRING, Integrator::VelocityVerlet, 40, 2.0);
}

#[test]
fn velocity_verlet_keeps_second_order_with_drag() {
    // The naive scheme (end kick at the half-step velocity) drops to order 1 with a
    // velocity-dependent force; Volley's predicted end velocity keeps order 2.
    assert_order(DRAG, Integrator::VelocityVerlet, 40, 2.0);
}

#[test]
fn exact_has_no_truncation_error_at_any_dt() {
    // Only rounding remains: a few ulps of a ~20 m position per step, far below 1e-9 m.
    for steps in [1, 7, 40, 333] {
        let e = final_error(DRAG, Integrator::Exact, 2.0, steps);
        assert!(e < 1e-9, "{steps} steps: error {e} m");
    }
}

#[test]
fn forest_ruth_is_fourth_order_on_a_spring() {
    assert_order(SPRING, Integrator::ForestRuth, 10, 4.0);
}

#[test]
fn forest_ruth_keeps_fourth_order_with_drag() {
    // Its substep is the symmetric generalised Verlet (drag implicit in the first half kick);
    // composing velocity Verlet's predicted form instead would give order 3 here.
    assert_order(DRAG, Integrator::ForestRuth, 10, 4.0);
}

#[test]
fn implicit_midpoint_is_second_order_on_drag_and_on_a_spring() {
    assert_order(DRAG, Integrator::ImplicitMidpoint, 40, 2.0);
    assert_order(SPRING, Integrator::ImplicitMidpoint, 40, 2.0);
}

/// `text` with Dormand-Prince at `tolerance`.
fn dopri(text: &str, tolerance: f64) -> String {
    text.replace(
        "integrator: ExplicitEuler,",
        &format!("integrator: Dopri5, tolerance: {tolerance:e},"),
    )
}

#[test]
fn dopri5_is_fifth_order_while_each_tick_is_one_internal_step() {
    // Tolerance 1 accepts every first attempt on this smooth scene: plain DP5 steps.
    assert_order(&dopri(DRAG, 1.0), Integrator::Dopri5, 5, 5.0);
}

#[test]
fn dopri5_error_follows_the_tolerance_and_costs_more_as_it_tightens() {
    // One 0.5 s tick is many internal steps at these tolerances. The controller holds the
    // 4th-order estimate near tol per internal step (h ~ tol^(1/5)); the kept 5th-order
    // solution errs ~h^6 ~ tol^(6/5) per step over ~tol^(-1/5) steps: global error ~ tol.
    let tolerances = [1e-6, 1e-8, 1e-10, 1e-12];
    let mut points = Vec::new();
    for tol in tolerances {
        let mut scene = scene::parse(&dopri(DRAG, tol), "inline.ron", "inline").unwrap();
        scene.set_dt(0.5).unwrap();
        let (e, evals) = stepped_error(&scene, 4);
        points.push((tol, e, evals));
    }
    println!("dopri5 (tolerance, error m, evaluations): {points:?}");
    for pair in points.windows(2) {
        let ((_, e0, n0), (_, e1, n1)) = (pair[0], pair[1]);
        assert!(
            e1 < e0,
            "error must fall as the tolerance tightens: {points:?}"
        );
        assert!(
            n1 > n0,
            "cost must rise as the tolerance tightens: {points:?}"
        );
    }
    // Least-squares slope of log(error) on log(tolerance): 1 in theory.
    let xs: Vec<f64> = points.iter().map(|p| p.0.log10()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.1.log10()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    let slope = sxy / sxx;
    assert!((0.7..=1.3).contains(&slope), "slope {slope}: {points:?}");
}
