//! A game's own loop on Volley's simulation, with no window and no GPU stack: the bundled seed
//! scene stepped by [`SimLoop`] at the scene's fixed timestep while a virtual clock plays a
//! 144 Hz display, a second shot fired from game code at a tick boundary, events read after each
//! tick, and the state hash a replay or a CI job would pin.
//!
//! ```text
//! cargo run -p volley-sim --example game_loop
//! ```

use std::time::Duration;

use volley_sim::{
    Command, EventKind, FrameSource, ObserverError, SimLoop, TickObserver, VirtualClock, World,
    bundled_scene, state_hash,
};

/// What the game does after every tick: here, report impacts, target passes and hits.
struct Game {
    impacts: usize,
    events: usize,
}

impl TickObserver for Game {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        for event in world.events() {
            self.events += 1;
            if matches!(event.kind, EventKind::Impact { .. }) {
                self.impacts += 1;
            }
            println!(
                "tick {:>4}  t = {:7.4} s  {event:?}",
                world.tick(),
                world.time()
            );
        }
        Ok(())
    }
}

fn main() {
    let scene = bundled_scene("seed").unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2);
    });
    let mut sim = SimLoop::new(World::new(&scene));
    let mut display = VirtualClock::display(144.0);
    let mut game = Game {
        impacts: 0,
        events: 0,
    };

    // The scene's duration in frames: the clock turns each 6.94 ms frame into the whole ticks of
    // the scene's timestep it has accumulated and keeps the remainder, so sim time stays exactly
    // start_time + tick * dt.
    let frames = (scene.duration() * 144.0).ceil() as u32;
    for frame in 0..frames {
        if frame == 144 {
            // Input from game code: applied at the next tick boundary, as a recording sees it.
            sim.push(Command::Fire);
        }
        let delta: Duration = display.next_delta();
        if let Err(e) = sim.frame(delta, &mut game) {
            eprintln!("{e}");
            std::process::exit(3);
        }
    }
    let world = &sim.world;
    println!(
        "{} ticks, t = {:.4} s, {} bodies, {} events ({} impacts), state hash {:#018x}",
        world.tick(),
        world.time(),
        world.bodies().len(),
        game.events,
        game.impacts,
        state_hash(world)
    );
}
