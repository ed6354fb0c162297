//! The in-memory timeline: a state reached by seeking (back or forward, from any keyframe, with
//! commands in between) is bit-identical to the one first computed at that tick, for every
//! integrator; replaying the recorded future records nothing twice; a new command behind the
//! end drops the future; the memory budget holds.

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::command::{Command, Stamped};
use volley_sim::internals::hash::state_hash;
use volley_sim::internals::scene;
use volley_sim::internals::sim_loop::{ObserverError, TickObserver};
use volley_sim::internals::timeline::Timeline;
use volley_sim::{ForceKind, Integrator, SimLoop, World};

/// Gravity, a spring (position-only, so velocity Verlet carries its force as state), linear
/// drag and a bouncing ground with a target: events, carries and commands all in play.
const SCENE: &str = "Scene(dt: 0.02, integrator: SemiImplicitEuler,
    forces: [Gravity((0, 0, -9.81)), LinearDrag(0.05),
             Spring(anchor: (0, 0, 4), stiffness: 3.0, damping: 0.1)],
    ground: (height: 0, restitution: 0.6),
    targets: [(center: (3, 0, 2), radius: 0.3, velocity: (0.1, 0, 0))],
    launcher: (position: (0, 0, 1), speed: 6, elevation_deg: 50, azimuth_deg: 10),
    bodies: [(mass: 1, position: (1, 0, 3), launch: Velocity((2, 0, 1))),
             (mass: 2, radius: 0.2, position: (-1, 1, 2))])";

const TICKS: u64 = 300;

fn commands(integrator: Integrator) -> Vec<Stamped> {
    let at = |tick, command| Stamped { tick, command };
    let mut list = vec![
        at(5, Command::Fire),
        at(
            20,
            Command::SetLaunch {
                speed: Some(8.0),
                elevation_deg: Some(30.0),
                azimuth_deg: None,
                position: None,
            },
        ),
        at(20, Command::Fire),
        at(
            37,
            Command::SetForce {
                kind: ForceKind::LinearDrag,
                enabled: false,
            },
        ),
        at(64, Command::Fire),
        at(120, Command::Reset),
        at(
            181,
            Command::SetForce {
                kind: ForceKind::LinearDrag,
                enabled: true,
            },
        ),
    ];
    // Switching away and back mid-run (the carried force is invalidated and rebuilt).
    if integrator != Integrator::Exact {
        list.push(at(150, Command::SetIntegrator(Integrator::Rk4)));
        list.push(at(170, Command::SetIntegrator(integrator)));
    }
    list.sort_by_key(|c| c.tick);
    list
}

/// The timeline and every tick's hash.
struct Recorder {
    timeline: Timeline,
    hashes: Vec<u64>,
}

impl TickObserver for Recorder {
    fn on_command(&mut self, w: &World, s: &Stamped) -> Result<(), ObserverError> {
        self.timeline.on_command(w, s)
    }
    fn after_tick(&mut self, w: &World) -> Result<(), ObserverError> {
        self.hashes.push(state_hash(w));
        self.timeline.after_tick(w)
    }
}

fn scene_with(integrator: Integrator) -> Option<scene::Scene> {
    let mut s = scene::parse(SCENE, "timeline.rs", "timeline").unwrap();
    s.set_integrator(integrator).ok()?;
    Some(s)
}

/// Runs the scene forward `TICKS` ticks with the commands; returns the timeline (a budget small
/// enough to make it thin its keyframes) and the hash at every tick, tick 0 first.
fn forward(integrator: Integrator, budget: usize) -> (scene::Scene, Timeline, Vec<u64>) {
    let scene = scene_with(integrator).unwrap();
    let world = World::new(&scene);
    let first = state_hash(&world);
    let mut rec = Recorder {
        timeline: Timeline::with_interval(&world, budget, EVERY),
        hashes: vec![first],
    };
    let mut sim = SimLoop::new(world);
    sim.schedule(commands(integrator));
    sim.run_until(TICKS, &mut VirtualClock::display(60.0), &mut rec)
        .unwrap();
    (scene, rec.timeline, rec.hashes)
}

/// Keyframes every 8 ticks to begin with, so 300 ticks cross many.
const EVERY: u64 = 8;

/// A budget a handful of keyframes of this scene fit in, so thinning happens.
const SMALL: usize = 12 * 1024;

#[test]
fn a_sought_state_is_the_state_first_computed_at_that_tick_for_every_integrator() {
    let mut checked = 0;
    for integrator in Integrator::ALL {
        if scene_with(integrator).is_none() {
            continue; // an integrator the forces refuse
        }
        let (scene, mut timeline, hashes) = forward(integrator, SMALL);
        assert!(
            timeline.every() > EVERY,
            "{integrator:?}: the budget never thinned"
        );
        assert!(
            timeline.bytes() <= SMALL,
            "{integrator:?}: {} bytes",
            timeline.bytes()
        );
        let every = timeline.every();
        // Around keyframes and commands, the ends, and going back and forth on one world.
        let mut ticks = vec![
            0,
            1,
            4,
            5,
            6,
            19,
            20,
            21,
            120,
            121,
            150,
            151,
            TICKS - 1,
            TICKS,
        ];
        ticks.extend([every - 1, every, every + 1, 2 * every, 3 * every + 7]);
        let mut world = World::new(&scene);
        for &tick in ticks.iter().chain(ticks.iter().rev()) {
            timeline.seek(&mut world, tick).unwrap();
            assert_eq!(world.tick(), tick);
            assert_eq!(
                state_hash(&world),
                hashes[tick as usize],
                "{integrator:?} at tick {tick} (keyframes every {every})"
            );
            checked += 1;
        }
    }
    assert!(checked >= 6 * 38, "{checked}");
}

#[test]
fn running_on_from_a_seek_replays_the_recorded_future_and_records_nothing_twice() {
    let (scene, mut timeline, hashes) = forward(Integrator::VelocityVerlet, SMALL);
    let (keyframes, bytes) = (timeline.keyframes(), timeline.bytes());
    let mut world = World::new(&scene);
    timeline.seek(&mut world, 100).unwrap();
    assert!(timeline.is_rewound(100));
    let mut sim = SimLoop::new(world);
    sim.schedule(timeline.commands_from(100).to_vec());
    let mut rec = Recorder {
        timeline,
        hashes: Vec::new(),
    };
    sim.run_until(TICKS, &mut VirtualClock::display(60.0), &mut rec)
        .unwrap();
    assert_eq!(rec.hashes, hashes[101..].to_vec());
    assert_eq!(rec.timeline.keyframes(), keyframes);
    assert_eq!(rec.timeline.bytes(), bytes);
    assert_eq!(rec.timeline.dropped_future(), 0);
    assert!(!rec.timeline.is_rewound(TICKS));
}

#[test]
fn a_new_command_behind_the_end_drops_the_future_after_its_tick() {
    let (scene, mut timeline, hashes) = forward(Integrator::Rk4, 1 << 20);
    let mut world = World::new(&scene);
    timeline.seek(&mut world, 90).unwrap();
    // The user fires at tick 90: a different future from here.
    let mut sim = SimLoop::new(world);
    sim.push(Command::Fire);
    let mut rec = Recorder {
        timeline,
        hashes: Vec::new(),
    };
    sim.run_until(95, &mut VirtualClock::display(60.0), &mut rec)
        .unwrap();
    let t = &rec.timeline;
    assert_eq!(t.dropped_future(), TICKS - 90);
    assert_eq!(t.end(), 95);
    // The commands before 90 are kept, the old future's are gone, the new one is logged.
    let logged: Vec<u64> = t.commands_from(0).iter().map(|c| c.tick).collect();
    assert_eq!(logged, vec![5, 20, 20, 37, 64, 90]);
    assert_ne!(rec.hashes[4], hashes[95], "the new shot changes tick 95");
    // And the new history seeks like the old one did.
    let mut again = World::new(&scene);
    let mut t = rec.timeline.clone();
    t.seek(&mut again, 95).unwrap();
    assert_eq!(state_hash(&again), rec.hashes[4]);
}

#[test]
fn seeking_outside_the_history_is_an_error_naming_the_range() {
    let (scene, mut timeline, _) = forward(Integrator::SemiImplicitEuler, 1 << 20);
    let mut world = World::new(&scene);
    let e = timeline.seek(&mut world, TICKS + 1).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "tick {} is outside the history held (ticks 0 to {TICKS})",
            TICKS + 1
        )
    );
}
