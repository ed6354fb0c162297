//! Recordings: what they hold, that they replay bit for bit under any frame pacing and thread
//! count, and how a divergence, a truncation or a damaged file is reported.

use std::time::Duration;

use crate::replay_support::*;
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::hash::state_hash;
use volley_sim::internals::replay::{FlushPolicy, Mismatch, Recorder, Value};
use volley_sim::internals::scene;
use volley_sim::{Integrator, Scene, SimLoop, World};

/// Three bodies under gravity and linear drag, no contacts: semi-implicit Euler updates the
/// momentum from the velocity alone, so a nudge of one body's `p.x` stays in that one field.
fn free_flight() -> Scene {
    scene::parse(
        "Scene(dt: 0.01, integrator: SemiImplicitEuler,
               forces: [Gravity((0, 0, -9.81)), LinearDrag(0.1)],
               bodies: [(mass: 1, position: (0, 0, 1), launch: Velocity((3, 0, 4))),
                        (mass: 2, position: (1, 0, 1), launch: Velocity((2, 1, 5))),
                        (mass: 1, position: (0, 2, 1), launch: Velocity((1, 0, 6)))])",
        "free_flight.ron",
        "free_flight",
    )
    .unwrap()
}

/// Records `scene` to `ticks`, moving body index 1's `p.x` up by one ulp after tick `nudge`: a
/// valid recording of a run that the scene alone does not reproduce.
fn record_nudged(
    scene: &Scene,
    ticks: u64,
    nudge: u64,
    opts: volley_sim::internals::replay::RecordOptions,
) -> Vec<u8> {
    let mut sim = SimLoop::new(World::new(scene));
    let mut source = VirtualClock::Steady(scene.timestep());
    let mut recorder = Recorder::start(Vec::new(), &sim.world, opts).unwrap();
    sim.run_until(nudge, &mut source, &mut recorder).unwrap();
    nudge_body_1(&mut sim.world);
    sim.run_until(ticks, &mut source, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap().0
}

fn nudge_body_1(world: &mut World) {
    let mut s = world.snapshot();
    s.bodies.p.x[1] = s.bodies.p.x[1].next_up();
    world.restore(&s).unwrap();
}

/// The world after `ticks`, optionally nudged as [`record_nudged`] does.
fn run(scene: &Scene, ticks: u64, nudge: Option<u64>) -> World {
    let mut sim = SimLoop::new(World::new(scene));
    let mut source = VirtualClock::Steady(scene.timestep());
    if let Some(n) = nudge {
        sim.run_until(n, &mut source, &mut ()).unwrap();
        nudge_body_1(&mut sim.world);
    }
    sim.run_until(ticks, &mut source, &mut ()).unwrap();
    sim.world
}

#[test]
fn a_recording_holds_the_scene_the_commands_and_every_ticks_hash() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let bytes = record(&scene, 300, &commands, options(1, 50));
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(commands.iter().copied());
    let mut hashes = Hashes(vec![(0, state_hash(&sim.world))]);
    sim.run_until(
        300,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut hashes,
    )
    .unwrap();

    let rec = open(&bytes).unwrap();
    let h = rec.header();
    assert_eq!(h.scene_source, scene.source());
    assert_eq!(h.timestep_ns, 10_000_000);
    assert_eq!(
        (h.integrator, h.substeps, h.start_tick),
        (Integrator::VelocityVerlet, 1, 0)
    );
    assert_eq!(rec.commands(), &commands[..]);
    assert_eq!(rec.hashes(), &hashes.0[..]);
    let ticks: Vec<u64> = rec.keyframes().iter().map(|k| k.tick).collect();
    assert_eq!(ticks, [0, 50, 100, 150, 200, 250, 300]);
    let footer = rec.footer().unwrap();
    assert_eq!(
        (footer.final_tick, footer.final_hash),
        (300, state_hash(&sim.world))
    );
    assert_eq!((rec.truncated_at(), rec.end_tick()), (None, 300));
}

#[test]
fn every_keyframe_restores_the_world_exactly() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let bytes = record(&scene, 300, &commands, options(1, 50));
    assert_keyframes_restore(&scene, &commands, &bytes, "coverage");
}

/// Every keyframe of `bytes` (a recording of `scene` with `commands`) restores the world a run
/// of them has at its tick: every field, including the launcher, force toggles, energy caps,
/// force evaluations and the carried force.
fn assert_keyframes_restore(
    scene: &Scene,
    commands: &[volley_sim::Stamped],
    bytes: &[u8],
    what: &str,
) {
    let mut rec = open(bytes).unwrap();
    let mut sim = SimLoop::new(World::new(scene));
    sim.schedule(commands.iter().copied());
    for i in 0..rec.keyframes().len() {
        let tick = rec.keyframes()[i].tick;
        sim.run_until(tick, &mut VirtualClock::Steady(scene.timestep()), &mut ())
            .unwrap();
        let restored = rec.world_at(i, &rec.scene().unwrap()).unwrap();
        assert_eq!(
            restored.snapshot(),
            sim.world.snapshot(),
            "{what}: keyframe at tick {tick}"
        );
    }
}

#[test]
fn recording_the_same_run_twice_gives_identical_bytes() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let a = record(&scene, 300, &commands, options(1, 50));
    let b = record(&scene, 300, &commands, options(1, 50));
    assert_eq!(a, b);
}

#[test]
fn frame_deltas_time_scale_pauses_and_single_steps_give_identical_recordings() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let reference = record(&scene, 300, &commands, options(1, 50));
    let ms = Duration::from_millis;
    let sources = [
        VirtualClock::display(144.0),
        VirtualClock::display(24.0),
        VirtualClock::Jitter {
            base: ms(16),
            spread: ms(15),
            rng: volley_sim::internals::world::SplitMix64(3),
        },
        VirtualClock::Hitch {
            base: ms(16),
            at: 9,
            length: Duration::from_secs(5),
            frame: 0,
        },
        VirtualClock::Script {
            deltas: vec![ms(0), ms(3), ms(41), ms(1)],
            next: 0,
        },
    ];
    for mut source in sources {
        let name = format!("{source:?}");
        let bytes = record_from(&scene, 300, &commands, options(1, 50), &mut source);
        assert!(
            bytes == reference,
            "frames from {name} changed the recording"
        );
    }

    // Time scale 0.37, pauses, single steps, frames of 7 to 19 ms.
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(commands.iter().copied());
    sim.clock.set_time_scale(0.37).unwrap();
    sim.stop_at(Some(300));
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 50)).unwrap();
    let mut frame = 0u64;
    while sim.world.tick() < 300 {
        match frame % 10 {
            3 => sim.clock.pause(),
            5 | 6 => sim.clock.single_step(),
            8 => sim.clock.resume(),
            _ => {}
        }
        sim.frame(ms(7 + frame % 13), &mut recorder).unwrap();
        frame += 1;
    }
    assert!(recorder.finish(&sim.world).unwrap().0 == reference);
}

#[test]
fn thread_counts_give_identical_hashes() {
    // 50 000 bodies: above 2 x 16 384, so 2 threads step 2 chunks and 4 threads step 3.
    let scene = scene::load(&crate::support::ws("tests/data/replay_crowd.ron")).unwrap();
    let mut hashes = Vec::new();
    let mut first = Vec::new();
    for threads in [1, 2, 4] {
        let mut world = World::new(&scene);
        world.set_threads(threads);
        let mut sim = SimLoop::new(world);
        let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 4)).unwrap();
        sim.run_until(
            10,
            &mut VirtualClock::Steady(scene.timestep()),
            &mut recorder,
        )
        .unwrap();
        let bytes = recorder.finish(&sim.world).unwrap().0;
        hashes.push(open(&bytes).unwrap().hashes().to_vec());
        if threads == 1 {
            first = bytes;
        }
    }
    assert_eq!(hashes[0].len(), 11);
    assert!(hashes.iter().all(|h| *h == hashes[0]));
    // And a one-thread recording verifies when replayed with three threads.
    let mut replay =
        volley_sim::internals::replay::Replay::start(open(&first).unwrap(), None).unwrap();
    replay.set_threads(3);
    replay.run_to(u64::MAX, &mut ()).unwrap();
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.keyframes_checked(), 4);
}

#[test]
fn an_unaltered_recording_verifies_every_tick_and_keyframe() {
    let bytes = record(&coverage_scene(), 300, &coverage_commands(), options(1, 50));
    let replay = replay(&bytes, None);
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.world().tick(), 300);
    assert_eq!(replay.hashes_checked(), 301);
    assert_eq!(replay.keyframes_checked(), 7);
}

#[test]
fn a_one_ulp_nudge_is_reported_at_its_tick_with_the_body_and_field() {
    let scene = free_flight();
    let bytes = record_nudged(&scene, 60, 37, options(1, 10));
    let replay = replay(&bytes, None);
    let d = replay
        .first_divergence()
        .expect("the nudged recording diverges");
    assert_eq!(
        (d.tick, d.last_match, d.compared_at),
        (38, Some(37), Some(40))
    );
    let (recorded, replayed) = (run(&scene, 38, Some(37)), run(&scene, 38, None));
    let hashes = (state_hash(&recorded), state_hash(&replayed));
    assert_eq!(
        d.mismatch,
        Mismatch::Hash {
            recorded: hashes.0,
            replayed: hashes.1
        }
    );
    // At the keyframe of tick 40 exactly one field differs: body 1's p.x.
    let (recorded, replayed) = (run(&scene, 40, Some(37)), run(&scene, 40, None));
    let (a, b) = (
        recorded.bodies().positions().x[1],
        replayed.bodies().positions().x[1],
    );
    assert_ne!(a, b);
    assert_eq!(d.fields.len(), 1, "{}", d.report(None));
    let f = &d.fields[0];
    assert_eq!((f.body.map(|b| b.0), f.field.as_str()), (Some(1), "p.x"));
    assert_eq!((&f.recorded, &f.replayed), (&Value::F64(a), &Value::F64(b)));
    assert_eq!(f.ulps(), volley_sim::internals::replay::ulps(a, b));
    assert!(
        d.report(None)
            .contains("the first keyframe at or after tick 38")
    );
    // The replay stops at the report: it does not run to the end.
    assert_eq!(replay.world().tick(), 40);
}

#[test]
fn with_a_keyframe_every_tick_the_fields_are_reported_at_the_divergent_tick() {
    let scene = free_flight();
    let bytes = record_nudged(&scene, 60, 37, options(1, 1));
    let replay = replay(&bytes, None);
    let d = replay.first_divergence().unwrap();
    assert_eq!((d.tick, d.compared_at), (38, Some(38)));
    let a = run(&scene, 38, Some(37)).bodies().positions().x[1];
    assert_eq!(d.fields[0].recorded, Value::F64(a));
}

#[test]
fn with_hashes_every_k_ticks_the_report_bounds_the_divergent_interval() {
    let bytes = record_nudged(&free_flight(), 60, 37, options(5, 20));
    let d = replay(&bytes, None).first_divergence().cloned().unwrap();
    // Hashes at 35 and 40: the state first differed somewhere in 36..=40 (it was 38).
    assert_eq!(
        (d.tick, d.last_match, d.compared_at),
        (40, Some(35), Some(40))
    );
    assert!(d.report(None).contains("first differed in ticks 36..=40"));
}

/// Counts the ticks the loop shows it and needs none of them, so the loop may batch any tick.
#[derive(Default)]
struct Shown(u64);

impl volley_sim::TickObserver for Shown {
    fn after_tick(
        &mut self,
        _world: &World,
    ) -> Result<(), volley_sim::internals::sim_loop::ObserverError> {
        self.0 += 1;
        Ok(())
    }

    fn next_needed_tick(&self, _tick: u64) -> u64 {
        u64::MAX
    }
}

#[test]
fn a_recording_hashing_every_kth_tick_replays_the_ticks_between_as_batches() {
    let scene = free_flight();
    let bytes = record(&scene, 2000, &[], options(10, 500));
    let mut played =
        volley_sim::internals::replay::Replay::start(open(&bytes).unwrap(), None).unwrap();
    let mut shown = Shown::default();
    played.run_to(u64::MAX, &mut shown).unwrap();
    assert!(played.first_divergence().is_none());
    assert_eq!(played.world().tick(), 2000);
    // Every stored hash (ticks 0, 10, ..., 2000) compared: a batch never runs past one.
    assert_eq!(played.hashes_checked(), 201);
    assert_eq!(played.keyframes_checked(), 5);
    // The loop hands over a tick at each stored hash and, per frame, at most two more: the
    // end of the batch before the frame's last tick and that tick, which runs alone. Frames
    // are 65 ticks, cut at the 4 keyframes: at most 2000 / 10 + 2 * (2000 / 65 + 1 + 4) calls,
    // where tick by tick it is 2000.
    assert!(shown.0 <= 200 + 2 * (30 + 1 + 4), "{} ticks shown", shown.0);
    // A nudge between stored hashes is still caught at the first hash after it.
    let bytes = record_nudged(&scene, 2000, 1234, options(10, 500));
    let d = replay(&bytes, None).first_divergence().cloned().unwrap();
    assert_eq!(
        (d.tick, d.last_match, d.compared_at),
        (1240, Some(1230), Some(1500))
    );
}

#[test]
fn batched_replays_keep_commands_seeks_and_a_recorded_divergence() {
    // Contact-free, so the replay batches; K = 7 puts stored hashes off the keyframe grid.
    let scene = free_flight();
    let script = "33: spawn mass=2 radius=0.2 position=1,0,3 velocity=4,0,6
                  90: integrator rk4
                  120: force LinearDrag off
                  200: despawn 0";
    let commands = volley_sim::internals::command::parse_script(script, "batched.txt").unwrap();
    let bytes = record(&scene, 300, &commands, options(7, 50));
    let stored: Vec<u64> = open(&bytes).unwrap().hashes().iter().map(|h| h.0).collect();
    let final_hash = open(&bytes).unwrap().hashes().last().unwrap().1;
    for (seek, from) in [(None, 0), (Some(120), 100), (Some(260), 250)] {
        let mut played =
            volley_sim::internals::replay::Replay::start(open(&bytes).unwrap(), seek).unwrap();
        let mut shown = Shown::default();
        played.run_to(u64::MAX, &mut shown).unwrap();
        assert_eq!(played.started_at(), from);
        assert!(played.first_divergence().is_none(), "seek {seek:?}");
        let due = stored.iter().filter(|&&t| t >= from).count() as u64;
        assert_eq!(played.hashes_checked(), due, "seek {seek:?}");
        assert_eq!(state_hash(played.world()), final_hash);
        assert!(
            shown.0 < (300 - from) / 2,
            "seek {seek:?}: {} ticks shown",
            shown.0
        );
    }
    // The stiff spring blows up; recorded hashing every 5th tick, its batched replay stops at
    // the recorded divergence (a batch that goes non-finite is re-run tick by tick).
    let stiff = stiff_scene();
    let mut sim = SimLoop::new(World::new(&stiff));
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(5, 0)).unwrap();
    let mut source = VirtualClock::Steady(stiff.timestep());
    assert!(sim.run_until(1000, &mut source, &mut recorder).is_err());
    let recorded = sim.world.divergence().unwrap();
    let bytes = recorder.finish(&sim.world).unwrap().0;
    let replayed = replay(&bytes, None);
    assert!(replayed.first_divergence().is_none());
    assert_eq!(replayed.world().divergence(), Some(recorded));
}

#[test]
fn a_keyframe_field_the_hash_does_not_cover_is_still_compared() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let bytes = record(&scene, 150, &commands, options(1, 50));
    let mut frames = frames(&bytes);
    let keyframe_100 = frames
        .iter_mut()
        .find(|f| f.kind == 2 && f.payload[..8] == 100u64.to_le_bytes())
        .unwrap();
    // Launcher speed: after tick, next_id, rng (3 x 8), the integrator, force mask (2 bytes),
    // carry and launch tags, the muzzle position (3 x 8).
    keyframe_100.payload[53..61].copy_from_slice(&99.0f64.to_bits().to_le_bytes());
    let d = replay(&assemble(&frames), None)
        .first_divergence()
        .cloned()
        .unwrap();
    assert_eq!(
        (d.tick, &d.mismatch, d.compared_at),
        (100, &Mismatch::Fields, Some(100))
    );
    assert_eq!(d.fields.len(), 1);
    assert_eq!(d.fields[0].field, "launcher.speed");
    assert_eq!(
        (&d.fields[0].recorded, &d.fields[0].replayed),
        (&Value::F64(99.0), &Value::F64(14.0))
    );
}

#[test]
fn a_force_evaluation_count_that_differs_is_a_warning_not_a_divergence() {
    let bytes = record(&coverage_scene(), 150, &coverage_commands(), options(1, 50));
    let mut frames = frames(&bytes);
    let keyframe_50 = frames
        .iter_mut()
        .find(|f| f.kind == 2 && f.payload[..8] == 50u64.to_le_bytes())
        .unwrap();
    // force_evals: after the 29 bytes of ticks, ids and tags and the 10 launcher floats.
    let evals = u64::from_le_bytes(keyframe_50.payload[109..117].try_into().unwrap());
    keyframe_50.payload[109..117].copy_from_slice(&(evals + 5).to_le_bytes());
    let replay = replay(&assemble(&frames), None);
    assert!(replay.first_divergence().is_none());
    let (tick, f) = replay.force_evals_differ().unwrap();
    assert_eq!((tick, f.field.as_str()), (50, "force_evals"));
    assert_eq!(
        (&f.recorded, &f.replayed),
        (&Value::U64(evals + 5), &Value::U64(evals))
    );
}

#[test]
fn a_recorded_divergence_replays_as_the_same_divergence() {
    // The reference's stiff spring: k/m = 1e4 at h = 1/60, explicit Euler, blows up.
    let scene = stiff_scene();
    let mut sim = SimLoop::new(World::new(&scene));
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 0)).unwrap();
    let err = sim.run_until(
        1000,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut recorder,
    );
    let recorded = sim
        .world
        .divergence()
        .expect("explicit Euler diverges here");
    assert!(err.is_err());
    let bytes = recorder.finish(&sim.world).unwrap().0;
    assert_eq!(
        open(&bytes).unwrap().footer().unwrap().diverged,
        Some(recorded)
    );
    let replayed = replay(&bytes, None);
    assert!(replayed.first_divergence().is_none());
    assert_eq!(replayed.world().divergence(), Some(recorded));
    // Seeking to the final keyframe restores the diverged state; there is nothing to re-run.
    assert!(
        replay(&bytes, Some(recorded.tick))
            .first_divergence()
            .is_none()
    );
}

#[test]
fn a_recording_started_mid_run_replays_from_its_first_keyframe() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(commands.iter().copied());
    let mut source = VirtualClock::Steady(scene.timestep());
    sim.run_until(130, &mut source, &mut ()).unwrap();
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 50)).unwrap();
    sim.run_until(260, &mut source, &mut recorder).unwrap();
    let bytes = recorder.finish(&sim.world).unwrap().0;
    let replay = replay(&bytes, None);
    assert_eq!(replay.recording().start_tick(), 130);
    assert!(replay.first_divergence().is_none());
    assert_eq!(replay.hashes_checked(), 131);
    assert_eq!(state_hash(replay.world()), state_hash(&sim.world));
}

#[test]
fn seek_starts_from_the_keyframe_at_or_before_the_tick() {
    let bytes = record(&coverage_scene(), 300, &coverage_commands(), options(1, 50));
    let full = replay(&bytes, None);
    for (seek, from) in [(0, 0), (49, 0), (50, 50), (199, 150), (300, 300)] {
        let r = replay(&bytes, Some(seek));
        assert_eq!(r.started_at(), from, "seek {seek}");
        assert!(r.first_divergence().is_none());
        assert_eq!(r.hashes_checked(), 301 - from);
        assert_eq!(state_hash(r.world()), state_hash(full.world()));
    }
}

#[test]
fn an_interrupted_recording_is_a_prefix_and_opens_truncated_after_its_last_tick() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let full = record(&scene, 60, &commands, options(1, 25));
    let mut interrupted = Vec::new();
    {
        let mut sim = SimLoop::new(World::new(&scene));
        sim.schedule(commands.iter().copied());
        let mut recorder = Recorder::start(&mut interrupted, &sim.world, options(1, 25)).unwrap();
        sim.run_until(
            40,
            &mut VirtualClock::Steady(scene.timestep()),
            &mut recorder,
        )
        .unwrap();
        // Dropped without `finish`, as a run that stops without ending its recording: the
        // drop closes the open run of hashes (ticks 26 to 40, after the keyframe of tick 25).
    }
    let last = *frame_starts(&interrupted).last().unwrap();
    assert!(
        full.starts_with(&interrupted[..last]),
        "append-only: the same run writes the same records up to the run the drop closed"
    );
    let (full_rec, rec) = (open(&full).unwrap(), open(&interrupted).unwrap());
    assert_eq!(
        rec.hashes(),
        &full_rec.hashes()[..41],
        "the hashes of ticks 0 to 40"
    );
    assert!(rec.footer().is_none());
    assert_eq!(
        (rec.truncated_at(), rec.end_tick()),
        (Some(interrupted.len() as u64), 40)
    );
    let r = replay(&interrupted, None);
    assert!(r.first_divergence().is_none());
    assert_eq!((r.world().tick(), r.hashes_checked()), (40, 41));

    // Cut inside the last record (the hashes of ticks 26 to 40): the file keeps ticks up to
    // 25, the keyframe before it.
    let cut = &interrupted[..interrupted.len() - 1];
    let rec = open(cut).unwrap();
    assert_eq!(
        (rec.truncated_at(), rec.end_tick()),
        (Some(last as u64), 25)
    );
    let r = replay(cut, None);
    assert!(r.first_divergence().is_none());
    assert_eq!((r.world().tick(), r.hashes_checked()), (25, 26));

    // Cut inside the header or the first keyframe: nothing to replay.
    let keyframe_start = frame_starts(&interrupted)[1];
    let e = open(&interrupted[..keyframe_start - 1]).unwrap_err();
    assert!(e.message.contains("ends before the header"), "{e}");
    let e = open(&interrupted[..keyframe_start + 9]).unwrap_err();
    assert!(e.message.contains("ends before the first keyframe"), "{e}");
}

/// A file other code can read while the recorder still holds it: what a crash would leave.
#[derive(Clone, Default)]
struct Shared(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

impl std::io::Write for Shared {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn flushing_every_tick_leaves_a_readable_file_after_every_tick() {
    let scene = free_flight();
    for (flush, holds_every_tick) in [
        (FlushPolicy::EveryTick, true),
        (FlushPolicy::OnFinish, false),
    ] {
        let file = Shared::default();
        let mut sim = SimLoop::new(World::new(&scene));
        let opts = volley_sim::internals::replay::RecordOptions {
            flush,
            ..options(1, 10)
        };
        let mut recorder = Recorder::start(file.clone(), &sim.world, opts).unwrap();
        for tick in 1..=25 {
            sim.run_until(
                tick,
                &mut VirtualClock::Steady(scene.timestep()),
                &mut recorder,
            )
            .unwrap();
            let crashed_now = open(&file.0.borrow()).unwrap();
            // Without flushing, the writer holds only what `start` flushed: tick 0.
            let expected = if holds_every_tick { tick } else { 0 };
            assert_eq!(crashed_now.end_tick(), expected, "{flush:?}");
        }
    }
}

#[test]
fn every_single_bit_flip_of_a_complete_recording_is_refused() {
    let bytes = record(&free_flight(), 30, &[], options(1, 10));
    assert!(open(&bytes).is_ok());
    for i in 0..bytes.len() {
        for bit in 0..8 {
            let mut damaged = bytes.clone();
            damaged[i] ^= 1 << bit;
            if let Ok(rec) = open(&damaged) {
                panic!(
                    "a flip of bit {bit} of byte {i} opened (end tick {})",
                    rec.end_tick()
                );
            }
        }
    }
}

#[test]
fn another_volley_version_or_arch_is_replayed_with_a_warning() {
    let bytes = record(&free_flight(), 30, &[], options(1, 10));
    let mut frames = frames(&bytes);
    let mut header: serde_json::Value = serde_json::from_slice(&frames[0].payload).unwrap();
    header["volley_version"] = "0.0.1".into();
    header["build"]["target_arch"] = "riscv64".into();
    frames[0].payload = serde_json::to_vec(&header).unwrap();
    let bytes = assemble(&frames);
    let warnings = open(&bytes).unwrap().build_warnings();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].contains("0.0.1") && warnings[1].contains("riscv64"));
    assert!(replay(&bytes, None).first_divergence().is_none());
}

#[test]
fn wrong_magic_another_format_version_or_an_unparsable_scene_is_a_one_line_error() {
    let bytes = record(&free_flight(), 30, &[], options(1, 10));
    let mut magic = bytes.clone();
    magic[1] = b'X';
    let mut newer = bytes.clone();
    newer[8..12].copy_from_slice(&5u32.to_le_bytes());
    let mut older = bytes.clone();
    older[8..12].copy_from_slice(&0u32.to_le_bytes());
    // Version 1 stored one record per hash; its files are refused, not misread.
    // Version 2 had an 8-bit force mask and no launch columns: refused too.
    let mut version_2 = bytes.clone();
    version_2[8..12].copy_from_slice(&2u32.to_le_bytes());
    // Version 3 wrote the launch columns with no flag.
    let mut version_3 = bytes.clone();
    version_3[8..12].copy_from_slice(&3u32.to_le_bytes());
    let mut version_1 = bytes.clone();
    version_1[8..12].copy_from_slice(&1u32.to_le_bytes());
    let cases = [
        (magic, "not a Volley recording (wrong magic bytes)"),
        (
            newer,
            "format version 5 is newer than the one this build reads (4)",
        ),
        (version_2, "format version 2 is older"),
        (version_3, "format version 3 is older"),
        (older, "format version 0 is older"),
        (version_1, "format version 1 is older"),
        (bytes[..5].to_vec(), "wrong magic"),
    ];
    for (file, expected) in cases {
        let e = open(&file).unwrap_err().to_string();
        assert!(
            e.starts_with("test.vrec: byte ") && e.contains(expected),
            "{e}"
        );
        assert!(!e.contains('\n'));
    }

    let mut frames = frames(&bytes);
    let mut header: serde_json::Value = serde_json::from_slice(&frames[0].payload).unwrap();
    header["scene_source"] =
        "Scene(dt: 0.01, integrator: Rk4,\n  bodies: [(mass: -1, position: (0, 0, 0))])".into();
    frames[0].payload = serde_json::to_vec(&header).unwrap();
    let rec = open(&assemble(&frames)).unwrap();
    let e = rec.scene().unwrap_err().to_string();
    assert!(e.contains("the embedded scene no longer parses"), "{e}");
    assert!(e.contains("bodies[0].mass"), "{e}");
    assert!(!e.contains('\n'));
}

/// Drives `sim` frame by frame as a window does (jittered 60 Hz frames, a pause, five single
/// steps, then time scale 3), running each frame with `frame`; returns the frames' tick counts.
fn drive_by_frames(
    sim: &mut SimLoop,
    mut frame: impl FnMut(&mut SimLoop, Duration) -> u32,
) -> Vec<u32> {
    use volley_sim::internals::clock::FrameSource;
    let mut source = VirtualClock::Jitter {
        base: Duration::from_nanos(16_666_667),
        spread: Duration::from_millis(9),
        rng: volley_sim::internals::world::SplitMix64(7),
    };
    let mut steps = Vec::new();
    for i in 0..400 {
        match i {
            40 => sim.clock.pause(),
            50..=54 => sim.clock.single_step(),
            60 => {
                sim.clock.resume();
                sim.clock.set_time_scale(3.0).unwrap();
            }
            _ => {}
        }
        steps.push(frame(sim, source.next_delta()));
    }
    steps
}

#[test]
fn a_replay_driven_by_display_frames_checks_every_tick_and_keyframe() {
    let (scene, commands) = (coverage_scene(), coverage_commands());
    let bytes = record(&scene, 300, &commands, options(1, 50));
    let (mut verifier, mut sim) =
        volley_sim::internals::replay::Verifier::start(open(&bytes).unwrap(), None).unwrap();
    let steps = drive_by_frames(&mut sim, |sim, delta| {
        verifier.frame(sim, delta, &mut ()).unwrap().steps
    });
    assert!(verifier.is_done(&sim.world));
    assert!(verifier.first_divergence().is_none());
    assert_eq!(sim.world.tick(), 300);
    // The same comparisons as a replay at one tick per frame: 301 hashes and 7 keyframes.
    assert_eq!(verifier.hashes_checked(), 301);
    assert_eq!(verifier.keyframes_checked(), 7);
    assert_eq!(
        state_hash(&sim.world),
        state_hash(replay(&bytes, None).world())
    );
    // Stopping at keyframes costs the clock nothing: up to the end, every frame ran exactly the
    // ticks a plain loop runs with the same frames (paused frames only the single steps), and
    // after it none.
    let mut plain = SimLoop::new(World::new(&scene));
    plain.schedule(commands);
    let expected = drive_by_frames(&mut plain, |sim, delta| {
        sim.frame(delta, &mut ()).unwrap().steps
    });
    let end = steps.iter().scan(0, |t, &s| {
        *t += u64::from(s);
        Some(*t)
    });
    let last = end.take_while(|&t| t < 300).count();
    assert_eq!(steps[..last], expected[..last]);
    assert!(steps[last] > 0 && steps[last] <= expected[last]);
    assert!(steps[last + 1..].iter().all(|&s| s == 0));
    assert_eq!(&steps[50..55], &[1; 5]);
}

#[test]
fn a_nudged_recording_replayed_by_frames_parts_at_the_same_tick_with_the_same_report() {
    let scene = free_flight();
    let bytes = record_nudged(&scene, 60, 37, options(1, 10));
    let (mut verifier, mut sim) =
        volley_sim::internals::replay::Verifier::start(open(&bytes).unwrap(), None).unwrap();
    let mut seen_before_report = false;
    for _ in 0..200 {
        verifier
            .frame(&mut sim, Duration::from_millis(7), &mut ())
            .unwrap();
        if let Some(p) = verifier.parted()
            && verifier.first_divergence().is_none()
        {
            // Seen at tick 38, before the keyframe of tick 40 completes the report.
            assert_eq!((p.tick, p.compared_at, p.fields.len()), (38, None, 0));
            seen_before_report = true;
        }
    }
    assert!(
        seen_before_report,
        "7 ms frames of a 10 ms step stop between ticks 38 and 40"
    );
    let by_ticks = replay(&bytes, None);
    assert_eq!(verifier.first_divergence(), by_ticks.first_divergence());
    assert_eq!(sim.world.tick(), 40, "the replay stops at the report");
}

#[test]
fn the_new_integrators_record_restore_and_verify_and_the_tolerance_travels_in_the_header() {
    for integrator in [
        Integrator::ForestRuth,
        Integrator::Dopri5,
        Integrator::ImplicitMidpoint,
    ] {
        let mut scene = coverage_scene();
        scene.set_integrator(integrator).unwrap();
        // Not the default: a replay must step at the recorded tolerance, not the scene file's.
        scene.set_tolerance(1e-6).unwrap();
        // No commands: they would switch the integrator away early.
        let bytes = record(&scene, 200, &[], options(1, 25));
        let replay = replay(&bytes, None);
        assert!(
            replay.first_divergence().is_none(),
            "{integrator}: {:?}",
            replay.first_divergence()
        );
        assert_eq!(replay.world().tick(), 200, "{integrator}");
        let rec = open(&bytes).unwrap();
        assert_eq!(rec.scene().unwrap().tolerance(), 1e-6, "{integrator}");
        // Forest-Ruth's carried position force included.
        assert_keyframes_restore(&scene, &[], &bytes, integrator.name());
    }
}
