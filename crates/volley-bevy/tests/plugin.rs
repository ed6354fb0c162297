//! The plugin in a headless Bevy app (the core plugins, manual time): ticks per frame, hashes
//! against Volley's own headless loop, events once each, draw modes that never touch the world,
//! bodies as entities, input, and recordings replayed through the plugin.

use std::io::Cursor;
use std::time::Duration;

use bevy::MinimalPlugins;
use bevy::app::{App, Update};
use bevy::ecs::message::MessageReader;
use bevy::ecs::prelude::*;
use bevy::input::ButtonInput;
use bevy::input::keyboard::KeyCode;
use bevy::time::{Fixed, Time, TimeUpdateStrategy};
use bevy::transform::components::Transform;
use glam::DVec3;
use volley_bevy::{
    Volley, VolleyBody, VolleyCommand, VolleyEvent, VolleyKeys, VolleyPlugin, to_bevy,
};
use volley_sim::{
    Command, Draw, DrawMode, Event, EventKind, Ground, Integrator, Launcher, ObserverError,
    RecordOptions, Recording, Replay, Scene, SimLoop, Target, TickObserver, World, bundled_scene,
    state_hash,
};

/// A headless app: Bevy's time (driven by hand), its fixed loop, and the plugin. The first
/// update of a manually driven clock has no delta (Bevy's `Time<Real>` starts there), so the
/// app is updated once before the test's frames.
fn app_of(plugin: VolleyPlugin) -> App {
    let mut app = App::new();
    app.add_plugins(MinimalPlugins)
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::ZERO))
        .init_resource::<Seen>()
        .add_plugins(plugin)
        .add_systems(Update, collect);
    // What `App::run` does before its first update.
    app.finish();
    app.cleanup();
    app.update();
    app
}

/// One frame of `delta`.
fn frame(app: &mut App, delta: Duration) {
    app.insert_resource(TimeUpdateStrategy::ManualDuration(delta));
    app.update();
}

fn volley(app: &App) -> &Volley {
    app.world().resource::<Volley>()
}

/// The events a game system read, in order.
#[derive(Resource, Default)]
struct Seen(Vec<VolleyEvent>);

fn collect(mut reader: MessageReader<VolleyEvent>, mut seen: ResMut<Seen>) {
    seen.0.extend(reader.read().copied());
}

/// Frame deltas that give some frames several ticks and some none: a jittery 144 Hz display
/// with a stall every 50 frames (under Bevy's 250 ms clamp), from a fixed generator.
fn deltas(n: usize) -> Vec<Duration> {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    (0..n)
        .map(|k| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let jitter = (x % 4_000_000) as i64 - 2_000_000;
            if k % 50 == 49 {
                Duration::from_millis(70)
            } else {
                Duration::from_nanos((6_944_444 + jitter) as u64)
            }
        })
        .collect()
}

/// What Volley's own headless loop (`volley headless` and `volley record`: the loop's unpaced
/// frames) gives at every tick: its hash and events.
struct Every {
    hashes: Vec<u64>,
    events: Vec<Event>,
}

impl TickObserver for Every {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.hashes.push(state_hash(world));
        self.events.extend_from_slice(world.events());
        Ok(())
    }
}

fn headless(scene: &str, ticks: u64, commands: &[(u64, Command)]) -> Every {
    let scene = bundled_scene(scene).unwrap();
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(
        commands
            .iter()
            .map(|&(tick, command)| volley_sim::Stamped { tick, command }),
    );
    let mut every = Every {
        hashes: vec![state_hash(&sim.world)],
        events: Vec::new(),
    };
    let mut source = sim.unpaced_source(volley_sim::internals::sim_loop::UNPACED_FRAME_TICKS);
    sim.run_until(ticks, &mut source, &mut every).unwrap();
    every
}

/// Hashes at each tick the plugin's world reaches, read after every frame: a frame of several
/// ticks shows only its last, so the test also records and has the replay check every tick.
fn hash_at_each_frame(app: &mut App, deltas: &[Duration], out: &mut Vec<(u64, u64)>) {
    for &d in deltas {
        frame(app, d);
        let world = volley(app).world();
        out.push((world.tick(), state_hash(world)));
    }
}

#[test]
fn a_frame_runs_as_many_ticks_as_bevys_fixed_clock_grants_several_or_none() {
    let scene = bundled_scene("bounce").unwrap();
    let step = scene.timestep();
    let mut app = app_of(VolleyPlugin::new(scene));
    assert_eq!(app.world().resource::<Time<Fixed>>().timestep(), step);
    // Three and a half timesteps: three ticks in one frame.
    frame(&mut app, step * 7 / 2);
    assert_eq!(volley(&app).world().tick(), 3);
    // A third of one, twice: no tick, then none again, then the carried half makes one.
    frame(&mut app, step / 3);
    assert_eq!(volley(&app).world().tick(), 3);
    assert_eq!(
        volley(&app).draw().previous_tick(),
        2,
        "before the frame's last tick"
    );
    frame(&mut app, step / 3);
    assert_eq!(volley(&app).world().tick(), 4);
    // Over a long irregular run, whole ticks of the time fed in, exactly.
    let run = deltas(600);
    let mut fed = step * 7 / 2 + step / 3 * 2;
    let mut per_frame = [0usize; 5];
    for &d in &run {
        let before = volley(&app).world().tick();
        frame(&mut app, d);
        fed += d;
        per_frame[((volley(&app).world().tick() - before) as usize).min(4)] += 1;
    }
    let ticks = volley(&app).world().tick();
    assert_eq!(u128::from(ticks), fed.as_nanos() / step.as_nanos());
    // A 144 Hz display over 60 Hz ticks: frames of none and of one, and the stalls' several.
    assert!(per_frame[0] > 200 && per_frame[1] > 200, "{per_frame:?}");
    assert_eq!(
        per_frame[4], 12,
        "the 70 ms stalls: 4 or 5 ticks each; {per_frame:?}"
    );
    assert!(volley(&app).stopped().is_none());
}

#[test]
fn every_tick_hashes_as_volley_headless_does() {
    // The seed's pinned hash at its last tick (27), which `volley headless seed --expect-hash`
    // checks in tests/cli/determinism.rs.
    let mut app = app_of(VolleyPlugin::new(bundled_scene("seed").unwrap()).recording(
        RecordOptions {
            scene_file: "seed".into(),
            ..RecordOptions::default()
        },
    ));
    app.world_mut().resource_mut::<Volley>().stop_at(Some(27));
    // The seed's 0.2 s ticks against a 144 Hz display: one tick in about 29 frames.
    let mut seen = Vec::new();
    hash_at_each_frame(&mut app, &deltas(800), &mut seen);
    assert_eq!(volley(&app).world().tick(), 27);
    assert_eq!(state_hash(volley(&app).world()), 0xe02a_9ef4_a1dd_b321);
    let reference = headless("seed", 27, &[]);
    for &(tick, hash) in &seen {
        assert_eq!(hash, reference.hashes[tick as usize], "tick {tick}");
    }

    // The bounce scene with shots fired from a game system between ticks: the plugin's run,
    // recorded, replays through Volley's own loop with every tick's hash checked.
    let mut app = app_of(
        VolleyPlugin::new(bundled_scene("bounce").unwrap()).recording(RecordOptions::default()),
    );
    let mut fired = Vec::new();
    for (k, &d) in deltas(900).iter().enumerate() {
        if k % 97 == 5 {
            fired.push(volley(&app).world().tick());
            app.world_mut().write_message(VolleyCommand(Command::Fire));
        }
        frame(&mut app, d);
    }
    let end = volley(&app).world().tick();
    let end_hash = state_hash(volley(&app).world());
    assert_eq!(volley(&app).world().bodies().len(), 3 + fired.len());
    let (bytes, stats) = app
        .world_mut()
        .resource_mut::<Volley>()
        .finish_recording()
        .expect("recording")
        .unwrap();
    assert_eq!(stats.hashes, end + 1, "a hash at every tick, 0 included");
    let recording = Recording::from_reader(Cursor::new(bytes.clone()), "bounce.vrec").unwrap();
    let mut replay = Replay::start(recording, None).unwrap();
    replay.run_to(u64::MAX, &mut ()).unwrap();
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.hashes_checked(), end + 1);
    assert_eq!(state_hash(replay.world()), end_hash);
    // And the same commands at the same ticks in the headless loop: the same hash at every
    // tick.
    let commands: Vec<(u64, Command)> = fired.iter().map(|&t| (t, Command::Fire)).collect();
    let reference = headless("bounce", end, &commands);
    assert_eq!(*reference.hashes.last().unwrap(), end_hash);

    // The recording replayed through the plugin: verified at every tick, the same end.
    let mut app = app_replaying(bytes);
    for &d in &deltas(900) {
        frame(&mut app, d);
    }
    assert_eq!(volley(&app).world().tick(), end);
    assert!(volley(&app).replay_divergence().is_none());
    assert_eq!(volley(&app).replay_hashes_checked(), end + 1);
    assert_eq!(state_hash(volley(&app).world()), end_hash);
    // A replay's commands are the recording's: a game's are refused.
    assert!(!app.world_mut().resource_mut::<Volley>().push(Command::Fire));
}

fn app_replaying(bytes: Vec<u8>) -> App {
    app_of(VolleyPlugin::replay(bytes, "bounce.vrec"))
}

#[test]
fn every_event_arrives_once_with_its_body() {
    let mut app = app_of(VolleyPlugin::new(bundled_scene("bounce").unwrap()));
    let run = deltas(2200);
    for &d in &run {
        frame(&mut app, d);
    }
    let end = volley(&app).world().tick();
    let reference = headless("bounce", end, &[]);
    let seen: Vec<Event> = app
        .world()
        .resource::<Seen>()
        .0
        .iter()
        .map(|e| e.event)
        .collect();
    assert!(
        seen.iter()
            .filter(|e| matches!(e.kind, EventKind::Impact { .. }))
            .count()
            > 20
    );
    assert!(
        seen.iter()
            .any(|e| matches!(e.kind, EventKind::Rest { .. }))
    );
    assert_eq!(seen, reference.events);
    let seen = &app.world().resource::<Seen>().0;
    for e in seen {
        let entity = e.entity.expect("the bounce scene's balls live on");
        let body = app.world().get::<VolleyBody>(entity).unwrap();
        assert_eq!(body.id, e.event.body);
    }
}

/// Hashes and drawn positions, frame by frame, with the draw mode set before each frame by
/// `mode`.
fn run_modes(mode: impl Fn(usize) -> DrawMode, n: usize) -> (Vec<u64>, Vec<Vec<[f32; 3]>>) {
    let mut app = app_of(VolleyPlugin::new(bundled_scene("bounce").unwrap()));
    let (mut hashes, mut drawn) = (Vec::new(), Vec::new());
    for (k, &d) in deltas(n).iter().enumerate() {
        app.world_mut()
            .resource_mut::<Volley>()
            .set_draw_mode(mode(k));
        frame(&mut app, d);
        hashes.push(state_hash(volley(&app).world()));
        let mut at: Vec<(volley_sim::BodyId, [f32; 3])> = app
            .world_mut()
            .query::<(&VolleyBody, &Transform)>()
            .iter(app.world())
            .map(|(b, t)| (b.id, t.translation.to_array()))
            .collect();
        at.sort_by_key(|(id, _)| *id);
        drawn.push(at.into_iter().map(|(_, p)| p).collect());
    }
    (hashes, drawn)
}

#[test]
fn switching_draw_mode_never_changes_a_hash() {
    let n = 900;
    let (steady, drawn_steady) = run_modes(|_| DrawMode::Swept, n);
    let (switched, drawn_switched) = run_modes(|k| DrawMode::ALL[k % DrawMode::COUNT], n);
    assert_eq!(steady, switched);
    // The switch did switch: frames drawn in another mode put the balls elsewhere.
    let moved = (0..n)
        .filter(|&k| DrawMode::ALL[k % DrawMode::COUNT] != DrawMode::Swept)
        .filter(|&k| drawn_steady[k] != drawn_switched[k])
        .count();
    assert!(moved > n / 2, "{moved}");
}

#[test]
fn bodies_are_drawn_where_volleys_own_loop_and_draw_place_them() {
    // Volley's loop and draw fed the same deltas (what Volley's window and an adopter of the
    // crate run): each transform is that position, to f32.
    for mode in DrawMode::ALL {
        let scene = bundled_scene("bounce").unwrap();
        let mut app = app_of(VolleyPlugin::new(scene.clone()).draw_mode(mode));
        let mut sim = SimLoop::new(World::new(&scene));
        let mut draw = Draw::new(&sim.world, mode);
        // The app's first (empty) update fed the draw a zero delta; so does this one.
        draw.frame(Duration::ZERO);
        let mut worst = 0.0f64;
        for &d in &deltas(700) {
            frame(&mut app, d);
            let ticks = sim.frame(d, &mut draw).unwrap();
            draw.frame(d);
            assert_eq!(sim.world.tick(), volley(&app).world().tick());
            let entities: Vec<Entity> = sim
                .world
                .bodies()
                .ids()
                .iter()
                .map(|&id| volley(&app).entity(id).unwrap())
                .collect();
            let mut places = Vec::new();
            draw.positions(&sim.world, ticks.alpha, |i, p| places.push((i, p)));
            for (i, p) in places {
                let t = app.world().get::<Transform>(entities[i]).unwrap();
                let want = to_bevy(p, DVec3::ZERO);
                // f32 rounding of a position within 20 m, plus the alphas' own rounding: Bevy's
                // overstep over its timestep and Volley's accumulator over its tick, each in
                // f64, may part in the last bit (a bounce scene's speeds are under 20 m/s).
                let off = (t.translation - want).abs().max_element();
                worst = worst.max(f64::from(off));
                assert!(
                    off <= 4e-6,
                    "{mode:?} body {i}: {} vs {want}",
                    t.translation
                );
            }
        }
        assert!(worst < 4e-6, "{worst}");
    }
}

#[test]
fn bodies_gain_and_lose_entities_with_the_world() {
    let mut app = app_of(VolleyPlugin::new(bundled_scene("bounce").unwrap()));
    frame(&mut app, Duration::from_millis(20));
    let count = |app: &mut App| {
        app.world_mut()
            .query::<&VolleyBody>()
            .iter(app.world())
            .count()
    };
    assert_eq!(count(&mut app), 3);
    app.world_mut().write_message(VolleyCommand(Command::Fire));
    // Queued in a frame that runs no tick, applied at the next tick boundary.
    frame(&mut app, Duration::from_millis(1));
    assert_eq!(count(&mut app), 3);
    frame(&mut app, Duration::from_millis(20));
    assert_eq!(count(&mut app), 4);
    let first = volley(&app).world().bodies().ids()[0];
    let entity = volley(&app).entity(first).unwrap();
    app.world_mut()
        .write_message(VolleyCommand(Command::Despawn(first)));
    frame(&mut app, Duration::from_millis(20));
    assert_eq!(count(&mut app), 3);
    assert!(app.world().get_entity(entity).is_err());
    assert_eq!(volley(&app).entity(first), None);
}

#[test]
fn keys_fire_and_aim_the_launcher_at_the_target() {
    // A target 30 m off and a launcher pointed elsewhere: aiming must turn it.
    let target = Target {
        center: DVec3::new(30.0, 8.0, 4.0),
        radius: 0.5,
        velocity: DVec3::ZERO,
    };
    let scene = Scene::builder("aim", 1.0 / 60.0)
        .integrator(Integrator::VelocityVerlet)
        .gravity(DVec3::new(0.0, 0.0, -9.81))
        .ground(Ground {
            height: 0.0,
            restitution: 0.5,
        })
        .target(target)
        .launcher(Launcher {
            position: DVec3::new(0.0, 0.0, 1.0),
            speed: 25.0,
            elevation_deg: 70.0,
            azimuth_deg: -40.0,
            mass: 0.5,
            radius: 0.1,
            backspin: 0.0,
            sidespin: 0.0,
        })
        .build()
        .unwrap();
    let mut app = app_of(VolleyPlugin::new(scene));
    app.insert_resource(VolleyKeys::default())
        .insert_resource(ButtonInput::<KeyCode>::default());
    let before = volley(&app).world().bodies().len();
    let press = |app: &mut App, key: KeyCode| {
        app.world_mut()
            .resource_mut::<ButtonInput<KeyCode>>()
            .press(key);
        frame(app, Duration::from_millis(17));
        let mut input = app.world_mut().resource_mut::<ButtonInput<KeyCode>>();
        input.release(key);
        input.clear();
    };
    let aim = volley(&app).aim_command();
    assert!(matches!(aim, Ok(Command::SetLaunch { .. })), "{aim:?}");
    press(&mut app, KeyCode::KeyA);
    press(&mut app, KeyCode::Space);
    assert_eq!(volley(&app).world().bodies().len(), before + 1);
    let shot = *volley(&app).world().bodies().ids().last().unwrap();
    for _ in 0..600 {
        frame(&mut app, Duration::from_millis(17));
    }
    // The aimed shot reached the target: its closest approach is within the two radii.
    let seen = &app.world().resource::<Seen>().0;
    let approach = seen.iter().find_map(|e| match e.event.kind {
        EventKind::Approach { distance, hit, .. } if e.event.body == shot => Some((distance, hit)),
        _ => None,
    });
    // A fired body's events carry its entity, from its first tick on.
    for e in seen.iter().filter(|e| e.event.body == shot) {
        let entity = e.entity.expect("the shot's entity");
        assert_eq!(app.world().get::<VolleyBody>(entity).unwrap().id, shot);
    }
    let (distance, hit) = approach.expect("the shot passed the target");
    assert!(
        hit,
        "missed by {distance} m (target radius {})",
        target.radius
    );
    // The lower arc: the first pass is the hit, dead centre to rounding.
    assert!(distance < 1e-9, "{distance}");
    let Ok(Command::SetLaunch {
        elevation_deg: Some(elevation),
        ..
    }) = aim
    else {
        unreachable!()
    };
    assert!(elevation < 45.0, "{elevation}");
}

#[test]
fn a_recording_that_does_not_read_stops_the_world_naming_the_file_and_never_panics() {
    let mut app = app_of(VolleyPlugin::replay(
        b"VOLLEY? not a recording".to_vec(),
        "broken.vrec",
    ));
    for _ in 0..10 {
        frame(&mut app, Duration::from_millis(20));
    }
    let why = volley(&app).stopped().expect("stopped").to_string();
    assert!(why.contains("broken.vrec"), "{why}");
    assert_eq!(volley(&app).world().tick(), 0);
    assert!(!app.world_mut().resource_mut::<Volley>().push(Command::Fire));
}
