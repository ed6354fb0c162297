//! bevy_transform_interpolation driven as a Bevy game drives it, for the plugin's bodies: what
//! the peer test and the display bench share.

use bevy::app::{App, FixedPostUpdate, PostStartup};
use bevy::ecs::prelude::*;
use bevy::transform::components::Transform;
use bevy_transform_interpolation::prelude::{
    TransformInterpolationPlugin, TranslationInterpolation,
};
use volley_bevy::{Volley, VolleyBody, VolleySystems, to_bevy};

/// The peer's entity for a body: its transform is the body's position at the last tick, and
/// bevy_transform_interpolation eases it between ticks.
#[derive(Component)]
pub struct Peer(pub Entity);

/// Adds the peer's plugin and a peer entity for each body, moved to the body's position in the
/// fixed schedule after every tick (as a physics crate writes its bodies' transforms).
pub fn add_peer(app: &mut App) {
    app.add_plugins(TransformInterpolationPlugin::default())
        .add_systems(PostStartup, move_peers)
        .add_systems(FixedPostUpdate, move_peers.after(VolleySystems::Step));
}

/// The peer's transform for the body drawn by `entity`.
pub fn peer_of(app: &App, entity: Entity) -> Option<Transform> {
    app.world()
        .iter_entities()
        .find_map(|e| (e.get::<Peer>()?.0 == entity).then(|| e.get::<Transform>().copied()))
        .flatten()
}

fn move_peers(
    volley: Res<Volley>,
    bodies: Query<(Entity, &VolleyBody)>,
    mut peers: Query<(&Peer, &mut Transform), Without<VolleyBody>>,
    mut commands: Commands,
) {
    let world = volley.world();
    let ids = world.bodies().ids();
    for (entity, body) in &bodies {
        let Ok(i) = ids.binary_search(&body.id) else {
            continue;
        };
        let at = to_bevy(world.bodies().positions().get(i), volley.origin());
        match peers.iter_mut().find(|(p, _)| p.0 == entity) {
            Some((_, mut t)) => t.translation = at,
            None => {
                commands.spawn((
                    Peer(entity),
                    Transform::from_translation(at),
                    TranslationInterpolation,
                ));
            }
        }
    }
}
