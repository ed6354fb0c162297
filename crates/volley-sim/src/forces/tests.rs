use super::*;

#[test]
fn constant_field_matches_general_model_bit_for_bit() {
    let forces = Forces {
        gravity: Some(DVec3::new(0.0, 0.0, -9.81)),
        constant: Some(DVec3::new(1.5, 0.0, 0.0)),
        ..Forces::default()
    };
    let field = forces
        .constant_field()
        .expect("only constant terms are declared");
    let (p, v, m) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-4.0, 5.0, 6.0), 2.5);
    assert_eq!(field.force(p, v, m), forces.force(p, v, m));
    assert_eq!(field.energy(p, v, m), forces.energy(p, v, m));
}

#[test]
fn drag_field_matches_general_model_bit_for_bit() {
    let plain = Forces {
        gravity: Some(DVec3::new(0.0, -0.0, -9.81)),
        linear_drag: Some(0.3),
        ..Forces::default()
    };
    let with_constant = Forces {
        constant: Some(DVec3::new(-0.0, 2.0, 0.5)),
        ..plain.clone()
    };
    let a = DragField::<false>::of(&plain).expect("gravity and drag only");
    let b = DragField::<true>::of(&with_constant).expect("gravity, drag, constant force");
    assert!(DragField::<true>::of(&plain).is_none());
    assert!(
        DragField::<false>::of(&Forces {
            linear_drag: None,
            ..plain.clone()
        })
        .is_none()
    );
    let (p, m) = (DVec3::new(1.0, 2.0, 3.0), 2.5);
    for v in [
        DVec3::new(-4.0, 0.0, 6.0),
        DVec3::new(0.0, -0.0, 1e-300),
        DVec3::ZERO,
    ] {
        let bits = |f: DVec3| f.to_array().map(f64::to_bits);
        assert_eq!(bits(a.force(p, v, m)), bits(plain.force(p, v, m)));
        assert_eq!(bits(b.force(p, v, m)), bits(with_constant.force(p, v, m)));
    }
    assert_eq!(a.linear_part(m), plain.linear_part(m));
    assert_eq!(b.linear_part(m), with_constant.linear_part(m));
}

#[test]
fn drag_disqualifies_the_constant_field() {
    let forces = Forces {
        gravity: Some(DVec3::NEG_Z),
        linear_drag: Some(0.1),
        ..Forces::default()
    };
    assert!(forces.constant_field().is_none());
    assert!(forces.velocity_dependent());
}

#[test]
fn closed_form_is_refused_by_the_first_term_without_one() {
    let spring = |rest_length| Spring {
        anchor: DVec3::ZERO,
        stiffness: 1.0,
        rest_length,
        damping: 0.5,
    };
    let pm = PointMass {
        center: DVec3::ZERO,
        mu: 1.0,
    };
    let linear = Forces {
        gravity: Some(DVec3::NEG_Z),
        constant: Some(DVec3::X),
        linear_drag: Some(0.1),
        spring: Some(spring(0.0)),
        ..Forces::default()
    };
    assert_eq!(linear.without_closed_form(), None);
    let rest = Forces {
        spring: Some(spring(1.0)),
        ..linear
    };
    assert_eq!(rest.without_closed_form(), Some(ForceKind::Spring));
    let air = Forces {
        quadratic_drag: Some(0.01),
        ..rest
    };
    assert_eq!(air.without_closed_form(), Some(ForceKind::QuadraticDrag));
    let kepler = Forces {
        point_mass: Some(pm),
        ..Forces::default()
    };
    assert_eq!(kepler.without_closed_form(), None);
    assert_eq!(kepler.lone_point_mass(), Some(pm));
    let perturbed = Forces {
        gravity: Some(DVec3::NEG_Z),
        ..kepler
    };
    assert_eq!(perturbed.without_closed_form(), Some(ForceKind::PointMass));
    assert_eq!(perturbed.lone_point_mass(), None);
}

#[test]
fn linear_spring_is_split_into_the_implicit_part() {
    let forces = Forces {
        spring: Some(Spring {
            anchor: DVec3::X,
            stiffness: 8.0,
            rest_length: 0.0,
            damping: 2.0,
        }),
        linear_drag: Some(1.0),
        ..Forces::default()
    };
    let part = forces.linear_part(2.0);
    assert_eq!((part.kd, part.w2, part.anchor), (1.5, 4.0, DVec3::X));
    assert_eq!(
        forces.nonlinear_force(DVec3::ONE, DVec3::ONE, 2.0),
        DVec3::ZERO
    );
}
