//! The draw list: everything one frame shows, as flat arrays ready for the GPU.
//!
//! Built on the CPU from the worlds being shown (one per integrator in compare mode), their
//! [`TickHistory`] and the loop's alpha; the renderer uploads it into buffers it keeps. Positions
//! are converted to `f32` relative to the render origin here and nowhere else. Colours are sRGB
//! bytes; the shaders convert them to linear light.
//!
//! The bodies, their markers, vectors and judder ghosts are built here; the scene's fixed parts
//! (targets, walls, the launcher) in `draw/scene_parts.rs` and the trajectories drawn ahead
//! (ghost paths, the launcher's next shot) in `draw/paths.rs`.

mod paths;
mod scene_parts;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::integrate::Integrator;
use crate::render::history::{DrawAt, TickHistory};
use crate::scene::Launcher;
use crate::world::World;
pub use paths::{DASH, PATH_TOLERANCE, horizon, launcher_shot, path_tolerance};
pub use scene_parts::clip_above;

/// An sRGB colour with alpha, 0-255 each.
pub type Rgba = [u8; 4];

/// Colour of the closed-form ghosts (trajectory and sphere).
pub const GHOST: Rgba = [235, 235, 250, 140];
/// Colour of target spheres.
pub const TARGET: Rgba = [255, 150, 40, 90];
/// Colour of wall slabs.
pub const WALL: Rgba = [120, 170, 255, 70];
/// Colour of the launcher and its predicted shot.
pub const LAUNCHER: Rgba = [210, 210, 220, 255];
/// Bodies shown with a ghost (the first ones in id order): a closed form per body per frame is
/// cheap, but a thousand dashed arcs only hide the bodies.
pub const GHOST_BODIES: usize = 16;

/// The colour an integrator is drawn in, everywhere (bodies, trails, legend, plots): the one
/// palette of [`crate::palette`].
pub fn integrator_colour(integrator: Integrator) -> Rgba {
    crate::palette::integrator(integrator)
}

/// One sphere: centre relative to the render origin (m), radius (m), colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SphereInstance {
    /// Centre (m, relative to the render origin).
    pub center: [f32; 3],
    /// Radius (m).
    pub radius: f32,
    /// sRGB colour.
    pub colour: Rgba,
}

/// A vertex of a line or a translucent surface.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ColouredVertex {
    /// Position (m, relative to the render origin).
    pub position: [f32; 3],
    /// sRGB colour.
    pub colour: Rgba,
}

/// One world to draw.
#[derive(Clone, Copy)]
pub struct Lane<'a> {
    /// The world.
    pub world: &'a World,
    /// Its previous state, trails and references.
    pub history: &'a TickHistory,
    /// Where between (or past) its ticks to draw: the draw mode, the loop's alpha, the lead.
    pub at: DrawAt,
    /// Colour of its bodies and trails.
    pub colour: Rgba,
    /// The judder ghosts of its measured body, oldest first (empty for none).
    pub judder: &'a [JudderMark],
}

/// One displayed frame of a body, for the judder ghosts: where the frame drew it, and where
/// the exact solution had it at the frame's display time (where the scene has a closed form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JudderMark {
    /// The drawn position (m).
    pub drawn: DVec3,
    /// The exact position at the frame's display time (m), if known.
    pub exact: Option<DVec3>,
    /// The body's radius (m): the ghosts are drawn at a fraction of it.
    pub radius: f64,
}

/// What to draw besides the bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawOptions {
    /// Positions are drawn relative to this point (m).
    pub origin: DVec3,
    /// Size of the scene (m): scales the launcher's barrel.
    pub scale: f64,
    /// Trails behind the bodies.
    pub trails: bool,
    /// Closed-form ghosts (trajectory and sphere) of the first lane's first bodies.
    pub ghosts: bool,
    /// Draw the launcher with this aim instead of the world's: the aim of a `launch` command
    /// still queued (while paused), which the next `fire` will use.
    pub aim: Option<Launcher>,
    /// Markers on the first bodies' paths: every 0.1 s and 1 s, the apex, impacts
    /// ([`crate::render::probe`]).
    pub markers: bool,
    /// Velocity and net-force arrows on the first bodies, at these scales.
    pub vectors: Option<ArrowScale>,
    /// A point to ring (the probe's): a larger translucent white sphere there.
    pub highlight: Option<DVec3>,
    /// The judder ghosts of each lane's measured body ([`Lane::judder`]).
    pub judder: bool,
}

impl DrawOptions {
    /// The bodies alone around `origin` at `scale`: no trails, ghosts, markers, arrows,
    /// highlight or judder ghosts. Set the rest with struct update syntax.
    pub fn bodies(origin: DVec3, scale: f64) -> DrawOptions {
        DrawOptions {
            origin,
            scale,
            trails: false,
            ghosts: false,
            aim: None,
            markers: false,
            vectors: None,
            highlight: None,
            judder: false,
        }
    }

    /// What a picture made off screen shows (the golden image, `--frames`, the render bench):
    /// the bodies with their trails and closed-form ghosts, around `origin` at `scale`.
    pub fn picture(origin: DVec3, scale: f64) -> DrawOptions {
        DrawOptions {
            trails: true,
            ghosts: true,
            ..DrawOptions::bodies(origin, scale)
        }
    }
}

/// How long the arrows are drawn: metres of arrow per m/s of velocity and per newton of force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrowScale {
    /// Metres of arrow per m/s.
    pub velocity: f64,
    /// Metres of arrow per newton.
    pub force: f64,
}

impl ArrowScale {
    /// Scales for `world` in a scene of size `scale` (m): the launcher's speed and the weight
    /// of its shot (or 1 N without gravity) each drawn 8 % of the scene long, rounded down to
    /// 1, 2 or 5 times a power of ten so the panel can state them plainly.
    pub fn of(world: &World, scale: f64) -> ArrowScale {
        let l = world.launcher();
        let speed = l.speed.max(1.0);
        let g = world.forces().gravity.map_or(0.0, DVec3::length);
        let weight = (l.mass * g).max(1.0);
        let nice = |x: f64| {
            let p = libm::pow(10.0, libm::floor(libm::log10(x)));
            let m = x / p;
            p * if m >= 5.0 {
                5.0
            } else if m >= 2.0 {
                2.0
            } else {
                1.0
            }
        };
        ArrowScale {
            velocity: nice(0.08 * scale / speed),
            force: nice(0.08 * scale / weight),
        }
    }
}

/// Colour of apex markers.
pub const APEX: Rgba = [250, 250, 255, 255];
/// Colour of impact markers.
pub const IMPACT: Rgba = [255, 220, 60, 255];
/// Declared events' markers: magenta, apart from every lane colour.
pub const EVENT: Rgba = [255, 80, 220, 255];
/// Colour of net-force arrows.
pub const FORCE: Rgba = [255, 90, 200, 255];
/// Colour of Magnus-lift arrows (a spun Mach drag).
pub const LIFT: Rgba = [170, 255, 60, 255];
/// Colour of thrust arrows (a motor).
pub const THRUST: Rgba = [255, 120, 0, 255];
/// Colour of the judder ghosts' drawn positions (spheres): cyan, apart from every lane colour.
pub const JUDDER_DRAWN: Rgba = [60, 230, 255, 255];
/// Colour of the judder ghosts' exact positions (crosses).
pub const JUDDER_EXACT: Rgba = [255, 255, 255, 255];

/// The arrays of one frame; kept between frames so their allocations are reused.
#[derive(Clone, Debug, Default)]
pub struct DrawList {
    /// Solid spheres: bodies and the launcher.
    pub solid: Vec<SphereInstance>,
    /// Translucent spheres: ghosts and targets.
    pub translucent: Vec<SphereInstance>,
    /// Line-list vertices: ghost trajectories, the launcher's barrel and predicted shot, wall
    /// outlines.
    pub lines: Vec<ColouredVertex>,
    /// Triangle-list vertices of translucent surfaces (walls).
    pub surfaces: Vec<ColouredVertex>,
    scratch: Vec<(f64, DVec3)>,
}

/// `p` relative to the render origin, in `f32`: the one place positions leave `f64`.
pub(crate) fn rel(p: DVec3, origin: DVec3) -> [f32; 3] {
    (p - origin).as_vec3().to_array()
}

impl DrawList {
    /// Rebuilds the list for `lanes` (the scene's fixed parts come from the first lane).
    pub fn build(&mut self, lanes: &[Lane<'_>], options: &DrawOptions) {
        self.solid.clear();
        self.translucent.clear();
        self.lines.clear();
        self.surfaces.clear();
        let Some(first) = lanes.first() else {
            return;
        };
        self.scene_parts(first.world, options);
        for lane in lanes {
            let bodies = lane.world.bodies();
            let radii = bodies.radii();
            let solid = &mut self.solid;
            solid.reserve(bodies.len());
            lane.history.drawn(lane.world, lane.at, |i, p| {
                solid.push(SphereInstance {
                    center: rel(p, options.origin),
                    radius: radii[i] as f32,
                    colour: lane.colour,
                });
            });
        }
        if options.ghosts {
            self.ghosts(first, options);
        }
        for lane in lanes {
            if options.markers {
                self.markers(lane, options);
            }
            if let Some(scale) = options.vectors {
                self.vectors(lane, scale, options);
            }
            if options.judder {
                self.judder(lane, options);
            }
        }
        if let Some(p) = options.highlight {
            self.translucent.push(SphereInstance {
                center: rel(p, options.origin),
                radius: (0.012 * options.scale) as f32,
                colour: [255, 255, 255, 110],
            });
        }
    }

    /// The markers of a lane's first bodies as small spheres: tenths dim, seconds in the
    /// lane's colour and twice the size, apexes white, impacts and rests yellow, declared events
    /// magenta. An impact or a rest on a level surface also rings the point it struck on that
    /// surface ([`DrawList::hit_ring`]).
    fn markers(&mut self, lane: &Lane<'_>, options: &DrawOptions) {
        use crate::render::probe::MarkerKind as K;
        let small = (0.0025 * options.scale) as f32;
        let mut dim = lane.colour;
        dim[3] = 255;
        let dim = [dim[0] / 2 + 60, dim[1] / 2 + 60, dim[2] / 2 + 60, 255];
        for track in lane.history.probe.tracks() {
            for m in &track.markers {
                let (radius, colour) = match m.kind {
                    K::Tenth => (small, dim),
                    K::Second => (2.0 * small, lane.colour),
                    K::Apex => (2.5 * small, APEX),
                    K::Impact(_) | K::Rest(_) => (2.5 * small, IMPACT),
                    K::Declared(_) => (3.0 * small, EVENT),
                };
                if let K::Impact(surface) | K::Rest(surface) = m.kind
                    && let Some(t) = lane.world.contacts().triangle(surface)
                {
                    self.hit_ring(t, m.at.p, 4.0 * f64::from(small), options.origin);
                }
                self.solid.push(SphereInstance {
                    center: rel(m.at.p, options.origin),
                    radius,
                    colour,
                });
            }
        }
    }

    /// The judder ghosts: each recent frame's drawn position as a small cyan sphere, fading
    /// with age, and the exact position at its display time as a white cross,
    /// joined by a faint line (the frame's display error). Even spacing of the spheres is
    /// smooth motion; uneven spacing, or spheres off their crosses by varying amounts, is
    /// judder.
    fn judder(&mut self, lane: &Lane<'_>, options: &DrawOptions) {
        let o = options.origin;
        let n = lane.judder.len();
        for (k, mark) in lane.judder.iter().enumerate() {
            // Small beside the body, so a frame's step to the next shows (at least 0.2 % of
            // the scene, to be seen at all).
            let radius = (0.35 * mark.radius).max(0.002 * options.scale);
            // The newest opaque, the oldest a third.
            let fade = 0.33 + 0.67 * (k + 1) as f32 / n as f32;
            let a = (255.0 * fade) as u8;
            let [r, g, b, _] = JUDDER_DRAWN;
            self.translucent.push(SphereInstance {
                center: rel(mark.drawn, o),
                radius: radius as f32,
                colour: [r, g, b, a],
            });
            let Some(x) = mark.exact else {
                continue;
            };
            let [r, g, b, _] = JUDDER_EXACT;
            let arm = 2.0 * radius;
            for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                self.line(x - arm * axis, x + arm * axis, [r, g, b, a], o);
            }
            self.line(mark.drawn, x, [r, g, b, a / 2], o);
        }
    }

    /// Velocity (the lane's colour) and net force (magenta) arrows from the first bodies, and
    /// where declared the Magnus lift (lime) and the thrust (orange), at the force's scale.
    fn vectors(&mut self, lane: &Lane<'_>, scale: ArrowScale, options: &DrawOptions) {
        let world = lane.world;
        let n = world.bodies().len().min(crate::render::probe::PROBE_BODIES);
        for i in 0..n {
            let p = world.bodies().state(i).p;
            self.arrow(p, scale.velocity * world.velocity(i), lane.colour, options);
            self.arrow(p, scale.force * world.force_on(i), FORCE, options);
            if let Some(lift) = world.lift_on(i) {
                self.arrow(p, scale.force * lift, LIFT, options);
            }
            if let Some(thrust) = world.thrust_on(i) {
                self.arrow(p, scale.force * thrust, THRUST, options);
            }
        }
    }

    /// A line from `from` along `d`, with a two-stroke head a fifth of its length.
    fn arrow(&mut self, from: DVec3, d: DVec3, colour: Rgba, options: &DrawOptions) {
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            return;
        }
        let tip = from + d;
        self.line(from, tip, colour, options.origin);
        let dir = d / len;
        let side = dir.cross(DVec3::Z).try_normalize().unwrap_or(DVec3::X);
        for s in [-1.0, 1.0] {
            let back = tip - 0.2 * len * dir + s * 0.08 * len * side;
            self.line(tip, back, colour, options.origin);
        }
    }

    /// A yellow ring of `radius` in the plane of triangle `t`, about the point of `t` nearest
    /// `centre` (the body's centre at its impact): where it struck the surface. Lifted off the
    /// face by a fiftieth of the radius towards the body, so the face's depth does not hide it.
    fn hit_ring(&mut self, t: [DVec3; 3], centre: DVec3, radius: f64, origin: DVec3) {
        let (q, _) = crate::contact::closest_point(centre, t[0], t[1], t[2]);
        let Some(mut n) = (t[1] - t[0]).cross(t[2] - t[0]).try_normalize() else {
            return;
        };
        if n.dot(centre - q) < 0.0 {
            n = -n;
        }
        let q = q + 0.02 * radius * n;
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        const SIDES: usize = 16;
        let at = |k: usize| {
            let a = std::f64::consts::TAU * k as f64 / SIDES as f64;
            q + radius * (a.cos() * u + a.sin() * v)
        };
        for k in 0..SIDES {
            self.line(at(k), at(k + 1), IMPACT, origin);
        }
    }

    fn line(&mut self, a: DVec3, b: DVec3, colour: Rgba, origin: DVec3) {
        for p in [a, b] {
            self.lines.push(ColouredVertex {
                position: rel(p, origin),
                colour,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_queued_aim_turns_the_launcher_before_the_world_does() {
        let text = "Scene(dt: 0.1, integrator: Rk4,
            launcher: (position: (0, 0, 0), speed: 10, elevation_deg: 0, azimuth_deg: 0))";
        let world = World::new(&crate::scene::parse(text, "aim.ron", "aim").unwrap());
        let history = TickHistory::new(&world, DVec3::ZERO);
        let lane = Lane {
            world: &world,
            history: &history,
            at: DrawAt::interpolated(1.0),
            colour: GHOST,
            judder: &[],
        };
        let mut options = DrawOptions::bodies(DVec3::ZERO, 100.0);
        let mut list = DrawList::default();
        list.build(&[lane], &options);
        // The barrel is the first line: 6 m (0.06 x scale) along the launch direction.
        assert_eq!(list.lines[1].position, [6.0, 0.0, 0.0]);
        options.aim = Some(Launcher {
            elevation_deg: 90.0,
            ..*world.launcher()
        });
        list.build(&[lane], &options);
        let tip = list.lines[1].position;
        assert!(tip[0].abs() < 1e-6 && tip[2] == 6.0, "{tip:?}");
    }
}
