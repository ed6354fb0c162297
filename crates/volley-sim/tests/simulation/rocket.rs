//! A model rocket motor: the Estes C6 and A8 thrust curves as RASP `.eng` files give them, their
//! certified total impulse, the propellant burning as OpenRocket tabulates it, and the rocket
//! equation, with the burnout inside a tick (hard case 15).
//!
//! Source of the curves: OpenRocket's motor data, `core/resources-src/datafiles/thrustcurves/
//! Estes_C6.eng` and `Estes_A8.eng` (github.com/openrocket/openrocket, commit bd66cc93), "made
//! from NAR published data", whose comment says the total impulse is the NAR certification's;
//! the companion `.rse` files print it (`Itot="8.817"` and `Itot="2.32"`, N s) and the
//! propellant left at each point of the C6 curve (`m`, g, 6 significant digits).

use glam::DVec3;
use volley_sim::internals::forces::ThrustCurve;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::scene;
use volley_sim::internals::world::World;

/// Estes_C6.eng's points (s, N); RASP curves start from (0, 0), which the file leaves implicit.
const C6: [(f64, f64); 25] = [
    (0.0, 0.0),
    (0.031, 0.946),
    (0.092, 4.826),
    (0.139, 9.936),
    (0.192, 14.09),
    (0.209, 11.446),
    (0.231, 7.381),
    (0.248, 6.151),
    (0.292, 5.489),
    (0.37, 4.921),
    (0.475, 4.448),
    (0.671, 4.258),
    (0.702, 4.542),
    (0.723, 4.164),
    (0.85, 4.448),
    (1.063, 4.353),
    (1.211, 4.353),
    (1.242, 4.069),
    (1.303, 4.258),
    (1.468, 4.353),
    (1.656, 4.448),
    (1.821, 4.448),
    (1.834, 2.933),
    (1.847, 1.325),
    (1.86, 0.0),
];

/// Estes_C6.eng's header: `C6 18 70 0-3-5-7 0.0108 0.0231 Estes` (propellant and launch mass,
/// kg).
const C6_PROPELLANT: f64 = 0.0108;
const C6_LAUNCH_MASS: f64 = 0.0231;

/// Estes_A8.eng's points.
const A8: [(f64, f64); 24] = [
    (0.0, 0.0),
    (0.041, 0.512),
    (0.084, 2.115),
    (0.127, 4.358),
    (0.166, 6.794),
    (0.192, 8.588),
    (0.206, 9.294),
    (0.226, 9.73),
    (0.236, 8.845),
    (0.247, 7.179),
    (0.261, 5.063),
    (0.277, 3.717),
    (0.306, 3.205),
    (0.351, 2.884),
    (0.405, 2.499),
    (0.467, 2.371),
    (0.532, 2.307),
    (0.589, 2.371),
    (0.632, 2.371),
    (0.652, 2.243),
    (0.668, 1.794),
    (0.684, 1.153),
    (0.703, 0.448),
    (0.73, 0.0),
];

#[test]
fn the_c6_and_a8_curves_deliver_their_certified_total_impulse() {
    // To half a unit of the `.rse` file's last printed digit.
    let c6 = ThrustCurve::new(C6.to_vec()).unwrap().total_impulse();
    assert!((c6 - 8.817).abs() <= 0.0005, "C6 {c6} N s");
    let a8 = ThrustCurve::new(A8.to_vec()).unwrap().total_impulse();
    assert!((a8 - 2.32).abs() <= 0.005, "A8 {a8} N s");
}

/// Estes_C6.rse's propellant left (g) at each point of the curve, in the curve's order.
const C6_PROPELLANT_LEFT_G: [f64; 25] = [
    10.8, 10.782, 10.5664, 10.1415, 9.36163, 9.09576, 8.84209, 8.7012, 8.38754, 7.89025, 7.28777,
    6.24272, 6.07565, 5.96368, 5.29384, 4.14576, 3.35665, 3.19675, 2.88566, 2.0155, 1.00217,
    0.103215, 0.04445, 0.0105492, 0.0,
];

#[test]
fn the_propellant_burns_as_openrocket_tabulates_it() {
    let scene = c6_in_space(Integrator::Rk4, 0.001);
    let motor = scene
        .forces()
        .thrust
        .as_ref()
        .expect("the scene declares a motor");
    for (&(t, _), printed) in C6.iter().zip(C6_PROPELLANT_LEFT_G) {
        let left = (motor.mass_at(t, C6_LAUNCH_MASS) - (C6_LAUNCH_MASS - C6_PROPELLANT)) * 1e3;
        // Six significant digits: half a unit of the last.
        let half = if printed == 0.0 {
            5e-7
        } else {
            0.5 * 10f64.powi(libm::floor(libm::log10(printed)) as i32 - 5)
        };
        assert!(
            (left - printed).abs() <= half + 1e-12,
            "t = {t}: {left} g left, the file {printed} g"
        );
    }
}

/// The motor alone on a body of its own launch mass, in space, pushing along +x from rest.
fn c6_in_space(integrator: Integrator, dt: f64) -> scene::Scene {
    let curve: Vec<String> = C6.iter().map(|(t, f)| format!("({t:?}, {f:?})")).collect();
    let text = format!(
        "Scene(dt: {dt:?}, integrator: {integrator:?}, duration: 2.5, tolerance: 1e-10,
           forces: [Thrust(curve: [{}], propellant: {C6_PROPELLANT:?}, direction: Fixed((1, 0, 0)))],
           bodies: [(mass: {C6_LAUNCH_MASS:?}, position: (0, 0, 0))])",
        curve.join(", ")
    );
    scene::parse(&text, "c6.ron", "c6").expect("the C6 scene parses")
}

/// Speed and mass at `t` s of the body of [`c6_in_space`].
fn fly(integrator: Integrator, dt: f64, t: f64) -> (f64, f64, DVec3) {
    let scene = c6_in_space(integrator, dt);
    let mut world = World::new(&scene);
    let ticks = scene.ticks_until(t);
    world.step_ticks(ticks).unwrap();
    (
        world.velocity(0).x,
        world.bodies().masses()[0],
        world.bodies().momenta().get(0),
    )
}

/// The rocket equation: with the propellant burning in proportion to the impulse (a constant
/// exhaust speed `c = I / m_p`), `dV = c ln(m_0 / m_1)` whatever the curve's shape.
fn tsiolkovsky() -> f64 {
    let c = ThrustCurve::new(C6.to_vec()).unwrap().total_impulse() / C6_PROPELLANT;
    c * libm::log(C6_LAUNCH_MASS / (C6_LAUNCH_MASS - C6_PROPELLANT))
}

#[test]
fn after_burnout_the_speed_is_the_rocket_equations_and_the_mass_is_the_dry_mass() {
    let (v, m, mv) = fly(Integrator::Rk4, 0.001, 2.0);
    let exact = tsiolkovsky();
    // At 1 ms every point of the curve is a tick boundary, so RK4 keeps its order on every
    // step: the error is its truncation, far below 1e-9 of the speed.
    assert!(
        (v - exact).abs() <= 1e-9 * exact,
        "{v} m/s, the equation {exact} m/s"
    );
    assert_eq!(
        m,
        C6_LAUNCH_MASS - C6_PROPELLANT,
        "the dry mass, to the bit"
    );
    assert_eq!(
        mv,
        m * DVec3::new(v, 0.0, 0.0),
        "the momentum is that mass's"
    );
}

/// A triangle curve, `F0` falling straight to 0 at burnout `tb`, with the C6's impulse,
/// propellant and launch mass: its only kink is the burnout (the start is the launch, a tick
/// boundary), and the rocket equation's speed is the same for every `tb`.
fn triangle(integrator: Integrator, dt: f64, tb: f64) -> f64 {
    let impulse = ThrustCurve::new(C6.to_vec()).unwrap().total_impulse();
    let f0 = 2.0 * impulse / tb;
    let text = format!(
        "Scene(dt: {dt:?}, integrator: {integrator:?}, duration: 2.5, tolerance: 1e-10,
           forces: [Thrust(curve: [(0.0, {f0:?}), ({tb:?}, 0.0)], propellant: {C6_PROPELLANT:?},
                           direction: Fixed((1, 0, 0)))],
           bodies: [(mass: {C6_LAUNCH_MASS:?}, position: (0, 0, 0))])"
    );
    let scene = scene::parse(&text, "triangle.ron", "triangle").unwrap();
    let mut world = World::new(&scene);
    world.step_ticks(scene.ticks_until(2.0)).unwrap();
    world.velocity(0).x
}

/// Hard case 15, the burnout inside a tick. Where the thrust's slope jumps inside a step, that
/// step integrates a kink: RK4's stages are Simpson's rule in time, whose error on a kink of
/// slope jump `J` at the step's middle is `J h^2 / 24`, so the global error is `O(h^2)` instead
/// of `O(h^4)`. Tested against that theory: with the burnout at the middle of a tick at 64,
/// 128, 256 and 512 Hz (steps exact in nanoseconds and in binary), RK4's observed order is
/// 2 +- 0.2; with the burnout on a tick boundary (1 s, the "event" a step can be split at) its
/// error is at least 1000 times smaller at 64 Hz. Adaptive steps find it too: Dopri5 at its
/// tolerance lands within 1e-7 of the speed.
#[test]
fn a_burnout_inside_a_tick_holds_rk4_at_order_two() {
    let exact = tsiolkovsky();
    let hs = [1.0 / 64.0, 1.0 / 128.0, 1.0 / 256.0, 1.0 / 512.0];
    let inside: Vec<f64> = hs
        .iter()
        .map(|&h| (triangle(Integrator::Rk4, h, 1.0 + h / 2.0) - exact).abs())
        .collect();
    let orders: Vec<f64> = inside.windows(2).map(|e| libm::log2(e[0] / e[1])).collect();
    println!("RK4, burnout mid-tick: errors {inside:?} m/s, orders {orders:?}");
    for order in &orders {
        assert!((1.8..=2.2).contains(order), "observed order {order}");
    }
    let aligned = (triangle(Integrator::Rk4, hs[0], 1.0) - exact).abs();
    println!("RK4, burnout on a tick: {aligned:e} m/s");
    assert!(aligned * 1000.0 <= inside[0], "aligned {aligned}");
    let adaptive = (triangle(Integrator::Dopri5, hs[0], 1.0 + hs[0] / 2.0) - exact).abs();
    println!("Dopri5, burnout mid-tick at 64 Hz: {adaptive:e} m/s");
    assert!(adaptive <= 1e-7 * exact, "Dopri5 {adaptive}");
}

/// Velocity Verlet carries the end-of-step force to the next step; a motor's burn changes the
/// mass between steps, so the carried force is evaluated afresh after it. With the burnout on
/// a tick (1 s) Verlet keeps its order 2 (a carried force scaled to the old mass would hold it
/// at 1).
#[test]
fn velocity_verlet_keeps_its_order_through_a_burn() {
    let exact = tsiolkovsky();
    let errs: Vec<f64> = [1.0 / 64.0, 1.0 / 128.0, 1.0 / 256.0]
        .iter()
        .map(|&h| (triangle(Integrator::VelocityVerlet, h, 1.0) - exact).abs())
        .collect();
    let orders: Vec<f64> = errs.windows(2).map(|e| libm::log2(e[0] / e[1])).collect();
    println!("velocity Verlet through the burn: errors {errs:?} m/s, orders {orders:?}");
    for o in orders {
        assert!((o - 2.0).abs() <= 0.2, "order {o}");
    }
}

/// A motor beside gravity and linear drag is not the linear-drag fast path (which knows neither
/// thrust nor a falling mass): the rocket climbs.
#[test]
fn a_motor_with_linear_drag_still_pushes() {
    let curve: Vec<String> = C6.iter().map(|(t, f)| format!("({t:?}, {f:?})")).collect();
    let text = format!(
        "Scene(dt: 0.01, integrator: Rk4, duration: 2.0,
           forces: [Gravity((0, 0, -9.81)), LinearDrag(0.001),
                    Thrust(curve: [{}], propellant: {C6_PROPELLANT:?})],
           bodies: [(mass: 0.06, position: (0, 0, 0))])",
        curve.join(", ")
    );
    let scene = scene::parse(&text, "ld.ron", "ld").unwrap();
    let mut world = World::new(&scene);
    world.step_ticks(150).unwrap();
    assert!(world.velocity(0).z > 50.0, "{}", world.velocity(0));
    assert!(world.bodies().masses()[0] < 0.06);
}
