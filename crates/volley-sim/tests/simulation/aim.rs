//! `aim`: both launch solutions, checked by flying them with the closed form.

use glam::DVec3;
use proptest::prelude::*;
use volley_sim::internals::exact::{AimError, LaunchSolution, aim, constant_accel};

const G: f64 = 9.81;

/// Where a launch from `from` is after its flight time, by the closed form.
fn landing(from: DVec3, s: &LaunchSolution, g: f64) -> DVec3 {
    constant_accel(from, s.velocity, DVec3::new(0.0, 0.0, -g), s.flight_time).0
}

#[test]
fn the_seeds_case_has_the_slow_high_arc_and_a_low_arc() {
    let (from, to) = (DVec3::new(10.0, 0.0, 2.0), DVec3::new(50.0, 0.0, 20.0));
    let [high, low] = aim(from, to, 30.0, G).unwrap();
    // docs/physics.md, "The seed's worked example": high 75.1652 deg (flight 5.2077 s), low 39.0625 deg (flight 1.7172 s),
    // printed to 4 decimals: each within half a unit of the last digit.
    for (got, want) in [
        (high.elevation_deg, 75.1652),
        (high.flight_time, 5.2077),
        (low.elevation_deg, 39.0625),
        (low.flight_time, 1.7172),
    ] {
        assert!((got - want).abs() <= 0.5e-4, "{got} vs {want}");
    }
    assert_eq!(format!("{:.2}", high.elevation_deg), "75.17");
    assert_eq!(format!("{:.2}", low.elevation_deg), "39.06");
    assert_eq!((high.azimuth_deg, low.azimuth_deg), (0.0, 0.0));
    for s in [high, low] {
        assert!((s.velocity.length() - 30.0).abs() < 1e-12);
        assert!((landing(from, &s, G) - to).length() < 1e-9);
    }
}

#[test]
fn an_unreachable_target_says_how_fast_it_would_need_to_be() {
    let (from, to) = (DVec3::ZERO, DVec3::new(200.0, 0.0, 0.0));
    // On level ground the range is v^2 / g, so 200 m needs sqrt(200 g) = 44.29 m/s.
    match aim(from, to, 30.0, G) {
        Err(AimError::OutOfReach { min_speed }) => {
            assert!((min_speed - (200.0 * G).sqrt()).abs() < 1e-9, "{min_speed}");
            let [a, b] = aim(from, to, min_speed * (1.0 + 1e-9), G).unwrap();
            assert!((a.elevation_deg - 45.0).abs() < 1e-2 && (b.elevation_deg - 45.0).abs() < 1e-2);
        }
        other => panic!("expected out of reach, got {other:?}"),
    }
}

#[test]
fn bad_arguments_are_errors_not_panics() {
    assert_eq!(
        aim(DVec3::ONE, DVec3::ONE, 10.0, G),
        Err(AimError::SamePoint)
    );
    for (speed, g) in [
        (0.0, G),
        (-1.0, G),
        (f64::NAN, G),
        (10.0, 0.0),
        (10.0, f64::INFINITY),
    ] {
        assert_eq!(
            aim(DVec3::ZERO, DVec3::X, speed, g),
            Err(AimError::InvalidInput)
        );
    }
}

#[test]
fn straight_up_and_straight_down_hit_the_target_too() {
    let from = DVec3::new(3.0, 4.0, 1.0);
    for to in [DVec3::new(3.0, 4.0, 11.0), DVec3::new(3.0, 4.0, -9.0)] {
        let [high, low] = aim(from, to, 15.0, G).unwrap();
        for s in [high, low] {
            assert!((landing(from, &s, G) - to).length() < 1e-9, "{to}: {s:?}");
        }
        assert!(low.flight_time < high.flight_time);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Every returned launch, flown by the closed form for its flight time, passes within
    /// 1e-9 m of the target: ~1e4 ulps of the largest coordinate involved (~500 m), room for the
    /// rounding of the angle and the flight time, and still far below anything visible.
    #[test]
    fn every_solution_passes_through_the_target(
        from in (-100.0..100.0f64, -100.0..100.0f64, -20.0..50.0f64),
        to in (-100.0..100.0f64, -100.0..100.0f64, -20.0..50.0f64),
        speed in 1.0..120.0f64,
        g in 1.0..30.0f64,
    ) {
        let (from, to) = (DVec3::from(from), DVec3::from(to));
        match aim(from, to, speed, g) {
            Ok(solutions) => for s in solutions {
                let miss = (landing(from, &s, g) - to).length();
                prop_assert!(miss < 1e-9, "missed by {miss} m with {s:?}");
                prop_assert!(s.flight_time > 0.0);
            },
            Err(AimError::OutOfReach { min_speed }) => prop_assert!(min_speed > speed),
            Err(e) => prop_assert!(false, "unexpected {e:?}"),
        }
    }
}
