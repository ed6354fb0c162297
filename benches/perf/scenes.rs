//! The benchmark worlds: the bench scenes at a chosen size and integrator, and the seed scene.

use std::path::Path;

use volley::scene::{self, Scene};
use volley::{Integrator, World};

/// Which bench scene (`assets/scenes/bench/NAME.ron`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchScene {
    /// Gravity only: the reference kernel's physics.
    Gravity,
    /// Gravity and linear drag: the velocity-dependent path of every integrator.
    Drag,
}

impl BenchScene {
    /// Both scenes, in report order.
    pub const ALL: [BenchScene; 2] = [BenchScene::Gravity, BenchScene::Drag];

    /// File stem and the name used in benchmark ids.
    pub fn name(self) -> &'static str {
        match self {
            BenchScene::Gravity => "gravity",
            BenchScene::Drag => "drag",
        }
    }

    /// The scene with `n` bodies (its volley's count) and `integrator`.
    pub fn load(self, n: u64, integrator: Integrator) -> Scene {
        let path = format!("assets/scenes/bench/{}.ron", self.name());
        let scene = scene::load(Path::new(&path)).expect("the bench scenes are valid");
        let volley = scene.volley().expect("the bench scenes declare a volley");
        let mut scene = scene
            .edit()
            .volley(volley::Volley {
                count: u32::try_from(n).expect("bench sizes fit a volley count"),
                ..volley
            })
            .build()
            .expect("a bench scene with another count is valid");
        scene
            .set_integrator(integrator)
            .expect("the bench scenes' forces have closed forms");
        scene
    }

    /// A world of `n` bodies stepped by `integrator` on `threads` threads.
    pub fn world(self, n: u64, integrator: Integrator, threads: usize) -> World {
        let mut world = World::new(&self.load(n, integrator));
        world.set_threads(threads);
        world
    }
}

/// The seed scene of the course slides, as bundled.
pub fn seed() -> Scene {
    scene::load(Path::new("assets/scenes/seed.ron")).expect("the seed scene is valid")
}
