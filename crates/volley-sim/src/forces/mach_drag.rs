//! Drag whose coefficient changes with the Mach number, in air that thins with height and moves
//! with the wind: the force of a bullet, a shell or a ball, the term [`super::Forces::mach_drag`]
//! holds.
//!
//! # The formula
//! With `u = V - w(z)` the velocity through the air (w the wind at the body's height),
//! `rho(z)` and `a(z)` the air's density and speed of sound, and `Cd(M)` the drag curve at
//! `M = |u| / a`:
//!
//! ```text
//! F = -(rho / 2) Cd_body A |u| u,   Cd_body A = i Cd(M) pi d^2 / 4 = m Cd(M) pi / (4 BC)
//! ```
//!
//! `i` is the form factor (the body's coefficient over the curve's) and `BC = m / (i d^2)` the
//! ballistic coefficient against the curve, so a body is described either by `BC` (the number
//! bullet makers publish, in lb/in^2; 1 lb/in^2 = 703.0696 kg/m^2) or by its diameter and form
//! factor with the body's own mass. This is the standard point-mass model of exterior ballistics
//! (McCoy, "Modern Exterior Ballistics", 1999, ch. 2 and 4; the same acceleration
//! `rho pi Cd |u| u / (8 BC)` is JBM's and py-ballisticcalc's). The curve is a [`DragTable`],
//! PCHIP between its points unless the term asks for straight lines ([`Interpolation`]).
//!
//! The wind is a velocity at a reference height, constant with height or following the power
//! law `w(z) = w_ref (z / z_ref)^alpha` above the ground (z > 0; none at or below it), the
//! profile of the atmospheric surface layer (Hellmann's exponent; 1/7 over open ground).
//!
//! The air is either uniform (one temperature and pressure everywhere, as ballistic tables are
//! usually computed) or a standard atmosphere over the scene's height ([`AirColumn`]).

use std::sync::Arc;

use glam::DVec3;

use crate::atmosphere::{Air, AirColumn, Atmosphere, GAMMA, R_AIR};
use crate::drag::{DragTable, Interpolation};

/// One lb/in^2 in kg/m^2: the unit ballistic coefficients are published in.
pub const KG_M2_PER_LB_IN2: f64 = 0.453_592_37 / (0.0254 * 0.0254);

/// The drag curve a [`MachDrag`] reads.
#[derive(Clone, Debug, PartialEq)]
pub enum DragCurve {
    /// The standard G1 function (flat-base bullet).
    G1,
    /// The standard G7 function (boat-tail spitzer).
    G7,
    /// A smooth sphere (the GS function).
    Sphere,
    /// A table given in the scene.
    Table(Arc<DragTable>),
}

impl DragCurve {
    /// A curve of the scene's own `(Mach, Cd)` points, checked ([`DragTable::new`]).
    pub fn from_points(points: &[(f64, f64)]) -> Result<DragCurve, crate::drag::DragTableError> {
        Ok(DragCurve::Table(Arc::new(DragTable::new(points)?)))
    }

    /// The curve's table.
    #[inline]
    pub fn table(&self) -> &DragTable {
        match self {
            DragCurve::G1 => DragTable::g1(),
            DragCurve::G7 => DragTable::g7(),
            DragCurve::Sphere => DragTable::sphere(),
            DragCurve::Table(t) => t,
        }
    }

    /// The curve's name as a scene file writes it (`Table` for a scene's own).
    pub fn name(&self) -> &'static str {
        match self {
            DragCurve::G1 => "G1",
            DragCurve::G7 => "G7",
            DragCurve::Sphere => "Sphere",
            DragCurve::Table(_) => "Table",
        }
    }
}

/// How a body's size and mass scale the curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DragSize {
    /// A ballistic coefficient against the curve, `BC = m / (i d^2)` (kg/m^2): every body
    /// slows the same whatever its mass.
    Ballistic(f64),
    /// The body's diameter d (m) and form factor i: the force is the same whatever its mass.
    Diameter {
        /// Diameter (m).
        diameter: f64,
        /// Form factor i: the body's drag coefficient over the curve's.
        form_factor: f64,
    },
}

impl DragSize {
    /// A ballistic coefficient as published, in lb/in^2 (a scene file's `bc`).
    pub fn from_bc_lb_in2(bc: f64) -> DragSize {
        DragSize::Ballistic(bc * KG_M2_PER_LB_IN2)
    }

    /// `Cd_body A / Cd(M) / 2` (m^2) for a body of mass `m`, so `F = -rho Cd(M) |u| u` times it.
    #[inline(always)]
    pub(crate) fn half_area(self, m: f64) -> f64 {
        match self {
            DragSize::Ballistic(bc) => m * (std::f64::consts::PI / 8.0) / bc,
            DragSize::Diameter {
                diameter,
                form_factor,
            } => (std::f64::consts::PI / 8.0) * form_factor * diameter * diameter,
        }
    }
}

/// The air a [`MachDrag`] acts in.
#[derive(Clone, Debug, PartialEq)]
pub enum AirModel {
    /// The same air at every height: its temperature and pressure, with the density and speed
    /// of sound of dry air at them.
    Uniform(Air),
    /// A standard atmosphere over the scene's height.
    Standard {
        /// Altitude above sea level (m) of the scene's z = 0.
        ground: f64,
        /// The ground's temperature (K), if not the standard day's.
        temperature: Option<f64>,
        /// The ground's pressure (Pa), if not the standard day's.
        pressure: Option<f64>,
        /// Its tabulation.
        column: Arc<AirColumn>,
    },
}

impl AirModel {
    /// Uniform dry air at `temperature` (K) and `pressure` (Pa).
    pub fn uniform(temperature: f64, pressure: f64) -> AirModel {
        AirModel::Uniform(Air {
            temperature,
            pressure,
            density: pressure / (R_AIR * temperature),
            speed_of_sound: libm::sqrt(GAMMA * R_AIR * temperature),
        })
    }

    /// The ICAO standard atmosphere with the scene's z = 0 at `ground` m above sea level and
    /// the ground's temperature (K) and pressure (Pa) where given
    /// ([`Atmosphere::from_ground`]).
    pub fn standard(ground: f64, temperature: Option<f64>, pressure: Option<f64>) -> AirModel {
        let atmosphere = Atmosphere::from_ground(ground, temperature, pressure);
        AirModel::Standard {
            ground,
            temperature,
            pressure,
            column: Arc::new(AirColumn::new(atmosphere, ground)),
        }
    }

    /// Density (kg/m^3) and speed of sound (m/s) at scene height `z` (m).
    #[inline(always)]
    pub fn at(&self, z: f64) -> (f64, f64) {
        match self {
            AirModel::Uniform(air) => (air.density, air.speed_of_sound),
            AirModel::Standard { column, .. } => column.at(z),
        }
    }
}

/// The wind: the air's velocity, at a reference height and with height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// The wind's velocity (m/s) at `reference_height`.
    pub velocity: DVec3,
    /// Height (m) at which `velocity` is measured.
    pub reference_height: f64,
    /// The profile's exponent alpha: 0 for the same wind at every height.
    pub exponent: f64,
}

impl Wind {
    /// The same wind `velocity` (m/s, world axes) at every height.
    pub fn uniform(velocity: DVec3) -> Wind {
        Wind {
            velocity,
            reference_height: 10.0,
            exponent: 0.0,
        }
    }

    /// `velocity` (m/s) at `reference_height` (m), growing with height as `(z / z_ref)^exponent`.
    pub fn profile(velocity: DVec3, reference_height: f64, exponent: f64) -> Wind {
        Wind {
            velocity,
            reference_height,
            exponent,
        }
    }

    /// The wind (m/s) at height `z` (m).
    #[inline(always)]
    pub fn at(&self, z: f64) -> DVec3 {
        if self.exponent == 0.0 {
            self.velocity
        } else if z > 0.0 {
            self.velocity * libm::pow(z / self.reference_height, self.exponent)
        } else {
            DVec3::ZERO
        }
    }
}

/// One revolution per minute in rad/s: spins are published in rpm.
pub const RAD_S_PER_RPM: f64 = std::f64::consts::PI / 30.0;

/// A lift coefficient against the spin parameter `S = r |omega| / |u|`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LiftModel {
    /// Alan Nathan's fit for a baseball, `C_L = 1.120 S / (0.583 + 2.333 S)`, the one his
    /// trajectory calculator uses (baseball.physics.illinois.edu, "TrajectoryCalculator";
    /// ported in pybaseball's `analysis/trajectories`).
    Nathan,
}

impl LiftModel {
    /// The largest lift coefficient the model reaches, as `S` grows without bound.
    pub fn max_coefficient(self) -> f64 {
        match self {
            LiftModel::Nathan => 1.120 / 2.333,
        }
    }

    /// The lift coefficient at spin parameter `s`.
    #[inline]
    pub fn coefficient(self, s: f64) -> f64 {
        match self {
            LiftModel::Nathan => 1.120 * s / (0.583 + 2.333 * s),
        }
    }
}

/// How a spin decays from its launch value, keeping its axis.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SpinDecay {
    /// It does not.
    None,
    /// `omega = omega_0 exp(-age / tau)`, tau in s.
    Time(f64),
    /// Nathan's calculator's form, `omega = omega_0 exp(-age |u| / (tau v_ref))` with
    /// `v_ref = 146.7 ft/s` (100 mph as the sheet converts it) and tau in s (30 in the sheet):
    /// the decay rate grows with the air speed.
    Nathan(f64),
}

/// 146.7 ft/s in m/s: the speed Nathan's spin decay is scaled to.
pub const NATHAN_DECAY_SPEED: f64 = 146.7 * 0.3048;

impl SpinDecay {
    /// The factor `omega / omega_0` at `age` s after launch, moving through the air at `speed`.
    #[inline]
    pub fn factor(self, age: f64, speed: f64) -> f64 {
        match self {
            SpinDecay::None => 1.0,
            SpinDecay::Time(tau) => libm::exp(-age / tau),
            SpinDecay::Nathan(tau) => libm::exp(-age * speed / (tau * NATHAN_DECAY_SPEED)),
        }
    }
}

/// A spinning body's aerodynamics beside its drag: Magnus lift and the drag the spin adds, with
/// the spin decaying from its launch value.
///
/// With `omega = omega_0 d(age, |u|)` (the spin keeps its axis; [`SpinDecay`] gives `d`) and
/// `u` the velocity through the air:
///
/// ```text
/// F_lift = (rho / 2) C_L(S) A |u| (omega_hat x u),   S = r |omega| / |u|,   A = pi r^2
/// Cd     = Cd(M) + k |omega|                           (the spin drag, k per rad/s)
/// ```
///
/// The lift is perpendicular to `u`, so it does no work in the air's frame. The body's size is
/// its diameter (a spin needs `size: Diameter`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpinLift {
    /// The lift coefficient.
    pub lift: LiftModel,
    /// How the spin decays.
    pub decay: SpinDecay,
    /// The drag coefficient added per rad/s of spin, k (s/rad).
    pub drag_per_spin: f64,
}

impl SpinLift {
    /// Alan Nathan's lift with `decay`, and `drag_per_1000_rpm` added to the drag coefficient
    /// per 1000 rpm of spin (a scene file's `spin: (lift: Nathan, decay: ..., drag_per_1000_rpm:
    /// ...)`).
    pub fn nathan(decay: SpinDecay, drag_per_1000_rpm: f64) -> SpinLift {
        SpinLift {
            lift: LiftModel::Nathan,
            decay,
            drag_per_spin: drag_per_1000_rpm / (1000.0 * RAD_S_PER_RPM),
        }
    }
}

/// Drag against a Mach-dependent curve (see the module doc for the formula and its source).
#[derive(Clone, Debug, PartialEq)]
pub struct MachDrag {
    /// The curve.
    pub curve: DragCurve,
    /// How the curve runs between its points.
    pub interpolation: Interpolation,
    /// How the body scales it.
    pub size: DragSize,
    /// The air.
    pub air: AirModel,
    /// The wind, if any.
    pub wind: Option<Wind>,
    /// A spin's lift and drag, if the bodies spin.
    pub spin: Option<SpinLift>,
}

impl MachDrag {
    /// Drag against `curve` for bodies sized by `size`, in the ICAO standard atmosphere with
    /// the scene's z = 0 at sea level, no wind, no spin, PCHIP between the curve's points: a
    /// scene file's `MachDrag(curve: ..., bc: ...)` with its defaults. Set the rest with the
    /// `with_` methods or the public fields.
    ///
    /// ```
    /// use glam::DVec3;
    /// use volley_sim::{DragCurve, DragSize, MachDrag, Scene, Wind};
    ///
    /// // The rifle scene's bullet: a G7 boat-tail, BC 0.223 lb/in^2, a 3 m/s crosswind.
    /// let drag = MachDrag::new(DragCurve::G7, DragSize::from_bc_lb_in2(0.223))
    ///     .with_wind(Wind::uniform(DVec3::new(0.0, 3.0, 0.0)));
    /// let scene = Scene::builder("rifle", 1.0 / 60.0)
    ///     .gravity(DVec3::new(0.0, 0.0, -9.80665))
    ///     .mach_drag(drag)
    ///     .build()?;
    /// assert!(scene.forces().mach_drag.is_some());
    /// # Ok::<(), volley_sim::SceneError>(())
    /// ```
    pub fn new(curve: DragCurve, size: DragSize) -> MachDrag {
        MachDrag {
            curve,
            interpolation: Interpolation::Pchip,
            size,
            air: AirModel::standard(0.0, None, None),
            wind: None,
            spin: None,
        }
    }

    /// The term in `air` instead.
    #[must_use]
    pub fn with_air(self, air: AirModel) -> MachDrag {
        MachDrag { air, ..self }
    }

    /// The term in `wind`.
    #[must_use]
    pub fn with_wind(self, wind: Wind) -> MachDrag {
        MachDrag {
            wind: Some(wind),
            ..self
        }
    }

    /// The term with a spin's lift and drag (needs a [`DragSize::Diameter`]).
    #[must_use]
    pub fn with_spin(self, spin: SpinLift) -> MachDrag {
        MachDrag {
            spin: Some(spin),
            ..self
        }
    }

    /// The term with `interpolation` between the curve's points.
    #[must_use]
    pub fn with_interpolation(self, interpolation: Interpolation) -> MachDrag {
        MachDrag {
            interpolation,
            ..self
        }
    }

    /// Force (N) on a body of mass `m` (kg) at `p` (m) moving at `v` (m/s). Out of line, so
    /// that the general model's force stays small enough to inline for the scenes without it.
    #[inline(never)]
    pub fn force(&self, p: DVec3, v: DVec3, m: f64) -> DVec3 {
        let u = v - self.wind_at(p.z);
        let (density, sound) = self.air.at(p.z);
        let speed = u.length();
        let cd = self.curve.table().cd_by(speed / sound, self.interpolation);
        -(self.size.half_area(m) * density * cd * speed) * u
    }

    /// The whole term with its spin ([`SpinLift`]) at time `t` on a body launched as
    /// `w.launch` says: the drag with the spin's addition, plus the lift. Out of line, as
    /// [`MachDrag::force`] is.
    #[inline(never)]
    pub(crate) fn spun_force(&self, t: f64, p: DVec3, v: DVec3, w: crate::body::Mass) -> DVec3 {
        let (drag, lift) = self.spun_parts(t, p, v, w);
        drag + lift
    }

    /// [`MachDrag::spun_force`] in its two parts: the drag (along `-u`) and the lift (across
    /// it; zero without a spin, a diameter, speed or spin rate).
    #[inline(always)]
    pub(crate) fn spun_parts(
        &self,
        t: f64,
        p: DVec3,
        v: DVec3,
        w: crate::body::Mass,
    ) -> (DVec3, DVec3) {
        let u = v - self.wind_at(p.z);
        let (density, sound) = self.air.at(p.z);
        let speed = u.length();
        let spin = self.spin.as_ref();
        let decay = spin.map_or(0.0, |s| s.decay.factor(t - w.launch.time, speed));
        let omega = w.launch.spin * decay;
        let rate = omega.length();
        let cd = self.curve.table().cd_by(speed / sound, self.interpolation)
            + spin.map_or(0.0, |s| s.drag_per_spin * rate);
        let drag = -(self.size.half_area(w.m) * density * cd * speed) * u;
        let (Some(s), DragSize::Diameter { diameter, .. }) = (spin, self.size) else {
            return (drag, DVec3::ZERO);
        };
        if speed == 0.0 || rate == 0.0 {
            return (drag, DVec3::ZERO);
        }
        let c_l = s.lift.coefficient(0.5 * diameter * rate / speed);
        let half_area = (std::f64::consts::PI / 8.0) * diameter * diameter;
        (
            drag,
            (half_area * density * c_l * speed / rate) * omega.cross(u),
        )
    }

    /// A body's spin (rad/s) at time `t` moving at `v` at `p`: its launch spin, decayed since
    /// its launch.
    pub fn spin_at(&self, t: f64, p: DVec3, v: DVec3, launch: crate::body::Launch) -> DVec3 {
        let speed = (v - self.wind_at(p.z)).length();
        self.spin.map_or(DVec3::ZERO, |s| {
            launch.spin * s.decay.factor(t - launch.time, speed)
        })
    }

    /// The wind (m/s) at height `z`: zero without one.
    #[inline(always)]
    pub fn wind_at(&self, z: f64) -> DVec3 {
        self.wind.map_or(DVec3::ZERO, |w| w.at(z))
    }

    /// The Mach number of a body at `p` moving at `v`: its speed through the air over the
    /// speed of sound there.
    pub fn mach(&self, p: DVec3, v: DVec3) -> f64 {
        (v - self.wind_at(p.z)).length() / self.air.at(p.z).1
    }

    /// The largest `rho Cd_body A / 2 / m` (1/m) the curve reaches near the ground, the
    /// coefficient of `|u| u` a quadratic drag with the same worst case would have: what the
    /// stability pre-check treats this term as.
    pub fn worst_quadratic_rate(&self, m: f64) -> f64 {
        let cd_max = self.curve.table().points().map(|p| p.1).fold(0.0, f64::max);
        let (density, _) = self.air.at(0.0);
        self.size.half_area(m) * density * cd_max / m
    }
}
