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
