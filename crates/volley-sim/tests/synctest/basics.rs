use volley_sim::{Command, SyncTest, World, bundled_scene};

#[test]
fn the_seed_passes_at_every_distance() {
    let scene = bundled_scene("seed").unwrap();
    for k in [1, 2, 7, 30] {
        let mut sync = SyncTest::new(World::new(&scene), k).unwrap();
        for tick in 0..27 {
            let c: &[Command] = if tick == 10 { &[Command::Fire] } else { &[] };
            sync.advance(c).unwrap();
        }
        assert_eq!(sync.checks(), 27);
        let mut plain = World::new(&scene);
        for tick in 0..27 {
            if tick == 10 {
                plain.apply(&Command::Fire).unwrap();
            }
            plain.step().unwrap();
        }
        assert_eq!(
            volley_sim::state_hash(&plain),
            volley_sim::state_hash(sync.world()),
            "k {k}"
        );
    }
}

#[test]
fn a_world_whose_declared_events_stop_something_is_refused_by_name() {
    // Its tallies, in-step despawns and run stop are not saved by the ring: refused, not
    // half-checked.
    let scene = volley_sim::parse_scene(
        "Scene(dt: 0.1, integrator: Exact, forces: [Gravity((0, 0, -9.81))],
               bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((1, 0, 10)))],
               events: [(when: Apex, stop: Body(1))])",
        "events.ron",
        "events",
    )
    .unwrap();
    let e = SyncTest::new(World::new(&scene), 7).err();
    assert_eq!(e, Some(volley_sim::SyncTestError::DeclaredEvents));
    let plain = bundled_scene("seed").unwrap();
    assert!(SyncTest::new(World::new(&plain), 7).is_ok());
}

/// Declared events that stop nothing change no state: such a world passes under every
/// integrator, ends where plain stepping ends, and each tick's events after a check (the
/// re-run's last tick, its horizons voided by the restore) are plain stepping's, bit for bit.
#[test]
fn a_world_whose_declared_events_stop_nothing_passes_with_the_same_events() {
    for integrator in volley_sim::Integrator::ALL {
        let text = format!(
            "Scene(dt: 0.02, integrator: {integrator:?}, forces: [Gravity((0, 0, -9.81))],
               ground: (height: 0.0, restitution: 0.5),
               launcher: (position: (0, 0, 1), speed: 15.0, elevation_deg: 50.0,
                          azimuth_deg: 0.0, mass: 1.0, radius: 0.1),
               volley: (count: 40, speed_spread: 3.0, angle_spread_deg: 8.0), seed: 5,
               events: [(when: Apex), (when: Altitude(4.0), direction: Falling),
                        (when: Downrange(12.0)), (when: Speed(9.0))])"
        );
        let Ok(scene) = volley_sim::parse_scene(&text, "events.ron", "events") else {
            continue; // an integrator the scene's forces do not take
        };
        let mut sync = SyncTest::new(World::new(&scene), 7).unwrap();
        let mut plain = World::new(&scene);
        let mut reported = 0;
        for tick in 0..150 {
            let c: &[Command] = if tick == 30 { &[Command::Fire] } else { &[] };
            for command in c {
                plain.apply(command).unwrap();
            }
            plain.step().unwrap();
            sync.advance(c).unwrap();
            assert_eq!(
                sync.world().events(),
                plain.events(),
                "{integrator}, tick {tick}"
            );
            reported += plain.events().len();
        }
        assert!(reported > 100, "{integrator}: only {reported} events");
        assert_eq!(
            volley_sim::state_hash(&plain),
            volley_sim::state_hash(sync.world()),
            "{integrator}"
        );
    }
}
