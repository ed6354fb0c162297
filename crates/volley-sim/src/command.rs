//! Tick-stamped commands: everything that changes a simulation from outside.
//!
//! The window's buttons and keys, a headless command script and a replay all produce the same
//! [`Command`] values, applied by [`World::apply`] at a tick boundary (before the step from tick
//! `t` to `t + 1` for a command stamped `t`), never inside a step. Together with the scene they
//! are all a replay needs to store.
//!
//! # Script format
//!
//! One command per line, `TICK: COMMAND`; `#` starts a comment; ticks never decrease; several
//! commands at one tick apply in file order.
//!
//! ```text
//! 0:   launch speed=25 elevation=40 azimuth=0
//! 10:  fire
//! 20:  spawn mass=1 radius=0.1 position=0,0,1 velocity=3,0,4
//! 30:  force LinearDrag off
//! 40:  integrator rk4
//! 50:  despawn 0
//! 60:  reset
//! ```

use glam::DVec3;

use crate::forces::ForceKind;
use crate::integrate::Integrator;
use crate::scene::{BodySpec, IntegratorError, MAX_BODIES, check_integrator};
use crate::world::{BodyId, World};

mod parse;

pub use parse::{CommandParseError, MAX_SCRIPT_COMMANDS, ScriptError, ScriptProblem, parse_script};

/// A change applied to the world at a tick boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// Spawn a projectile from the launcher.
    Fire,
    /// Spawn a body with the given state.
    Spawn(BodySpec),
    /// Remove a body.
    Despawn(BodyId),
    /// Change the launcher; `None` fields keep their value.
    SetLaunch {
        /// Launch speed (m/s).
        speed: Option<f64>,
        /// Elevation (degrees).
        elevation_deg: Option<f64>,
        /// Azimuth (degrees).
        azimuth_deg: Option<f64>,
        /// Muzzle position (m).
        position: Option<DVec3>,
    },
    /// Turn a declared force term off or back on.
    SetForce {
        /// Which term.
        kind: ForceKind,
        /// On or off.
        enabled: bool,
    },
    /// Switch the integrator.
    SetIntegrator(Integrator),
    /// Bodies, launcher, force terms and generator back to the scene's; the tick keeps
    /// counting (sim time never goes back), and the integrator stays as chosen. A divergence is
    /// cleared: the reset is a fresh start of the scene's bodies, so a stopped world steps again.
    Reset,
}

/// A command and the tick it applies at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stamped {
    /// Applied before the step from this tick.
    pub tick: u64,
    /// The command.
    pub command: Command,
}

/// Why a command could not be applied to the world ([`World::apply`]); what reading one can
/// fail with is [`CommandParseError`].
#[derive(Clone, Debug, PartialEq)]
pub enum CommandError {
    /// `despawn` of a body the world does not have.
    NoSuchBody(BodyId),
    /// `launch` with a value that is not finite, or a negative speed.
    InvalidLaunch,
    /// `force` of a term the scene does not declare.
    UndeclaredForce {
        /// The term asked for.
        kind: ForceKind,
        /// The terms the scene declares, in declaration order.
        declared: Vec<ForceKind>,
    },
    /// An integrator the (resulting) forces refuse.
    Integrator(IntegratorError),
    /// `fire` or `spawn` in a world that already holds [`MAX_BODIES`] bodies.
    TooManyBodies,
    /// `spawn` with a mass that is not a finite number > 0.
    SpawnMass(f64),
    /// `spawn` with a radius that is not a finite number >= 0.
    SpawnRadius(f64),
    /// `spawn` with a position, velocity or spin that is not finite.
    SpawnState,
    /// `spawn` of a body not heavier than the scene's motor's propellant.
    SpawnPropellant {
        /// The body's mass (kg).
        mass: f64,
        /// The propellant (kg).
        propellant: f64,
    },
}

impl std::fmt::Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CommandError::NoSuchBody(id) => write!(f, "despawn: there is no body {id}"),
            CommandError::InvalidLaunch => {
                f.write_str("launch: values must be finite and the speed >= 0")
            }
            CommandError::UndeclaredForce { kind, declared } => write!(
                f,
                "force: the scene does not declare {} (declared: {})",
                kind.name(),
                declared
                    .iter()
                    .map(|k| k.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            CommandError::Integrator(e) => write!(f, "{e}"),
            CommandError::TooManyBodies => write!(
                f,
                "the world already holds {MAX_BODIES} bodies, the most it may hold"
            ),
            CommandError::SpawnMass(m) => write!(f, "spawn: mass must be > 0, got {m}"),
            CommandError::SpawnRadius(r) => write!(f, "spawn: radius must be >= 0, got {r}"),
            CommandError::SpawnState => {
                f.write_str("spawn: position, velocity and spin must be finite")
            }
            CommandError::SpawnPropellant { mass, propellant } => write!(
                f,
                "spawn: mass must be more than the motor's {propellant} kg of propellant, got {mass}"
            ),
        }
    }
}

impl std::error::Error for CommandError {}

impl World {
    /// Applies one command at the current tick boundary.
    pub fn apply(&mut self, command: &Command) -> Result<(), CommandError> {
        match *command {
            Command::Fire | Command::Spawn(_) if self.bodies().len() >= MAX_BODIES => {
                return Err(CommandError::TooManyBodies);
            }
            Command::Fire => {
                let body = self.state.launcher.body();
                self.spawn(&body);
            }
            Command::Spawn(spec) => {
                check_spec(&spec)?;
                if let Some(t) = &self.state.forces.thrust
                    && spec.mass <= t.propellant
                {
                    return Err(CommandError::SpawnPropellant {
                        mass: spec.mass,
                        propellant: t.propellant,
                    });
                }
                self.spawn(&spec);
            }
            Command::Despawn(id) => {
                if !self.despawn(id) {
                    return Err(CommandError::NoSuchBody(id));
                }
            }
            Command::SetLaunch {
                speed,
                elevation_deg,
                azimuth_deg,
                position,
            } => {
                let numbers = [speed, elevation_deg, azimuth_deg];
                if numbers.iter().flatten().any(|x| !x.is_finite())
                    || position.is_some_and(|p| !p.is_finite())
                    || speed.is_some_and(|s| s < 0.0)
                {
                    return Err(CommandError::InvalidLaunch);
                }
                let l = &mut self.state.launcher;
                l.speed = speed.unwrap_or(l.speed);
                l.elevation_deg = elevation_deg.unwrap_or(l.elevation_deg);
                l.azimuth_deg = azimuth_deg.unwrap_or(l.azimuth_deg);
                l.position = position.unwrap_or(l.position);
            }
            Command::SetForce { kind, enabled } => {
                let declared = self.params.declared.clone();
                if !declared.has(kind) {
                    return Err(CommandError::UndeclaredForce {
                        kind,
                        declared: declared.kinds().collect(),
                    });
                }
                let candidate = if enabled {
                    // The declared terms that are on, and this one: every kind, so a term added
                    // later cannot be forgotten here.
                    let active = &self.state.forces;
                    declared.filtered(|k| k == kind || active.has(k))
                } else {
                    self.state.forces.clone().without(kind)
                };
                check_integrator(self.state.integrator, &candidate)
                    .map_err(CommandError::Integrator)?;
                self.state.forces = candidate;
                self.facts = crate::world::ForceFacts::of(&self.state.forces);
            }
            Command::SetIntegrator(integrator) => {
                check_integrator(integrator, &self.state.forces)
                    .map_err(CommandError::Integrator)?;
                self.state.integrator = integrator;
            }
            Command::Reset => {
                self.clear_bodies();
                self.state.forces = self.params.declared.clone();
                self.facts = crate::world::ForceFacts::of(&self.state.forces);
                self.state.launcher = self.scene.launcher;
                self.state.rng = crate::world::SplitMix64(self.scene.seed);
                self.populate();
                self.halt = crate::world::Halt::Running;
            }
        }
        self.carry_valid = false;
        // Forces, integrator or bodies may have changed: every horizon is void, but for a
        // spawn's or a despawn's, which keep the others' ([`World::spawn`]).
        if !matches!(
            command,
            Command::Fire | Command::Spawn(_) | Command::Despawn(_)
        ) {
            self.scratch.due.clear();
        }
        self.rebase_energy_caps();
        Ok(())
    }
}

fn check_spec(spec: &BodySpec) -> Result<(), CommandError> {
    if !(spec.mass.is_finite() && spec.mass > 0.0) {
        return Err(CommandError::SpawnMass(spec.mass));
    }
    if !(spec.radius.is_finite() && spec.radius >= 0.0) {
        return Err(CommandError::SpawnRadius(spec.radius));
    }
    if !(spec.position.is_finite() && spec.velocity.is_finite() && spec.spin.is_finite()) {
        return Err(CommandError::SpawnState);
    }
    Ok(())
}

fn vec3(v: DVec3) -> String {
    format!("{},{},{}", v.x, v.y, v.z)
}

impl std::fmt::Display for Command {
    /// The script form; floats print in their shortest form that reads back to the same bits.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Command::Fire => f.write_str("fire"),
            Command::Spawn(s) => {
                write!(
                    f,
                    "spawn mass={} radius={} position={} velocity={}",
                    s.mass,
                    s.radius,
                    vec3(s.position),
                    vec3(s.velocity)
                )?;
                if s.spin != DVec3::ZERO {
                    write!(f, " spin={}", vec3(s.spin))?;
                }
                Ok(())
            }
            Command::Despawn(id) => write!(f, "despawn {id}"),
            Command::SetLaunch {
                speed,
                elevation_deg,
                azimuth_deg,
                position,
            } => {
                f.write_str("launch")?;
                if let Some(x) = speed {
                    write!(f, " speed={x}")?;
                }
                if let Some(x) = elevation_deg {
                    write!(f, " elevation={x}")?;
                }
                if let Some(x) = azimuth_deg {
                    write!(f, " azimuth={x}")?;
                }
                if let Some(p) = position {
                    write!(f, " position={}", vec3(*p))?;
                }
                Ok(())
            }
            Command::SetForce { kind, enabled } => {
                write!(
                    f,
                    "force {} {}",
                    kind.name(),
                    if *enabled { "on" } else { "off" }
                )
            }
            Command::SetIntegrator(i) => write!(f, "integrator {}", i.name()),
            Command::Reset => f.write_str("reset"),
        }
    }
}

impl std::fmt::Display for Stamped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.tick, self.command)
    }
}

#[cfg(test)]
mod tests;
