//! Declared events (docs/physics.md, "Declared events"): crossings, apexes, speeds, Mach numbers
//! and closest approaches, found once each with their exact time and state.

mod adversarial;
mod basic;
mod kinds;

use volley_sim::{BodyState, Event, EventDirection, EventKind, Scene, World};

/// A declared event as the tests read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    pub event: u32,
    pub body: u64,
    pub tick: u64,
    pub time: f64,
    pub direction: EventDirection,
    pub graze: bool,
    pub state: BodyState,
}

pub fn declared(e: &Event) -> Option<Seen> {
    match e.kind {
        EventKind::Declared {
            event,
            direction,
            graze,
            state,
        } => Some(Seen {
            event,
            body: e.body.0,
            tick: e.tick,
            time: e.time,
            direction,
            graze,
            state,
        }),
        _ => None,
    }
}

/// Every declared event of `ticks` ticks of `scene`, in order.
pub fn run(scene: &Scene, ticks: u64) -> Vec<Seen> {
    let mut world = World::new(scene);
    let mut out = Vec::new();
    for _ in 0..ticks {
        world.step().unwrap();
        out.extend(world.events().iter().filter_map(declared));
    }
    out
}

pub fn parse(text: &str) -> Scene {
    volley_sim::parse_scene(text, "test.ron", "test").unwrap_or_else(|e| panic!("{e}"))
}
