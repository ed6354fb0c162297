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
fn a_world_with_declared_events_is_refused_by_name() {
    // Its tallies and in-step despawns are not saved by the ring: refused, not half-checked.
    let scene = volley_sim::parse_scene(
        "Scene(dt: 0.1, integrator: Exact, forces: [Gravity((0, 0, -9.81))],
               bodies: [(mass: 1, position: (0, 0, 0), launch: Velocity((1, 0, 10)))],
               events: [(when: Apex)])",
        "events.ron",
        "events",
    )
    .unwrap();
    let e = SyncTest::new(World::new(&scene), 7).err();
    assert_eq!(e, Some(volley_sim::SyncTestError::DeclaredEvents));
    let plain = bundled_scene("seed").unwrap();
    assert!(SyncTest::new(World::new(&plain), 7).is_ok());
}
