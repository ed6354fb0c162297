//! Observed order of convergence: halve dt, measure the error against the closed form.
//!
//! For a method of order p the global error at a fixed time scales as C h^p, so
//! log2(e(h) / e(h/2)) -> p as h -> 0. The runs go through `World::step`, the real stepping
//! path, on scenes with no contacts so nothing but the integrator contributes.

use volley_sim::exact::closed_form;
use volley_sim::integrate::BodyState;
use volley_sim::{Integrator, World, scene};

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
    let spec = scene.bodies[0];
    let mut world = World::new(&scene);
    for _ in 0..steps {
        world.step().unwrap();
    }
    let start = BodyState {
        p: spec.position,
        mv: spec.mass * spec.velocity,
    };
    let exact = closed_form(&scene.forces, start, spec.mass, world.time()).unwrap();
    (world.bodies().positions().get(0) - exact.p).length()
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
