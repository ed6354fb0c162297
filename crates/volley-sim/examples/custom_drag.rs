//! A game's own force term: an arrow whose drag curve is the game's, not one of Volley's.
//!
//! The game implements [`ForceTerm`], passes it to Volley in its [`ForceTerms`], and names it
//! in a scene like any built-in term. Volley steps it with the scene's integrator, at each stage's own time, and a recording
//! of the run names it (`Custom(name: "my-game/arrow-drag", version: 1)`), so a replay without
//! this game's code is refused instead of drifting.
//!
//! ```text
//! cargo run -p volley-sim --example custom_drag
//! ```

use glam::DVec3;
use volley_sim::{EventKind, Integrator, World, parse_scene_with, state_hash};
use volley_sim::{ForceInput, ForceTerm, ForceTerms};

/// The game's arrow: drag `F = -(rho / 2) Cd(|v|) A |v| v` with its own curve, a coefficient that
/// rises as the arrow slows and starts to yaw (a made-up fit a game might tune by eye), and
/// a fletching that adds a fixed share.
#[derive(Debug)]
struct ArrowDrag {
    /// Frontal area (m^2).
    area: f64,
}

impl ArrowDrag {
    /// The game's curve: 1.6 at rest falling to 1.2 at speed, plus the fletching's 0.3.
    fn cd(speed: f64) -> f64 {
        1.2 + 0.4 / (1.0 + (speed / 30.0) * (speed / 30.0)) + 0.3
    }
}

impl ForceTerm for ArrowDrag {
    fn name(&self) -> &str {
        "my-game/arrow-drag"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        let speed = i.v.length();
        let rho = 1.225;
        -(0.5 * rho * Self::cd(speed) * self.area * speed) * i.v
    }
}

fn main() {
    let terms = ForceTerms::new().with(ArrowDrag { area: 5.0e-5 });
    for integrator in [Integrator::SemiImplicitEuler, Integrator::Rk4] {
        let scene = parse_scene_with(
            &format!(
                "Scene(dt: 0.016666667, integrator: {integrator:?}, duration: 10,
                   forces: [Gravity((0, 0, -9.81)),
                            Custom(name: \"my-game/arrow-drag\", version: 1)],
                   ground: (height: 0, restitution: 0),
                   bodies: [(mass: 0.025, radius: 0.004, position: (0, 0, 1.6),
                             launch: Angles(speed: 60, elevation_deg: 20))])"
            ),
            "arrow.ron",
            "arrow",
            &terms,
        )
        .expect("the arrow's scene parses");
        let mut world = World::new(&scene);
        let mut landed = None;
        while landed.is_none() && world.tick() < 600 {
            world.step().expect("the arrow steps");
            landed = world
                .events()
                .iter()
                .find(|e| matches!(e.kind, EventKind::Impact { .. } | EventKind::Rest { .. }))
                .map(|e| (e.time, world.bodies().positions().get(0)));
        }
        match landed {
            Some((t, p)) => println!(
                "{integrator}: the arrow lands {:.2} m away after {t:.3} s (hash {:#018x})",
                p.x,
                state_hash(&world)
            ),
            None => println!("{integrator}: still flying after 10 s"),
        }
    }
    println!("the scene, as a saved setup names the term:");
    let text = parse_scene_with(
        "Scene(dt: 0.01, integrator: Rk4, forces: [Custom(name: \"my-game/arrow-drag\", version: 1)])",
        "arrow.ron",
        "arrow",
        &terms,
    )
    .expect("parses")
    .to_ron();
    for line in text
        .lines()
        .filter(|l| l.contains("Custom") || l.contains("name: \"my") || l.contains("version"))
    {
        println!("{line}");
    }
}
