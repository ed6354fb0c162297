//! The scene's fixed parts in the draw list: the targets where they are at this tick, the walls
//! as translucent slabs cut off at the ground, and the launcher with its barrel and its next
//! shot ([`super::paths`]).

use glam::DVec3;

use super::{ColouredVertex, DrawList, DrawOptions, LAUNCHER, SphereInstance, TARGET, WALL, rel};
use crate::world::World;

impl DrawList {
    /// Targets, walls and the launcher (the aim being set, if any, instead of the world's).
    pub(super) fn scene_parts(&mut self, world: &World, options: &DrawOptions) {
        let o = options.origin;
        let since_start = world.tick() as f64 * world.dt();
        for t in &world.contacts().targets {
            self.translucent.push(SphereInstance {
                center: rel(t.center_at(since_start), o),
                radius: t.radius as f32,
                colour: TARGET,
            });
        }
        for w in &world.contacts().walls {
            self.wall(w.point, w.normal, w.thickness, world, options);
        }
        let l = options.aim.unwrap_or(*world.launcher());
        self.solid.push(SphereInstance {
            center: rel(l.position, o),
            radius: (2.0 * l.radius).max(0.01 * options.scale) as f32,
            colour: LAUNCHER,
        });
        let dir = l.velocity().try_normalize().unwrap_or(DVec3::Z);
        self.line(
            l.position,
            l.position + 0.06 * options.scale * dir,
            LAUNCHER,
            o,
        );
        self.launcher_shot(world, options);
    }

    /// A wall as a translucent square slab around its point (both faces, with an outline), cut
    /// off at the ground: the ground is solid, nothing of a wall shows below it.
    fn wall(
        &mut self,
        point: DVec3,
        normal: DVec3,
        thickness: f64,
        world: &World,
        o: &DrawOptions,
    ) {
        let helper = if normal.z.abs() < 0.9 {
            DVec3::Z
        } else {
            DVec3::X
        };
        let u = normal.cross(helper).normalize() * o.scale;
        let v = normal.cross(u).normalize() * o.scale;
        let floor = world.contacts().ground.map(|g| g.height);
        for side in [-0.5, 0.5] {
            let c = point + side * thickness * normal;
            let square = [c - u - v, c + u - v, c + u + v, c - u + v];
            let face = match floor {
                Some(z) => clip_above(&square, z),
                None => square.to_vec(),
            };
            for k in 1..face.len().saturating_sub(1) {
                for p in [face[0], face[k], face[k + 1]] {
                    self.surfaces.push(ColouredVertex {
                        position: rel(p, o.origin),
                        colour: WALL,
                    });
                }
            }
            for k in 0..face.len() {
                self.line(face[k], face[(k + 1) % face.len()], WALL, o.origin);
            }
        }
    }
}

/// The part of a convex polygon at or above height `z` (Sutherland-Hodgman against one plane).
pub fn clip_above(polygon: &[DVec3], z: f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        if a.z >= z {
            out.push(a);
        }
        if (a.z >= z) != (b.z >= z) {
            let t = (z - a.z) / (b.z - a.z);
            out.push(a + t * (b - a));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_a_square_at_its_middle_keeps_the_upper_half() {
        let square = [
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        let upper = clip_above(&square, 0.0);
        assert_eq!(
            upper,
            [
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 1.0),
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(0.0, 0.0, 0.0),
            ]
        );
        assert!(clip_above(&square, 2.0).is_empty());
        assert_eq!(clip_above(&square, -1.0).len(), 4);
    }
}
