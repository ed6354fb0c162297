//! Batched stepping: `World::step_ticks(n)` must be indistinguishable from `n` calls of
//! `World::step` (the same state bits, carried force, force-evaluation count, events, and the
//! same divergence at the same tick, body and cause), and the loop's batching (frames of many
//! ticks, observers that need only some of them) must not change what any observer sees.
//!
//! The worlds are larger than two of `step::BATCH_BLOCK` blocks and not a multiple of it, and
//! the runs are longer than `step::BATCH_MAX_TICKS`, so whole blocks, the remainder block and
//! several batches are all exercised.

use crate::support;

use volley::clock::VirtualClock;
use volley::command::Stamped;
use volley::hash::state_hash;
use volley::replay::{FlushPolicy, RecordOptions, Recorder};
use volley::scene::{self, Scene};
use volley::step::{BATCH_BLOCK, BATCH_MAX_TICKS, PARALLEL_MIN_CHUNK};
use volley::{Command, Divergence, Integrator, SimLoop, World};

const BODIES: usize = 2 * BATCH_BLOCK + 37;

fn scene(text: &str) -> Scene {
    scene::parse(text, "batch.ron", "batch").expect("the test scene is valid")
}

/// A volley of `count` bodies under `forces`, no contacts, with the given guard period.
fn volley(forces: &str, count: usize, guard_every: u32) -> Scene {
    scene(&format!(
        "Scene(dt: 0.01, integrator: ExplicitEuler, seed: 11,
               forces: [{forces}],
               launcher: (position: (1.0, 0.0, 1.0), speed: 20.0, elevation_deg: 50.0, azimuth_deg: 10.0),
               volley: (count: {count}, speed_spread: 5.0, angle_spread_deg: 20.0),
               guard: (every: {guard_every}))"
    ))
}

/// Everything `step` and `step_ticks` must agree on.
#[derive(Debug, PartialEq)]
struct Outcome {
    result: Result<(), Divergence>,
    tick: u64,
    hash: u64,
    force_evals: u64,
    snapshot: volley::world::Snapshot,
    events: Vec<volley::Event>,
}

fn outcome(world: &World, result: Result<(), Divergence>) -> Outcome {
    Outcome {
        result,
        tick: world.tick(),
        hash: state_hash(world),
        force_evals: world.force_evals(),
        snapshot: world.snapshot(),
        events: world.events().to_vec(),
    }
}

fn tick_by_tick(scene: &Scene, threads: usize, ticks: u64) -> Outcome {
    let mut world = World::new(scene);
    world.set_threads(threads);
    let result = (0..ticks).try_for_each(|_| world.step());
    outcome(&world, result)
}

fn batched(scene: &Scene, threads: usize, ticks: u64) -> Outcome {
    let mut world = World::new(scene);
    world.set_threads(threads);
    let result = world.step_ticks(ticks);
    outcome(&world, result)
}

fn pool() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a two-thread pool")
}

#[test]
fn every_integrator_batches_to_the_same_bits_as_stepping_tick_by_tick() {
    let ticks = 2 * BATCH_MAX_TICKS + 5;
    let cases = [
        ("Gravity((0.0, 0.0, -9.81))", true),
        ("Gravity((0.0, 0.0, -9.81)), LinearDrag(0.3)", true),
        (
            "Gravity((0.0, 0.0, -9.81)), QuadraticDrag(0.01), ConstantForce((0.5, 0.2, 0.0))",
            false,
        ),
        // A zero-rest-length spring and a lone point mass have closed forms: `exact` runs them.
        ("Spring(anchor: (0.0, 0.0, 5.0), stiffness: 4.0)", true),
        ("PointMass(center: (0.0, 0.0, -50.0), mu: 5000.0)", true),
    ];
    for (forces, closed_form) in cases {
        for integrator in Integrator::ALL {
            let mut s = volley(forces, BODIES, 0);
            if s.set_integrator(integrator).is_err() {
                assert!(!closed_form, "{integrator} refused {forces}");
                continue;
            }
            let expected = tick_by_tick(&s, 1, ticks);
            assert_eq!(expected.result, Ok(()), "{integrator}, {forces}");
            assert_eq!(batched(&s, 1, ticks), expected, "{integrator}, {forces}");
        }
    }
}

#[test]
fn substeps_and_the_guard_batch_to_the_same_bits() {
    // Verlet carries its force across substeps and batches; the guard runs every 7 ticks
    // inside a batch of 64 without tripping, on the general force model (a spring) and on the
    // constant-field one (gravity alone).
    for forces in [
        "Spring(anchor: (0.0, 0.0, 5.0), stiffness: 4.0)",
        "Gravity((0.0, 0.0, -9.81))",
    ] {
        for integrator in [
            Integrator::VelocityVerlet,
            Integrator::Rk4,
            Integrator::SemiImplicitEuler,
        ] {
            let mut s = volley(forces, BODIES, 7);
            s.set_integrator(integrator).expect("both allow it");
            s.set_substeps(3).expect("3 substeps are valid");
            let expected = tick_by_tick(&s, 1, 150);
            assert_eq!(expected.result, Ok(()), "{integrator}, {forces}");
            assert_eq!(batched(&s, 1, 150), expected, "{integrator}, {forces}");
        }
    }
}

#[test]
fn no_ticks_is_nothing_even_for_a_stopped_world() {
    let s = unstable(3);
    let mut world = World::new(&s);
    let d = world.step_ticks(500).expect_err("the guard trips");
    assert_eq!(world.step_ticks(0), Ok(()));
    assert_eq!(world.step_ticks(1), Err(d));
}

#[test]
fn a_divergence_inside_a_loop_batch_leaves_the_clock_on_the_worlds_tick() {
    let s = unstable(3);
    let expected = tick_by_tick(&s, 1, 500);
    let Err(d) = expected.result else {
        panic!("the guard must trip")
    };
    let mut sim = SimLoop::new(World::new(&s));
    let mut source = sim.unpaced_source(1000);
    let err = sim
        .run_until(500, &mut source, &mut ())
        .expect_err("the run diverges");
    assert_eq!(err, volley::LoopError::Diverged(d));
    assert_eq!(outcome(&sim.world, Err(d)), expected);
    assert_eq!(sim.clock.tick(), d.tick, "the unrun ticks went back");
    // A stopped world's next frame runs no tick, and the clock does not count one.
    let again = sim
        .frame(s.timestep(), &mut ())
        .expect_err("it stays stopped");
    assert_eq!(again, volley::LoopError::Diverged(d));
    assert_eq!(sim.clock.tick(), d.tick);
}

#[test]
fn two_threads_batch_to_the_same_bits_as_one_thread_tick_by_tick() {
    let count = 2 * PARALLEL_MIN_CHUNK + 2 * BATCH_BLOCK + 3;
    for integrator in [Integrator::ExplicitEuler, Integrator::VelocityVerlet] {
        let mut s = volley("Gravity((0.0, 0.0, -9.81)), LinearDrag(0.3)", count, 5);
        s.set_integrator(integrator).expect("drag allows it");
        let expected = tick_by_tick(&s, 1, BATCH_MAX_TICKS + 3);
        let two = pool().install(|| batched(&s, 2, BATCH_MAX_TICKS + 3));
        assert_eq!(two, expected, "{integrator}");
    }
}

/// A stiff spring (w h = 5 at h = 0.05) under explicit Euler: amplitude grows about 5x a tick.
fn unstable(guard_every: u32) -> Scene {
    let mut s = volley(
        "Gravity((0.0, 0.0, -9.81)), Spring(anchor: (0.0, 0.0, 0.0), stiffness: 10000.0)",
        BODIES,
        guard_every,
    );
    s.set_dt(0.05).unwrap();
    s
}

#[test]
fn a_batch_that_goes_non_finite_stops_where_stepping_stops() {
    // With the guard off only the non-finite check stops it: at 5x a tick the state overflows
    // after about 440 ticks, inside a batch.
    let s = unstable(0);
    let expected = tick_by_tick(&s, 1, 2000);
    let Err(d) = expected.result else {
        panic!("the stiff spring must diverge: {:?}", expected.result)
    };
    assert!(
        !d.tick.is_multiple_of(BATCH_MAX_TICKS),
        "the divergence should fall inside a batch, not at its end: tick {}",
        d.tick
    );
    assert_eq!(batched(&s, 1, 2000), expected);
}

#[test]
fn a_batch_that_trips_the_guard_stops_where_stepping_stops() {
    // The guard, every 3 ticks, catches the growth long before the state overflows.
    let s = unstable(3);
    let expected = tick_by_tick(&s, 1, 500);
    let Err(d) = expected.result else {
        panic!("the guard must trip: {:?}", expected.result)
    };
    assert!(d.tick < 100, "tripped at tick {}", d.tick);
    assert_eq!(batched(&s, 1, 500), expected);
    // A stopped world stays stopped.
    let mut world = World::new(&s);
    assert_eq!(world.step_ticks(500), Err(d));
    assert_eq!(world.step_ticks(10), Err(d));
    assert_eq!(world.tick(), d.tick);
}

#[test]
fn worlds_with_contacts_step_tick_by_tick_and_keep_the_last_ticks_events() {
    let s = scene(&format!(
        "Scene(dt: 0.02, integrator: SemiImplicitEuler, seed: 5,
               forces: [Gravity((0.0, 0.0, -9.81))],
               ground: (height: 0.0, restitution: 0.6),
               launcher: (position: (0.0, 0.0, 0.5), speed: 8.0, elevation_deg: 20.0, azimuth_deg: 0.0),
               volley: (count: {BODIES}, speed_spread: 3.0, angle_spread_deg: 25.0))"
    ));
    // Find a tick with events, and batch up to exactly it.
    let mut probe = World::new(&s);
    let mut ticks = 0;
    while probe.events().is_empty() {
        probe.step().expect("bouncing does not diverge");
        ticks += 1;
        assert!(ticks < 500, "no event within 500 ticks");
    }
    let expected = tick_by_tick(&s, 1, ticks);
    assert!(!expected.events.is_empty());
    assert_eq!(batched(&s, 1, ticks), expected);
}

/// Records every tick's hash, or only every `every`-th tick's (letting the loop batch).
struct Hashes {
    every: u64,
    seen: Vec<(u64, u64)>,
    calls: u64,
}

impl volley::TickObserver for Hashes {
    fn after_tick(&mut self, world: &World) -> Result<(), volley::sim_loop::ObserverError> {
        self.calls += 1;
        if world.tick().is_multiple_of(self.every) {
            self.seen.push((world.tick(), state_hash(world)));
        }
        Ok(())
    }
    fn next_needed_tick(&self, tick: u64) -> u64 {
        (tick / self.every + 1) * self.every
    }
}

#[test]
fn the_loop_batches_between_commands_and_needed_ticks_without_changing_them() {
    let s = volley("Gravity((0.0, 0.0, -9.81)), LinearDrag(0.3)", BODIES, 1);
    let commands = || {
        [
            Stamped {
                tick: 37,
                command: Command::Fire,
            },
            Stamped {
                tick: 101,
                command: Command::SetIntegrator(Integrator::Rk4),
            },
            Stamped {
                tick: 102,
                command: Command::Fire,
            },
            // Verlet carries a force, which a new body makes stale: refilled after the fire.
            Stamped {
                tick: 150,
                command: Command::SetIntegrator(Integrator::VelocityVerlet),
            },
            Stamped {
                tick: 201,
                command: Command::Fire,
            },
        ]
    };
    let run = |every: u64, source: &mut VirtualClock, unpaced: bool| {
        let mut sim = SimLoop::new(World::new(&s));
        sim.schedule(commands());
        let mut source = if unpaced {
            sim.unpaced_source(100)
        } else {
            source.clone()
        };
        let mut seen = Hashes {
            every,
            seen: Vec::new(),
            calls: 0,
        };
        sim.run_until(300, &mut source, &mut seen)
            .expect("no divergence");
        assert_eq!(sim.world.tick(), 300);
        assert_eq!(sim.clock.tick(), 300, "the clock counts the batched ticks");
        (
            seen.seen,
            state_hash(&sim.world),
            sim.world.force_evals(),
            seen.calls,
        )
    };
    let steady = VirtualClock::Steady(s.timestep());
    let (every_tick, final_hash, evals, calls) = run(1, &mut steady.clone(), false);
    assert_eq!((every_tick.len(), calls), (300, 300));
    for every in [1, 10, 64, 1000] {
        let (seen, hash, e, calls) = run(every, &mut steady.clone(), true);
        // One call per batch: batches really ran (and ended at every needed tick).
        if every > 1 {
            assert!(calls < 300, "every {every}: {calls} calls, no batching");
        }
        let expected: Vec<_> = every_tick
            .iter()
            .copied()
            .filter(|(t, _)| t.is_multiple_of(every))
            .collect();
        assert_eq!(seen, expected, "every {every}");
        assert_eq!((hash, e), (final_hash, evals), "every {every}");
    }
}

#[test]
fn a_recording_hashing_every_tenth_tick_is_the_same_file_batched_or_not() {
    let s = volley("Gravity((0.0, 0.0, -9.81)), LinearDrag(0.3)", BODIES, 1);
    let record = |unpaced: bool| {
        let mut sim = SimLoop::new(World::new(&s));
        sim.schedule([Stamped {
            tick: 55,
            command: Command::Fire,
        }]);
        let options = RecordOptions {
            hash_every: 10,
            keyframe_every: 50,
            flush: FlushPolicy::OnFinish,
            scene_file: "batch.ron".into(),
        };
        let mut recorder = Recorder::start(Vec::new(), &sim.world, options).expect("in memory");
        let mut source = if unpaced {
            sim.unpaced_source(64)
        } else {
            VirtualClock::Steady(s.timestep())
        };
        sim.run_until(200, &mut source, &mut recorder)
            .expect("no divergence");
        recorder.finish(&sim.world).expect("in memory").0
    };
    let bytes = record(false);
    assert!(bytes.len() > 1000);
    assert_eq!(record(true), bytes);
}

#[test]
fn headless_prints_the_same_rows_and_summary_whether_ticks_are_batched_or_not() {
    // `--every 1` observes every tick (no batch); `--every 10` and `--no-table` let the loop
    // batch the ticks between rows (1000 bodies, no contacts).
    let run = |extra: &[&str]| {
        let mut args = vec![
            "headless",
            "bench/drag",
            "--ticks",
            "150",
            "--format",
            "csv",
            "--integrator",
            "verlet",
        ];
        args.extend_from_slice(extra);
        support::volley_stdout(&args, &[])
    };
    let every_tick = run(&["--every", "1"]);
    let summary = |text: &str| {
        text.lines()
            .find(|l| l.contains("summary"))
            .expect("a summary line")
            .to_string()
    };
    // CSV rows: tick first; keep the header, the rows at multiples of 10 and the summary.
    let tenth: Vec<&str> = every_tick
        .lines()
        .filter(|l| match l.split(',').next().map(str::parse::<u64>) {
            Some(Ok(tick)) => tick.is_multiple_of(10),
            _ => true,
        })
        .collect();
    let ticks = |text: &str| {
        let mut t: Vec<u64> = text
            .lines()
            .filter_map(|l| l.split(',').next()?.parse().ok())
            .collect();
        t.dedup();
        t
    };
    assert_eq!(ticks(&every_tick), (0..=150).collect::<Vec<_>>());
    let batched = run(&["--every", "10"]);
    assert_eq!(ticks(&batched), (0..=150).step_by(10).collect::<Vec<_>>());
    assert_eq!(batched.lines().collect::<Vec<_>>(), tenth);
    let no_table = run(&["--no-table"]);
    assert_eq!(summary(&no_table), summary(&every_tick));
}

#[test]
fn an_empty_world_batches_its_ticks_too() {
    let s = scene(
        "Scene(dt: 0.01, integrator: VelocityVerlet, forces: [Gravity((0.0, 0.0, -9.81))], bodies: [])",
    );
    let expected = tick_by_tick(&s, 1, 100);
    assert_eq!(expected.tick, 100);
    assert_eq!(batched(&s, 1, 100), expected);
}
