//! The bundled `seed` scene stepped by Volley's plugin in Bevy's fixed schedule and drawn by Bevy's
//! renderer: `cargo run -p volley-bevy --example seed`. D switches the draw mode (the window's
//! title names it), Space fires, A aims at the scene's target.

mod common;

fn main() -> bevy::app::AppExit {
    common::run("seed")
}
