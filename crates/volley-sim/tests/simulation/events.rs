//! Contact events: the ground impact and the target hit are solved inside the step.

use glam::DVec3;
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::exact::{constant_accel, ground_impact_time};
use volley_sim::internals::scene;
use volley_sim::{EventKind, Integrator, Scene, SimLoop, World};

fn seed(integrator: Integrator) -> Scene {
    let mut s = scene::load(&crate::support::ws("assets/scenes/seed.ron")).unwrap();
    s.set_integrator(integrator).unwrap();
    s
}

/// All events of a run of `ticks` ticks.
fn events(scene: &Scene, ticks: u64) -> Vec<volley_sim::Event> {
    struct Collect(Vec<volley_sim::Event>);
    impl volley_sim::TickObserver for Collect {
        fn after_tick(
            &mut self,
            w: &World,
        ) -> Result<(), volley_sim::internals::sim_loop::ObserverError> {
            self.0.extend_from_slice(w.events());
            Ok(())
        }
    }
    let mut sim = SimLoop::new(World::new(scene));
    let mut seen = Collect(Vec::new());
    sim.run_until(
        ticks,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut seen,
    )
    .unwrap();
    seen.0
}

/// Analytic time the seed's projectile (radius r) touches the ground z = 0.
fn analytic_impact(scene: &Scene) -> f64 {
    let b = scene.bodies()[0];
    scene.start_time() + ground_impact_time(b.position.z, b.velocity.z, 9.81, b.radius).unwrap()
}

#[test]
fn ground_impact_time_is_within_a_nanosecond_for_integrators_exact_under_gravity() {
    // Exact, RK4, midpoint and Verlet reproduce constant-force motion exactly, so the only error
    // left is the root search's (a few ulps of the step) and rounding: far below 1e-9 s.
    for integrator in [
        Integrator::Exact,
        Integrator::Rk4,
        Integrator::Midpoint,
        Integrator::VelocityVerlet,
    ] {
        let scene = seed(integrator);
        let expected = analytic_impact(&scene);
        let impact = events(&scene, 30)
            .into_iter()
            .find(|e| matches!(e.kind, EventKind::Impact { .. }))
            .unwrap_or_else(|| panic!("{integrator}: no impact"));
        assert!(
            (impact.time - expected).abs() < 1e-9,
            "{integrator}: impact at {} s, analytic {expected} s",
            impact.time
        );
        // The step that contains it reports it: 0.2 s steps from t = 5.0.
        assert_eq!(impact.tick, ((expected - 5.0) / 0.2).ceil() as u64);
    }
}

#[test]
fn explicit_euler_lands_late_because_it_flies_high() {
    // Explicit Euler ends g T h / 2 high (docs/physics.md, "The seed's worked example"), about 5.1 m after 5.2 s at h = 0.2:
    // the impact comes later than the analytic one, by much more than a step's rounding.
    let scene = seed(Integrator::ExplicitEuler);
    let impact = events(&scene, 40)
        .into_iter()
        .find(|e| matches!(e.kind, EventKind::Impact { .. }))
        .unwrap();
    assert!(impact.time - analytic_impact(&scene) > 0.1, "{impact:?}");
}

#[test]
fn the_exact_launch_hits_the_target_dead_centre() {
    let scene = seed(Integrator::Exact);
    let (b, target) = (scene.bodies()[0], scene.targets()[0]);
    let g = DVec3::new(0.0, 0.0, -9.81);
    let all = events(&scene, 27);
    let hit = all
        .iter()
        .find(|e| matches!(e.kind, EventKind::Hit { target: 0 }))
        .expect("a hit");
    let (time, distance, hit_flag) = all
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::Approach { distance, hit, .. } => Some((e.time, distance, hit)),
            _ => None,
        })
        .next_back()
        .expect("the projectile passes the target");
    // Closest approach at the aim's flight time, 5.207666 s after launch, at distance ~0.
    let flight = volley_sim::internals::exact::aim(b.position, target.center, 30.0, 9.81).unwrap()
        [0]
    .flight_time;
    assert!(
        (time - (5.0 + flight)).abs() < 1e-9,
        "closest approach at {time}"
    );
    assert!(distance < 1e-9 && hit_flag, "{distance} m from the centre");
    // First contact is where the centres are the two radii apart (0.6 m, about 0.02 s before
    // the centre at 30 m/s): check the reported time against the closed form.
    let at = |t: f64| constant_accel(b.position, b.velocity, g, t - 5.0).0;
    let gap = (at(hit.time) - target.center).length() - (target.radius + b.radius);
    assert!(gap.abs() < 1e-9, "gap at the reported hit time: {gap} m");
    assert!(hit.time < time && time - hit.time < 0.03);
}

#[test]
fn explicit_euler_misses_the_target_and_says_by_how_much() {
    let scene = seed(Integrator::ExplicitEuler);
    let all = events(&scene, 28);
    assert!(
        !all.iter().any(|e| matches!(e.kind, EventKind::Hit { .. })),
        "{all:?}"
    );
    let passes: Vec<f64> = all
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::Approach { distance, hit, .. } => Some(distance).filter(|_| !hit),
            _ => None,
        })
        .collect();
    // Two passes of the high arc: over the target on the way up (32.58 m), then past it on the
    // way down. At the target's x Euler flies g T h / 2 = 5.1 m high, on a path falling at
    // about 71 deg, so it passes 5.1 m * cos(71 deg) = 1.67 m from the centre.
    assert_eq!(passes.len(), 2, "{passes:?}");
    assert!(
        (passes[0] - 32.58).abs() < 0.01 && (passes[1] - 1.67).abs() < 0.01,
        "{passes:?}"
    );
}
