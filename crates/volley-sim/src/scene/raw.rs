//! The scene file's raw schema, as serde reads and writes it: the force terms, launches and
//! bodies as written, before validation, and [`Scene::to_ron`], which writes a scene back in it.

use glam::DVec3;
use serde::Deserialize;

use super::*;

impl Scene {
    /// The scene as a scene file that parses back to it: every force term, surface, target
    /// and body (launches as velocities), the launcher, the volley, the seed, the guard and the
    /// compare lanes. What the window's "Save setup" writes; `parse` of it gives a scene that
    /// steps to the same bits.
    pub fn to_ron(&self) -> String {
        format!(
            "// Written by Volley's \"Save setup\": the scene `{}` as set up in the window (its\n\
             // launcher, targets, integrator, step and compare lanes), bodies as launch\n\
             // velocities. `volley window FILE` and `volley headless FILE` open it.\n{}\n",
            // Escaped: a name with a line break would end the comment and break the file.
            self.name.escape_debug(),
            self.ron_body()
        )
    }

    /// The scene as RON, without the header comment [`Scene::to_ron`] adds.
    pub(super) fn ron_body(&self) -> String {
        let f = &self.forces;
        let mut forces = Vec::new();
        if let Some(g) = f.gravity {
            forces.push(ForceTerm::Gravity(g));
        }
        if let Some(c) = f.constant {
            forces.push(ForceTerm::ConstantForce(c));
        }
        if let Some(b) = f.linear_drag {
            forces.push(ForceTerm::LinearDrag(b));
        }
        if let Some(c) = f.quadratic_drag {
            forces.push(ForceTerm::QuadraticDrag(c));
        }
        if let Some(sp) = f.spring {
            forces.push(ForceTerm::Spring {
                anchor: sp.anchor,
                stiffness: sp.stiffness,
                rest_length: sp.rest_length,
                damping: sp.damping,
            });
        }
        if let Some(pm) = f.point_mass {
            forces.push(ForceTerm::PointMass {
                center: pm.center,
                mu: pm.mu,
            });
        }
        for c in &f.custom {
            forces.push(ForceTerm::Custom {
                name: c.name().to_string(),
                version: c.version(),
            });
        }
        if let Some(d) = &f.mach_drag {
            let r = RawMachDrag::of(d);
            forces.push(ForceTerm::MachDrag {
                curve: r.curve,
                interpolation: r.interpolation,
                bc: r.bc,
                diameter: r.diameter,
                form_factor: r.form_factor,
                air: r.air,
                wind: r.wind,
                spin: r.spin,
            });
        }
        if let Some(t) = &f.thrust {
            forces.push(ForceTerm::Thrust {
                curve: t.curve.points().to_vec(),
                propellant: t.propellant,
                direction: match t.direction {
                    ThrustDirection::Fixed(d) => RawThrustDirection::Fixed(d),
                    ThrustDirection::Velocity {
                        along,
                        rail_exit_speed,
                    } => RawThrustDirection::Velocity {
                        along,
                        rail_exit_speed,
                    },
                },
            });
        }
        let raw = RawScene {
            name: Some(self.name.clone()),
            description: self.description.clone(),
            dt: self.dt(),
            start_time: self.start_time,
            duration: self.duration,
            integrator: self.integrator,
            substeps: self.substeps,
            tolerance: (self.tolerance != DEFAULT_TOLERANCE).then_some(self.tolerance),
            forces,
            ground: self.ground,
            walls: self.walls.clone(),
            targets: self.targets.clone(),
            meshes: self.meshes.iter().map(levels::raw_mesh).collect(),
            heightfields: self
                .heightfields
                .iter()
                .map(levels::raw_heightfield)
                .collect(),
            detection: self.detection,
            bodies: self
                .bodies
                .iter()
                .map(|b| RawBody {
                    mass: b.mass,
                    radius: b.radius,
                    position: b.position,
                    launch: Launch::Velocity(b.velocity),
                    spin: b.spin,
                })
                .collect(),
            launcher: Some(self.launcher),
            volley: self.volley,
            seed: self.seed,
            guard: self.guard,
            compare: self.compare.clone(),
            events: self.events.iter().map(RawEvent::of).collect(),
        };
        let config = ron::ser::PrettyConfig::new()
            .struct_names(true)
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
        ron::ser::to_string_pretty(&raw, config)
            .unwrap_or_else(|e| format!("// could not write the scene: {e}\n"))
    }
}

/// One force term as written in a scene file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum ForceTerm {
    Gravity(DVec3),
    ConstantForce(DVec3),
    LinearDrag(f64),
    QuadraticDrag(f64),
    Spring {
        anchor: DVec3,
        stiffness: f64,
        #[serde(default)]
        rest_length: f64,
        #[serde(default)]
        damping: f64,
    },
    PointMass {
        center: DVec3,
        mu: f64,
    },
    MachDrag {
        curve: RawCurve,
        #[serde(default, skip_serializing_if = "is_pchip")]
        interpolation: Interpolation,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bc: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        diameter: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        form_factor: Option<f64>,
        #[serde(default)]
        air: RawAir,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        wind: Option<RawWind>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spin: Option<RawSpin>,
    },
    Custom {
        name: String,
        version: u32,
    },
    Thrust {
        curve: Vec<(f64, f64)>,
        #[serde(default)]
        propellant: f64,
        #[serde(default = "straight_up")]
        direction: RawThrustDirection,
    },
}

/// A motor's direction as written: `Fixed((x, y, z))`, or `Velocity(along: (x, y, z),
/// rail_exit_speed: m/s)` (along the rail until that speed, then along the velocity); vectors
/// of any length but zero.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum RawThrustDirection {
    Fixed(DVec3),
    Velocity {
        along: DVec3,
        #[serde(default)]
        rail_exit_speed: f64,
    },
}

fn straight_up() -> RawThrustDirection {
    RawThrustDirection::Fixed(DVec3::Z)
}

/// A Mach drag's spin as written: the lift model, the decay (`None`, `Time(tau)`,
/// `Nathan(tau)`, tau in s) and the drag coefficient added per 1000 rpm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSpin {
    #[serde(default = "nathan")]
    pub(super) lift: LiftModel,
    #[serde(default = "no_decay")]
    pub(super) decay: SpinDecay,
    #[serde(default)]
    pub(super) drag_per_1000_rpm: f64,
}

fn nathan() -> LiftModel {
    LiftModel::Nathan
}

fn no_decay() -> SpinDecay {
    SpinDecay::None
}

/// A Mach drag term's fields as written (the `ForceTerm::MachDrag` variant's): the curve, the
/// body's size (a ballistic coefficient in lb/in^2, or a diameter in m with a form factor),
/// the air and the wind.
pub(super) struct RawMachDrag {
    pub(super) curve: RawCurve,
    pub(super) interpolation: Interpolation,
    pub(super) bc: Option<f64>,
    pub(super) diameter: Option<f64>,
    pub(super) form_factor: Option<f64>,
    pub(super) air: RawAir,
    pub(super) wind: Option<RawWind>,
    pub(super) spin: Option<RawSpin>,
}

/// A drag curve as written: a standard one by name, or (Mach, Cd) points.
#[derive(Clone, Debug, PartialEq, serde::Serialize, Deserialize)]
pub(super) enum RawCurve {
    G1,
    G7,
    Sphere,
    Table(Vec<(f64, f64)>),
}

/// The air as written: a standard atmosphere (the ground's altitude in m, and optionally its
/// temperature in K and pressure in Pa) or uniform air.
#[derive(Clone, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum RawAir {
    Standard {
        #[serde(default)]
        ground: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        temperature: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pressure: Option<f64>,
    },
    Uniform {
        temperature: f64,
        pressure: f64,
    },
}

impl Default for RawAir {
    fn default() -> Self {
        RawAir::Standard {
            ground: 0.0,
            temperature: None,
            pressure: None,
        }
    }
}

/// The wind as written: its velocity (m/s) at a reference height (m, default 10) and the
/// profile's exponent (default 0: the same wind at every height).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWind {
    pub(super) velocity: DVec3,
    #[serde(default = "ten")]
    pub(super) reference_height: f64,
    #[serde(default)]
    pub(super) exponent: f64,
}

impl RawMachDrag {
    /// The term as a scene file writes it back.
    fn of(d: &MachDrag) -> RawMachDrag {
        let curve = match &d.curve {
            DragCurve::G1 => RawCurve::G1,
            DragCurve::G7 => RawCurve::G7,
            DragCurve::Sphere => RawCurve::Sphere,
            DragCurve::Table(t) => RawCurve::Table(t.points().collect()),
        };
        let (bc, diameter, form_factor) = match d.size {
            DragSize::Ballistic(bc) => (Some(bc / KG_M2_PER_LB_IN2), None, None),
            DragSize::Diameter {
                diameter,
                form_factor,
            } => (None, Some(diameter), Some(form_factor)),
        };
        let air = match &d.air {
            AirModel::Uniform(air) => RawAir::Uniform {
                temperature: air.temperature,
                pressure: air.pressure,
            },
            AirModel::Standard {
                ground,
                temperature,
                pressure,
                ..
            } => RawAir::Standard {
                ground: *ground,
                temperature: *temperature,
                pressure: *pressure,
            },
        };
        let wind = d.wind.map(|w| RawWind {
            velocity: w.velocity,
            reference_height: w.reference_height,
            exponent: w.exponent,
        });
        let spin = d.spin.map(|s| RawSpin {
            lift: s.lift,
            decay: s.decay,
            drag_per_1000_rpm: s.drag_per_spin * (1000.0 * RAD_S_PER_RPM),
        });
        RawMachDrag {
            curve,
            interpolation: d.interpolation,
            bc,
            diameter,
            form_factor,
            air,
            wind,
            spin,
        }
    }
}

impl ForceTerm {
    pub(super) fn kind(&self) -> ForceKind {
        match self {
            ForceTerm::Gravity(_) => ForceKind::Gravity,
            ForceTerm::ConstantForce(_) => ForceKind::ConstantForce,
            ForceTerm::LinearDrag(_) => ForceKind::LinearDrag,
            ForceTerm::QuadraticDrag(_) => ForceKind::QuadraticDrag,
            ForceTerm::Spring { .. } => ForceKind::Spring,
            ForceTerm::PointMass { .. } => ForceKind::PointMass,
            ForceTerm::MachDrag { .. } => ForceKind::MachDrag,
            ForceTerm::Custom { .. } => ForceKind::Custom,
            ForceTerm::Thrust { .. } => ForceKind::Thrust,
        }
    }
}

/// A launch as written in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum Launch {
    Velocity(DVec3),
    Angles {
        speed: f64,
        elevation_deg: f64,
        #[serde(default)]
        azimuth_deg: f64,
    },
    Aim {
        target: DVec3,
        speed: f64,
        arc: Arc,
    },
}

#[derive(Debug, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBody {
    pub(super) mass: f64,
    #[serde(default = "tenth")]
    pub(super) radius: f64,
    pub(super) position: DVec3,
    #[serde(default = "at_rest")]
    pub(super) launch: Launch,
    #[serde(default, skip_serializing_if = "is_zero3")]
    pub(super) spin: DVec3,
}

fn is_zero3(v: &DVec3) -> bool {
    *v == DVec3::ZERO
}

pub(super) fn at_rest() -> Launch {
    Launch::Velocity(DVec3::ZERO)
}

#[derive(Debug, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub(super) struct RawScene {
    #[serde(default)]
    pub(super) name: Option<String>,
    #[serde(default)]
    pub(super) description: String,
    pub(super) dt: f64,
    #[serde(default)]
    pub(super) start_time: f64,
    #[serde(default = "ten")]
    pub(super) duration: f64,
    pub(super) integrator: Integrator,
    #[serde(default = "one_u32")]
    pub(super) substeps: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) tolerance: Option<f64>,
    #[serde(default)]
    pub(super) forces: Vec<ForceTerm>,
    #[serde(default)]
    pub(super) ground: Option<Ground>,
    #[serde(default)]
    pub(super) walls: Vec<Wall>,
    #[serde(default)]
    pub(super) targets: Vec<Target>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) meshes: Vec<levels::RawMesh>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) heightfields: Vec<levels::RawHeightfield>,
    #[serde(default)]
    pub(super) detection: Detection,
    #[serde(default)]
    pub(super) bodies: Vec<RawBody>,
    #[serde(default)]
    pub(super) launcher: Option<Launcher>,
    #[serde(default)]
    pub(super) volley: Option<Volley>,
    #[serde(default)]
    pub(super) seed: u64,
    #[serde(default)]
    pub(super) guard: Guard,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) compare: Vec<CompareLane>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) events: Vec<RawEvent>,
}

/// A declared event as written: `(name: "...", body: id, when: ..., direction: ..., stop: ...)`,
/// all but `when` optional.
#[derive(Clone, Debug, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEvent {
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub(super) name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) body: Option<u64>,
    pub(super) when: EventCondition,
    #[serde(default, skip_serializing_if = "is_either")]
    pub(super) direction: EventDirection,
    #[serde(default, skip_serializing_if = "is_never")]
    pub(super) stop: EventStop,
}

fn is_either(d: &EventDirection) -> bool {
    *d == EventDirection::Either
}

fn is_never(s: &EventStop) -> bool {
    *s == EventStop::Never
}

impl RawEvent {
    /// The event as a scene file writes it back.
    fn of(e: &EventSpec) -> RawEvent {
        RawEvent {
            name: e.name.clone(),
            body: e.body.map(|b| b.0),
            when: e.condition,
            direction: e.direction,
            stop: e.stop,
        }
    }
}

fn is_pchip(i: &Interpolation) -> bool {
    *i == Interpolation::Pchip
}

pub(super) fn one_u32() -> u32 {
    1
}

pub(super) fn ten() -> f64 {
    10.0
}
