//! A game adopting `volley-sim`, written as one would be against the published crate: root names
//! only. It builds a scene in code with every built-in force term and two of its own, steps it
//! in its own frame loop, draws it with Volley's measured default, records the run, and replays
//! the recording: no divergence. It exits non-zero, saying why, if any step fails.

use std::io::Cursor;
use std::time::Duration;

use glam::DVec3;
use volley_sim::{
    AirModel, BodySpec, Command, DEFAULT_POLICY, DragCurve, DragSize, Draw, EventKind, ForceInput,
    ForceTerm, ForceTerms, Ground, Integrator, Launcher, MachDrag, PointMass, Reads, RecordOptions,
    Recorder, Recording, Replay, Scene, SimLoop, SpinDecay, SpinLift, Spring, Target, Thrust,
    ThrustDirection, Wall, Wind, World, state_hash,
};

/// The game's homing pull toward a point, stronger up close: `F = m k (c - p) / |c - p|`.
#[derive(Debug)]
struct Homing {
    center: DVec3,
    k: f64,
}

impl ForceTerm for Homing {
    fn name(&self) -> &str {
        "adopter/homing"
    }
    fn version(&self) -> u32 {
        1
    }
    fn reads(&self) -> Reads {
        Reads::POSITION
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        let d = self.center - i.p;
        let r = d.length();
        if r == 0.0 {
            DVec3::ZERO
        } else {
            (i.m * self.k / r) * d
        }
    }
}

/// The game's fuse: a push along +x for the first 0.4 s of each body's own flight, which it
/// reads from the body's launch.
#[derive(Debug)]
struct Fuse;

impl ForceTerm for Fuse {
    fn name(&self) -> &str {
        "adopter/fuse"
    }
    fn version(&self) -> u32 {
        2
    }
    fn reads(&self) -> Reads {
        Reads {
            velocity: false,
            launch: true,
        }
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        let launch = i.launch.expect("a term that reads the launch is given it");
        let age = i.t - launch.time;
        if age < 0.4 {
            DVec3::new(2.0 * i.m, 0.0, 0.0)
        } else {
            DVec3::ZERO
        }
    }
}

fn scene() -> Result<Scene, Box<dyn std::error::Error>> {
    let drag = MachDrag::new(
        DragCurve::from_points(&[(0.0, 0.47), (0.8, 0.5), (1.2, 0.9), (3.0, 0.7)])?,
        DragSize::Diameter {
            diameter: 0.07,
            form_factor: 1.0,
        },
    )
    .with_air(AirModel::uniform(288.15, 101_325.0))
    .with_wind(Wind::uniform(DVec3::new(0.0, 2.0, 0.0)))
    .with_spin(SpinLift::nathan(SpinDecay::Time(20.0), 0.01));
    let motor = Thrust::new(
        vec![(0.0, 0.0), (0.05, 3.0), (0.3, 1.0), (0.5, 0.0)],
        0.01,
        ThrustDirection::Fixed(DVec3::Z),
    )?;
    let ball = |x: f64, vx: f64| BodySpec {
        mass: 0.2,
        radius: 0.035,
        position: DVec3::new(x, 0.0, 1.5),
        velocity: DVec3::new(vx, 0.0, 6.0),
        spin: DVec3::new(0.0, -150.0, 0.0),
    };
    Ok(Scene::builder("adopter", 1.0 / 60.0)
        .integrator(Integrator::Rk4)
        .gravity(DVec3::new(0.0, 0.0, -9.81))
        .constant_force(DVec3::new(0.0, 0.01, 0.0))
        .linear_drag(0.001)
        .quadratic_drag(0.0005)
        .spring(Spring {
            anchor: DVec3::new(0.0, 0.0, 10.0),
            stiffness: 0.05,
            rest_length: 2.0,
            damping: 0.0,
        })
        .point_mass(PointMass {
            center: DVec3::new(50.0, 0.0, -100.0),
            mu: 50.0,
        })
        .mach_drag(drag)
        .thrust(motor)
        .custom(Homing {
            center: DVec3::new(20.0, 0.0, 0.0),
            k: 0.3,
        })
        .custom(Fuse)
        .ground(Ground {
            height: 0.0,
            restitution: 0.6,
        })
        .wall(Wall {
            point: DVec3::new(12.0, 0.0, 0.0),
            normal: DVec3::X,
            thickness: 0.2,
            restitution: 0.9,
        })
        .target(Target {
            center: DVec3::new(8.0, 0.0, 3.0),
            radius: 0.5,
            velocity: DVec3::ZERO,
        })
        .body(ball(0.0, 8.0))
        .body(ball(-1.0, 10.0))
        .launcher(Launcher {
            position: DVec3::new(0.0, 0.0, 1.5),
            speed: 12.0,
            elevation_deg: 40.0,
            azimuth_deg: 0.0,
            mass: 0.2,
            radius: 0.035,
            backspin: 1500.0,
            sidespin: 0.0,
        })
        .seed(7)
        .build()?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = scene()?;
    let kinds: Vec<_> = scene.forces().kinds().collect();
    assert_eq!(kinds.len(), 9, "every built-in kind: {kinds:?}");
    assert_eq!(
        scene.forces().custom.len(),
        2,
        "two terms of the game's own"
    );

    // The game's own loop: a 144 Hz display, Volley's measured policy and draw, a recorder.
    let mut sim = SimLoop::new(World::new(&scene));
    sim.clock.set_policy(DEFAULT_POLICY);
    let mut draw = Draw::measured(&sim.world);
    let mut recorder = Recorder::start(Vec::new(), &sim.world, RecordOptions::default())?;
    let delta = Duration::from_nanos(6_944_444);
    let (mut impacts, mut drawn) = (0usize, 0usize);
    for frame in 0..(144 * 4) {
        if frame == 100 || frame == 300 {
            sim.push(Command::Fire);
        }
        let ticks = sim.frame(delta, &mut (&mut draw, &mut recorder))?;
        draw.frame(delta);
        impacts += sim
            .world
            .events()
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Impact { .. }))
            .count();
        draw.positions(&sim.world, ticks.alpha, |i, p| {
            assert!(p.is_finite(), "body {i} drawn at {p}");
            drawn += 1;
        });
    }
    let (bytes, stats) = recorder.finish(&sim.world)?;
    let end = state_hash(&sim.world);

    // The replay finds the game's terms in the list the program passes in.
    let terms = ForceTerms::new()
        .with(Homing {
            center: DVec3::new(20.0, 0.0, 0.0),
            k: 0.3,
        })
        .with(Fuse);
    let recording = Recording::from_reader(Cursor::new(bytes.clone()), "adopter.vrec")?;
    let mut replay = Replay::start(recording.with_terms(terms), None)?;
    replay.run_to(u64::MAX, &mut ())?;
    if let Some(d) = replay.first_divergence() {
        return Err(format!("the replay parted from the run: {d:?}").into());
    }
    assert_eq!(replay.world().tick(), sim.world.tick());
    assert_eq!(state_hash(replay.world()), end);

    // Without them, it is refused naming the first.
    let without = Recording::from_reader(Cursor::new(bytes), "adopter.vrec")?;
    let refused = Replay::start(without, None).err().map(|e| e.to_string());
    assert!(
        refused
            .as_deref()
            .is_some_and(|e| e.contains("adopter/homing")),
        "{refused:?}"
    );

    println!(
        "adopter: {} ticks, {} bodies, {impacts} impacts, {drawn} bodies drawn, recording of \
         {} bytes replayed to the same hash {end:#018x}",
        sim.world.tick(),
        sim.world.bodies().len(),
        stats.bytes
    );
    Ok(())
}
