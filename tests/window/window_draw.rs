//! The library's measured draw (`volley_sim::Draw`) places every body where the window draws
//! it: a game that draws with it shows what Volley's window shows, frame by frame.

use std::time::Duration;

use volley::app::session::Session;
use volley::{Draw, SimLoop, World, scene};

use crate::support;

/// The bounce scene at 144 Hz frames (6.944 ms, so ticks fall between frames and some frames
/// run none), under every draw mode: the window's session and a game's own loop with a `Draw`,
/// fed the same deltas, draw every body at the same bits every frame.
#[test]
fn a_games_draw_places_every_body_where_the_window_does() {
    let path = support::crate_path("assets/scenes/bounce.ron");
    let scene = scene::load(&path).unwrap();
    for mode in volley::DrawMode::ALL {
        let mut session = Session::new(scene.clone(), &path, Vec::new());
        session.set_draw_mode(mode);
        let mut sim = SimLoop::new(World::new(&scene));
        sim.clock.set_policy(session.policy());
        let mut draw = Draw::new(&sim.world, mode);
        let delta = Duration::from_nanos(6_944_444);
        let mut compared = 0;
        for frame in 0..300 {
            session.frame(delta);
            let ticks = sim.frame(delta, &mut draw).unwrap();
            draw.frame(delta);
            assert_eq!(session.world().tick(), sim.world.tick(), "frame {frame}");
            let lane = &session.draw_lanes()[0];
            let mut window = Vec::new();
            lane.history
                .drawn(lane.world, lane.at, |i, p| window.push((i, p)));
            let mut game = Vec::new();
            draw.positions(&sim.world, ticks.alpha, |i, p| game.push((i, p)));
            assert_eq!(window, game, "{mode:?}, frame {frame}");
            compared += game.len();
        }
        assert!(compared >= 3 * 300, "{compared}");
    }
}
