//! The divergence guard in every mode: the library step, the loop and its observers, parallel
//! stepping, and the headless command (exit 3, table kept, pre-check warnings first). The study
//! records divergence as a result (tests/study.rs); the window's pause is the window's.

use std::process::Command as Process;

use volley::clock::VirtualClock;
use volley::scene::{self, BodySpec};
use volley::sim_loop::TickObserver;
use volley::world::DivergenceCause;
use volley::{BodyId, Command, Divergence, LoopError, SimLoop, Stamped, World};

/// A soft spring (k = 1 N/m): stable for 1 kg bodies at 60 Hz, wildly unstable for 1e-8 kg
/// (w h = 167).
fn spring_scene(volley: u32, every: u32) -> scene::Scene {
    let text = format!(
        "Scene(dt: 0.016666667, integrator: SemiImplicitEuler,
               forces: [Spring(anchor: (0, 0, 0), stiffness: 1.0)],
               bodies: [(mass: 1.0, position: (1, 0, 0))],
               launcher: (position: (1, 0, 0), speed: 0.0, elevation_deg: 0.0, azimuth_deg: 0.0,
                          mass: 1.0),
               volley: (count: {volley}),
               guard: (every: {every}))"
    );
    scene::parse(&text, "spring.ron", "spring").unwrap_or_else(|e| panic!("{e}"))
}

fn light_body() -> Command {
    Command::Spawn(BodySpec {
        mass: 1e-8,
        radius: 0.0,
        position: glam::DVec3::new(0.0, 1.0, 0.0),
        velocity: glam::DVec3::ZERO,
        spin: Default::default(),
    })
}

#[derive(Default)]
struct Seen(Option<(u64, Divergence)>);

impl TickObserver for Seen {
    fn on_divergence(&mut self, world: &World, d: &Divergence) {
        self.0 = Some((world.tick(), *d));
    }
}

fn run_with_light_body(volley: u32, every: u32, threads: usize) -> (Divergence, Seen, World) {
    let scene = spring_scene(volley, every);
    let mut world = World::new(&scene);
    world.set_threads(threads);
    let mut sim = SimLoop::new(world);
    sim.schedule([Stamped {
        tick: 0,
        command: light_body(),
    }]);
    let mut seen = Seen::default();
    let result = sim.run_until(
        10_000,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut seen,
    );
    match result {
        Err(LoopError::Diverged(d)) => (d, seen, sim.world),
        other => panic!("expected a divergence, got {other:?}"),
    }
}

#[test]
fn the_guard_names_the_body_that_diverged_and_the_observer_sees_it() {
    let (d, seen, world) = run_with_light_body(0, 1, 1);
    assert_eq!(
        d.body,
        BodyId(1),
        "body 0 is stable; the light body spawned second is not"
    );
    assert!(
        matches!(d.cause, DivergenceCause::EnergyGrowth { .. }),
        "{d}"
    );
    assert_eq!(
        seen.0,
        Some((d.tick, d)),
        "the observer sees the world at the bad tick"
    );
    assert_eq!(world.divergence(), Some(d));
}

#[test]
fn a_stopped_world_stays_stopped_where_it_stopped() {
    let (d, _, mut world) = run_with_light_body(0, 1, 1);
    let state = world.bodies().state(1);
    assert_eq!(world.step(), Err(d));
    assert_eq!((world.tick(), world.bodies().state(1)), (d.tick, state));
}

#[test]
fn without_the_energy_check_overflow_is_caught_as_non_finite() {
    let (d, _, world) = run_with_light_body(0, 0, 1);
    assert_eq!((d.body, d.cause), (BodyId(1), DivergenceCause::NonFinite));
    // Semi-implicit Euler at w h = 167 grows by about (w h)^2 = 2.8e4 per step: the state
    // overflows within 709 / ln(2.8e4) = 70 ticks, and not in the first 60.
    assert!((60..=75).contains(&d.tick), "tick {}", d.tick);
    assert!(!world.bodies().state(1).is_finite());
}

#[test]
fn parallel_stepping_stops_at_the_same_tick_and_body() {
    // 40 000 stable bodies, then the light one: with 2 threads it sits in the second chunk.
    let one = run_with_light_body(40_000, 0, 1).0;
    let two = run_with_light_body(40_000, 0, 2).0;
    assert_eq!(one, two);
    assert_eq!(
        (one.body, one.cause),
        (BodyId(40_001), DivergenceCause::NonFinite)
    );
}

#[test]
fn headless_exits_3_after_warning_and_keeps_the_rows_before_the_divergence() {
    let run = Process::new(env!("CARGO_BIN_EXE_volley"))
        .args(["headless", "hard/stiff_spring", "--format", "csv"])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&run.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    assert!(
        lines[..lines.len() - 1]
            .iter()
            .all(|l| l.starts_with("warning: ")),
        "{stderr}"
    );
    assert!(
        stderr.contains("explicit-euler is outside its linear stability region"),
        "{stderr}"
    );
    let last = lines.last().unwrap();
    assert!(
        last.starts_with("error: diverged at tick 2 (body 0):"),
        "{last}"
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.lines().any(|l| l.starts_with("1,0,")),
        "the row of tick 1 is kept"
    );
    assert!(
        !stdout.lines().any(|l| l.starts_with("2,")),
        "the bad state is not a row"
    );
}
