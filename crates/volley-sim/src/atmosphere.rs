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

    /// The day whose air at geometric altitude `ground` (m) has `temperature` (K) and
    /// `pressure` (Pa): the standard lapse shifted by the temperature difference (ISA + dT),
    /// with the sea-level pressure that gives `pressure` there. Either left `None` is the ICAO
    /// standard day's value at `ground`.
    pub fn from_ground(ground: f64, temperature: Option<f64>, pressure: Option<f64>) -> Atmosphere {
        let standard = Atmosphere::ICAO.at(ground);
        let t0 = SEA_LEVEL_TEMPERATURE
            + (temperature.unwrap_or(standard.temperature) - standard.temperature);
        // Pressure at `ground` is proportional to the sea-level one for a given temperature.
        let per_pascal = Atmosphere::new(t0, 1.0).at(ground).pressure;
        Atmosphere::new(t0, pressure.unwrap_or(standard.pressure) / per_pascal)
    }

    /// The air at geometric altitude `z` (m above sea level).
    pub fn at(&self, z: f64) -> Air {
        self.at_geopotential(geopotential(z), false).0
    }

    /// The air at geopotential altitude `h` (m), with the slopes per metre of geopotential
    /// altitude of its density and speed of sound, from the layer's lapse and hydrostatics
    /// (`dT/dH = L`, `dp/dH = -rho g0`). On a layer boundary the slopes are the layer above's,
    /// or the one below's when `from_below`.
    fn at_geopotential(&self, h: f64, from_below: bool) -> (Air, f64, f64) {
        let (mut t, mut p) = (self.sea_level_temperature, self.sea_level_pressure);
        let mut base = 0.0;
        let mut lapse = LAYERS[0].1;
        // Walk up to the layer holding `h`, carrying each layer's top as the next one's base.
        for &(next_base, next_lapse) in &LAYERS[1..] {
            if h < next_base || (from_below && h == next_base) {
                break;
            }
            (t, p) = climb(t, p, lapse, next_base - base);
            base = next_base;
            lapse = next_lapse;
        }
        let (temperature, pressure) = climb(t, p, lapse, h - base);
        let air = Air {
            temperature,
            pressure,
            density: pressure / (R_AIR * temperature),
            speed_of_sound: libm::sqrt(GAMMA * R_AIR * temperature),
        };
        let dp = -air.density * G0;
        let d_density = (dp - air.density * R_AIR * lapse) / (R_AIR * temperature);
        let d_sound = air.speed_of_sound * lapse / (2.0 * temperature);
        (air, d_density, d_sound)
    }
}

/// The density and speed of sound of an [`Atmosphere`] against a scene's height, tabulated
/// once so a force evaluation reads two cubics instead of a power and an exponential.
///
/// Heights are the scene's z; `ground` is the altitude above sea level of z = 0. The nodes are
/// every `COLUMN_STEP` m of geopotential altitude, covering scene heights from
/// `COLUMN_BOTTOM` to `COLUMN_TOP`, so every layer boundary (11, 20, 32 and 47 km) is a
/// node; each holds the exact values and their slopes on both sides. Between two nodes runs
/// the cubic Hermite through both, inside one layer where the values are smooth: its error is
/// below `h^4 / 384` times the fourth derivative, about 1e-13 relative (the tests check 1e-9
/// everywhere against [`Atmosphere::at`]). A lookup costs a division (geometric to
/// geopotential altitude) and two cubics. Outside the nodes the exact formulas run.
#[derive(Clone, Debug, PartialEq)]
pub struct AirColumn {
    atmosphere: Atmosphere,
    ground: f64,
    /// Geopotential altitude (m) of the first node.
    first: f64,
    /// Per node: density, its slope from below and from above, speed of sound, its slope from
    /// below and from above (per metre of geopotential altitude).
    nodes: Vec<[f64; 6]>,
}

/// Spacing of an [`AirColumn`]'s nodes (m of geopotential altitude): a divisor of every layer
/// boundary.
pub const COLUMN_STEP: f64 = 25.0;
/// Lowest tabulated scene height (m).
pub const COLUMN_BOTTOM: f64 = -1_000.0;
/// Highest tabulated scene height (m).
pub const COLUMN_TOP: f64 = 30_000.0;

impl AirColumn {
    /// The column of `atmosphere` over a scene whose z = 0 is `ground` m above sea level.
    pub fn new(atmosphere: Atmosphere, ground: f64) -> AirColumn {
        let first = (geopotential(ground + COLUMN_BOTTOM) / COLUMN_STEP).floor() * COLUMN_STEP;
        let last = (geopotential(ground + COLUMN_TOP) / COLUMN_STEP).ceil() * COLUMN_STEP;
        let n = ((last - first) / COLUMN_STEP) as usize + 1;
        let nodes = (0..n)
            .map(|i| {
                let h = first + i as f64 * COLUMN_STEP;
                let (air, dr_below, da_below) = atmosphere.at_geopotential(h, true);
                let (_, dr_above, da_above) = atmosphere.at_geopotential(h, false);
                [
                    air.density,
                    dr_below,
                    dr_above,
                    air.speed_of_sound,
                    da_below,
                    da_above,
                ]
            })
            .collect();
        AirColumn {
            atmosphere,
            ground,
            first,
            nodes,
        }
    }

    /// The atmosphere tabulated.
    pub fn atmosphere(&self) -> Atmosphere {
        self.atmosphere
    }

    /// Altitude above sea level (m) of the scene's z = 0.
    pub fn ground(&self) -> f64 {
        self.ground
    }

    /// Density (kg/m^3) and speed of sound (m/s) at scene height `z` (m).
    #[inline]
    pub fn at(&self, z: f64) -> (f64, f64) {
        let h = geopotential(self.ground + z);
        let x = (h - self.first) * (1.0 / COLUMN_STEP);
        // `!(..)` so NaN takes the exact path too (and turns the force NaN, as it should).
        if !(x >= 0.0 && x < (self.nodes.len() - 1) as f64) {
            let air = self.atmosphere.at(self.ground + z);
            return (air.density, air.speed_of_sound);
        }
        let i = x as usize;
        let t = x - i as f64;
        let (a, b) = (&self.nodes[i], &self.nodes[i + 1]);
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = (t3 - 2.0 * t2 + t) * COLUMN_STEP;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = (t3 - t2) * COLUMN_STEP;
        (
            h00 * a[0] + h10 * a[2] + h01 * b[0] + h11 * b[1],
            h00 * a[3] + h10 * a[5] + h01 * b[3] + h11 * b[4],
        )
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
