//! A Volley world under GGRS's own `SyncTestSession` (gschup/ggrs 0.13), the way a game wires
//! Volley into GGRS (docs/replays.md, "Under GGRS"): a saved state is a `volley_sim::State`
//! ([`World::snapshot`]), a load is [`World::restore`], the checksum is [`state_hash`], and each
//! tick's commands are the players' inputs, one command per player per frame.
//!
//! Every bundled scene passes with commands of every kind as inputs, and ends on the state plain
//! stepping and Volley's own [`SyncTest`] end on. With a nondeterministic term GGRS reports the
//! frames whose checksums differ; Volley's sync test names the tick, body, field and stage.

use std::sync::atomic::{AtomicU64, Ordering};

use ggrs::{Config, GgrsError, GgrsRequest, PredictRepeatLast, SessionBuilder, SyncTestSession};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use volley::scene::BUNDLED;
use volley_sim::{
    BodyId, BodySpec, Command, Divergence, ForceInput, ForceKind, ForceTerm, ForceTerms,
    Integrator, Scene, SyncError, SyncTest, World, bundled_scene, parse_scene_with, state_hash,
};

/// The check distance: GGRS's default prediction window is 8 frames, and the distance must be
/// below it.
const K: usize = 7;

/// One Volley command as a GGRS input: plain data GGRS can send, store and compare. `kind` 0 is
/// no command; floats travel as their bit patterns, so a command arrives with the same bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Input {
    kind: u8,
    /// Which optional values a `launch` carries, one bit each.
    present: u8,
    words: [u64; 11],
}

impl Input {
    fn encode(command: &Command) -> Input {
        let mut input = Input::default();
        let f = |x: f64| x.to_bits();
        match *command {
            Command::Fire => input.kind = 1,
            Command::Spawn(s) => {
                input.kind = 2;
                let values = [
                    s.mass,
                    s.radius,
                    s.position.x,
                    s.position.y,
                    s.position.z,
                    s.velocity.x,
                    s.velocity.y,
                    s.velocity.z,
                    s.spin.x,
                    s.spin.y,
                    s.spin.z,
                ];
                input.words = values.map(f);
            }
            Command::Despawn(id) => (input.kind, input.words[0]) = (3, id.0),
            Command::SetLaunch {
                speed,
                elevation_deg,
                azimuth_deg,
                position,
            } => {
                input.kind = 4;
                let values = [speed, elevation_deg, azimuth_deg];
                for (k, v) in values.into_iter().enumerate() {
                    if let Some(v) = v {
                        input.present |= 1 << k;
                        input.words[k] = f(v);
                    }
                }
                if let Some(p) = position {
                    input.present |= 1 << 3;
                    input.words[3..6].copy_from_slice(&[f(p.x), f(p.y), f(p.z)]);
                }
            }
            Command::SetForce { kind, enabled } => {
                input.kind = 5;
                input.words[0] = ForceKind::ALL.iter().position(|&k| k == kind).unwrap() as u64;
                input.words[1] = u64::from(enabled);
            }
            Command::SetIntegrator(i) => {
                input.kind = 6;
                input.words[0] = Integrator::ALL.iter().position(|&x| x == i).unwrap() as u64;
            }
            Command::Reset => input.kind = 7,
        }
        input
    }

    fn decode(&self) -> Option<Command> {
        let f = |k: usize| f64::from_bits(self.words[k]);
        let v = |k: usize| DVec3::new(f(k), f(k + 1), f(k + 2));
        let given = |k: usize| (self.present & (1 << k) != 0).then(|| f(k));
        Some(match self.kind {
            1 => Command::Fire,
            2 => Command::Spawn(BodySpec {
                mass: f(0),
                radius: f(1),
                position: v(2),
                velocity: v(5),
                spin: v(8),
            }),
            3 => Command::Despawn(BodyId(self.words[0])),
            4 => Command::SetLaunch {
                speed: given(0),
                elevation_deg: given(1),
                azimuth_deg: given(2),
                position: (self.present & (1 << 3) != 0).then(|| v(3)),
            },
            5 => Command::SetForce {
                kind: ForceKind::ALL[self.words[0] as usize],
                enabled: self.words[1] != 0,
            },
            6 => Command::SetIntegrator(Integrator::ALL[self.words[0] as usize]),
            7 => Command::Reset,
            _ => return None,
        })
    }
}

/// What the game saves each frame: the world's state, and whether the run has stopped at a
/// divergence (a `State` does not hold that flag: `World::restore` clears it, so a game that
/// keeps a stopped world stopped across rollbacks saves it beside the state).
#[derive(Clone)]
struct Saved {
    state: volley_sim::State,
    stopped: Option<Divergence>,
}

/// The session's types: inputs are commands, a saved state is a Volley `State` (and the flag).
struct Volley;

impl Config for Volley {
    type Input = Input;
    type InputPredictor = PredictRepeatLast;
    type State = Saved;
    // A sync test has no network; GGRS still asks for an address type.
    type Address = usize;
}

/// The game: its world, and the divergence that stopped it, if one did.
struct Game {
    world: World,
    stopped: Option<Divergence>,
}

/// Does what GGRS asks, in order: save (snapshot and state hash), load (restore), advance
/// (apply each player's command, then step, unless the run stopped at a divergence).
fn handle(game: &mut Game, requests: Vec<GgrsRequest<Volley>>) {
    for request in requests {
        match request {
            GgrsRequest::SaveGameState { cell, frame } => {
                let checksum = u128::from(state_hash(&game.world));
                let saved = Saved {
                    state: game.world.snapshot(),
                    stopped: game.stopped,
                };
                cell.save(frame, Some(saved), Some(checksum));
            }
            GgrsRequest::LoadGameState { cell, .. } => {
                let saved = cell.load().expect("GGRS loads only frames it saved");
                game.world
                    .restore(&saved.state)
                    .expect("a state this world saved fits it");
                game.stopped = saved.stopped;
            }
            GgrsRequest::AdvanceFrame { inputs } => {
                if game.stopped.is_some() {
                    continue;
                }
                for (input, _status) in inputs {
                    if let Some(command) = input.decode() {
                        game.world
                            .apply(&command)
                            .expect("the test's commands apply");
                    }
                }
                game.stopped = game.world.step().err();
            }
        }
    }
}

/// Commands of every kind the scene takes, by tick: fires, a launcher change, a spawn beside a
/// fire (two players that tick), the first fired body despawned, a declared term off and on, an
/// integrator switch the forces allow, a reset.
fn script(scene: &Scene) -> Vec<Vec<Command>> {
    let mut ticks = vec![Vec::new(); 24];
    let first_fired = BodyId(World::new(scene).state().next_id);
    ticks[2].push(Command::Fire);
    ticks[4].push(Command::SetLaunch {
        speed: Some(scene.launcher().speed + 1.0),
        elevation_deg: None,
        azimuth_deg: Some(5.0),
        position: Some(DVec3::new(0.0, 1.0, 2.0)),
    });
    let mass = scene.launcher().mass * 2.0;
    ticks[5].push(Command::Spawn(BodySpec {
        mass,
        radius: 0.1,
        position: DVec3::new(1.0, 0.0, 3.0),
        velocity: DVec3::new(4.0, 0.0, 6.0),
        spin: DVec3::ZERO,
    }));
    ticks[5].push(Command::Fire);
    ticks[9].push(Command::Despawn(first_fired));
    if let Some(kind) = scene.forces().kinds().last() {
        ticks[12].push(Command::SetForce {
            kind,
            enabled: false,
        });
        ticks[14].push(Command::SetForce {
            kind,
            enabled: true,
        });
    }
    ticks[16].push(Command::SetIntegrator(Integrator::Rk4));
    ticks[20].push(Command::Reset);
    // Keep only what this scene's world takes (a term the integrator needs, an integrator
    // the forces refuse): plain stepping decides.
    let mut world = World::new(scene);
    for commands in &mut ticks {
        commands.retain(|c| world.clone().apply(c).is_ok());
        for c in commands.iter() {
            world.apply(c).expect("kept because it applies");
        }
        let _ = world.step();
    }
    ticks
}

/// `scene` for `frames` frames under GGRS's sync test; the world it ends with.
fn under_ggrs(scene: &Scene, commands: &[Vec<Command>], frames: usize) -> Result<World, GgrsError> {
    let players = commands.iter().map(Vec::len).max().unwrap_or(0).max(1);
    let mut session: SyncTestSession<Volley> = SessionBuilder::<Volley>::new()
        .with_num_players(players)?
        .with_check_distance(K)
        .with_input_delay(0)
        .start_synctest_session()?;
    let mut game = Game {
        world: World::new(scene),
        stopped: None,
    };
    for frame in 0..frames {
        let now = commands.get(frame).map_or(&[][..], Vec::as_slice);
        for player in 0..players {
            let input = now.get(player).map_or_else(Input::default, Input::encode);
            session.add_local_input(player, input)?;
        }
        handle(&mut game, session.advance_frame()?);
    }
    Ok(game.world)
}

/// The same commands stepped plainly, up to a divergence.
fn plain(scene: &Scene, commands: &[Vec<Command>], frames: usize) -> World {
    let mut world = World::new(scene);
    for frame in 0..frames {
        for c in commands.get(frame).into_iter().flatten() {
            world.apply(c).expect("the test's commands apply");
        }
        if world.step().is_err() {
            break;
        }
    }
    world
}

/// The same commands under Volley's own sync test (which stops at a reproduced divergence).
fn volley_sync(scene: &Scene, commands: &[Vec<Command>], frames: usize) -> World {
    let mut sync = SyncTest::new(World::new(scene), K as u32).expect("K is in range");
    for frame in 0..frames {
        let now = commands.get(frame).map_or(&[][..], Vec::as_slice);
        match sync.advance(now) {
            Ok(()) => {}
            Err(SyncError::Diverged(_)) => break,
            Err(e) => panic!("{}: {e}", scene.name()),
        }
    }
    sync.into_world()
}

#[test]
fn every_bundled_scene_passes_ggrs_sync_test_session_with_commands_as_inputs() {
    for (name, _) in BUNDLED {
        let scene = bundled_scene(name).expect("bundled scenes parse");
        let commands = script(&scene);
        // GGRS clones a whole state on every save (8 a frame here): fewer frames for the
        // worlds of thousands of bodies, in the dev profile tests run in.
        let bodies = World::new(&scene).bodies().len();
        let frames = if bodies >= 1000 { 24 } else { 120 };
        let world = under_ggrs(&scene, &commands, frames)
            .unwrap_or_else(|e| panic!("{name}: GGRS's sync test failed: {e}"));
        let expected = plain(&scene, &commands, frames);
        assert_eq!(world.snapshot(), expected.snapshot(), "{name}");
        if expected.divergence().is_none() {
            let ours = volley_sync(&scene, &commands, frames);
            assert_eq!(ours.snapshot(), expected.snapshot(), "{name}");
        }
    }
}

#[test]
fn every_command_survives_the_trip_through_a_ggrs_input() {
    let scene = bundled_scene("seed").expect("the seed parses");
    let all = script(&scene);
    let mut kinds = std::collections::BTreeSet::new();
    for c in all.iter().flatten() {
        assert_eq!(Input::encode(c).decode(), Some(*c));
        kinds.insert(Input::encode(c).kind);
    }
    assert_eq!(kinds.len(), 7, "every kind of command: {kinds:?}");
    assert_eq!(Input::default().decode(), None);
}

/// A game's term with hidden state: every evaluation bumps a counter.
#[derive(Debug, Default)]
struct Counter(AtomicU64);

impl ForceTerm for Counter {
    fn name(&self) -> &str {
        "test/counter"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, _: &ForceInput) -> DVec3 {
        let n = self.0.fetch_add(1, Ordering::Relaxed);
        DVec3::new(0.0, 0.0, 1e-6 * n as f64)
    }
}

#[test]
fn ggrs_names_the_frames_where_volley_names_the_tick_body_field_and_stage() {
    let scene = || {
        let terms = ForceTerms::new().with(Counter::default());
        parse_scene_with(
            "Scene(dt: 0.05, integrator: SemiImplicitEuler,
                   forces: [Gravity((0, 0, -9.81)), Custom(name: \"test/counter\", version: 1)],
                   bodies: [(mass: 1, position: (0, 0, 10), launch: Velocity((1, 0, 5)))])",
            "counter.ron",
            "counter",
            &terms,
        )
        .expect("the scene is valid")
    };
    // GGRS: frame numbers only (bevy_ggrs #117: "then what?").
    match under_ggrs(&scene(), &[], 40) {
        Err(GgrsError::MismatchedChecksum {
            mismatched_frames, ..
        }) => assert!(!mismatched_frames.is_empty()),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("GGRS's sync test missed the hidden state"),
    }
    // Volley: the tick, the body, the field with both values and their bits, the stage.
    let mut sync = SyncTest::new(World::new(&scene()), K as u32).expect("K is in range");
    let m = loop {
        match sync.advance(&[]) {
            Ok(()) => {}
            Err(SyncError::Mismatch(m)) => break m,
            Err(e) => panic!("{e}"),
        }
    };
    assert_eq!(m.stage.map(|s| s.stage.name()), Some("integrate"));
    let field = m
        .fields
        .iter()
        .find(|d| d.field == "mV.z")
        .expect("mV.z differs");
    assert_eq!(field.body, Some(BodyId(0)));
    assert!(m.report(None).contains("body 0 mV.z: first run "));
}
