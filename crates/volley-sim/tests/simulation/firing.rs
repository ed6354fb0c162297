//! `firing`: launches solved on the stepped trajectory hit in the simulation; the textbook aim
//! misses by what the discrete closed form predicts; moving targets; every bad case answered.
//!
//! Every miss below is the engine's own: the closest-approach event of the shot fired in a
//! `World` with the target in it (swept detection), not the solver's residual.

use glam::DVec3;
use volley_sim::Integrator;
use volley_sim::internals::contact::Target;
use volley_sim::internals::exact::Arc;
use volley_sim::internals::firing::{self, FiringError, Mode, Range, ShotKind};
use volley_sim::internals::integrate::Integrator as I;
use volley_sim::internals::scene::{self, Scene};

/// The promise: the stepped shot passes the target's centre within this (m).
const HIT: f64 = 1e-9;

fn bundled(name: &str) -> Scene {
    scene::bundled(name).unwrap()
}

fn inline(text: &str) -> Scene {
    scene::parse(text, "inline.ron", "inline").unwrap()
}

/// The seed's launch point and target, on `scene`.
fn seed_range(scene: &Scene) -> Range {
    let mut range = Range::new(scene, bundled("seed").targets()[0]);
    range.from = DVec3::new(10.0, 0.0, 2.0);
    range.mass = 2.5;
    range.radius = 0.1;
    range
}

fn with_integrator(scene: &Scene, integrator: Integrator) -> Option<Scene> {
    let mut s = scene.clone();
    s.set_integrator(integrator).ok().map(|_| s)
}

#[test]
fn every_integrator_hits_within_1e_9_m_on_the_seed_the_drag_and_the_wind_scene() {
    fn own_target(s: &Scene) -> Range {
        Range::new(s, s.targets()[0])
    }
    type RangeOf = fn(&Scene) -> Range;
    let cases: [(&str, RangeOf, f64); 3] = [
        ("seed", seed_range, 30.0),
        ("drag", seed_range, 30.0),
        ("wind", own_target, 24.0),
    ];
    let mut checked = 0;
    for (name, range_of, speed) in &cases {
        for integrator in Integrator::ALL {
            let Some(scene) = with_integrator(&bundled(name), integrator) else {
                continue;
            };
            let range = range_of(&scene);
            for mode in [Mode::Speed(*speed), Mode::MinSpeed, Mode::Elevation(50.0)] {
                let shots = firing::solve(&range, mode)
                    .unwrap_or_else(|e| panic!("{name} {integrator:?} {mode:?}: {e}"));
                let want = if matches!(mode, Mode::Speed(_)) { 2 } else { 1 };
                assert_eq!(shots.len(), want, "{name} {integrator:?} {mode:?}");
                for shot in &shots {
                    assert!(
                        shot.miss < HIT,
                        "{name} {integrator:?} {}: misses by {} m",
                        shot.kind.label(),
                        shot.miss
                    );
                    assert!(shot.blocked.is_none(), "{name} {integrator:?} {shot:?}");
                    if let Mode::Speed(v) = mode {
                        // The speed is the root's: bracketed to a few ulps of the arrival time.
                        assert!((shot.speed - v).abs() <= 1e-9 * v, "{}", shot.speed);
                    }
                    if let Mode::Elevation(e) = mode {
                        assert!(
                            (shot.elevation_deg - e).abs() <= 1e-9,
                            "{}",
                            shot.elevation_deg
                        );
                    }
                    checked += 1;
                }
            }
        }
    }
    // seed and drag: every integrator; wind: all but `exact` (no closed form); 4 shots each.
    let all = I::ALL.len();
    assert_eq!(checked, (all + all + all - 1) * 4);
}

#[test]
fn the_high_arc_arrives_later_and_the_minimum_speed_lies_between_the_arcs() {
    let scene = with_integrator(&bundled("drag"), I::Rk4).unwrap();
    let range = seed_range(&scene);
    let arcs = firing::solve(&range, Mode::Speed(30.0)).unwrap();
    assert_eq!(arcs[0].kind, ShotKind::Arc(Arc::High));
    assert_eq!(arcs[1].kind, ShotKind::Arc(Arc::Low));
    assert!(arcs[0].flight_time > arcs[1].flight_time);
    assert!(arcs[0].elevation_deg > arcs[1].elevation_deg);
    let slowest = &firing::solve(&range, Mode::MinSpeed).unwrap()[0];
    assert!(slowest.speed < 30.0);
    assert!(arcs[1].flight_time < slowest.flight_time && slowest.flight_time < arcs[0].flight_time);
    // The arrival tick is the first tick past the arrival time.
    for s in &arcs {
        let h = scene.dt();
        assert!((s.arrival_tick - 1) as f64 * h <= s.flight_time);
        assert!(s.flight_time < s.arrival_tick as f64 * h);
    }
}

#[test]
fn under_the_closed_form_the_solution_is_the_textbook_one() {
    // `exact` steps the closed form, so shooting must land on `exact::aim`'s answer and the
    // textbook must hit too: both within the 1e-9 m promise.
    let scene = with_integrator(&bundled("seed"), I::Exact).unwrap();
    let range = seed_range(&scene);
    let [high, low] =
        volley_sim::internals::exact::aim(range.from, range.target.center, 30.0, 9.81).unwrap();
    let shots = firing::solve(&range, Mode::Speed(30.0)).unwrap();
    for (shot, want) in shots.iter().zip([high, low]) {
        assert!(
            (shot.velocity - want.velocity).length() < 1e-9,
            "{shot:?} vs {want:?}"
        );
        assert!((shot.flight_time - want.flight_time).abs() < 1e-9);
        let tb = shot.textbook.unwrap();
        assert!(tb.miss < HIT, "{tb:?}");
    }
}

#[test]
fn shooting_agrees_with_the_discrete_closed_form_of_both_eulers() {
    for integrator in [I::ExplicitEuler, I::SemiImplicitEuler] {
        for (dt, substeps) in [(0.2, 1), (1.0 / 60.0, 1), (1.0 / 60.0, 3)] {
            let mut scene = with_integrator(&bundled("seed"), integrator).unwrap();
            scene.set_dt(dt).unwrap();
            scene.set_substeps(substeps).unwrap();
            let range = seed_range(&scene);
            for mode in [Mode::Speed(30.0), Mode::MinSpeed, Mode::Elevation(60.0)] {
                let shot = firing::solve(&range, mode).unwrap();
                let closed = firing::solve_discrete(&range, mode).unwrap();
                assert_eq!(shot.len(), closed.len());
                for (a, b) in shot.iter().zip(&closed) {
                    let what = format!("{integrator:?} dt {dt} x{substeps} {mode:?}");
                    // Two routes to the same root: the shooting's Newton residual is below
                    // 1e-12 of the 40 m range, so velocities agree to about 1e-12 relative;
                    // the minimum is flat, so there the arrival time is only good to 1e-6.
                    let tol = if mode == Mode::MinSpeed { 1e-6 } else { 1e-9 };
                    assert!((a.velocity - b.velocity).length() < tol * 30.0, "{what}");
                    assert!((a.flight_time - b.flight_time).abs() < tol * 10.0, "{what}");
                    assert!(b.miss < HIT, "{what}: closed form misses by {}", b.miss);
                }
            }
        }
    }
}

/// Closest approach of the discrete closed form's path at `v0` to `c` near `t_guess`: the
/// prediction of the textbook aim's miss, by golden-section search on the closed form.
fn predicted_miss(integrator: Integrator, range: &Range, v0: DVec3, t_guess: f64) -> f64 {
    let hs = range.scene.dt() / f64::from(range.scene.substeps());
    let a = DVec3::new(0.0, 0.0, -9.81);
    let dist = |t: f64| {
        let p = firing::discrete_position(integrator, (range.from, v0, a), hs, t).unwrap();
        (p - range.target_at(t)).length()
    };
    let (mut lo, mut hi) = (t_guess - 0.5, t_guess + 0.5);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (c, d) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if dist(c) < dist(d) {
            hi = d;
        } else {
            lo = c;
        }
    }
    dist(0.5 * (lo + hi))
}

#[test]
fn the_textbook_aims_miss_under_both_eulers_is_the_discrete_closed_forms_prediction() {
    for integrator in [I::ExplicitEuler, I::SemiImplicitEuler] {
        for dt in [0.2, 1.0 / 60.0] {
            let mut scene = with_integrator(&bundled("seed"), integrator).unwrap();
            scene.set_dt(dt).unwrap();
            let range = seed_range(&scene);
            for shot in firing::solve(&range, Mode::Speed(30.0)).unwrap() {
                let tb = shot.textbook.unwrap();
                let predicted = predicted_miss(integrator, &range, tb.velocity, tb.time);
                // The engine's closest approach and the closed form's are the same minimum of
                // a smooth distance, so they agree to rounding; 1e-9 m is the promise's scale.
                assert!(
                    (tb.miss - predicted).abs() < 1e-9,
                    "{integrator:?} {dt}: engine {} vs closed form {predicted}",
                    tb.miss
                );
                // And it is not small: at its flight time T the Euler path is off the arc by
                // g (h T - tau (h - tau)) / 2 vertically, at least g h (T - h / 4) / 2; the
                // closest approach is that offset across the path, so above a tenth of it.
                let floor = 9.81 * dt * (shot.flight_time - dt / 4.0) / 2.0;
                assert!(
                    tb.miss > 0.1 * floor,
                    "{integrator:?} {dt}: {} vs {floor}",
                    tb.miss
                );
            }
        }
    }
}

#[test]
fn a_moving_target_is_intercepted_with_its_lead() {
    for integrator in [I::SemiImplicitEuler, I::Rk4, I::Exact] {
        let scene = with_integrator(&bundled("drag"), integrator).unwrap();
        let mut range = seed_range(&scene);
        range.target.velocity = DVec3::new(-3.0, 2.0, 0.5);
        let shots = firing::solve(&range, Mode::Speed(30.0)).unwrap();
        assert_eq!(shots.len(), 2);
        for s in &shots {
            assert!(s.miss < HIT, "{integrator:?} {s:?}");
            // Led: aimed off the line to the target's launch-time position.
            assert!(s.azimuth_deg > 0.5, "{integrator:?} {}", s.azimuth_deg);
            // The textbook aims where the target was, so it misses by about the target's
            // travel: over a metre in these flights.
            assert!(s.textbook.unwrap().miss > 1.0, "{integrator:?} {s:?}");
        }
        if integrator == I::Exact {
            // Independently: the closed-form position at arrival is the target's there.
            let lin = DVec3::new(0.0, 0.0, -9.81);
            for s in &shots {
                let (p, _) = volley_sim::internals::exact::linear_drag_flow(
                    range.from,
                    s.velocity,
                    lin,
                    0.1,
                    s.flight_time,
                );
                assert!((p - range.target_at(s.flight_time)).length() < HIT);
            }
        }
    }
}

#[test]
fn a_moving_target_scene_field_moves_the_target_in_the_world() {
    let scene = inline(
        "Scene(dt: 0.1, integrator: Exact, forces: [],
               targets: [(center: (10, 0, 0), radius: 0.5, velocity: (-1, 0, 0))],
               bodies: [(mass: 1, radius: 0, position: (0, 0, 0), launch: Velocity((1, 0, 0)))])",
    );
    // They meet at t = 5 s at x = 5: the body's centre enters the 0.5 m sphere at 4.75 s.
    let mut world = volley_sim::World::new(&scene);
    let mut hit = None;
    for _ in 0..60 {
        world.step().unwrap();
        for e in world.events() {
            if let volley_sim::EventKind::Hit { .. } = e.kind {
                hit.get_or_insert(e.time);
            }
        }
    }
    let t = hit.expect("the moving target is hit");
    assert!((t - 4.75).abs() < 1e-9, "{t}");
}

#[test]
fn out_of_reach_gives_the_speed_it_needs_and_the_closest_miss() {
    let scene = with_integrator(&bundled("seed"), I::Exact).unwrap();
    let range = seed_range(&scene);
    let Err(FiringError::OutOfReach {
        min_speed,
        best_miss,
        ..
    }) = firing::solve(&range, Mode::Speed(15.0))
    else {
        panic!("15 m/s should not reach");
    };
    // The closed form's slowest launch: v^2 = g (dz + r).
    let d = range.target.center - range.from;
    let want = (9.81 * (d.z + d.length())).sqrt();
    let got = min_speed.unwrap();
    // A minimum found by golden-section search: |v(T)| is flat there, so its value is good
    // to about the square of the 1e-13 relative bracket in T, far inside 1e-9.
    assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    assert!(best_miss > 0.0 && best_miss < d.length(), "{best_miss}");
}

#[test]
fn drag_that_caps_the_range_is_answered_with_the_best_miss() {
    // Quadratic drag: the 200 m target is out of reach at 40 m/s. No elevation of a 5 degree
    // grid does better than the miss reported.
    let scene = inline(
        "Scene(dt: 0.016666666666666666, integrator: Rk4,
               forces: [Gravity((0, 0, -9.81)), QuadraticDrag(0.05)],
               launcher: (position: (0, 0, 1), speed: 40, elevation_deg: 30, azimuth_deg: 0,
                          mass: 0.5))",
    );
    let mut range = Range::new(
        &scene,
        Target {
            center: DVec3::new(200.0, 0.0, 1.0),
            radius: 0.5,
            velocity: DVec3::ZERO,
        },
    );
    range.max_flight_time = 30.0;
    let err = firing::solve(&range, Mode::Speed(40.0)).unwrap_err();
    let FiringError::OutOfReach {
        best_miss,
        best_elevation_deg,
        ..
    } = err
    else {
        panic!("{err}");
    };
    assert!(best_miss > 50.0, "{best_miss}");
    assert!(best_elevation_deg > 0.0 && best_elevation_deg < 60.0);
    assert!(err.to_string().contains("out of reach at 40 m/s"), "{err}");
}

#[test]
fn a_target_behind_a_wall_is_blocked_naming_the_wall_and_the_tick() {
    // Walls are infinite slabs, so every arc from in front of one to behind it is blocked.
    let scene = inline(
        "Scene(dt: 0.016666666666666666, integrator: SemiImplicitEuler,
               forces: [Gravity((0, 0, -9.81))], ground: (height: 0, restitution: 0.5),
               walls: [(point: (30, 0, 0), normal: (1, 0, 0), thickness: 0.5, restitution: 0.5)],
               launcher: (position: (10, 0, 2), speed: 30, elevation_deg: 45, azimuth_deg: 0,
                          mass: 2.5))",
    );
    let range = Range::new(&scene, bundled("seed").targets()[0]);
    let err = firing::solve(&range, Mode::Speed(30.0)).unwrap_err();
    let FiringError::Blocked(ref shots) = err else {
        panic!("{err}");
    };
    assert_eq!(shots.len(), 2);
    for (_, b) in shots {
        assert_eq!(b.surface, volley_sim::internals::contact::Surface::Wall(0));
        // The wall's near face is at x = 29.75 - 0.1 (the shot's radius): 19.65 m from the
        // launch, so the impact comes before the arrival and after the start.
        assert!(b.time > 0.0 && b.tick >= 1, "{b:?}");
    }
    assert!(err.to_string().contains("hits wall 0 at"), "{err}");
    // With contacts off the same shots fly through.
    let mut range = range;
    range.contacts = false;
    assert_eq!(firing::solve(&range, Mode::Speed(30.0)).unwrap().len(), 2);
}

/// A steel plate mesh (restitution 0, so every contact is a rest) and a heightfield ridge (a
/// bounce) between the launcher and the target: each blocks every arc, named by its surface
/// and triangle or cell; with contacts off the same shots fly through.
#[test]
fn a_target_behind_a_plate_or_a_ridge_is_blocked_naming_the_level_surface() {
    use volley_sim::internals::contact::{HeightGrid, MeshGeometry, Surface, Transform};
    let base = inline(
        "Scene(dt: 0.016666666666666666, integrator: Rk4, forces: [Gravity((0, 0, -9.81))],
               launcher: (position: (10, 0, 2), speed: 30, elevation_deg: 45, azimuth_deg: 0,
                          mass: 2.5))",
    );
    // A sheet 60 m wide and 60 m tall at x = 30, between the launcher at x = 10 and the seed's
    // target at (50, 0, 20): the high arc peaks near 45 m, so both arcs meet it.
    let v = vec![
        DVec3::new(0.0, -30.0, 0.0),
        DVec3::new(0.0, 30.0, 0.0),
        DVec3::new(0.0, 30.0, 60.0),
        DVec3::new(0.0, -30.0, 60.0),
    ];
    let plate = MeshGeometry::new(v, vec![[0, 1, 2], [0, 2, 3]]);
    let walled = base
        .edit()
        .mesh(
            "plate",
            plate,
            Transform::at(DVec3::new(30.0, 0.0, 0.0)),
            0.0,
        )
        .build()
        .unwrap();
    let range = Range::new(&walled, bundled("seed").targets()[0]);
    let err = firing::solve(&range, Mode::Speed(30.0)).unwrap_err();
    let FiringError::Blocked(ref shots) = err else {
        panic!("{err}");
    };
    assert_eq!(shots.len(), 2);
    for (_, b) in shots {
        assert!(
            matches!(b.surface, Surface::Mesh { surface: 0, .. }),
            "{b:?}"
        );
        assert!(b.time > 0.0 && b.tick >= 1, "{b:?}");
    }
    assert!(err.to_string().contains("hits mesh 0 triangle "), "{err}");
    let mut off = range;
    off.contacts = false;
    assert_eq!(firing::solve(&off, Mode::Speed(30.0)).unwrap().len(), 2);
    // A ridge 60 m high along y at x = 30 (3 samples 10 m apart in x, the middle one high):
    // restitution 0.5, so the contact is an impact.
    let ridge = HeightGrid {
        columns: 3,
        rows: 2,
        heights: vec![0.0, 60.0, 0.0, 0.0, 60.0, 0.0],
    };
    let ridged = base
        .edit()
        .heightfield(
            "ridge",
            ridge,
            10.0,
            Transform {
                position: DVec3::new(20.0, -50.0, 0.0),
                rotation_deg: DVec3::ZERO,
                scale: DVec3::new(1.0, 10.0, 1.0),
            },
            0.5,
        )
        .build()
        .unwrap();
    let range = Range::new(&ridged, bundled("seed").targets()[0]);
    let err = firing::solve(&range, Mode::Speed(30.0)).unwrap_err();
    let FiringError::Blocked(ref shots) = err else {
        panic!("{err}");
    };
    for (_, b) in shots {
        assert!(
            matches!(b.surface, Surface::Heightfield { surface: 0, .. }),
            "{b:?}"
        );
    }
    assert!(
        err.to_string().contains("hits heightfield 0 cell "),
        "{err}"
    );
}

#[test]
fn a_target_below_the_ground_is_refused() {
    let scene = bundled("seed");
    let mut range = seed_range(&scene);
    range.target.center.z = -1.0;
    let err = firing::solve(&range, Mode::Speed(30.0)).unwrap_err();
    assert!(matches!(err, FiringError::BelowGround { .. }), "{err}");
    assert!(err.to_string().contains("below the ground"));
}

#[test]
fn vertical_shots() {
    let scene = with_integrator(&bundled("seed"), I::SemiImplicitEuler).unwrap();
    let mut range = seed_range(&scene);
    range.target.center = range.from + DVec3::new(0.0, 0.0, 20.0);
    // Speed given: both passes, straight up.
    let shots = firing::solve(&range, Mode::Speed(30.0)).unwrap();
    assert_eq!(shots.len(), 2);
    for s in &shots {
        assert_eq!((s.elevation_deg, s.azimuth_deg), (90.0, 0.0), "{s:?}");
        assert!(s.miss < HIT, "{s:?}");
    }
    // Elevation given for a target straight above: any speed works, so say so.
    let err = firing::solve(&range, Mode::Elevation(90.0)).unwrap_err();
    assert!(
        matches!(err, FiringError::VerticalNeedsSpeed { .. }),
        "{err}"
    );
    // Straight up at a target off to the side: no arc.
    let range = seed_range(&scene);
    let err = firing::solve(&range, Mode::Elevation(90.0)).unwrap_err();
    assert!(matches!(err, FiringError::NoArcAtElevation { .. }), "{err}");
    // Below the line of sight: no arc either.
    let err = firing::solve(&range, Mode::Elevation(10.0)).unwrap_err();
    assert!(err.to_string().contains("line of sight"), "{err}");
}

#[test]
fn an_unstable_step_is_an_error_naming_the_step_not_a_hang() {
    // Explicit Euler on a stiff spring at 60 Hz grows without bound: every arrival past a few
    // ticks is a non-finite or far-off shot. The answer must be an error, quickly.
    let mut scene = bundled("hard/stiff_spring");
    scene.set_integrator(I::ExplicitEuler).unwrap();
    let mut range = Range::new(
        &scene,
        Target {
            center: DVec3::new(0.0, 0.0, 5.0),
            radius: 0.1,
            velocity: DVec3::ZERO,
        },
    );
    range.from = DVec3::new(1.0, 0.0, 0.0);
    let err = firing::solve(&range, Mode::Speed(3.0)).unwrap_err();
    assert!(
        matches!(err, FiringError::Diverged { tick: Some(_), .. }),
        "{err}"
    );
    assert!(err.to_string().contains("diverges at tick"), "{err}");
}

#[test]
fn newton_that_does_not_converge_is_an_error_naming_the_arrival_and_its_tick() {
    // Quadratic drag is not affine in the launch velocity: one Newton iteration cannot land
    // within 1e-12 of the range, so with the budget cut to one every arrival time stalls.
    let scene = bundled("wind");
    let mut range = Range::new(&scene, scene.targets()[0]);
    range.newton_iterations = 1;
    let err = firing::solve(&range, Mode::Speed(24.0)).unwrap_err();
    let FiringError::Stalled {
        tick,
        iterations,
        residual,
        ..
    } = err
    else {
        panic!("{err}");
    };
    assert_eq!(iterations, 1);
    assert!(tick >= 1 && residual > 0.0, "{err}");
    assert!(
        err.to_string().contains("stalled solving for arrival at"),
        "{err}"
    );
}

#[test]
fn every_bundled_scene_is_aimed_with_its_own_integrator_and_step() {
    // A target 20 m out, 5 m across and 3 m up from each scene's launcher, the slowest shot
    // (always defined: no speed to be too slow), solved for the scene's own integrator, dt and
    // substeps, contacts on.
    let mut solved = 0;
    for (name, _) in scene::BUNDLED {
        let scene = bundled(name);
        let l = scene.launcher();
        let target = Target {
            center: l.position + DVec3::new(20.0, 5.0, 3.0),
            radius: 0.5,
            velocity: DVec3::ZERO,
        };
        let range = Range::new(&scene, target);
        let result = firing::solve(&range, Mode::MinSpeed);
        match *name {
            // A wall stands between the launcher and every point beyond x = 5 m or so.
            // So do the level meshes of two hard cases: the grazing shots' launcher (their first
            // bullet) is 0.3 m from the plate's face, and the tick-boundary wall spans the
            // launcher's line of fire.
            "bounce" | "hard/tunnelling" | "hard/grazing" | "hard/tick_boundary" => {
                assert!(
                    matches!(result, Err(FiringError::Blocked(_))),
                    "{name}: {result:?}"
                );
            }
            // A motor's flight is steered, not aimed: refused in one line.
            "model_rocket" => {
                assert!(
                    matches!(&result, Err(FiringError::Invalid(e)) if e.contains("Thrust")),
                    "{name}: {result:?}"
                );
            }
            // Explicit Euler on k/m = 1e4 and 1e5 at 60 Hz is unstable: the world's guard
            // stops the shot, and the answer says at which tick.
            "hard/stiff_spring" | "hard/stiff_spring_1e5" => {
                assert!(
                    matches!(result, Err(FiringError::Diverged { tick: Some(_), .. })),
                    "{name}: {result:?}"
                );
            }
            _ => {
                let shot = result.unwrap_or_else(|e| panic!("{name}: {e}"))[0];
                // 1e-9 m, or the rounding floor of positions this far out over this many steps
                // where that is larger (10 km out over a 120 s flight: a few nm).
                let steps = (shot.flight_time / scene.dt()).ceil() * f64::from(scene.substeps());
                let size = target.center.abs().max_element();
                let bound = HIT.max(firing::rounding_floor(steps + 1.0, size));
                assert!(shot.miss < bound, "{name}: {} vs {bound}", shot.miss);
                solved += 1;
            }
        }
    }
    assert_eq!(solved, scene::BUNDLED.len() - 7);
}

/// The bundled rifle zeroed at 100 m with a 1.5 in (38.1 mm) sight: the holdover table from
/// 100 m to 1000 m under its own integrator and tick (RK4 at 60 Hz). Each row's shot hits the
/// line of sight in a world (the solve's own check); the zero's row holds nothing; the hold
/// grows with the range; and the textbook (vacuum) aim, which ignores the drag, misses by more
/// at every range, by metres at 1000 m.
#[test]
fn the_rifle_zeroed_at_100_m_has_a_holdover_table_to_1000_m() {
    let scene = bundled("rifle");
    // Every 300 m here (docs/aiming/holdover-rifle.txt has every 100 m, from the CLI).
    let ranges = [100.0, 400.0, 700.0, 1000.0];
    let table = firing::holdover(&scene, 0.0381, 100.0, &ranges).unwrap();
    assert_eq!(table.zero.0, 100.0);
    assert_eq!(table.rows[0].hold_mrad, 0.0, "the zero holds nothing");
    let mut last = (f64::NEG_INFINITY, 0.0);
    for row in &table.rows {
        assert!(
            row.shot.miss < HIT,
            "{} m: miss {}",
            row.range,
            row.shot.miss
        );
        let textbook = row
            .shot
            .textbook
            .expect("gravity gives a textbook aim")
            .miss;
        println!(
            "{:>5} m  elevation {:.4} deg  hold {:+.3} mrad {:+.2} MOA {:+.3} m  \
             {:.3} s  textbook misses by {textbook:.3} m",
            row.range,
            row.shot.elevation_deg,
            row.hold_mrad,
            row.hold_moa,
            row.hold_at_target,
            row.shot.flight_time
        );
        assert!(row.hold_mrad >= last.0, "the hold grows with the range");
        assert!(
            textbook > last.1,
            "the textbook's miss grows with the range"
        );
        last = (row.hold_mrad, textbook);
    }
    assert!(last.1 > 1.0, "the textbook misses 1000 m by {} m", last.1);
    // The angles in the units a scope is marked in, from one number.
    let r = &table.rows[3];
    assert!((r.hold_moa - r.hold_mrad * 3.437_746_770_784_939).abs() < 1e-12 * r.hold_moa);
}

#[test]
fn a_holdover_table_refuses_bad_ranges_in_one_line() {
    let scene = bundled("rifle");
    for (zero, ranges) in [
        (0.0, vec![100.0]),
        (100.0, vec![-5.0]),
        (f64::NAN, vec![1.0]),
    ] {
        let e = firing::holdover(&scene, 0.04, zero, &ranges)
            .unwrap_err()
            .to_string();
        assert!(
            !e.contains('\n') && (e.contains("zero") || e.contains("range")),
            "{e}"
        );
    }
}
