//! Trajectories drawn ahead of the bodies: the first bodies' closed-form paths as dashed ghosts,
//! each with a ghost sphere where the exact solution is at the drawn time, and the launcher's
//! next shot. Paths are sampled to [`PATH_TOLERANCE`] of the scene's scale and dashed at
//! [`DASH`] of it, measured along the path.

use glam::DVec3;

use super::{
    DrawList, DrawOptions, GHOST, GHOST_BODIES, LAUNCHER, Lane, Rgba, SphereInstance, rel,
};
use crate::scene::Launcher;
use crate::world::World;

impl DrawList {
    /// The closed-form path of the next shot from the launcher, dashed, where one exists.
    pub(super) fn launcher_shot(&mut self, world: &World, options: &DrawOptions) {
        let shot = launcher_shot(world, &options.aim.unwrap_or(*world.launcher()));
        let floor = world.contacts().ground.map(|g| g.height);
        let mut points = std::mem::take(&mut self.scratch);
        shot.trajectory(
            horizon(world),
            world.dt(),
            floor,
            path_tolerance(options),
            &mut points,
        );
        let mut faint = LAUNCHER;
        faint[3] = 90;
        self.dashed(&points, faint, options);
        self.scratch = points;
    }

    pub(super) fn ghosts(&mut self, lane: &Lane<'_>, options: &DrawOptions) {
        let world = lane.world;
        let dt = world.dt();
        let floor = world.contacts().ground.map(|g| g.height);
        let drawn = lane.history.drawn_ticks(world, lane.at);
        let mut points = std::mem::take(&mut self.scratch);
        let bodies = world.bodies();
        for &id in bodies.ids().iter().take(GHOST_BODIES) {
            let Some(r) = lane.history.references.get(id) else {
                continue;
            };
            if !r.has_closed_form {
                continue;
            }
            r.trajectory(
                horizon(world),
                dt,
                floor,
                path_tolerance(options),
                &mut points,
            );
            self.dashed(&points, GHOST, options);
            let t = (drawn - r.spawn_tick as f64).max(0.0) * dt;
            let ended = r.ends_after(dt).is_some_and(|end| t > end);
            if let (false, Some(s)) = (ended, r.exact_at(t)) {
                let i = bodies.index_of(id).unwrap_or(0);
                self.translucent.push(SphereInstance {
                    center: rel(s.p, options.origin),
                    radius: bodies.radii()[i] as f32,
                    colour: GHOST,
                });
            }
        }
        self.scratch = points;
    }

    /// A polyline drawn dashed: dashes and gaps of [`DASH`] times the scene's scale each,
    /// measured along the line, so the pattern does not depend on how finely it was sampled.
    fn dashed(&mut self, points: &[(f64, DVec3)], colour: Rgba, options: &DrawOptions) {
        let dash = DASH * options.scale;
        // Length still to go in the current dash or gap, and whether it is a dash.
        let (mut left, mut on) = (dash, true);
        for pair in points.windows(2) {
            let (mut a, b) = (pair[0].1, pair[1].1);
            let mut length = (b - a).length();
            while length > 0.0 {
                let step = left.min(length);
                let next = a + (b - a) * (step / length);
                if on {
                    self.line(a, next, colour, options.origin);
                }
                (a, length, left) = (next, length - step, left - step);
                if left <= 0.0 {
                    (left, on) = (dash, !on);
                }
            }
        }
    }
}

/// The shot `launcher` would fire now, as a closed-form reference from its muzzle: the
/// launcher's predicted path ([`Reference::trajectory`] of it, over [`horizon`]).
///
/// [`Reference::trajectory`]: crate::render::Reference::trajectory
pub fn launcher_shot(world: &World, l: &Launcher) -> crate::render::reference::Reference {
    crate::render::reference::Reference {
        id: crate::world::BodyId(u64::MAX),
        spawn_tick: world.tick(),
        spawn_time: world.time(),
        state: crate::integrate::BodyState {
            p: l.position,
            mv: l.mass * l.velocity(),
        },
        mass: l.mass,
        launch: crate::integrate::Launch {
            time: world.time(),
            mass: l.mass,
            spin: l.spin_at(l.azimuth_deg),
        },
        forces: world.forces().clone(),
        has_closed_form: true,
        numeric: false,
        cache: std::cell::Cell::new(None),
        end: None,
    }
}

/// How long a drawn trajectory (a ghost, the launcher's predicted shot) runs: the scene's
/// duration, at least 1 s.
pub fn horizon(world: &World) -> f64 {
    world.scene().duration().max(1.0)
}

/// How far a drawn trajectory's chord may leave the path, as a fraction of the scene's scale
/// (the radius the default camera frames). The default view draws that radius about 360 px
/// across in a window 800 px tall, so a thousandth of it is a third of a pixel there, and under
/// a pixel for a point as near the eye as the scene's edge.
pub const PATH_TOLERANCE: f64 = 1e-3;

/// Length of a dash and of a gap in dashed trajectories, as a fraction of the scene's scale.
pub const DASH: f64 = 0.025;

/// [`PATH_TOLERANCE`] in metres for `options`.
pub fn path_tolerance(options: &DrawOptions) -> f64 {
    PATH_TOLERANCE * options.scale
}
