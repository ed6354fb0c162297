//! A batted ball under Alan Nathan's model (spin-dependent drag, Magnus lift from the spin
//! parameter, the spin decaying), against his own calculator's output: the spreadsheet
//! TrajectoryCalculator-new-3D.xlsx (baseball.physics.illinois.edu), as stored with every value
//! a full double in ProjectMOSAIC/mosaicCalc (commit a50ff033,
//! `inst/data_raw/Fly_ball/TrajectoryCalculator-new-3D.rds`; copied into
//! `tests/data/nathan_fly_ball.csv` by `scripts/extract-fly-ball`). The hit: 103 mph at 27.5
//! degrees, 2500 rpm of pure backspin, from (0, 2, 3) ft, in air at 70 F (its documented
//! 50 % humidity, 29.92 inHg and 15 ft of elevation give the sheet's drag constant
//! `c0 = 0.005367953626861678` per ft, printed in every row).
//!
//! The sheet's model, as its columns show: `a = -c0 Cd |v| v + c0 C_L |v| (w_hat x v) + g`,
//! `Cd = 0.3008 + 0.0292 (rpm / 1000) d`, `C_L = 1.120 S / (0.583 + 2.333 S)`,
//! `S = r omega d / |v|`, `d = exp(-t |v| / (30 s * 146.7 ft/s))`, `g = 32.174 ft/s^2`. In a
//! scene: a `MachDrag` with a constant curve 0.3008, the ball's diameter, the spin
//! `(lift: Nathan, decay: Nathan(30), drag_per_1000_rpm: 0.0292)`, and uniform air at the
//! density that makes `rho pi d^2 / (8 m)` the sheet's `c0` (computed below from it).
//!
//! Its step, `p += v dt + a dt^2 / 2`, `v += a dt` with `a` at the step's start and
//! `dt = 0.01 s`, is not one of Volley's integrators, but it is one from two of them: with a
//! force that reads no position (uniform air, no wind), explicit and semi-implicit Euler step
//! the same velocities, `v += a dt`, and the sheet's position is the mean of theirs
//! (`p + v dt` and `p + (v + a dt) dt`). So Volley reproduces every row of the sheet.

use glam::DVec3;
use volley_sim::internals::forces::{ForceModel, RAD_S_PER_RPM};
use volley_sim::internals::integrate::{Integrator, Launch, Mass};
use volley_sim::internals::scene;
use volley_sim::internals::world::World;

const FT: f64 = 0.3048;
const OZ: f64 = 0.028_349_523_125;
const INCH: f64 = 0.0254;

/// The sheet's drag constant (1/ft), printed in every row of its output.
const C0: f64 = 0.005_367_953_626_861_678;

/// One row of the sheet: time (s), position (ft), velocity (ft/s), Cd, S, C_L, acceleration
/// (ft/s^2).
struct Row {
    t: f64,
    p: DVec3,
    v: DVec3,
    cd: f64,
    s: f64,
    cl: f64,
    a: DVec3,
}

fn rows() -> Vec<Row> {
    include_str!("../data/nathan_fly_ball.csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let x: Vec<f64> = l.split(',').map(|f| f.parse().unwrap()).collect();
            Row {
                t: x[0],
                p: DVec3::new(x[1], x[2], x[3]),
                v: DVec3::new(x[4], x[5], x[6]),
                cd: x[7],
                s: x[8],
                cl: x[9],
                a: DVec3::new(x[10], x[11], x[12]),
            }
        })
        .collect()
}

/// The ball: 5.125 oz, 9.125 in around.
fn mass() -> f64 {
    5.125 * OZ
}
fn diameter() -> f64 {
    9.125 * INCH / std::f64::consts::PI
}

/// The spin (rad/s): 2500 rpm of backspin on a ball hit along +y, about +x.
fn spin() -> DVec3 {
    DVec3::new(2500.0 * RAD_S_PER_RPM, 0.0, 0.0)
}

fn fly_ball(integrator: Integrator) -> scene::Scene {
    let (m, d) = (mass(), diameter());
    // rho pi d^2 / (8 m) = c0 per metre; at 70 F (294.261 K) that density is this pressure.
    let temperature = (70.0 - 32.0) / 1.8 + 273.15;
    let density = (C0 / FT) * 8.0 * m / (std::f64::consts::PI * d * d);
    let pressure = density * volley_sim::internals::atmosphere::R_AIR * temperature;
    let first = &rows()[0];
    let text = format!(
        "Scene(dt: 0.01, integrator: {integrator:?}, duration: 6.0,
           forces: [
             Gravity((0, 0, {g:?})),
             MachDrag(curve: Table([(0.0, 0.3008), (1.0, 0.3008)]), interpolation: Linear,
                      diameter: {d:?},
                      air: Uniform(temperature: {temperature:?}, pressure: {pressure:?}),
                      spin: (lift: Nathan, decay: Nathan(30.0), drag_per_1000_rpm: 0.0292)),
           ],
           bodies: [(mass: {m:?}, radius: {r:?}, position: ({px:?}, {py:?}, {pz:?}),
                     launch: Velocity(({vx:?}, {vy:?}, {vz:?})),
                     spin: ({wx:?}, 0.0, 0.0))])",
        g = -32.174 * FT,
        r = d / 2.0,
        px = first.p.x * FT,
        py = first.p.y * FT,
        pz = first.p.z * FT,
        vx = first.v.x * FT,
        vy = first.v.y * FT,
        vz = first.v.z * FT,
        wx = spin().x,
    );
    scene::parse(&text, "fly_ball.ron", "fly ball").expect("the fly ball scene parses")
}

/// Relative agreement every row must reach: the same formula in metres instead of feet, a few
/// dozen roundings of 1.1e-16 each (the exponential and square root in libm to 1 ulp).
const MODEL_REL: f64 = 1e-12;

#[test]
fn the_ball_feels_the_force_nathans_calculator_prints_in_every_row() {
    let scene = fly_ball(Integrator::ExplicitEuler);
    let forces = scene.forces();
    let w = Mass::launched(
        mass(),
        Launch {
            time: 0.0,
            mass: mass(),
            spin: spin(),
        },
    );
    let drag = forces.mach_drag.as_ref().unwrap();
    let rows = rows();
    assert_eq!(rows.len(), 553, "every row above the ground and one below");
    for row in &rows {
        let a = forces.force_at(row.t, row.p * FT, row.v * FT, w) / (mass() * FT);
        let err = (a - row.a).length();
        assert!(
            err <= MODEL_REL * row.a.length(),
            "t = {}: Volley {a} ft/s^2, the sheet {} ({err:e})",
            row.t,
            row.a
        );
        // The spin parameter the lift was computed from, through the term's own decay.
        let omega = drag
            .spin_at(row.t, row.p * FT, row.v * FT, w.launch)
            .length();
        let s = 0.5 * diameter() * omega / (row.v.length() * FT);
        assert!(
            (s - row.s).abs() <= MODEL_REL * row.s,
            "t = {}: S {s}",
            row.t
        );
        let cl = volley_sim::internals::forces::LiftModel::Nathan.coefficient(s);
        assert!(
            (cl - row.cl).abs() <= MODEL_REL * row.cl,
            "t = {}: C_L {cl}",
            row.t
        );
        assert!(
            row.cd > 0.3008 && row.cd <= 0.3738,
            "the sheet's Cd includes the spin's"
        );
    }
}

/// Positions agree to this (ft) over the 5.5 s: 552 steps, each rounding the 420 ft position
/// and its units' conversion to about 2 ulps (1e-13 ft), with margin for the velocities'
/// rounding carried into them.
const PATH_FT: f64 = 1e-9;

/// The whole flight, step by step: every row's position and velocity, and the carry the sheet's
/// rows give, 421.486 ft where the path crosses the ground between its last two rows.
#[test]
fn volley_flies_the_ball_row_by_row_as_nathans_calculator_does() {
    let rows = rows();
    let mut explicit = World::new(&fly_ball(Integrator::ExplicitEuler));
    let mut semi = World::new(&fly_ball(Integrator::SemiImplicitEuler));
    let mut path = Vec::new();
    for row in &rows {
        let pe = explicit.bodies().positions().get(0) / FT;
        let ps = semi.bodies().positions().get(0) / FT;
        let (ve, vs) = (explicit.velocity(0) / FT, semi.velocity(0) / FT);
        assert!(
            (ve - vs).length() <= PATH_FT,
            "the two Eulers' velocities part"
        );
        let p = 0.5 * (pe + ps);
        assert!(
            (p - row.p).length() <= PATH_FT && (ve - row.v).length() <= PATH_FT,
            "t = {}: Volley p {p} v {ve}, the sheet p {} v {}",
            row.t,
            row.p,
            row.v
        );
        path.push(p);
        explicit.step().unwrap();
        semi.step().unwrap();
    }
    let (a, b) = (path[path.len() - 2], path[path.len() - 1]);
    let carry = a.y + (b.y - a.y) * (a.z / (a.z - b.z));
    assert!((carry - 421.486).abs() < 5e-4, "carry {carry} ft");
}

/// The sheet's own step, against the same model converged (RK4 at 1 ms; halving it moves the
/// carry by less than 1e-6 ft): what 10 ms of its Euler step costs. Printed, and checked only
/// to be the size a first-order step of 0.01 s gives (tenths of a foot, not feet or
/// thousandths); docs/physics.md quotes it.
#[test]
fn the_sheets_ten_millisecond_step_costs_tenths_of_a_foot_of_carry() {
    let mut scene = fly_ball(Integrator::Rk4);
    scene.set_dt(0.001).unwrap();
    let mut world = World::new(&scene);
    let mut prev = world.bodies().positions().get(0);
    let carry = loop {
        world.step().unwrap();
        let p = world.bodies().positions().get(0);
        if p.z < 0.0 {
            break (prev.y + (p.y - prev.y) * (prev.z / (prev.z - p.z))) / FT;
        }
        prev = p;
    };
    let sheet = 421.486;
    println!("converged carry {carry:.3} ft, the sheet's {sheet} ft");
    assert!((0.01..3.0).contains(&(carry - sheet).abs()), "{carry}");
}

/// A curve ball: 75 mph (33.528 m/s) from 1.8 m up, 1 degree down, with 1800 rpm of spin whose
/// axis tilts from topspin towards sidespin, in Nathan's model; stepped at `hz` for 0.5 s (the
/// flight to the plate), its position then.
fn curve_ball(integrator: Integrator, hz: u32) -> DVec3 {
    let (m, d) = (mass(), diameter());
    let w = 1800.0 * RAD_S_PER_RPM;
    let (top, side) = (w * 0.5, w * 0.75f64.sqrt());
    let text = format!(
        "Scene(dt: {dt:?}, integrator: {integrator:?}, duration: 1.0, tolerance: 1e-12,
           forces: [
             Gravity((0, 0, -9.80665)),
             MachDrag(curve: Table([(0.0, 0.3008), (1.0, 0.3008)]), interpolation: Linear,
                      diameter: {d:?}, air: Uniform(temperature: 294.26, pressure: 101325.0),
                      spin: (lift: Nathan, decay: Nathan(30.0), drag_per_1000_rpm: 0.0292)),
           ],
           bodies: [(mass: {m:?}, radius: {r:?}, position: (0, 0, 1.8),
                     launch: Angles(speed: 33.528, elevation_deg: -1.0),
                     spin: (0.0, {top:?}, {side:?}))])",
        dt = 1.0 / f64::from(hz),
        r = d / 2.0,
    );
    let scene = scene::parse(&text, "curve.ron", "curve ball").unwrap();
    let mut world = World::new(&scene);
    world.step_ticks(u64::from(hz) / 2).unwrap();
    assert_eq!(world.time(), 0.5, "steps that land on the plate's time");
    world.bodies().positions().get(0)
}

/// Hard case 16 (docs/physics.md): the break of a curve ball keeps every integrator's order,
/// since nothing in Nathan's model is kinked. Against Dormand-Prince at a 1e-12 tolerance:
/// explicit Euler 1 +- 0.2 (64 to 256 Hz), midpoint 2 +- 0.2 (32 to 128 Hz), RK4 4 +- 0.3
/// (16 to 64 Hz), where each is above the reference's error.
#[test]
fn a_curve_balls_break_keeps_each_integrators_order() {
    let reference = curve_ball(Integrator::Dopri5, 64);
    println!("break at the plate: {:.3} m sideways", reference.y);
    assert!(reference.y.abs() > 0.1, "it breaks");
    for (integrator, rates, order, slack) in [
        (Integrator::ExplicitEuler, [64, 128, 256], 1.0, 0.2),
        (Integrator::Midpoint, [32, 64, 128], 2.0, 0.2),
        (Integrator::Rk4, [16, 32, 64], 4.0, 0.3),
    ] {
        let errs: Vec<f64> = rates
            .iter()
            .map(|&hz| (curve_ball(integrator, hz) - reference).length())
            .collect();
        let orders: Vec<f64> = errs.windows(2).map(|e| libm::log2(e[0] / e[1])).collect();
        println!("{integrator:?}: errors {errs:?} m at {rates:?} Hz, orders {orders:?}");
        for o in orders {
            assert!((o - order).abs() <= slack, "{integrator:?}: order {o}");
        }
    }
}
