//! Validation: a raw scene to a [`Scene`], every value checked and every error naming its
//! field.

use std::time::Duration;

use glam::DVec3;

use super::raw::*;
use super::*;

/// At most [`MAX_TICK_WORK`] body-steps a tick in the scene's own lane and in each compare lane.
pub(super) fn check_tick_work(raw: &RawScene, bodies: u64) -> Result<(), InvalidValue> {
    let lanes = raw.compare.iter().enumerate();
    let asked = std::iter::once(("substeps".to_string(), raw.substeps)).chain(
        lanes.filter_map(|(i, l)| l.substeps.map(|n| (format!("compare[{i}].substeps"), n))),
    );
    for (field, substeps) in asked {
        if bodies.max(1) * u64::from(substeps) > MAX_TICK_WORK {
            return Err(invalid(field, ValueProblem::TickWork { bodies, substeps }));
        }
    }
    Ok(())
}

pub(super) fn invalid(field: impl Into<String>, problem: ValueProblem) -> InvalidValue {
    InvalidValue {
        field: field.into(),
        problem,
    }
}

pub(super) fn finite(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotFinite(x)))
    }
}

pub(super) fn positive(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotPositive(x)))
    }
}

pub(super) fn non_negative(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotNonNegative(x)))
    }
}

pub(super) fn unit_interval(field: &str, x: f64) -> Result<f64, InvalidValue> {
    if (0.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(invalid(field, ValueProblem::NotUnitInterval(x)))
    }
}

pub(super) fn finite3(field: &str, v: DVec3) -> Result<DVec3, InvalidValue> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(field, ValueProblem::NotFiniteVector(v)))
    }
}

/// Converts a step in seconds to whole nanoseconds, the clock's unit; errors name `field`.
pub fn timestep_from_secs(field: &str, dt: f64) -> Result<Duration, InvalidValue> {
    let dt = positive(field, dt)?;
    let nanos = (dt * 1e9).round();
    if !(1.0..=1e12).contains(&nanos) {
        return Err(invalid(field, ValueProblem::Step(dt)));
    }
    Ok(Duration::from_nanos(nanos as u64))
}

pub(super) fn validate(
    raw: RawScene,
    text: &str,
    default_name: &str,
    terms: &ForceTerms,
    files: &LevelFiles,
) -> Result<Scene, InvalidValue> {
    let timestep = timestep_from_secs("dt", raw.dt)?;
    let start_time = finite("start_time", raw.start_time)?;
    let duration = non_negative("duration", raw.duration)?;
    let integrator = raw.integrator;
    if !(1..=MAX_SUBSTEPS).contains(&raw.substeps) {
        return Err(invalid("substeps", ValueProblem::Substeps(raw.substeps)));
    }
    let tolerance = match raw.tolerance {
        Some(x) => check_tolerance("tolerance", x)?,
        None => DEFAULT_TOLERANCE,
    };
    let forces = validate_forces(&raw.forces, terms)?;
    check_integrator(integrator, &forces)
        .map_err(|e| invalid("integrator", ValueProblem::Integrator(e)))?;
    if raw.compare.len() > MAX_COMPARE_LANES {
        return Err(invalid(
            "compare",
            ValueProblem::TooManyLanes(raw.compare.len()),
        ));
    }
    // A volley too large on its own is said of its count, below.
    let total = raw.bodies.len() as u64 + raw.volley.map_or(0, |v| u64::from(v.count));
    if total > MAX_BODIES as u64 && raw.volley.is_none_or(|v| v.count <= MAX_VOLLEY) {
        let field = if raw.volley.is_some() {
            "volley.count"
        } else {
            "bodies"
        };
        return Err(invalid(field, ValueProblem::TooManyBodies(total)));
    }
    for (i, lane) in raw.compare.iter().enumerate() {
        check_integrator(lane.integrator, &forces).map_err(|e| {
            invalid(
                format!("compare[{i}].integrator"),
                ValueProblem::Integrator(e),
            )
        })?;
        if let Some(dt) = lane.dt {
            timestep_from_secs(&format!("compare[{i}].dt"), dt)?;
        }
        if let Some(n) = lane.substeps
            && !(1..=MAX_SUBSTEPS).contains(&n)
        {
            return Err(invalid(
                format!("compare[{i}].substeps"),
                ValueProblem::Substeps(n),
            ));
        }
    }
    check_tick_work(&raw, total)?;
    let ground = raw
        .ground
        .map(|g| -> Result<Ground, InvalidValue> {
            finite("ground.height", g.height)?;
            unit_interval("ground.restitution", g.restitution)?;
            Ok(g)
        })
        .transpose()?;
    let walls = raw
        .walls
        .iter()
        .enumerate()
        .map(|(i, w)| validate_wall(i, w))
        .collect::<Result<Vec<_>, _>>()?;
    for (i, t) in raw.targets.iter().enumerate() {
        finite3(&format!("targets[{i}].center"), t.center)?;
        finite3(&format!("targets[{i}].velocity"), t.velocity)?;
        positive(&format!("targets[{i}].radius"), t.radius)?;
    }
    let meshes = raw
        .meshes
        .iter()
        .enumerate()
        .map(|(i, m)| super::levels::validate_mesh(i, m, files))
        .collect::<Result<Vec<_>, _>>()?;
    let triangles: usize = meshes.iter().map(|m| m.geometry.triangles.len()).sum();
    if triangles > super::levels::MAX_LEVEL_TRIANGLES {
        return Err(invalid(
            "meshes",
            ValueProblem::Level(format!(
                "{triangles} triangles in all, more than the {} a scene may have",
                super::levels::MAX_LEVEL_TRIANGLES
            )),
        ));
    }
    let heightfields = raw
        .heightfields
        .iter()
        .enumerate()
        .map(|(i, h)| super::levels::validate_heightfield(i, h, files))
        .collect::<Result<Vec<_>, _>>()?;
    let bodies = raw
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| validate_body(i, b, &forces))
        .collect::<Result<Vec<_>, _>>()?;
    let launcher = match raw.launcher {
        Some(l) => validate_launcher(l)?,
        None => default_launcher(bodies.first()),
    };
    if let Some(t) = &forces.thrust {
        check_propellant("launcher.mass", launcher.mass, t.propellant)?;
    }
    if let Some(v) = raw.volley {
        if v.count > MAX_VOLLEY {
            return Err(invalid("volley.count", ValueProblem::VolleyCount(v.count)));
        }
        non_negative("volley.speed_spread", v.speed_spread)?;
        non_negative("volley.angle_spread_deg", v.angle_spread_deg)?;
    }
    if raw.events.len() > MAX_EVENTS {
        return Err(invalid(
            "events",
            ValueProblem::TooManyEvents(raw.events.len()),
        ));
    }
    let events = raw
        .events
        .iter()
        .enumerate()
        .map(|(i, e)| validate_event(i, e, raw.targets.len(), &forces))
        .collect::<Result<Vec<_>, _>>()?;
    if !(raw.guard.energy_factor.is_finite() && raw.guard.energy_factor > 1.0) {
        return Err(invalid(
            "guard.energy_factor",
            ValueProblem::EnergyFactor(raw.guard.energy_factor),
        ));
    }
    Ok(Scene {
        name: raw.name.unwrap_or_else(|| default_name.to_string()),
        description: raw.description,
        source: text.to_string(),
        timestep,
        start_time,
        duration,
        integrator,
        substeps: raw.substeps,
        forces,
        ground,
        walls,
        targets: raw.targets,
        meshes,
        heightfields,
        level_dir: files.dir.clone(),
        compare: raw.compare,
        tolerance,
        detection: raw.detection,
        bodies,
        launcher,
        volley: raw.volley,
        seed: raw.seed,
        guard: raw.guard,
        events,
    })
}

/// A declared event: finite numbers, a non-zero normal (made unit), a speed >= 0, a Mach
/// number > 0 in a scene with a Mach drag (whose air it is read in), a target the scene has,
/// a stop count of at least 1.
pub(super) fn validate_event(
    i: usize,
    e: &RawEvent,
    targets: usize,
    forces: &Forces,
) -> Result<EventSpec, InvalidValue> {
    let field = |name: &str| format!("events[{i}].{name}");
    let condition = match e.when {
        EventCondition::Plane { point, normal } => {
            finite3(&field("when.point"), point)?;
            let normal = unit_vector(&field("when.normal"), normal)?;
            EventCondition::Plane { point, normal }
        }
        EventCondition::Altitude(z) => EventCondition::Altitude(finite(&field("when"), z)?),
        EventCondition::Downrange(x) => EventCondition::Downrange(finite(&field("when"), x)?),
        EventCondition::Speed(v) => EventCondition::Speed(non_negative(&field("when"), v)?),
        EventCondition::Mach(m) => {
            let m = positive(&field("when"), m)?;
            if forces.mach_drag.is_none() {
                return Err(invalid(field("when"), ValueProblem::MachNeedsAir));
            }
            EventCondition::Mach(m)
        }
        EventCondition::Apex => EventCondition::Apex,
        EventCondition::Closest { point, velocity } => EventCondition::Closest {
            point: finite3(&field("when.point"), point)?,
            velocity: finite3(&field("when.velocity"), velocity)?,
        },
        EventCondition::ClosestToTarget(t) => {
            if t as usize >= targets {
                return Err(invalid(
                    field("when"),
                    ValueProblem::UnknownTarget { index: t, targets },
                ));
            }
            EventCondition::ClosestToTarget(t)
        }
    };
    if let EventStop::Body(0) | EventStop::Run(0) = e.stop {
        return Err(invalid(field("stop"), ValueProblem::StopCount));
    }
    Ok(EventSpec {
        name: e.name.clone(),
        body: e.body.map(crate::body::BodyId),
        condition,
        direction: e.direction,
        stop: e.stop,
    })
}

/// Refuses `exact` for forces without a closed form, and Forest-Ruth for velocity terms it
/// cannot solve (Mach drag, a velocity-dependent custom term), naming the force.
pub fn check_integrator(integrator: Integrator, forces: &Forces) -> Result<(), IntegratorError> {
    match integrator {
        Integrator::Exact => match forces.without_closed_form() {
            Some(kind) => Err(IntegratorError::NoClosedForm(kind)),
            None => Ok(()),
        },
        Integrator::ForestRuth if forces.thrust.is_some() => {
            Err(IntegratorError::NoVelocitySolve(ForceKind::Thrust))
        }
        Integrator::ForestRuth if forces.mach_drag.is_some() => {
            Err(IntegratorError::NoVelocitySolve(ForceKind::MachDrag))
        }
        Integrator::ForestRuth if forces.custom.iter().any(|c| c.reads().velocity) => {
            Err(IntegratorError::NoVelocitySolve(ForceKind::Custom))
        }
        _ => Ok(()),
    }
}

/// The declared terms, checked, with a game's own resolved in `terms`. Each built-in kind at
/// most once; several custom terms, each name once.
pub(super) fn validate_forces(
    declared: &[ForceTerm],
    terms: &ForceTerms,
) -> Result<Forces, InvalidValue> {
    let mut forces = Forces::default();
    for (i, term) in declared.iter().enumerate() {
        let field = format!("forces[{i}]");
        if let ForceTerm::Custom { name, .. } = term {
            if forces.custom.iter().any(|c| c.name() == name) {
                return Err(invalid(field, ValueProblem::DuplicateTerm(name.clone())));
            }
        } else if forces.has(term.kind()) {
            return Err(invalid(field, ValueProblem::DuplicateForce(term.kind())));
        }
        match term.clone() {
            ForceTerm::Gravity(g) => forces.gravity = Some(finite3(&field, g)?),
            ForceTerm::ConstantForce(f) => forces.constant = Some(finite3(&field, f)?),
            ForceTerm::LinearDrag(b) => forces.linear_drag = Some(non_negative(&field, b)?),
            ForceTerm::QuadraticDrag(c) => forces.quadratic_drag = Some(non_negative(&field, c)?),
            ForceTerm::Spring {
                anchor,
                stiffness,
                rest_length,
                damping,
            } => {
                forces.spring = Some(Spring {
                    anchor: finite3(&format!("{field}.anchor"), anchor)?,
                    stiffness: non_negative(&format!("{field}.stiffness"), stiffness)?,
                    rest_length: non_negative(&format!("{field}.rest_length"), rest_length)?,
                    damping: non_negative(&format!("{field}.damping"), damping)?,
                });
            }
            ForceTerm::PointMass { center, mu } => {
                forces.point_mass = Some(PointMass {
                    center: finite3(&format!("{field}.center"), center)?,
                    mu: positive(&format!("{field}.mu"), mu)?,
                });
            }
            ForceTerm::MachDrag {
                curve,
                interpolation,
                bc,
                diameter,
                form_factor,
                air,
                wind,
                spin,
            } => {
                let raw = RawMachDrag {
                    curve,
                    interpolation,
                    bc,
                    diameter,
                    form_factor,
                    air,
                    wind,
                    spin,
                };
                forces.mach_drag = Some(validate_mach_drag(&field, &raw)?);
            }
            ForceTerm::Custom { name, version } => {
                forces.custom.push(
                    terms
                        .resolve(&name, version)
                        .map_err(|e| invalid(field, ValueProblem::Custom(e)))?,
                );
            }
            ForceTerm::Thrust {
                curve,
                propellant,
                direction,
            } => {
                let curve = crate::forces::ThrustCurve::new(curve)
                    .map_err(|e| invalid(format!("{field}.curve"), ValueProblem::ThrustCurve(e)))?;
                let unit = |d: DVec3| unit_vector(&format!("{field}.direction"), d);
                forces.thrust = Some(Thrust {
                    curve: std::sync::Arc::new(curve),
                    propellant: non_negative(&format!("{field}.propellant"), propellant)?,
                    direction: match direction {
                        RawThrustDirection::Fixed(d) => ThrustDirection::Fixed(unit(d)?),
                        RawThrustDirection::Velocity {
                            along,
                            rail_exit_speed,
                        } => ThrustDirection::Velocity {
                            along: unit(along)?,
                            rail_exit_speed: non_negative(
                                &format!("{field}.direction.rail_exit_speed"),
                                rail_exit_speed,
                            )?,
                        },
                    },
                });
            }
        }
    }
    Ok(forces)
}

/// A Mach drag term's values: a valid curve; exactly one of a ballistic coefficient (> 0,
/// lb/in^2) or a diameter (> 0, m) with a form factor (> 0); finite temperatures and pressures
/// (> 0) and ground altitude; a finite wind with a reference height > 0 and an exponent >= 0.
fn validate_mach_drag(field: &str, raw: &RawMachDrag) -> Result<MachDrag, InvalidValue> {
    let curve = match &raw.curve {
        RawCurve::G1 => DragCurve::G1,
        RawCurve::G7 => DragCurve::G7,
        RawCurve::Sphere => DragCurve::Sphere,
        RawCurve::Table(points) => DragCurve::Table(std::sync::Arc::new(
            crate::drag::DragTable::new(points)
                .map_err(|e| invalid(format!("{field}.curve"), ValueProblem::DragTable(e)))?,
        )),
    };
    let size = match (raw.bc, raw.diameter, raw.form_factor) {
        (Some(bc), None, None) => {
            DragSize::Ballistic(positive(&format!("{field}.bc"), bc)? * KG_M2_PER_LB_IN2)
        }
        (None, Some(d), form_factor) => DragSize::Diameter {
            diameter: positive(&format!("{field}.diameter"), d)?,
            form_factor: positive(&format!("{field}.form_factor"), form_factor.unwrap_or(1.0))?,
        },
        _ => return Err(invalid(field, ValueProblem::DragSize)),
    };
    let air = match raw.air.clone() {
        RawAir::Standard {
            ground,
            temperature,
            pressure,
        } => {
            let ground = finite(&format!("{field}.air.ground"), ground)?;
            // The column is tabulated from 1 km below the ground to 30 km up: a ground far
            // below sea level would make it a table of millions of nodes.
            if !(-1000.0..=20_000.0).contains(&ground) {
                return Err(invalid(
                    format!("{field}.air.ground"),
                    ValueProblem::Altitude(ground),
                ));
            }
            let temperature = temperature
                .map(|t| positive(&format!("{field}.air.temperature"), t))
                .transpose()?;
            let pressure = pressure
                .map(|p| positive(&format!("{field}.air.pressure"), p))
                .transpose()?;
            AirModel::standard(ground, temperature, pressure)
        }
        RawAir::Uniform {
            temperature,
            pressure,
        } => AirModel::uniform(
            positive(&format!("{field}.air.temperature"), temperature)?,
            positive(&format!("{field}.air.pressure"), pressure)?,
        ),
    };
    let wind = raw
        .wind
        .map(|w| {
            Ok::<_, InvalidValue>(Wind {
                velocity: finite3(&format!("{field}.wind.velocity"), w.velocity)?,
                reference_height: positive(
                    &format!("{field}.wind.reference_height"),
                    w.reference_height,
                )?,
                exponent: non_negative(&format!("{field}.wind.exponent"), w.exponent)?,
            })
        })
        .transpose()?;
    let spin = raw
        .spin
        .map(|s| {
            if !matches!(size, DragSize::Diameter { .. }) {
                return Err(invalid(
                    format!("{field}.spin"),
                    ValueProblem::SpinNeedsDiameter,
                ));
            }
            let tau = format!("{field}.spin.decay");
            let decay = match s.decay {
                SpinDecay::None => SpinDecay::None,
                SpinDecay::Time(t) => SpinDecay::Time(positive(&tau, t)?),
                SpinDecay::Nathan(t) => SpinDecay::Nathan(positive(&tau, t)?),
            };
            let per_krpm = non_negative(
                &format!("{field}.spin.drag_per_1000_rpm"),
                s.drag_per_1000_rpm,
            )?;
            Ok(SpinLift {
                lift: s.lift,
                decay,
                drag_per_spin: per_krpm / (1000.0 * RAD_S_PER_RPM),
            })
        })
        .transpose()?;
    Ok(MachDrag {
        curve,
        interpolation: raw.interpolation,
        size,
        air,
        wind,
        spin,
    })
}

/// `v` scaled to unit length, refusing a zero or non-finite vector. A vector already of unit
/// length to rounding is kept as written: normalising it again could move its last bit, and a
/// saved setup (which writes the vector used) would then step to other bits than the scene it
/// was saved from.
fn unit_vector(field: &str, v: DVec3) -> Result<DVec3, InvalidValue> {
    let v = finite3(field, v)?;
    if (v.length_squared() - 1.0).abs() <= 8.0 * f64::EPSILON {
        return Ok(v);
    }
    v.try_normalize()
        .ok_or_else(|| invalid(field, ValueProblem::ZeroVector))
}

pub(super) fn validate_wall(i: usize, w: &Wall) -> Result<Wall, InvalidValue> {
    finite3(&format!("walls[{i}].point"), w.point)?;
    let unit = unit_vector(&format!("walls[{i}].normal"), w.normal)?;
    positive(&format!("walls[{i}].thickness"), w.thickness)?;
    unit_interval(&format!("walls[{i}].restitution"), w.restitution)?;
    Ok(Wall { normal: unit, ..*w })
}

pub(super) fn validate_body(
    i: usize,
    b: &RawBody,
    forces: &Forces,
) -> Result<BodySpec, InvalidValue> {
    let at = |f: &str| format!("bodies[{i}].{f}");
    let mass = positive(&at("mass"), b.mass)?;
    let radius = non_negative(&at("radius"), b.radius)?;
    let position = finite3(&at("position"), b.position)?;
    let velocity = match b.launch {
        Launch::Velocity(v) => finite3(&at("launch"), v)?,
        Launch::Angles {
            speed,
            elevation_deg,
            azimuth_deg,
        } => {
            non_negative(&at("launch.speed"), speed)?;
            finite(&at("launch.elevation_deg"), elevation_deg)?;
            finite(&at("launch.azimuth_deg"), azimuth_deg)?;
            angles_to_velocity(speed, elevation_deg, azimuth_deg)
        }
        Launch::Aim { target, speed, arc } => {
            finite3(&at("launch.target"), target)?;
            positive(&at("launch.speed"), speed)?;
            let g = forces.gravity.unwrap_or(DVec3::ZERO);
            if g.x != 0.0 || g.y != 0.0 || g.z >= 0.0 {
                return Err(invalid(at("launch"), ValueProblem::AimNeedsGravity));
            }
            let [high, low] = aim(position, target, speed, -g.z)
                .map_err(|e| invalid(at("launch"), ValueProblem::CannotAim(e)))?;
            match arc {
                Arc::High => high.velocity,
                Arc::Low => low.velocity,
            }
        }
    };
    let spin = finite3(&at("spin"), b.spin)?;
    if let Some(t) = &forces.thrust {
        check_propellant(&at("mass"), mass, t.propellant)?;
    }
    Ok(BodySpec {
        mass,
        radius,
        position,
        velocity,
        spin,
    })
}

/// A body's mass at launch must exceed the motor's propellant: what is left at burnout is > 0.
pub(crate) fn check_propellant(
    field: &str,
    mass: f64,
    propellant: f64,
) -> Result<(), InvalidValue> {
    if mass > propellant {
        Ok(())
    } else {
        Err(invalid(
            field,
            ValueProblem::Propellant { mass, propellant },
        ))
    }
}

pub(super) fn validate_launcher(l: Launcher) -> Result<Launcher, InvalidValue> {
    finite3("launcher.position", l.position)?;
    non_negative("launcher.speed", l.speed)?;
    finite("launcher.elevation_deg", l.elevation_deg)?;
    finite("launcher.azimuth_deg", l.azimuth_deg)?;
    positive("launcher.mass", l.mass)?;
    non_negative("launcher.radius", l.radius)?;
    finite("launcher.backspin", l.backspin)?;
    finite("launcher.sidespin", l.sidespin)?;
    Ok(l)
}

/// The launcher implied by the first body (its position, mass, size and launch), or a 20 m/s,
/// 45 degree launcher at the origin for a scene without bodies.
pub(super) fn default_launcher(first: Option<&BodySpec>) -> Launcher {
    match first {
        Some(b) => {
            let v = b.velocity;
            let horizontal = (v.x * v.x + v.y * v.y).sqrt();
            Launcher {
                position: b.position,
                speed: v.length(),
                elevation_deg: libm::atan2(v.z, horizontal).to_degrees(),
                azimuth_deg: libm::atan2(v.y, v.x).to_degrees(),
                mass: b.mass,
                radius: b.radius,
                backspin: 0.0,
                sidespin: 0.0,
            }
        }
        None => Launcher {
            position: DVec3::ZERO,
            speed: 20.0,
            elevation_deg: 45.0,
            azimuth_deg: 0.0,
            mass: 1.0,
            radius: 0.1,
            backspin: 0.0,
            sidespin: 0.0,
        },
    }
}
