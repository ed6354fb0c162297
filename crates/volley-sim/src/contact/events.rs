//! Declared events: conditions on a body's state that a game or a study asks to be told of,
//! with the exact time and state, never missed (docs/physics.md, "Declared events").
//!
//! Each is a function `g` of a body's state (and, for a moving point, of the time) whose sign
//! changes are the events: a plane, an altitude or a downrange distance crossed, a speed or a
//! Mach number passed, the apex (the vertical velocity changing sign), the closest approach to a
//! point (the distance's rate changing sign). They are looked for after the contact stage, on
//! the same segments of each body's own sub-step path (a bounce splits it), by the first-root
//! search the level surfaces use ([`super::roots::first_root`]), with margins from bounds on
//! how far the path bends inside a piece ([`search`]).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::body::BodyId;
use crate::forces::MachDrag;

pub(crate) mod horizon;
pub(crate) mod search;

/// One declared event: which bodies, which condition, which way, and whether it stops them.
///
/// Written in a scene file as `(name: "300 m", when: Downrange(300.0), direction: Either,
/// stop: Never)`, everything but `when` optional (docs/scenes.md, "Events"); in code:
///
/// ```
/// use volley_sim::{EventCondition, EventSpec};
///
/// let subsonic = EventSpec::new(EventCondition::Mach(1.0)).named("subsonic").falling();
/// assert_eq!(subsonic.name, "subsonic");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct EventSpec {
    /// A name for reports; empty for the condition's own ([`EventSpec::label`]).
    pub name: String,
    /// The body it is watched on; every body when `None`.
    pub body: Option<BodyId>,
    /// The condition: the function whose sign changes are the events.
    pub condition: EventCondition,
    /// Which sign changes count.
    pub direction: EventDirection,
    /// What an occurrence stops.
    pub stop: EventStop,
}

impl EventSpec {
    /// `condition` on every body, either way, stopping nothing.
    pub fn new(condition: EventCondition) -> EventSpec {
        EventSpec {
            name: String::new(),
            body: None,
            condition,
            direction: EventDirection::Either,
            stop: EventStop::Never,
        }
    }

    /// The same, named `name`.
    pub fn named(self, name: &str) -> EventSpec {
        EventSpec {
            name: name.to_string(),
            ..self
        }
    }

    /// The same, on body `id` only.
    pub fn on_body(self, id: BodyId) -> EventSpec {
        EventSpec {
            body: Some(id),
            ..self
        }
    }

    /// The same, counting only rises (the function going from below zero to zero or above).
    pub fn rising(self) -> EventSpec {
        EventSpec {
            direction: EventDirection::Rising,
            ..self
        }
    }

    /// The same, counting only falls (from above zero to zero or below).
    pub fn falling(self) -> EventSpec {
        EventSpec {
            direction: EventDirection::Falling,
            ..self
        }
    }

    /// The same, stopping what `stop` says.
    pub fn stopping(self, stop: EventStop) -> EventSpec {
        EventSpec { stop, ..self }
    }

    /// Its name, or the condition's own when it has none (`Downrange(300)`, `Apex`).
    pub fn label(&self) -> String {
        if self.name.is_empty() {
            self.condition.to_string()
        } else {
            self.name.clone()
        }
    }
}

/// The condition of an [`EventSpec`]: a function `g` of the body's state whose sign changes
/// are the events. Written in a scene file as shown on each variant.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EventCondition {
    /// `Plane(point: (x, y, z), normal: (x, y, z))`: `g = n . (p - point)`, `n` the normal
    /// made unit. Rising is crossing along the normal.
    Plane {
        /// A point of the plane (m).
        point: DVec3,
        /// Its normal (any length but zero).
        normal: DVec3,
    },
    /// `Altitude(z)`: `g = p.z - z` (m). Rising is going up through it.
    Altitude(f64),
    /// `Downrange(m)`: the distance along the launcher's azimuth, horizontally, from the
    /// launcher's position, less this (m): the plane a range table reads at. Rising is going
    /// out past it.
    Downrange(f64),
    /// `Speed(m/s)`: `g = |V| - speed`. Falling is slowing below it.
    Speed(f64),
    /// `Mach(M)`: `g = |V - wind| / c - M` in the air of the scene's Mach drag (its wind, its
    /// speed of sound `c` at the body's height). Falling is slowing below it: `Mach(1.0)`
    /// falling is going subsonic.
    Mach(f64),
    /// `Apex`: `g = V.z`. Falling is the top of an arc, rising the bottom of a dip.
    Apex,
    /// `Closest(point: (x, y, z), velocity: (x, y, z))`: `g = (p - c) . (V - u)` for the
    /// point `c = point + u t` moving at `u` (default at rest) from tick 0: the distance's
    /// rate, over the distance. Rising is the closest approach, falling the farthest.
    Closest {
        /// Where the point is at tick 0 (m).
        point: DVec3,
        /// Its constant velocity (m/s).
        #[serde(default)]
        velocity: DVec3,
    },
    /// `ClosestToTarget(i)`: [`EventCondition::Closest`] to the scene's target `i` (counted
    /// from 0), moving as it moves.
    ClosestToTarget(u32),
}

impl std::fmt::Display for EventCondition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EventCondition::Plane { point, normal } => write!(
                f,
                "Plane(point: ({}, {}, {}), normal: ({}, {}, {}))",
                point.x, point.y, point.z, normal.x, normal.y, normal.z
            ),
            EventCondition::Altitude(z) => write!(f, "Altitude({z})"),
            EventCondition::Downrange(x) => write!(f, "Downrange({x})"),
            EventCondition::Speed(v) => write!(f, "Speed({v})"),
            EventCondition::Mach(m) => write!(f, "Mach({m})"),
            EventCondition::Apex => f.write_str("Apex"),
            EventCondition::Closest { point, .. } => {
                write!(f, "Closest(({}, {}, {}))", point.x, point.y, point.z)
            }
            EventCondition::ClosestToTarget(i) => write!(f, "ClosestToTarget({i})"),
        }
    }
}

/// Which sign changes of an event's function count; an event reports the one it saw (rising
/// or falling, never `Either`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventDirection {
    /// From below zero to zero or above.
    Rising,
    /// From above zero to zero or below.
    Falling,
    /// Both.
    #[default]
    Either,
}

impl EventDirection {
    /// Whether an event seen going `seen` way counts.
    #[inline]
    pub fn counts(self, seen: EventDirection) -> bool {
        self == EventDirection::Either || self == seen
    }

    /// `rising`, `falling`, `either`.
    pub fn name(self) -> &'static str {
        match self {
            EventDirection::Rising => "rising",
            EventDirection::Falling => "falling",
            EventDirection::Either => "either",
        }
    }
}

/// What an event's occurrences stop: nothing, the body after its `n`-th (it leaves the world
/// at the end of that tick's step), or the run after the `n`-th of all bodies' together (the
/// world stops at the end of that tick; [`crate::World::stopped`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventStop {
    /// Nothing.
    #[default]
    Never,
    /// `Body(n)`: the body, at its `n`-th occurrence (n >= 1).
    Body(u32),
    /// `Run(n)`: the run, at the `n`-th occurrence over all bodies (n >= 1).
    Run(u32),
}

impl EventStop {
    /// The count, 0 for `Never`.
    pub fn count(self) -> u32 {
        match self {
            EventStop::Never => 0,
            EventStop::Body(n) | EventStop::Run(n) => n,
        }
    }
}

/// An event's function as the step evaluates it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Test {
    /// `n . p - d`, `n` unit: a plane, an altitude, a downrange distance.
    Linear { n: DVec3, d: f64 },
    /// `|V| - speed`.
    Speed(f64),
    /// `|V - wind| / c - mach` in the Mach drag's air.
    Mach { mach: f64, drag: Box<MachDrag> },
    /// `V.z`.
    Apex,
    /// `(p - c(t)) . (V - u)`, `c(t) = c0 + u t` since tick 0.
    Closest { c0: DVec3, u: DVec3 },
}

/// One declared event, prepared for the step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Watch {
    pub body: Option<BodyId>,
    pub direction: EventDirection,
    pub test: Test,
}

/// A scene's declared events: as declared, and prepared for the step. Empty in a scene that
/// declares none, which then pays nothing for them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EventSet {
    specs: Vec<EventSpec>,
    watches: Vec<Watch>,
}

impl EventSet {
    /// The events of a scene: `specs` (already checked: unit normals, known targets, a Mach
    /// drag for a Mach event), with the downrange plane of the launcher at `(position,
    /// azimuth_deg)`, the targets' centres and velocities and the scene's Mach drag.
    pub fn prepare(
        specs: &[EventSpec],
        launcher: (DVec3, f64),
        targets: &[super::Target],
        drag: Option<&MachDrag>,
    ) -> EventSet {
        let watches = specs
            .iter()
            .map(|s| {
                let test = match s.condition {
                    EventCondition::Plane { point, normal } => {
                        let n = normal.normalize_or_zero();
                        Test::Linear { n, d: n.dot(point) }
                    }
                    EventCondition::Altitude(z) => Test::Linear { n: DVec3::Z, d: z },
                    EventCondition::Downrange(x) => {
                        let az = launcher.1.to_radians();
                        let n = DVec3::new(libm::cos(az), libm::sin(az), 0.0);
                        Test::Linear {
                            n,
                            d: n.dot(launcher.0) + x,
                        }
                    }
                    EventCondition::Speed(v) => Test::Speed(v),
                    EventCondition::Mach(m) => match drag {
                        Some(d) => Test::Mach {
                            mach: m,
                            drag: Box::new(d.clone()),
                        },
                        // Refused when the scene is read; a set built without one never fires.
                        None => Test::Speed(f64::INFINITY),
                    },
                    EventCondition::Apex => Test::Apex,
                    EventCondition::Closest { point, velocity } => Test::Closest {
                        c0: point,
                        u: velocity,
                    },
                    EventCondition::ClosestToTarget(i) => match targets.get(i as usize) {
                        Some(t) => Test::Closest {
                            c0: t.center,
                            u: t.velocity,
                        },
                        None => Test::Speed(f64::INFINITY),
                    },
                };
                Watch {
                    body: s.body,
                    direction: s.direction,
                    test,
                }
            })
            .collect();
        EventSet {
            specs: specs.to_vec(),
            watches,
        }
    }

    /// Whether no event is declared.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.specs.is_empty()
    }

    /// The events as declared, in order (an [`crate::EventKind::Declared`] names its event by
    /// its index here).
    #[inline]
    pub fn specs(&self) -> &[EventSpec] {
        &self.specs
    }

    /// The prepared events.
    #[inline]
    pub(crate) fn watches(&self) -> &[Watch] {
        &self.watches
    }

    /// Whether any event stops a body or the run.
    pub fn stops(&self) -> bool {
        self.specs.iter().any(|s| s.stop != EventStop::Never)
    }

    /// How many events stop a body after more than one occurrence: the counts each body keeps
    /// ([`crate::world::Tallies::per_body`]).
    pub fn body_slots(&self) -> usize {
        self.specs
            .iter()
            .filter(|s| matches!(s.stop, EventStop::Body(n) if n > 1))
            .count()
    }

    /// How many events stop the run after more than one occurrence.
    pub fn run_slots(&self) -> usize {
        self.specs
            .iter()
            .filter(|s| matches!(s.stop, EventStop::Run(n) if n > 1))
            .count()
    }

    /// Event `index`'s place among a body's counts, if it has one.
    pub fn body_slot(&self, index: usize) -> Option<usize> {
        self.slot(index, |s| matches!(s, EventStop::Body(n) if n > 1))
    }

    /// Event `index`'s place among the run's counts, if it has one.
    pub fn run_slot(&self, index: usize) -> Option<usize> {
        self.slot(index, |s| matches!(s, EventStop::Run(n) if n > 1))
    }

    fn slot(&self, index: usize, counted: impl Fn(EventStop) -> bool) -> Option<usize> {
        let spec = self.specs.get(index)?;
        counted(spec.stop).then(|| {
            self.specs[..index]
                .iter()
                .filter(|s| counted(s.stop))
                .count()
        })
    }

    /// The value of event `index`'s function for a body at `state` (1/mass `inv_m`) at
    /// `since` s after tick 0: its sign is the side of the event the body is on.
    pub fn value(&self, index: usize, since: f64, state: &crate::BodyState, inv_m: f64) -> f64 {
        self.watches[index].test.value(since, state, inv_m)
    }
}

impl Test {
    /// The function at a state `since` s after tick 0.
    #[inline]
    pub(crate) fn value(&self, since: f64, s: &crate::BodyState, inv_m: f64) -> f64 {
        match self {
            Test::Linear { n, d } => n.dot(s.p) - d,
            Test::Speed(v) => (s.mv * inv_m).length() - v,
            Test::Mach { mach, drag } => drag.mach(s.p, s.mv * inv_m) - mach,
            Test::Apex => s.mv.z * inv_m,
            Test::Closest { c0, u } => {
                let c = if *u == DVec3::ZERO {
                    *c0
                } else {
                    *c0 + since * *u
                };
                (s.p - c).dot(s.mv * inv_m - *u)
            }
        }
    }
}
