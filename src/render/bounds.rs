//! The region a scene plays in: what the default camera frames and where the render origin is.

use glam::DVec3;

use crate::command::Command;
use crate::scene::Scene;
use crate::world::World;

/// Bodies a preview run follows: enough to see the spread of a volley, cheap for any scene.
const PREVIEW_BODIES: u32 = 64;
/// Most ticks a preview run steps.
const PREVIEW_TICKS: u64 = 4000;
/// The default camera's yaw (degrees): from -y, x to the right.
const DEFAULT_YAW_DEG: f64 = -90.0;
/// Its yaw for a scene with level surfaces.
const LEVEL_YAW_DEG: f64 = -145.0;
/// Largest extent framed (m): a diverging preview must not zoom the camera out to infinity.
const MAX_EXTENT: f64 = 1e4;

/// An axis-aligned box (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneBounds {
    /// Lowest corner.
    pub min: DVec3,
    /// Highest corner.
    pub max: DVec3,
    /// The yaw (degrees) the default camera frames it from: -90 (from -y, x to the right) for
    /// most scenes; -145 for a scene with level surfaces, from behind the launcher's right, so
    /// that faces square to the line of fire (a range's plates) are not seen edge-on.
    pub yaw_deg: f64,
}

impl SceneBounds {
    /// Corner `k` of the box (0 to 7): bit 0 picks the x bound (0: min), bit 1 y, bit 2 z.
    pub fn corner(&self, k: u8) -> DVec3 {
        let pick = |bit: u8, lo: f64, hi: f64| if k & bit == 0 { lo } else { hi };
        DVec3::new(
            pick(1, self.min.x, self.max.x),
            pick(2, self.min.y, self.max.y),
            pick(4, self.min.z, self.max.z),
        )
    }

    /// A box holding only `p`.
    pub fn point(p: DVec3) -> SceneBounds {
        SceneBounds {
            min: p,
            max: p,
            yaw_deg: DEFAULT_YAW_DEG,
        }
    }

    /// Grows the box to hold `p` (non-finite points are ignored).
    pub fn include(&mut self, p: DVec3) {
        if p.is_finite() {
            self.min = self.min.min(p);
            self.max = self.max.max(p);
        }
    }

    /// Centre of the box: the render origin and the camera's default target.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the diagonal (m).
    pub fn radius(&self) -> f64 {
        0.5 * (self.max - self.min).length()
    }

    /// The launcher, the scene's bodies, targets and level surfaces (their boxes, within
    /// 1e4 m of the launcher), and where the first bodies and one shot from the launcher go
    /// over the scene's duration: a short preview run of the scene with at most 64 bodies,
    /// stopped at the ground, a divergence, or 4000 ticks.
    pub fn of_scene(scene: &Scene) -> SceneBounds {
        let launcher = scene.launcher().position;
        let mut bounds = SceneBounds::point(launcher);
        for t in scene.targets() {
            bounds.include(t.center - DVec3::splat(t.radius));
            bounds.include(t.center + DVec3::splat(t.radius));
        }
        for w in scene.walls() {
            bounds.include(w.point);
        }
        let levels = scene.meshes().iter().map(|m| m.bounds());
        let levels = levels.chain(scene.heightfields().iter().map(|h| h.bounds()));
        let reach = DVec3::splat(MAX_EXTENT);
        if !scene.meshes().is_empty() || !scene.heightfields().is_empty() {
            bounds.yaw_deg = LEVEL_YAW_DEG;
        }
        for b in levels {
            for p in [b.min, b.max] {
                bounds.include(p.clamp(launcher - reach, launcher + reach));
            }
        }
        let bodies = scene.bodies();
        let mut edit = scene
            .edit()
            .bodies(bodies[..bodies.len().min(PREVIEW_BODIES as usize)].to_vec());
        if let Some(v) = scene.volley() {
            edit = edit.volley(crate::scene::Volley {
                count: v.count.min(PREVIEW_BODIES),
                ..v
            });
        }
        // Fewer bodies of a checked scene check too; the scene itself if not.
        let preview = edit.build().unwrap_or_else(|_| scene.clone());
        let mut world = World::new(&preview);
        let _ = world.apply(&Command::Fire);
        let ticks = preview.ticks_until(preview.start_time() + preview.duration());
        for _ in 0..=ticks.min(PREVIEW_TICKS) {
            let b = world.bodies();
            for i in 0..b.len() {
                let p = b.positions().get(i);
                if (p - launcher).abs().max_element() <= MAX_EXTENT {
                    bounds.include(p);
                }
            }
            if world.step().is_err() {
                break;
            }
        }
        if let Some(g) = scene.ground() {
            bounds.min.z = bounds.min.z.max(g.height);
            bounds.include(DVec3::new(bounds.min.x, bounds.min.y, g.height));
        }
        bounds
    }
}
