//! What the examples share: a bundled scene stepped by [`VolleyPlugin`] and drawn by Bevy's
//! renderer, with keys to switch the draw mode (D), fire (Space) and aim (A), and the run
//! recorded from the start: R writes it to `volley-bevy-NAME.vrec` in the current folder
//! (`volley replay` plays it back and `volley replay --verify` checks it), and the run goes on
//! unrecorded.
//!
//! With `VOLLEY_BEVY_SCREENSHOT=FILE.png` the example runs each frame as a 60th of a second of
//! game time (not the wall clock's), saves the window after `VOLLEY_BEVY_FRAMES` frames
//! (default 90) and exits: the CI test runs it that way under Xvfb.

use std::time::Duration;

use bevy::app::AppExit;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured, save_to_disk};
use bevy::time::TimeUpdateStrategy;
use bevy::window::{PrimaryWindow, WindowResolution};
use glam::DVec3;
use volley_bevy::{Volley, VolleyBody, VolleyKeys, VolleyPlugin, to_bevy};
use volley_sim::{DrawMode, RecordOptions, SimLoop, World, bundled_scene};

/// The colour bodies are drawn in: the CI test looks for it in the screenshot.
pub const BODY: Color = Color::srgb(1.0, 0.45, 0.0);

pub fn run(name: &str) -> AppExit {
    let scene = match bundled_scene(name) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("volley-bevy: {e}");
            return AppExit::error();
        }
    };
    let view = View::of(&scene);
    let shot = std::env::var_os("VOLLEY_BEVY_SCREENSHOT").map(std::path::PathBuf::from);
    let frames = std::env::var("VOLLEY_BEVY_FRAMES")
        .ok()
        .and_then(|f| f.parse().ok())
        .unwrap_or(90u32);
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: title(name, volley_sim::DEFAULT_DRAW),
            resolution: WindowResolution::new(960, 600),
            ..default()
        }),
        ..default()
    }))
    .add_plugins(VolleyPlugin::new(scene).recording(RecordOptions {
        scene_file: name.to_string(),
        ..RecordOptions::default()
    }))
    .insert_resource(VolleyKeys::default())
    .insert_resource(ClearColor(Color::srgb(0.06, 0.07, 0.09)))
    .insert_resource(GlobalAmbientLight {
        brightness: 400.0,
        ..default()
    })
    .insert_resource(view)
    .insert_resource(Named(name.to_string()))
    .add_systems(Startup, setup)
    .add_systems(Update, (dress_bodies, switch_draw_mode, save_recording));
    if let Some(path) = shot {
        // Each frame a 60th of a second of game time whatever the machine's speed, so the
        // screenshot shows the same moment on a slow software adapter as on a GPU.
        app.insert_resource(ScreenshotAt { frames, path })
            .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_nanos(
                16_666_667,
            )))
            .add_systems(Update, screenshot);
    }
    app.run()
}

fn title(name: &str, mode: DrawMode) -> String {
    format!(
        "Volley in Bevy: {name}, drawn {} (D: draw mode, Space: fire, A: aim, R: save the recording)",
        mode.name()
    )
}

#[derive(Resource)]
struct Named(String);

#[derive(Resource)]
struct ScreenshotAt {
    frames: u32,
    path: std::path::PathBuf,
}

/// Where the camera looks from and at: the box the scene's bodies sweep over its duration
/// (stepped once here, before the app starts), seen from the side and a little above.
#[derive(Resource, Clone, Copy)]
struct View {
    min: DVec3,
    max: DVec3,
    ground: Option<f64>,
}

impl View {
    fn of(scene: &volley_sim::Scene) -> View {
        let mut sim = SimLoop::new(World::new(scene));
        let seconds = if scene.duration() > 0.0 {
            scene.duration()
        } else {
            10.0
        };
        let ticks = (seconds / sim.world.dt()).ceil() as u64;
        let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for _ in 0..ticks.min(20_000) {
            for p in sim.world.bodies().positions().iter() {
                min = min.min(p);
                max = max.max(p);
            }
            if sim.frame(sim.clock.timestep(), &mut ()).is_err() {
                break;
            }
        }
        if !min.is_finite() {
            (min, max) = (DVec3::splat(-5.0), DVec3::splat(5.0));
        }
        View {
            min,
            max,
            ground: scene.ground().map(|g| g.height),
        }
    }

    /// The box's largest side (m), at least 4.
    fn size(&self) -> f64 {
        (self.max - self.min).max_element().max(4.0)
    }

    /// The radius a body is drawn with: its own, or a 150th of the view where that is larger,
    /// so a 0.1 m ball in a 60 m scene is still seen (a choice of the example: the plugin
    /// gives each body its true radius in [`VolleyBody`]).
    fn drawn_radius(&self, radius: f64) -> f32 {
        radius.max(self.size() / 150.0) as f32
    }
}

fn setup(
    mut commands: Commands,
    view: Res<View>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    volley: Res<Volley>,
) {
    let centre = (view.min + view.max) / 2.0;
    let size = view.size();
    let look = to_bevy(centre, DVec3::ZERO);
    // From the side (Volley's -y, Bevy's +z) and a little above, far enough that the box fits
    // the default 45-degree vertical field of view with a margin.
    let distance = 0.5 * size as f32 / (22.5f32).to_radians().tan() * 1.2;
    let eye = look + Vec3::new(0.0, 0.2, 1.0).normalize() * distance;
    commands.spawn((
        Camera3d::default(),
        Tonemapping::None,
        Transform::from_translation(eye).looking_at(look, Vec3::Y),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 6000.0,
            ..default()
        },
        Transform::from_xyz(0.3, 1.0, 0.6).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    if let Some(height) = view.ground {
        let at = to_bevy(DVec3::new(centre.x, centre.y, height), DVec3::ZERO);
        let side = size as f32 * 2.0;
        commands.spawn((
            Mesh3d(meshes.add(Plane3d::default().mesh().size(side, side))),
            MeshMaterial3d(materials.add(Color::srgb(0.18, 0.24, 0.2))),
            Transform::from_translation(at),
        ));
    }
    let scene = volley.world().scene();
    for wall in scene.walls() {
        // A slab through the wall's point, its normal along the slab's thin side.
        let normal = to_bevy(wall.normal, DVec3::ZERO).normalize();
        let at = to_bevy(wall.point, DVec3::ZERO);
        let height = (view.max.z - view.ground.unwrap_or(view.min.z)).max(2.0) as f32 * 1.2;
        commands.spawn((
            Mesh3d(meshes.add(Cuboid::new(wall.thickness as f32, height, size as f32))),
            MeshMaterial3d(materials.add(Color::srgb(0.45, 0.47, 0.52))),
            Transform::from_translation(at + Vec3::Y * height / 2.0)
                .with_rotation(Quat::from_rotation_arc(Vec3::X, normal)),
        ));
    }
    for target in scene.targets() {
        commands.spawn((
            Mesh3d(meshes.add(Sphere::new(target.radius as f32))),
            MeshMaterial3d(materials.add(Color::srgb(0.85, 0.15, 0.2))),
            Transform::from_translation(to_bevy(target.center, DVec3::ZERO)),
        ));
    }
}

/// A sphere for each new body.
fn dress_bodies(
    mut commands: Commands,
    added: Query<(Entity, &VolleyBody), Added<VolleyBody>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut material: Local<Option<Handle<StandardMaterial>>>,
    view: Res<View>,
) {
    let material = material
        .get_or_insert_with(|| {
            materials.add(StandardMaterial {
                base_color: BODY,
                unlit: true,
                ..default()
            })
        })
        .clone();
    for (entity, body) in &added {
        commands.entity(entity).insert((
            Mesh3d(meshes.add(Sphere::new(view.drawn_radius(body.radius)))),
            MeshMaterial3d(material.clone()),
        ));
    }
}

/// D steps through the draw modes; the window's title names the one drawn.
fn switch_draw_mode(
    keys: Res<ButtonInput<KeyCode>>,
    mut volley: ResMut<Volley>,
    named: Res<Named>,
    mut window: Single<&mut Window, With<PrimaryWindow>>,
) {
    if keys.just_pressed(KeyCode::KeyD) {
        let k = DrawMode::ALL
            .iter()
            .position(|&m| m == volley.draw_mode())
            .unwrap_or(0);
        let next = DrawMode::ALL[(k + 1) % DrawMode::COUNT];
        volley.set_draw_mode(next);
        window.title = title(&named.0, next);
    }
}

/// R: the recording so far, written to `volley-bevy-NAME.vrec`.
fn save_recording(keys: Res<ButtonInput<KeyCode>>, mut volley: ResMut<Volley>, named: Res<Named>) {
    if !keys.just_pressed(KeyCode::KeyR) {
        return;
    }
    let path = format!("volley-bevy-{}.vrec", named.0);
    match volley.finish_recording() {
        None => eprintln!("volley-bevy: the recording was already saved"),
        Some(Err(e)) => eprintln!("volley-bevy: the recording could not be finished: {e}"),
        Some(Ok((bytes, stats))) => {
            // Where the current folder refuses it, the temp folder: a recording is not lost
            // because one place could not take it.
            let fallback = std::env::temp_dir().join(&path);
            let written = std::fs::write(&path, &bytes)
                .map(|()| std::path::PathBuf::from(&path))
                .or_else(|e| {
                    eprintln!("volley-bevy: cannot write {path}: {e}");
                    std::fs::write(&fallback, &bytes).map(|()| fallback.clone())
                });
            match written {
                Ok(at) => eprintln!(
                    "volley-bevy: wrote {} (ticks {} to {}, {} bytes; `volley replay {}`)",
                    at.display(),
                    stats.start_tick,
                    stats.last_tick,
                    stats.bytes,
                    at.display()
                ),
                Err(e) => eprintln!("volley-bevy: cannot write {}: {e}", fallback.display()),
            }
        }
    }
}

/// Saves the window after the wanted frame count, then exits.
fn screenshot(mut commands: Commands, at: Res<ScreenshotAt>, mut frame: Local<u32>) {
    *frame += 1;
    if *frame == at.frames {
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(at.path.clone()))
            .observe(
                |_: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                    exit.write(AppExit::Success);
                },
            );
    }
}
