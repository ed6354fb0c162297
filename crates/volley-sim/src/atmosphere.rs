//! The ICAO standard atmosphere (ICAO Doc 7488; identical to the U.S. Standard Atmosphere 1976
//! below 32 km): temperature, pressure, density and the speed of sound with altitude, for the
//! force terms whose air thins with height and whose drag depends on the Mach number.
//!
//! # The model
//! Altitude is geometric (metres above mean sea level, as a scene's z); the layers are defined on
//! geopotential altitude `H = r0 Z / (r0 + Z)`, `r0 = 6 356 766 m`. In each layer the temperature
//! is linear in `H` with lapse rate `L`, and the pressure follows from hydrostatics with the
//! standard gravity `g0 = 9.80665 m/s^2`:
//!
//! ```text
//! L != 0:  T = Tb + L (H - Hb),  p = pb (T / Tb)^(-g0 / (L R))
//! L == 0:  T = Tb,               p = pb exp(-g0 (H - Hb) / (R Tb))
//! rho = p / (R T),  a = sqrt(gamma R T),  R = 287.05287 J/(kg K),  gamma = 1.4
//! ```
//!
//! with the layers 0-11 km (L = -6.5 K/km), 11-20 km (isothermal), 20-32 km (+1.0 K/km),
//! 32-47 km (+2.8 K/km) and 47-51 km (isothermal). Above 51 km the last layer goes on (the
//! projectiles Volley models do not go there); below sea level the first layer goes on down.
//!
//! A non-standard day is the same lapse from another sea-level temperature and pressure
//! ([`Atmosphere::new`]): every layer's base temperature shifts with the sea-level one, the
//! usual "ISA + dT" convention, and the pressures follow from the hydrostatic equations.
//!
//! Transcendental functions come from `libm`, as everywhere in the crate, so the values are
//! the same bits on every platform.

/// Standard gravity (m/s^2), by which geopotential altitude is defined.
pub const G0: f64 = 9.806_65;
/// The specific gas constant of dry air (J/(kg K)): ICAO's `R* / M0 = 8314.32 / 28.9644`.
pub const R_AIR: f64 = 287.052_87;
/// The ratio of specific heats of air.
pub const GAMMA: f64 = 1.4;
/// The Earth's radius in the geopotential conversion (m).
pub const EARTH_RADIUS: f64 = 6_356_766.0;
/// ICAO sea-level temperature (K): 15 C.
pub const SEA_LEVEL_TEMPERATURE: f64 = 288.15;
/// ICAO sea-level pressure (Pa): 1013.25 hPa.
pub const SEA_LEVEL_PRESSURE: f64 = 101_325.0;

/// The layers' base geopotential altitudes (m) and lapse rates (K/m), bottom up.
const LAYERS: [(f64, f64); 5] = [
    (0.0, -0.0065),
    (11_000.0, 0.0),
    (20_000.0, 0.001),
    (32_000.0, 0.0028),
    (47_000.0, 0.0),
];

/// The air at one altitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Air {
    /// Temperature (K).
    pub temperature: f64,
    /// Pressure (Pa).
    pub pressure: f64,
    /// Density (kg/m^3).
    pub density: f64,
    /// Speed of sound (m/s).
    pub speed_of_sound: f64,
}

/// A standard atmosphere from a sea-level temperature and pressure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Atmosphere {
    /// Sea-level temperature (K).
    pub sea_level_temperature: f64,
    /// Sea-level pressure (Pa).
    pub sea_level_pressure: f64,
}

impl Default for Atmosphere {
    fn default() -> Self {
        Atmosphere::ICAO
    }
}

impl Atmosphere {
    /// The ICAO standard day: 15 C and 1013.25 hPa at sea level.
    pub const ICAO: Atmosphere = Atmosphere {
        sea_level_temperature: SEA_LEVEL_TEMPERATURE,
        sea_level_pressure: SEA_LEVEL_PRESSURE,
    };

    /// Another day: `temperature` (K) and `pressure` (Pa) at sea level, the standard lapse.
    pub fn new(temperature: f64, pressure: f64) -> Atmosphere {
        Atmosphere {
            sea_level_temperature: temperature,
            sea_level_pressure: pressure,
        }
    }

    /// The air at geometric altitude `z` (m above sea level).
    pub fn at(&self, z: f64) -> Air {
        let h = geopotential(z);
        let (mut t, mut p) = (self.sea_level_temperature, self.sea_level_pressure);
        let mut base = 0.0;
        let mut lapse = LAYERS[0].1;
        // Walk up to the layer holding `h`, carrying each layer's top as the next one's base.
        for &(next_base, next_lapse) in &LAYERS[1..] {
            if h < next_base {
                break;
            }
            (t, p) = climb(t, p, lapse, next_base - base);
            base = next_base;
            lapse = next_lapse;
        }
        let (temperature, pressure) = climb(t, p, lapse, h - base);
        Air {
            temperature,
            pressure,
            density: pressure / (R_AIR * temperature),
            speed_of_sound: libm::sqrt(GAMMA * R_AIR * temperature),
        }
    }
}

/// Geopotential altitude (m) of geometric altitude `z` (m).
pub fn geopotential(z: f64) -> f64 {
    EARTH_RADIUS * z / (EARTH_RADIUS + z)
}

/// Temperature and pressure `dh` of geopotential altitude above a base at `t`, `p`, in a layer
/// of lapse rate `lapse`.
fn climb(t: f64, p: f64, lapse: f64, dh: f64) -> (f64, f64) {
    if lapse == 0.0 {
        (t, p * libm::exp(-G0 * dh / (R_AIR * t)))
    } else {
        let top = t + lapse * dh;
        (top, p * libm::pow(top / t, -G0 / (lapse * R_AIR)))
    }
}
