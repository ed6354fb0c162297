//! Reading commands: one command from its text (`Command::from_str`) and a command script
//! (`TICK: COMMAND` lines), with what each can fail with ([`CommandParseError`],
//! [`ScriptError`]). What applying a command can fail with is [`super::CommandError`].

use glam::DVec3;

use super::*;
use crate::forces::ForceKind;
use crate::integrate::Integrator;
use crate::scene::BodySpec;

/// What reading one command's text can fail with. Displays as the CLI prints it.
#[derive(Clone, Debug, PartialEq)]
pub enum CommandParseError {
    /// A word that should be `key=value` is not.
    ExpectedKeyValue(String),
    /// A command that takes one argument got none or several.
    ExpectedOne {
        /// The command (`despawn`, `integrator`).
        verb: &'static str,
        /// What the argument is (`a body id`).
        what: &'static str,
    },
    /// `despawn` of something that is not a body id.
    InvalidBodyId(String),
    /// `integrator` with a name that is not one.
    UnknownIntegrator(String),
    /// `force` with a term name that is not one.
    UnknownForce(String),
    /// `force` not of the form `force KIND on|off`.
    ForceSyntax,
    /// `launch` with a key other than speed, elevation, azimuth and position.
    UnknownLaunchKey(String),
    /// `spawn` with a key other than mass, radius, position and velocity.
    UnknownSpawnKey(String),
    /// A value that should be a finite number is not.
    InvalidNumber {
        /// The key it was given for.
        key: &'static str,
        /// The text given.
        value: String,
    },
    /// A value that should be `x,y,z` has another number of parts.
    InvalidVector {
        /// The key it was given for.
        key: &'static str,
        /// The text given.
        value: String,
    },
    /// A line that is no command.
    UnknownCommand(String),
    /// A `spawn` the world would refuse (its mass, radius or state), caught as it is read.
    Spawn(CommandError),
}

impl std::fmt::Display for CommandParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CommandParseError::ExpectedKeyValue(w) => write!(f, "expected key=value, got `{w}`"),
            CommandParseError::ExpectedOne { verb, what } => write!(f, "{verb}: expected {what}"),
            CommandParseError::InvalidBodyId(id) => {
                write!(f, "despawn: expected a body id, got `{id}`")
            }
            CommandParseError::UnknownIntegrator(name) => {
                let names: Vec<_> = Integrator::ALL.iter().map(|i| i.name()).collect();
                write!(
                    f,
                    "integrator: unknown `{name}`, expected one of {}",
                    names.join(", ")
                )
            }
            CommandParseError::UnknownForce(kind) => {
                let names: Vec<_> = ForceKind::ALL.iter().map(|k| k.name()).collect();
                write!(
                    f,
                    "force: unknown term `{kind}`, expected one of {}",
                    names.join(", ")
                )
            }
            CommandParseError::ForceSyntax => f.write_str("force: expected `force KIND on|off`"),
            CommandParseError::UnknownLaunchKey(key) => write!(
                f,
                "launch: unknown key `{key}`, expected speed, elevation, azimuth or position"
            ),
            CommandParseError::UnknownSpawnKey(key) => write!(
                f,
                "spawn: unknown key `{key}`, expected mass, radius, position, velocity or spin"
            ),
            CommandParseError::InvalidNumber { key, value } => {
                write!(f, "{key}: expected a finite number, got `{value}`")
            }
            CommandParseError::InvalidVector { key, value } => {
                write!(f, "{key}: expected x,y,z, got `{value}`")
            }
            CommandParseError::UnknownCommand(text) => write!(
                f,
                "unknown command `{text}`, expected fire, spawn, despawn, launch, force, \
                 integrator or reset"
            ),
            CommandParseError::Spawn(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CommandParseError {}

/// An error in a command script ([`parse_script`]): the file, the line and what is wrong there.
/// Displays as `FILE:LINE: PROBLEM`.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptError {
    /// The file, as given to [`parse_script`].
    pub file: String,
    /// Line number, 1-based.
    pub line: usize,
    /// What is wrong on that line.
    pub problem: ScriptProblem,
}

/// What is wrong on a line of a command script.
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptProblem {
    /// No `TICK:` before the command.
    ExpectedTick,
    /// The tick is not a number (the text given).
    InvalidTick(String),
    /// The tick is before the previous line's.
    TickGoesBack(u64),
    /// The command does not parse.
    Command(CommandParseError),
    /// More than [`MAX_SCRIPT_COMMANDS`] commands.
    TooManyCommands,
}

/// Most commands one script may hold (about 80 MB of commands in memory): a generated script
/// gone wrong should be an error, not a run that never ends.
pub const MAX_SCRIPT_COMMANDS: usize = 1_000_000;

impl std::fmt::Display for ScriptError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.problem)
    }
}

impl std::fmt::Display for ScriptProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ScriptProblem::ExpectedTick => f.write_str("expected `TICK: COMMAND`"),
            ScriptProblem::InvalidTick(tick) => {
                write!(f, "expected a tick number, got `{tick}`")
            }
            ScriptProblem::TickGoesBack(tick) => {
                write!(f, "tick {tick} comes after a later tick")
            }
            ScriptProblem::Command(e) => write!(f, "{e}"),
            ScriptProblem::TooManyCommands => {
                write!(
                    f,
                    "expected at most {MAX_SCRIPT_COMMANDS} commands in a script"
                )
            }
        }
    }
}

impl std::error::Error for ScriptError {}

fn number(key: &'static str, value: &str) -> Result<f64, CommandParseError> {
    match value.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(CommandParseError::InvalidNumber {
            key,
            value: value.into(),
        }),
    }
}

fn vector(key: &'static str, value: &str) -> Result<DVec3, CommandParseError> {
    let parts: Vec<&str> = value.split(',').collect();
    if parts.len() != 3 {
        return Err(CommandParseError::InvalidVector {
            key,
            value: value.into(),
        });
    }
    Ok(DVec3::new(
        number(key, parts[0])?,
        number(key, parts[1])?,
        number(key, parts[2])?,
    ))
}

impl std::str::FromStr for Command {
    type Err = CommandParseError;

    /// Parses the script form written by `Display`.
    fn from_str(text: &str) -> Result<Command, CommandParseError> {
        let mut words = text.split_whitespace();
        let verb = words.next().unwrap_or("");
        let rest: Vec<&str> = words.collect();
        let pairs = || -> Result<Vec<(&str, &str)>, CommandParseError> {
            rest.iter()
                .map(|w| {
                    w.split_once('=')
                        .ok_or_else(|| CommandParseError::ExpectedKeyValue(w.to_string()))
                })
                .collect()
        };
        let single = |verb: &'static str, what: &'static str| -> Result<&str, CommandParseError> {
            match rest.as_slice() {
                [one] => Ok(one),
                _ => Err(CommandParseError::ExpectedOne { verb, what }),
            }
        };
        match verb {
            "fire" if rest.is_empty() => Ok(Command::Fire),
            "reset" if rest.is_empty() => Ok(Command::Reset),
            "despawn" => {
                let id = single("despawn", "a body id")?;
                id.parse::<u64>()
                    .map(|id| Command::Despawn(BodyId(id)))
                    .map_err(|_| CommandParseError::InvalidBodyId(id.to_string()))
            }
            "integrator" => {
                let name = single("integrator", "an integrator name")?;
                Integrator::parse(name)
                    .map(Command::SetIntegrator)
                    .ok_or_else(|| CommandParseError::UnknownIntegrator(name.to_string()))
            }
            "force" => match rest.as_slice() {
                [kind, state @ ("on" | "off")] => {
                    let kind = ForceKind::parse(kind)
                        .ok_or_else(|| CommandParseError::UnknownForce(kind.to_string()))?;
                    Ok(Command::SetForce {
                        kind,
                        enabled: *state == "on",
                    })
                }
                _ => Err(CommandParseError::ForceSyntax),
            },
            "launch" => {
                let (mut speed, mut elevation_deg, mut azimuth_deg, mut position) =
                    (None, None, None, None);
                for (key, value) in pairs()? {
                    match key {
                        "speed" => speed = Some(number("speed", value)?),
                        "elevation" => elevation_deg = Some(number("elevation", value)?),
                        "azimuth" => azimuth_deg = Some(number("azimuth", value)?),
                        "position" => position = Some(vector("position", value)?),
                        _ => {
                            return Err(CommandParseError::UnknownLaunchKey(key.to_string()));
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
                    spin: DVec3::ZERO,
                };
                for (key, value) in pairs()? {
                    match key {
                        "mass" => spec.mass = number("mass", value)?,
                        "radius" => spec.radius = number("radius", value)?,
                        "position" => spec.position = vector("position", value)?,
                        "velocity" => spec.velocity = vector("velocity", value)?,
                        "spin" => spec.spin = vector("spin", value)?,
                        _ => {
                            return Err(CommandParseError::UnknownSpawnKey(key.to_string()));
                        }
                    }
                }
                check_spec(&spec).map_err(CommandParseError::Spawn)?;
                Ok(Command::Spawn(spec))
            }
            _ => Err(CommandParseError::UnknownCommand(text.to_string())),
        }
    }
}

/// Parses a command script; errors name the line.
pub fn parse_script(text: &str, file: &str) -> Result<Vec<Stamped>, ScriptError> {
    let mut out: Vec<Stamped> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let at = |problem: ScriptProblem| ScriptError {
            file: file.to_string(),
            line: n + 1,
            problem,
        };
        if out.len() == MAX_SCRIPT_COMMANDS {
            return Err(at(ScriptProblem::TooManyCommands));
        }
        let (tick, command) = line
            .split_once(':')
            .ok_or_else(|| at(ScriptProblem::ExpectedTick))?;
        let tick: u64 = tick
            .trim()
            .parse()
            .map_err(|_| at(ScriptProblem::InvalidTick(tick.trim().to_string())))?;
        if out.last().is_some_and(|last| last.tick > tick) {
            return Err(at(ScriptProblem::TickGoesBack(tick)));
        }
        let command: Command = command
            .trim()
            .parse()
            .map_err(|e| at(ScriptProblem::Command(e)))?;
        out.push(Stamped { tick, command });
    }
    Ok(out)
}
