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
use crate::scene::{BodySpec, check_integrator};
use crate::world::{BodyId, World};

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

/// Why a command could not be applied or parsed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CommandError(pub String);

impl std::fmt::Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CommandError {}

fn err<T>(message: impl Into<String>) -> Result<T, CommandError> {
    Err(CommandError(message.into()))
}

impl World {
    /// Applies one command at the current tick boundary.
    pub fn apply(&mut self, command: &Command) -> Result<(), CommandError> {
        match *command {
            Command::Fire => {
                let l = self.launcher;
                self.spawn(&BodySpec {
                    mass: l.mass,
                    radius: l.radius,
                    position: l.position,
                    velocity: l.velocity(),
                });
            }
            Command::Spawn(spec) => {
                check_spec(&spec)?;
                self.spawn(&spec);
            }
            Command::Despawn(id) => {
                if !self.despawn(id) {
                    return err(format!("despawn: there is no body {id}"));
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
                    return err("launch: values must be finite and the speed >= 0");
                }
                let l = &mut self.launcher;
                l.speed = speed.unwrap_or(l.speed);
                l.elevation_deg = elevation_deg.unwrap_or(l.elevation_deg);
                l.azimuth_deg = azimuth_deg.unwrap_or(l.azimuth_deg);
                l.position = position.unwrap_or(l.position);
            }
            Command::SetForce { kind, enabled } => {
                let declared = self.scene.forces;
                if !declared.has(kind) {
                    return err(format!(
                        "force: the scene does not declare {} (declared: {})",
                        kind.name(),
                        declared
                            .kinds()
                            .map(ForceKind::name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                let candidate = if enabled {
                    let only = declared.filtered(|k| k == kind);
                    let mut f = self.forces;
                    f.gravity = f.gravity.or(only.gravity);
                    f.constant = f.constant.or(only.constant);
                    f.linear_drag = f.linear_drag.or(only.linear_drag);
                    f.quadratic_drag = f.quadratic_drag.or(only.quadratic_drag);
                    f.spring = f.spring.or(only.spring);
                    f.point_mass = f.point_mass.or(only.point_mass);
                    f
                } else {
                    self.forces.without(kind)
                };
                check_integrator(self.integrator, &candidate).map_err(CommandError)?;
                self.forces = candidate;
            }
            Command::SetIntegrator(integrator) => {
                check_integrator(integrator, &self.forces).map_err(CommandError)?;
                self.integrator = integrator;
            }
            Command::Reset => {
                self.clear_bodies();
                self.forces = self.scene.forces;
                self.launcher = self.scene.launcher;
                self.rng = crate::world::SplitMix64(self.scene.seed);
                self.populate();
                self.diverged = None;
            }
        }
        self.carry_valid = false;
        self.rebase_energy_caps();
        Ok(())
    }
}

fn check_spec(spec: &BodySpec) -> Result<(), CommandError> {
    if !(spec.mass.is_finite() && spec.mass > 0.0) {
        return err(format!("spawn: mass must be > 0, got {}", spec.mass));
    }
    if !(spec.radius.is_finite() && spec.radius >= 0.0) {
        return err(format!("spawn: radius must be >= 0, got {}", spec.radius));
    }
    if !(spec.position.is_finite() && spec.velocity.is_finite()) {
        return err("spawn: position and velocity must be finite");
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
            Command::Spawn(s) => write!(
                f,
                "spawn mass={} radius={} position={} velocity={}",
                s.mass,
                s.radius,
                vec3(s.position),
                vec3(s.velocity)
            ),
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

fn number(key: &str, value: &str) -> Result<f64, CommandError> {
    match value.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => err(format!("{key}: expected a finite number, got `{value}`")),
    }
}

fn vector(key: &str, value: &str) -> Result<DVec3, CommandError> {
    let parts: Vec<&str> = value.split(',').collect();
    if parts.len() != 3 {
        return err(format!("{key}: expected x,y,z, got `{value}`"));
    }
    Ok(DVec3::new(
        number(key, parts[0])?,
        number(key, parts[1])?,
        number(key, parts[2])?,
    ))
}

impl std::str::FromStr for Command {
    type Err = CommandError;

    /// Parses the script form written by `Display`.
    fn from_str(text: &str) -> Result<Command, CommandError> {
        let mut words = text.split_whitespace();
        let verb = words.next().unwrap_or("");
        let rest: Vec<&str> = words.collect();
        let pairs = || -> Result<Vec<(&str, &str)>, CommandError> {
            rest.iter()
                .map(|w| {
                    w.split_once('=')
                        .ok_or_else(|| CommandError(format!("expected key=value, got `{w}`")))
                })
                .collect()
        };
        let single = |what: &str| -> Result<&str, CommandError> {
            match rest.as_slice() {
                [one] => Ok(one),
                _ => err(format!("{verb}: expected {what}")),
            }
        };
        match verb {
            "fire" if rest.is_empty() => Ok(Command::Fire),
            "reset" if rest.is_empty() => Ok(Command::Reset),
            "despawn" => {
                let id = single("a body id")?;
                id.parse::<u64>()
                    .map(|id| Command::Despawn(BodyId(id)))
                    .or_else(|_| err(format!("despawn: expected a body id, got `{id}`")))
            }
            "integrator" => {
                let name = single("an integrator name")?;
                Integrator::parse(name)
                    .map(Command::SetIntegrator)
                    .ok_or_else(|| {
                        let names: Vec<_> = Integrator::ALL.iter().map(|i| i.name()).collect();
                        CommandError(format!(
                            "integrator: unknown `{name}`, expected one of {}",
                            names.join(", ")
                        ))
                    })
            }
            "force" => match rest.as_slice() {
                [kind, state @ ("on" | "off")] => {
                    let kind = ForceKind::parse(kind).ok_or_else(|| {
                        let names: Vec<_> = ForceKind::ALL.iter().map(|k| k.name()).collect();
                        CommandError(format!(
                            "force: unknown term `{kind}`, expected one of {}",
                            names.join(", ")
                        ))
                    })?;
                    Ok(Command::SetForce {
                        kind,
                        enabled: *state == "on",
                    })
                }
                _ => err("force: expected `force KIND on|off`"),
            },
            "launch" => {
                let (mut speed, mut elevation_deg, mut azimuth_deg, mut position) =
                    (None, None, None, None);
                for (key, value) in pairs()? {
                    match key {
                        "speed" => speed = Some(number(key, value)?),
                        "elevation" => elevation_deg = Some(number(key, value)?),
                        "azimuth" => azimuth_deg = Some(number(key, value)?),
                        "position" => position = Some(vector(key, value)?),
                        _ => {
                            return err(format!(
                                "launch: unknown key `{key}`, expected speed, elevation, azimuth \
                                 or position"
                            ));
                        }
                    }
                }
                Ok(Command::SetLaunch {
                    speed,
                    elevation_deg,
                    azimuth_deg,
                    position,
                })
            }
            "spawn" => {
                let mut spec = BodySpec {
                    mass: 1.0,
                    radius: 0.1,
                    position: DVec3::ZERO,
                    velocity: DVec3::ZERO,
                };
                for (key, value) in pairs()? {
                    match key {
                        "mass" => spec.mass = number(key, value)?,
                        "radius" => spec.radius = number(key, value)?,
                        "position" => spec.position = vector(key, value)?,
                        "velocity" => spec.velocity = vector(key, value)?,
                        _ => {
                            return err(format!(
                                "spawn: unknown key `{key}`, expected mass, radius, position or \
                                 velocity"
                            ));
                        }
                    }
                }
                check_spec(&spec)?;
                Ok(Command::Spawn(spec))
            }
            _ => err(format!(
                "unknown command `{text}`, expected fire, spawn, despawn, launch, force, \
                 integrator or reset"
            )),
        }
    }
}

/// Parses a command script; errors name the line.
pub fn parse_script(text: &str, file: &str) -> Result<Vec<Stamped>, CommandError> {
    let mut out: Vec<Stamped> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let at = |message: String| CommandError(format!("{file}:{}: {message}", n + 1));
        let (tick, command) = line
            .split_once(':')
            .ok_or_else(|| at("expected `TICK: COMMAND`".into()))?;
        let tick: u64 = tick
            .trim()
            .parse()
            .map_err(|_| at(format!("expected a tick number, got `{}`", tick.trim())))?;
        if out.last().is_some_and(|last| last.tick > tick) {
            return Err(at(format!("tick {tick} comes after a later tick")));
        }
        let command: Command = command.trim().parse().map_err(|e: CommandError| at(e.0))?;
        out.push(Stamped { tick, command });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_round_trips_through_its_script_form() {
        let commands = [
            Command::Fire,
            Command::Reset,
            Command::Despawn(BodyId(7)),
            Command::SetIntegrator(Integrator::Rk4),
            Command::SetForce {
                kind: ForceKind::LinearDrag,
                enabled: false,
            },
            Command::SetLaunch {
                speed: Some(0.1 + 0.2),
                elevation_deg: None,
                azimuth_deg: Some(-3.5),
                position: Some(DVec3::new(1.0, 2.0, 1e-300)),
            },
            Command::Spawn(BodySpec {
                mass: 2.5,
                radius: 0.0,
                position: DVec3::new(10.0, 0.0, 2.0),
                velocity: DVec3::new(7.681, 0.0, 29.000_04),
            }),
        ];
        for c in commands {
            let text = c.to_string();
            assert_eq!(text.parse::<Command>(), Ok(c), "{text}");
        }
    }

    #[test]
    fn script_errors_name_the_line() {
        let e = parse_script("# intro\n0: fire\n5: warp 9\n", "s.txt").unwrap_err();
        assert!(e.0.starts_with("s.txt:3: unknown command"), "{e}");
        let e = parse_script("5: fire\n4: fire\n", "s.txt").unwrap_err();
        assert!(e.0.starts_with("s.txt:2:"), "{e}");
    }
}
