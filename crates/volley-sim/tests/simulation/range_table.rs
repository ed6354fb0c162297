//! The range table (`firing::range_table`): the launcher's shot read at chosen ranges by
//! declared `Downrange` events, against the closed form under gravity alone, and the holdover's
//! one-trajectory column read by the same events.

use volley_sim::internals::firing;
use volley_sim::internals::scene::{self, Scene};

/// A launcher 30 m/s at 40 degrees, azimuth 30 degrees, from (1, 2, 3), under g = 9.81, no
/// contacts in the way (the table turns them off).
fn free(integrator: &str) -> Scene {
    let text = format!(
        "Scene(dt: 0.016666667, integrator: {integrator}, forces: [Gravity((0, 0, -9.81))],
           ground: (height: 0, restitution: 0.5),
           launcher: (position: (1, 2, 3), speed: 30, elevation_deg: 40, azimuth_deg: 30,
                      mass: 0.5, radius: 0.05))"
    );
    scene::parse(&text, "free.ron", "free").unwrap()
}

#[test]
fn under_gravity_the_rows_are_the_closed_form_for_the_schemes_exact_under_constant_force() {
    let (v, e, g) = (30.0f64, 40f64.to_radians(), 9.81);
    let (vh, vz) = (v * e.cos(), v * e.sin());
    let ranges = [10.0, 40.0, 80.0];
    // Exact under constant force: the step's partial path is the parabola itself, so the
    // crossing is the closed form's up to the root search (1e-9 s, docs/physics.md) and
    // rounding (positions of tens of metres: 1e-12 m scale). Bound: 1e-9 s and 30 m/s * 1e-9 s
    // plus rounding, 1e-7 m.
    for integrator in ["Exact", "Rk4", "VelocityVerlet", "Midpoint"] {
        let table = firing::range_table(&free(integrator), &ranges, 20.0).unwrap();
        assert!(table.unreached.is_empty(), "{integrator}");
        for (row, &r) in table.rows.iter().zip(&ranges) {
            let t = r / vh;
            let z = vz * t - 0.5 * g * t * t;
            let speed = (vh * vh + (vz - g * t) * (vz - g * t)).sqrt();
            assert!(
                (row.time - t).abs() < 1e-9,
                "{integrator} {r}: {} vs {t}",
                row.time
            );
            assert!(
                (row.height - z).abs() < 1e-7,
                "{integrator} {r}: {}",
                row.height
            );
            assert!(
                (row.drop - (z - r * e.tan())).abs() < 1e-7,
                "{integrator} {r}"
            );
            assert!(
                row.windage.abs() < 1e-7,
                "{integrator} {r}: {}",
                row.windage
            );
            assert!((row.speed - speed).abs() < 1e-7, "{integrator} {r}");
            assert!(
                (row.energy - 0.25 * speed * speed).abs() < 1e-5,
                "{integrator} {r}"
            );
            assert_eq!(row.mach, None);
            // Downrange is along the azimuth from the muzzle, horizontally.
            let az = 30f64.to_radians();
            let along = (row.position.x - 1.0) * az.cos() + (row.position.y - 2.0) * az.sin();
            assert!((along - r).abs() < 1e-7, "{integrator} {r}: {along}");
        }
    }
}

#[test]
fn a_range_past_the_longest_flight_is_listed_as_not_reached_and_bad_ranges_are_refused() {
    // 30 m/s reaches 91.7 m at the muzzle's height and flies on down: 200 m is reached only
    // after about 12 s, past a 5 s flight.
    let table = firing::range_table(&free("Exact"), &[50.0, 200.0], 5.0).unwrap();
    assert_eq!(table.rows.len(), 1);
    assert_eq!(table.unreached, vec![200.0]);
    for bad in [0.0, -1.0, f64::NAN] {
        let e = firing::range_table(&free("Exact"), &[bad], 5.0).unwrap_err();
        assert!(e.to_string().contains("range"), "{e}");
    }
    let e = firing::range_table(&free("Exact"), &[10.0], 0.0).unwrap_err();
    assert!(e.to_string().contains("max flight time"), "{e}");
}

#[test]
fn the_rifles_zeroed_path_crosses_the_line_of_sight_at_the_zero() {
    // The zero shot hits the sight point to within its miss, and the one-trajectory column
    // reads that same path at the zero's range: its height against the line of sight is
    // within that miss (plus the root search's 1e-9 s at 770 m/s, 1e-6 m).
    let s = scene::bundled("rifle").unwrap();
    let table = firing::holdover(&s, 0.0381, 100.0, &[100.0, 500.0, 1000.0]).unwrap();
    let zero = &table.rows[0];
    assert!(
        zero.path_height.abs() <= zero.shot.miss + 1e-6,
        "{} vs miss {}",
        zero.path_height,
        zero.shot.miss
    );
    // Farther out the zeroed path is low, so both holds are up, and they differ only by the
    // second-order effect of firing higher (under 1 % here).
    for row in &table.rows[1..] {
        assert!(
            row.path_height < 0.0 && row.hold_mrad > 0.0,
            "{}",
            row.range
        );
        let rel = (row.path_hold_mrad - row.hold_mrad).abs() / row.hold_mrad;
        assert!(
            rel < 0.01,
            "{} m: {} vs {}",
            row.range,
            row.path_hold_mrad,
            row.hold_mrad
        );
    }
}
