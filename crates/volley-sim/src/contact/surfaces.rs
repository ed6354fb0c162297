//! What a scene declares for contacts and what they report: the ground, walls and targets,
//! the detection mode, and the events a step emits.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::*;

/// An infinite ground plane `z = height`, solid below.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ground {
    /// Height of the plane (m).
    #[serde(default)]
    pub height: f64,
    /// Coefficient of restitution, 0 (stops) to 1 (perfectly elastic).
    pub restitution: f64,
}

/// A thin infinite wall: the slab of `thickness` centred on `point` across `normal`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wall {
    /// A point on the wall's mid-plane (m).
    pub point: DVec3,
    /// Normal of the wall (normalised when the scene is loaded).
    pub normal: DVec3,
    /// Thickness (m).
    pub thickness: f64,
    /// Coefficient of restitution, 0 to 1.
    #[serde(default = "elastic")]
    pub restitution: f64,
}

pub(super) fn elastic() -> f64 {
    1.0
}

/// A target sphere. Targets do not deflect bodies; they report passes and hits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// Centre (m) at tick 0.
    pub center: DVec3,
    /// Radius (m); a body hits when its centre comes within this plus its own radius.
    pub radius: f64,
    /// Constant velocity (m/s); zero (the default) for a target that stays put.
    #[serde(default)]
    pub velocity: DVec3,
}

impl Target {
    /// The centre `since_start` seconds after tick 0: `center + velocity * since_start`. A
    /// target at rest returns `center` itself (no `+ 0`, which would turn a `-0.0` into `0.0`).
    #[inline]
    pub fn center_at(&self, since_start: f64) -> DVec3 {
        if self.velocity == DVec3::ZERO {
            self.center
        } else {
            self.center + since_start * self.velocity
        }
    }
}

/// When contacts are detected.
///
/// For level surfaces (meshes, heightfields) discrete detection pushes a body that overlaps a
/// triangle at the end of its step out along the nearest triangle's contact normal and reflects
/// its normal momentum there; a body that went through a thin part in one step is missed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Detection {
    /// Time of impact solved inside the step; nothing is missed, impacts are on time.
    #[default]
    Swept,
    /// Overlap tested at the end of each step only: late, penetrating, and thin walls are missed
    /// when a body moves further than their thickness in one step.
    Discrete,
}

/// Everything a body can touch in a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contacts {
    /// Ground plane.
    pub ground: Option<Ground>,
    /// Walls.
    pub walls: Vec<Wall>,
    /// Targets.
    pub targets: Vec<Target>,
    /// Static triangle meshes, in scene order.
    pub meshes: Vec<MeshSurface>,
    /// Heightfields, in scene order.
    pub heightfields: Vec<HeightfieldSurface>,
    /// Detection mode.
    pub detection: Detection,
    /// The declared events: not contacts, but found on the same paths by the same stage
    /// (a scene with neither skips the stage entirely).
    pub events: EventSet,
}

impl Contacts {
    /// Whether the scene declares no contacts and no events (then the step skips this stage
    /// entirely).
    pub fn is_empty(&self) -> bool {
        self.ground.is_none()
            && self.walls.is_empty()
            && self.targets.is_empty()
            && self.meshes.is_empty()
            && self.heightfields.is_empty()
            && self.events.is_empty()
    }

    /// Whether the scene has something a body cannot be inside: a ground, a wall, a mesh or a
    /// heightfield (targets are sensors). Without one, [`Contacts::penetration`] is 0 wherever
    /// a body is drawn.
    pub fn has_solids(&self) -> bool {
        self.ground.is_some() || !self.walls.is_empty() || self.has_levels()
    }

    /// The world triangle an impact on `surface` met, as the contact met it: for a mesh's
    /// triangle or a heightfield's half cell; `None` for the ground, a wall, or an index the
    /// scene does not have.
    pub fn triangle(&self, surface: Surface) -> Option<[DVec3; 3]> {
        match surface {
            Surface::Mesh { surface, triangle } => {
                self.meshes.get(surface as usize)?.triangle(triangle)
            }
            Surface::Heightfield {
                surface,
                cell,
                triangle,
            } => self
                .heightfields
                .get(surface as usize)?
                .triangle(cell, triangle),
            Surface::Ground | Surface::Wall(_) => None,
        }
    }

    /// The scene's name for `surface`: a mesh's or a heightfield's own name, `ground`, or
    /// `wall N`; `None` for an index the scene does not have.
    pub fn surface_name(&self, surface: Surface) -> Option<String> {
        match surface {
            Surface::Ground => self.ground.map(|_| "ground".to_string()),
            Surface::Wall(i) => self.walls.get(i as usize).map(|_| format!("wall {i}")),
            Surface::Mesh { surface, .. } => {
                self.meshes.get(surface as usize).map(|m| m.name.clone())
            }
            Surface::Heightfield { surface, .. } => self
                .heightfields
                .get(surface as usize)
                .map(|h| h.name.clone()),
        }
    }

    /// Whether the scene has something to hit: a ground, a wall, a target, a mesh or a
    /// heightfield (declared events are not).
    pub fn has_surfaces(&self) -> bool {
        self.ground.is_some()
            || !self.walls.is_empty()
            || !self.targets.is_empty()
            || !self.meshes.is_empty()
            || !self.heightfields.is_empty()
    }
}

/// Which surface an impact was on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Surface {
    /// The ground plane.
    Ground,
    /// The wall with this index in the scene.
    Wall(u32),
    /// A triangle of a mesh.
    Mesh {
        /// Index of the mesh in the scene's `meshes`.
        surface: u32,
        /// Index of the triangle in the mesh as read (degenerate ones dropped, see
        /// [`MeshGeometry::degenerate`]).
        triangle: u32,
    },
    /// A triangle of a heightfield's cell.
    Heightfield {
        /// Index of the heightfield in the scene's `heightfields`.
        surface: u32,
        /// The cell, `row * (columns - 1) + column` (its corner sample is at that column and
        /// row).
        cell: u32,
        /// Which half of the cell: 0 below its diagonal from `(i, j)` to `(i + 1, j + 1)` (the
        /// side of `(i + 1, j)`), 1 above it.
        triangle: u8,
    },
}

impl std::fmt::Display for Surface {
    /// `ground`, `wall 1`, `mesh 0 triangle 5`, `heightfield 0 cell 12.1` (cell 12, its upper
    /// half).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Surface::Ground => f.write_str("ground"),
            Surface::Wall(i) => write!(f, "wall {i}"),
            Surface::Mesh { surface, triangle } => write!(f, "mesh {surface} triangle {triangle}"),
            Surface::Heightfield {
                surface,
                cell,
                triangle,
            } => write!(f, "heightfield {surface} cell {cell}.{triangle}"),
        }
    }
}

/// Something that happened to a body during a tick.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// The tick whose step produced the event (the state after it is tick `tick`).
    pub tick: u64,
    /// Sim time of the event (s), inside the step for swept detection.
    pub time: f64,
    /// The body.
    pub body: BodyId,
    /// What happened.
    pub kind: EventKind,
}

/// The kinds of [`Event`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum EventKind {
    /// The body hit a surface and bounced.
    Impact {
        /// Which surface.
        surface: Surface,
        /// Normal speed into the surface at impact (m/s).
        normal_speed: f64,
        /// Penetration when detected (m): 0 for swept detection.
        depth: f64,
    },
    /// The body came to rest on a surface (its bounce fell below one step of gravity's speed).
    Rest {
        /// Which surface.
        surface: Surface,
    },
    /// The body touched a target: its centre came within the two radii of the target's. The
    /// event's time is the moment of first contact.
    Hit {
        /// Index of the target in the scene.
        target: u32,
    },
    /// The body passed a target: the event's time is its closest approach (swept detection).
    Approach {
        /// Index of the target in the scene.
        target: u32,
        /// Closest distance between the body's and the target's centres (m): 0 is dead centre.
        distance: f64,
        /// Whether that is within the two radii (a [`EventKind::Hit`] was reported on entry).
        hit: bool,
    },
    /// A declared event ([`EventSpec`]): its function changed sign (or touched zero) at the
    /// event's time, on the integrator's own path.
    Declared {
        /// Index of the event in the scene's `events` ([`EventSet::specs`]).
        event: u32,
        /// Which way the function went: [`EventDirection::Rising`] or
        /// [`EventDirection::Falling`] (for a graze, the side it came from).
        direction: EventDirection,
        /// Whether it only touched zero (a tangent) rather than crossing it.
        graze: bool,
        /// The body's state at the event: the integrator's partial step to its time (for
        /// Dormand-Prince, the step's continuous extension).
        state: BodyState,
    },
}
