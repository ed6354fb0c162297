//! `exact` is the closed form, not an approximation: at any t, for any dt. Here the drag flow;
//! the linear system with a spring in `linear`, Kepler's problem in `kepler`.

mod extrapolation;
mod kepler;
mod linear;

use glam::DVec3;
use proptest::prelude::*;
use volley_sim::internals::scene;
use volley_sim::{Integrator, World};

/// The reference form of docs/physics.md ("Closed forms"), evaluated directly: linear drag k = b/m under gravity,
/// vT = g/k, p(t) = p0 + vT t + (v0 - vT)(1 - e^-kt)/k.
fn reference(p0: DVec3, v0: DVec3, g: DVec3, k: f64, t: f64) -> DVec3 {
    if k == 0.0 {
        return p0 + v0 * t + 0.5 * g * t * t;
    }
    let vt = g / k;
    p0 + vt * t + (v0 - vt) * (1.0 - (-k * t).exp()) / k
}

fn run(b: f64, dt: f64, steps: u64, v0: DVec3) -> (World, DVec3) {
    let text = format!(
        "Scene(dt: {dt}, integrator: Exact, forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag({b})],
               bodies: [(mass: 2.0, position: (1.0, -2.0, 3.0), launch: Velocity(({}, {}, {})))],
               guard: (every: 0))",
        v0.x, v0.y, v0.z
    );
    let scene = scene::parse(&text, "inline.ron", "inline").unwrap();
    let mut world = World::new(&scene);
    for _ in 0..steps {
        world.step().unwrap();
    }
    let t = world.time();
    let p = reference(
        DVec3::new(1.0, -2.0, 3.0),
        v0,
        DVec3::new(0.0, 0.0, -9.81),
        b / 2.0,
        t,
    );
    (world, p)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Stepping `exact` n times lands on the closed form at t = n h within 1e-9 relative: each
    /// step composes the exact flow, so only rounding accumulates (~n ulps at worst, 1e-13 for
    /// the 2000 steps here), and the reference form itself cancels when k t is small.
    #[test]
    fn exact_matches_the_closed_form_for_any_dt_and_time(
        b in prop_oneof![Just(0.0), 1e-3..5.0f64],
        dt in 1e-4..0.5f64,
        steps in 1u64..2000,
        v0 in (-30.0..30.0f64, -30.0..30.0f64, -30.0..30.0f64),
    ) {
        let (world, expected) = run(b, dt, steps, DVec3::from(v0));
        let got = world.bodies().positions().get(0);
        let scale = expected.length().max(1.0);
        prop_assert!((got - expected).length() <= 1e-9 * scale,
            "t = {}: {got} vs {expected}", world.time());
    }
}

#[test]
fn exact_costs_no_force_evaluations() {
    let (world, _) = run(0.4, 0.01, 100, DVec3::new(3.0, 0.0, 9.0));
    assert_eq!(world.integrator(), Integrator::Exact);
    assert_eq!(world.force_evals(), 0);
}
