//! Every built-in force term can be made in code, with no scene-file text: the bundled rifle,
//! baseball and model rocket built with `Scene::builder` and the terms' constructors hold the
//! same terms as their files and step to the same bits.

use glam::DVec3;
use volley_sim::{
    AirModel, DragCurve, DragSize, Ground, Integrator, Interpolation, Launcher, MachDrag, Scene,
    SpinDecay, SpinLift, Thrust, ThrustDirection, Wind, World, bundled_scene, state_hash,
};

/// `built` holds the same force terms as the bundled `name`, and with the file's bodies,
/// ground and launcher steps to its bits.
fn same_as_bundled(name: &str, built: Scene) {
    let file = bundled_scene(name).unwrap();
    assert_eq!(built.forces(), file.forces(), "{name}");
    let built = built
        .edit()
        .bodies(file.bodies().to_vec())
        .launcher(file.launcher())
        .build()
        .unwrap();
    let (mut a, mut b) = (World::new(&built), World::new(&file));
    a.step_ticks(120).unwrap();
    b.step_ticks(120).unwrap();
    assert_eq!(state_hash(&a), state_hash(&b), "{name}");
}

fn base(name: &str, dt: f64) -> volley_sim::SceneBuilder {
    Scene::builder(name, dt)
        .integrator(Integrator::Rk4)
        .gravity(DVec3::new(0.0, 0.0, -9.80665))
        .ground(Ground {
            height: 0.0,
            restitution: 0.0,
        })
}

#[test]
fn the_rifle_in_code_is_the_rifle_file() {
    let drag = MachDrag::new(DragCurve::G7, DragSize::from_bc_lb_in2(0.223))
        .with_wind(Wind::uniform(DVec3::new(0.0, 3.0, 0.0)));
    same_as_bundled(
        "rifle",
        base("rifle", 0.016666667).mach_drag(drag).build().unwrap(),
    );
}

#[test]
fn the_baseball_in_code_is_the_baseball_file() {
    let drag = MachDrag::new(
        DragCurve::from_points(&[(0.0, 0.3008), (1.0, 0.3008)]).unwrap(),
        DragSize::Diameter {
            diameter: 0.07378,
            form_factor: 1.0,
        },
    )
    .with_interpolation(Interpolation::Linear)
    .with_air(AirModel::standard(4.6, None, None))
    .with_spin(SpinLift::nathan(SpinDecay::Nathan(30.0), 0.0292));
    same_as_bundled(
        "baseball",
        base("baseball", 0.016666667)
            .mach_drag(drag)
            .build()
            .unwrap(),
    );
}

#[test]
fn the_model_rocket_in_code_is_the_rocket_file() {
    let drag = MachDrag::new(
        DragCurve::from_points(&[(0.0, 0.6), (1.0, 0.6)]).unwrap(),
        DragSize::Diameter {
            diameter: 0.0248,
            form_factor: 1.0,
        },
    )
    .with_interpolation(Interpolation::Linear);
    let c6 = vec![
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
    let motor = Thrust::new(
        c6,
        0.0108,
        ThrustDirection::Velocity {
            along: DVec3::new(0.08716, 0.0, 0.99619),
            rail_exit_speed: 12.0,
        },
    )
    .unwrap();
    let built = base("model_rocket", 0.016666667)
        .mach_drag(drag)
        .thrust(motor)
        .launcher(Launcher {
            position: DVec3::new(0.0, 0.0, 0.0224),
            speed: 0.0,
            elevation_deg: 85.0,
            azimuth_deg: 0.0,
            mass: 0.0571,
            radius: 0.0124,
            backspin: 0.0,
            sidespin: 0.0,
        })
        .build()
        .unwrap();
    same_as_bundled("model_rocket", built);
}

/// Values a file would refuse are refused in code too, naming the field.
#[test]
fn a_bad_term_in_code_is_refused_naming_the_field() {
    let drag = MachDrag::new(DragCurve::G1, DragSize::from_bc_lb_in2(-1.0));
    let err = Scene::builder("bad", 0.01)
        .mach_drag(drag)
        .build()
        .unwrap_err();
    assert_eq!(err.field.as_deref(), Some("forces[0].bc"), "{err}");
    assert!(Thrust::new(vec![(0.0, 1.0)], 0.0, ThrustDirection::Fixed(DVec3::Z)).is_err());
    assert!(DragCurve::from_points(&[(0.0, 0.3)]).is_err());
}
