//! The window and the GPU: the renderer against its golden image, trails and history, the real
//! winit window under Xvfb (smoke, sessions, recording and replaying from the panel).

#[path = "../support/mod.rs"]
mod support;

#[path = "../../crates/volley-sim/tests/replay_support/mod.rs"]
mod replay_support;

mod render_golden;
mod render_history;
mod render_paths;
mod window_aim;
mod window_compare;
mod window_draw;
mod window_levels;
mod window_pacing;
mod window_plots;
mod window_probe;
mod window_projectiles;
mod window_record_replay;
mod window_rewind;
mod window_session;
mod window_setup;
mod window_smoke;
mod window_surface;
