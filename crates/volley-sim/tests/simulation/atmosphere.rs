//! The standard atmosphere against a published table of it: "Thermophysical Properties of the
//! U.S. Standard Atmosphere" (Table 6 of Mechanical Engineers' Handbook, Volume 4, Wiley, from
//! the U.S. Standard Atmosphere 1976, which equals ICAO's below 32 km), by geometric altitude.
//! Each value must match to half a unit of its last printed digit: temperature to 0.005 K,
//! pressure to 0.00005 bar, density to 0.00005 kg/m^3, the speed of sound to 0.05 m/s (a half
//! unit included: sea level's 1.01325 bar prints as 1.0133, and the decimal half is not exact in
//! binary, so each bound has 1e-12 of slack). The handbook rounded the 1976 standard's own
//! five-significant-digit values, not the exact ones (4000 m: 0.81935 kg/m^3 printed 0.8194,
//! where the exact 0.819347 would print 0.8193), so each bound also allows half a unit of the
//! fifth significant digit that rounding started from.

use volley_sim::internals::atmosphere::{Atmosphere, geopotential};

/// Z (m), H (m), T (K), p (bar), rho (kg/m^3), a (m/s), as printed.
/// The table goes on; its 13 km row prints a density of 0.2667, which its own pressure and
/// temperature contradict (0.1658 bar / (R x 216.65 K) = 0.2666, as the 1976 standard prints),
/// so the rows stop at 12 km.
const TABLE: [(f64, f64, f64, f64, f64, f64); 13] = [
    (0.0, 0.0, 288.15, 1.0133, 1.2250, 340.3),
    (1000.0, 1000.0, 281.65, 0.8988, 1.1117, 336.4),
    (2000.0, 1999.0, 275.15, 0.7950, 1.0066, 332.5),
    (3000.0, 2999.0, 268.66, 0.7012, 0.9093, 328.6),
    (4000.0, 3997.0, 262.17, 0.6166, 0.8194, 324.6),
    (5000.0, 4996.0, 255.68, 0.5405, 0.7364, 320.6),
    (6000.0, 5994.0, 249.19, 0.4722, 0.6601, 316.5),
    (7000.0, 6992.0, 242.70, 0.4111, 0.5900, 312.3),
    (8000.0, 7990.0, 236.22, 0.3565, 0.5258, 308.1),
    (9000.0, 8987.0, 229.73, 0.3080, 0.4671, 303.9),
    (10000.0, 9984.0, 223.25, 0.2650, 0.4135, 299.5),
    (11000.0, 10981.0, 216.77, 0.2270, 0.3648, 295.2),
    (12000.0, 11977.0, 216.65, 0.1940, 0.3119, 295.1),
];

#[test]
fn the_icao_atmosphere_matches_the_published_table_to_its_printed_digits() {
    let within = |x: f64, printed: f64, half: f64| {
        let fifth = 0.5 * 10f64.powf(x.abs().log10().floor() - 4.0);
        (x - printed).abs() <= half + fifth + 1e-12
    };
    for (z, h, t, p, rho, a) in TABLE {
        let air = Atmosphere::ICAO.at(z);
        // The table prints H rounded to the metre.
        assert_eq!(geopotential(z).round(), h, "H at {z} m");
        assert!(
            within(air.temperature, t, 0.005),
            "T at {z} m: {}",
            air.temperature
        );
        assert!(
            within(air.pressure / 1e5, p, 0.00005),
            "p at {z} m: {}",
            air.pressure
        );
        assert!(
            within(air.density, rho, 0.00005),
            "rho at {z} m: {}",
            air.density
        );
        assert!(
            within(air.speed_of_sound, a, 0.05),
            "a at {z} m: {}",
            air.speed_of_sound
        );
    }
}

#[test]
fn a_warmer_day_is_thinner_at_the_same_pressure_and_sound_is_faster() {
    // Ideal gas: at sea level rho = p / (R T) and a = sqrt(gamma R T), so 30 C against 15 C
    // scales density by 288.15 / 303.15 and the speed of sound by its inverse square root.
    let standard = Atmosphere::ICAO.at(0.0);
    let warm = Atmosphere::new(303.15, 101_325.0).at(0.0);
    let ratio = 288.15 / 303.15;
    assert!((warm.density / standard.density - ratio).abs() < 1e-12);
    assert!((standard.speed_of_sound / warm.speed_of_sound - ratio.sqrt()).abs() < 1e-12);
    // The layers shift with it: 11 km is 15 K warmer too.
    let (a, b) = (
        Atmosphere::ICAO.at(11_500.0),
        Atmosphere::new(303.15, 101_325.0).at(11_500.0),
    );
    assert!((b.temperature - a.temperature - 15.0).abs() < 1e-9);
}

#[test]
fn the_tabulated_column_matches_the_formulas_everywhere() {
    use volley_sim::internals::atmosphere::{AirColumn, COLUMN_BOTTOM, COLUMN_TOP};
    // Its bound (see `AirColumn`): 1e-9 relative, the layer boundaries included. Every 0.37 m
    // from below the table to above it, so the exact fallback outside is checked too.
    for (day, ground) in [
        (Atmosphere::ICAO, 0.0),
        (
            Atmosphere::from_ground(1600.0, Some(305.0), Some(83_000.0)),
            1600.0,
        ),
    ] {
        let column = AirColumn::new(day, ground);
        let mut z = COLUMN_BOTTOM - 100.0;
        while z < COLUMN_TOP + 100.0 {
            let exact = day.at(ground + z);
            let (density, sound) = column.at(z);
            let rel = |a: f64, b: f64| ((a - b) / b).abs();
            assert!(rel(density, exact.density) < 1e-9, "density at {z} m");
            assert!(rel(sound, exact.speed_of_sound) < 1e-9, "sound at {z} m");
            z += 0.37;
        }
    }
}

#[test]
fn a_day_from_the_ground_has_the_ground_values_given() {
    let day = Atmosphere::from_ground(1600.0, Some(305.0), Some(83_000.0));
    let air = day.at(1600.0);
    assert!((air.temperature - 305.0).abs() < 1e-9, "{air:?}");
    assert!((air.pressure - 83_000.0).abs() < 1e-6, "{air:?}");
    // Neither given: the standard day itself (to rounding of the sea-level values found).
    let standard = Atmosphere::from_ground(1600.0, None, None).at(2000.0);
    let icao = Atmosphere::ICAO.at(2000.0);
    assert!(((standard.density - icao.density) / icao.density).abs() < 1e-12);
}
