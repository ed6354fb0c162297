//! The plugin's interpolate mode against bevy_transform_interpolation, the smoothing crate Bevy
//! games use: on the same app and frames, the peer's eased transform is where the plugin draws
//! in `DrawMode::Interpolate`, to f32 rounding. A reference nobody here wrote for what the loop
//! lab calls interpolation, and the check that the display bench (benches/display.rs) drives
//! the peer as a game does (without `App::finish`, the peer never eases: its transform would
//! be the tick's).

mod support;

use std::time::Duration;

use bevy::MinimalPlugins;
use bevy::app::App;
use bevy::time::TimeUpdateStrategy;
use bevy::transform::components::Transform;
use volley_bevy::{Volley, VolleyPlugin};
use volley_sim::{DrawMode, bundled_scene};

#[test]
fn the_peers_interpolation_is_the_plugins_interpolate_mode() {
    let mut app = App::new();
    app.add_plugins(MinimalPlugins)
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::ZERO))
        .add_plugins(
            VolleyPlugin::new(bundled_scene("bounce").unwrap()).draw_mode(DrawMode::Interpolate),
        );
    support::peer::add_peer(&mut app);
    app.finish();
    app.cleanup();
    app.update();
    // A jittery 144 Hz display over the 60 Hz scene, with a 50 ms stall every 40 frames.
    let (mut eased, mut worst) = (0, 0.0f32);
    for k in 0..1500u64 {
        let delta = if k % 40 == 39 {
            Duration::from_millis(50)
        } else {
            Duration::from_nanos(6_944_444 + (k * 7_919 % 1_000_000))
        };
        app.insert_resource(TimeUpdateStrategy::ManualDuration(delta));
        app.update();
        let volley = app.world().resource::<Volley>();
        let bodies = volley.world().bodies();
        for (i, &id) in bodies.ids().iter().enumerate() {
            let entity = volley.entity(id).unwrap();
            let ours = app.world().get::<Transform>(entity).unwrap().translation;
            let peer = support::peer::peer_of(&app, entity).unwrap().translation;
            let tick = volley_bevy::to_bevy(bodies.positions().get(i), volley.origin());
            if (peer - tick).length() > 1e-3 {
                eased += 1;
            }
            // Positions within 20 m: f32's spacing there is 2e-6 m, and the peer lerps in f32
            // where the plugin lerps in f64 and rounds once.
            let off = (ours - peer).abs().max_element();
            worst = worst.max(off);
            assert!(
                off <= 1e-5,
                "frame {k} body {i}: plugin {ours}, peer {peer}"
            );
        }
    }
    // The peer did ease: most frames drew the balls between ticks, not at them.
    assert!(eased > 1500, "{eased}");
    eprintln!("largest difference {worst} m");
}
