//! The simulation's tests: clock, loop, world, integrators, closed forms, events, the stability
//! pre-check and the hard cases. One binary, no GPU stack: it links `volley-sim` alone.

#[path = "../support/mod.rs"]
mod support;

mod aim;
mod atmosphere;
mod ballistics;
mod ballistics_g7;
mod baseball;
mod clock;
mod convergence;
mod custom;
mod declared;
mod drag;
mod draw;
mod events;
mod exact;
mod firing;
mod hard_cases;
mod in_code;
mod layers;
mod levels;
mod parallel;
mod range_table;
mod rest_event;
mod rocket;
mod scene_headers;
mod seed;
mod transonic;
mod world;
