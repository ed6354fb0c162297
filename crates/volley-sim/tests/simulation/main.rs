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
mod drag;
mod events;
mod exact;
mod firing;
mod hard_cases;
mod layers;
mod levels;
mod pacing;
mod parallel;
mod rest_event;
mod rocket;
mod seed;
mod stability;
mod transonic;
mod world;
