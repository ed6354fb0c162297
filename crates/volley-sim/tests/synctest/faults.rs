//! Injected nondeterminism: each class is caught within K + 1 ticks of the first tick it can
//! change, and the report names the stage and the fields it changes.
//!
//! Every fault switches on at `FROM` (so the test also pins how soon it is caught); the game's
//! terms push along z only, so the right fields are `p.z` and `mV.z` and nothing else. The
//! seams are a game's: its own force terms, its own restore ([`SyncTest::with_restore`]), the
//! re-runs' thread count ([`SyncTest::with_rerun_threads`]), and for faults between stages the
//! hidden stage hook.

use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use glam::DVec3;
use volley_sim::{
    Command, ForceInput, ForceKind, ForceTerm, ForceTerms, Scene, SyncError, SyncFoundBy,
    SyncMismatch, SyncTest, TickStage, World, parse_scene_with,
};

/// The check distance of every case.
const K: u32 = 7;
/// The tick from which each fault acts (the first run's step from `FROM` to `FROM + 1` is
/// the first it can change).
const FROM: u64 = 20;
/// The timestep of the scenes (s).
const H: f64 = 0.05;

/// Two balls thrown up and along x under gravity and light linear drag, bouncing on the
/// ground, with the game's term `test/TERM`.
fn scene(term: &dyn ForceTerm, terms: &ForceTerms) -> Scene {
    let text = format!(
        "Scene(dt: {H}, integrator: SemiImplicitEuler, duration: 10,
               forces: [Gravity((0, 0, -9.81)), LinearDrag(0.01),
                        Custom(name: \"{}\", version: 1)],
               ground: (height: 0, restitution: 0.6),
               bodies: [(mass: 1, radius: 0.1, position: (0, 0, 1), launch: Velocity((3, 0, 4))),
                        (mass: 2, radius: 0.2, position: (1, 0, 2), launch: Velocity((1, 0, 8)))])",
        term.name()
    );
    parse_scene_with(&text, "faults.ron", "faults", terms).expect("the test scene is valid")
}

/// A scene with `term`, and a sync test of it at distance `K`.
fn sync_with(term: impl ForceTerm + 'static) -> SyncTest {
    let name_holder: &dyn ForceTerm = &term;
    let name = name_holder.name().to_string();
    let terms = ForceTerms::new().with(term);
    let term = terms
        .iter()
        .find(|t| t.name() == name)
        .expect("the term was just added")
        .clone();
    SyncTest::new(World::new(&scene(term.as_ref(), &terms)), K).expect("K is in range")
}

/// Runs until the sync test fails; the tick it failed at and its report.
fn caught(sync: &mut SyncTest) -> (u64, SyncMismatch) {
    caught_with(sync, |_| {})
}

/// [`caught`], calling `before` with each tick before it runs.
fn caught_with(sync: &mut SyncTest, mut before: impl FnMut(u64)) -> (u64, SyncMismatch) {
    for _ in 0..120 {
        before(sync.world().tick());
        match sync.advance(&[]) {
            Ok(()) => {}
            Err(SyncError::Mismatch(m)) => {
                if std::env::var("SHOW").is_ok() {
                    eprintln!("caught at {}: {}", m.checked, m.report(None));
                }
                return (m.checked, *m);
            }
            Err(e) => panic!("{e}"),
        }
    }
    panic!("not caught in 120 ticks")
}

/// The fault acts from `FROM`: caught at most K + 1 ticks after the first tick it changes,
/// and not before it acts.
fn assert_in_time(at: u64) {
    assert!(
        (FROM + 1..=FROM + 1 + u64::from(K)).contains(&at),
        "caught at tick {at}, not within K + 1 = {} ticks of tick {}",
        K + 1,
        FROM + 1
    );
}

/// Every differing field is one of `fields` of a body, and each of `fields` is among them.
fn assert_fields(m: &SyncMismatch, fields: &[&str]) {
    assert!(!m.fields.is_empty(), "{}", m.report(None));
    for d in &m.fields {
        assert!(
            d.body.is_some() && fields.contains(&d.field.as_str()),
            "unexpected field {d}\n{}",
            m.report(None)
        );
    }
    for f in fields {
        assert!(
            m.fields.iter().any(|d| d.field == *f),
            "{f} not named\n{}",
            m.report(None)
        );
    }
}

fn assert_stage(m: &SyncMismatch, stage: &str) {
    let named = m.stage.map(|s| s.stage.name());
    assert_eq!(named, Some(stage), "{}", m.report(None));
}

/// Whether the fault acts at time `t` (from the start of the step out of tick `FROM`).
fn acting(t: f64) -> bool {
    t >= FROM as f64 * H - 1e-9
}

/// Class 1: a game's force term with hidden mutable state: a counter bumped by every evaluation.
#[derive(Debug, Default)]
struct Counter(AtomicU64);

impl ForceTerm for Counter {
    fn name(&self) -> &str {
        "test/counter"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        // Not periodic: no number of evaluations between two runs of a tick gives them the
        // same force.
        let n = self.0.fetch_add(1, Ordering::Relaxed);
        DVec3::new(0.0, 0.0, 1e-6 * n as f64)
    }
}

#[test]
fn a_term_with_hidden_mutable_state_is_caught_in_integrate() {
    let mut sync = sync_with(Counter::default());
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_eq!(m.found_by, SyncFoundBy::ReExecuted);
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 2: a wall-clock read inside a term.
#[derive(Debug)]
struct WallClock(std::time::Instant);

impl ForceTerm for WallClock {
    fn name(&self) -> &str {
        "test/wall-clock"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        let ns = self.0.elapsed().as_nanos() % 1000;
        DVec3::new(0.0, 0.0, 1e-3 * ns as f64)
    }
}

#[test]
fn a_wall_clock_read_is_caught_in_integrate() {
    let mut sync = sync_with(WallClock(std::time::Instant::now()));
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 3: random numbers drawn from a generator of the term's own, outside the world's.
#[derive(Debug)]
struct OwnRng(AtomicU64);

impl ForceTerm for OwnRng {
    fn name(&self) -> &str {
        "test/own-rng"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        // SplitMix64, stepped on every draw.
        let mut z = self
            .0
            .fetch_add(0x9e37_79b9_7f4a_7c15, Ordering::Relaxed)
            .wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        let u = (z ^ (z >> 31)) >> 11;
        DVec3::new(0.0, 0.0, 0.1 * (u as f64 / (1u64 << 53) as f64 - 0.5))
    }
}

#[test]
fn random_numbers_outside_the_worlds_generator_are_caught_in_integrate() {
    let mut sync = sync_with(OwnRng(AtomicU64::new(7)));
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 4: hash-map iteration order: a sum over a map built per evaluation (each `HashMap::new`
/// draws new keys, so the order differs), of values whose sum depends on the order.
#[derive(Debug)]
struct MapOrder;

impl ForceTerm for MapOrder {
    fn name(&self) -> &str {
        "test/map-order"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        let values = [1e16, 1.0, -1e16, 3.0, 0.5, 7.0, -2.5, 1e-3, 2e15, -2e15];
        let map: HashMap<usize, f64> = values.iter().copied().enumerate().collect();
        let sum: f64 = map.values().sum();
        DVec3::new(0.0, 0.0, 1e-3 * sum)
    }
}

#[test]
fn hash_map_iteration_order_is_caught_in_integrate() {
    let mut sync = sync_with(MapOrder);
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// A term that pushes nothing, for the faults outside the terms.
#[derive(Debug)]
struct Quiet;

impl ForceTerm for Quiet {
    fn name(&self) -> &str {
        "test/quiet"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, _: &ForceInput) -> DVec3 {
        DVec3::ZERO
    }
}

/// Class 5: a restore that drops a column: the game's restore puts everything back but the
/// momenta's z, which keeps the world's value from before the restore.
#[test]
fn a_restore_that_drops_a_column_is_caught_in_restore_naming_the_column() {
    let sync = sync_with(Quiet).with_restore(|world, saved| {
        if saved.tick + u64::from(K) < FROM + 1 {
            return world.restore(saved);
        }
        let mut kept = saved.clone();
        kept.bodies.mv.z = world.state().bodies.mv.z.clone();
        world.restore(&kept)
    });
    let mut sync = sync;
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "restore");
    assert_fields(&m, &["mV.z"]);
    assert!(m.report(None).contains("saved"), "{}", m.report(None));
}

/// Values whose sum rounds differently in every grouping below (checked by the test).
fn parallel_values() -> Vec<f64> {
    (0..64)
        .map(|k| 0.1 * f64::from(k + 1) + 1e-3 / f64::from(k + 3))
        .collect()
}

/// A sum split into one chunk per thread of the current rayon pool, the partial sums added
/// in order: a parallel reduction whose grouping follows the thread count.
fn chunked_sum(values: &[f64], threads: usize) -> f64 {
    let size = values.len().div_ceil(threads.max(1));
    values.chunks(size).map(|c| c.iter().sum::<f64>()).sum()
}

/// Class 6: a parallel sum whose order depends on the thread count.
#[derive(Debug)]
struct ParallelSum(Vec<f64>);

impl ForceTerm for ParallelSum {
    fn name(&self) -> &str {
        "test/parallel-sum"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        let sum = chunked_sum(&self.0, rayon::current_num_threads());
        DVec3::new(0.0, 0.0, 1e3 * (sum - 208.0))
    }
}

/// A one-thread pool for the first run (the re-runs get three).
fn one_thread() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool")
}

#[test]
fn a_parallel_sum_that_follows_the_thread_count_is_caught_in_integrate() {
    let values = parallel_values();
    assert_ne!(
        chunked_sum(&values, 1),
        chunked_sum(&values, 3),
        "the data must show it"
    );
    let pool = one_thread();
    let (at, m) = pool.install(|| {
        let mut sync = sync_with(ParallelSum(values))
            .with_rerun_threads(3)
            .expect("three threads");
        caught(&mut sync)
    });
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 7: a fused multiply-add path: the term's multi-threaded path fuses `a * b + c`, its
/// one-thread path does not. With these values the product rounds to 1 unfused (the sum is
/// 0) while the fused result keeps -2^-60.
#[derive(Debug)]
struct FusedPath;

impl ForceTerm for FusedPath {
    fn name(&self) -> &str {
        "test/fused"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        let (a, b, c) = (1.0 + 2f64.powi(-30), 1.0 - 2f64.powi(-30), -1.0);
        let r = if rayon::current_num_threads() > 1 {
            a.mul_add(b, c)
        } else {
            a * b + c
        };
        DVec3::new(0.0, 0.0, 1e15 * r)
    }
}

#[test]
fn a_fused_multiply_add_path_is_caught_in_integrate() {
    let pool = one_thread();
    let (at, m) = pool.install(|| {
        let mut sync = sync_with(FusedPath)
            .with_rerun_threads(3)
            .expect("three threads");
        caught(&mut sync)
    });
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 8: a command applied mid-tick, by the first run only (live input applied between the
/// integrate and contacts stages; a re-run applies the recorded commands at the boundary).
#[test]
fn a_command_applied_mid_tick_is_caught_after_the_stage_it_followed() {
    let once = AtomicBool::new(false);
    let mut sync = sync_with(Quiet).with_stage_hook(move |stage, world| {
        if stage == (TickStage::Integrate { substep: 0 })
            && world.tick() == FROM
            && !once.swap(true, Ordering::Relaxed)
        {
            let off = Command::SetForce {
                kind: ForceKind::LinearDrag,
                enabled: false,
            };
            world.apply(&off).expect("linear drag is declared");
        }
    });
    let (at, m) = caught(&mut sync);
    assert_eq!(at, FROM + 1);
    assert_eq!(m.tick, FROM + 1, "{}", m.report(None));
    assert_stage(&m, "integrate");
    assert_eq!(m.found_by, SyncFoundBy::StageHashes);
    let first = m.fields.first().expect("a field differs");
    assert_eq!(
        (first.body, first.field.as_str()),
        (None, "force LinearDrag")
    );
}

/// Class 9: a scratch buffer reused across ticks without being cleared: each evaluation adds into
/// what the last one left.
#[derive(Debug, Default)]
struct StaleScratch(Mutex<Vec<f64>>);

impl ForceTerm for StaleScratch {
    fn name(&self) -> &str {
        "test/stale-scratch"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        if !acting(i.t) {
            return DVec3::ZERO;
        }
        let mut scratch = self.0.lock().expect("not poisoned");
        scratch.resize(4, 0.0);
        // Meant as `=`: the buffer is never reset.
        scratch[0] += i.p.z;
        DVec3::new(0.0, 0.0, 1e-3 * scratch[0])
    }
}

#[test]
fn a_stale_scratch_buffer_is_caught_in_integrate() {
    let mut sync = sync_with(StaleScratch::default());
    let (at, m) = caught(&mut sync);
    assert_in_time(at);
    assert_stage(&m, "integrate");
    assert_fields(&m, &["p.z", "mV.z"]);
}

/// Class 10: state outside the world that the game changes between frames (a setting read by a
/// term, changed directly instead of through a command): the first run saw the old value,
/// every later run sees the new one.
static WIND: AtomicU64 = AtomicU64::new(0);

#[derive(Debug)]
struct GlobalWind;

impl ForceTerm for GlobalWind {
    fn name(&self) -> &str {
        "test/global-wind"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, _: &ForceInput) -> DVec3 {
        DVec3::new(0.0, 0.0, f64::from_bits(WIND.load(Ordering::Relaxed)))
    }
}

#[test]
fn state_outside_the_world_is_caught_with_stage_hashes_and_named_as_the_first_runs() {
    WIND.store(0.0f64.to_bits(), Ordering::Relaxed);
    let mut sync = sync_with(GlobalWind).with_stage_hashes(true);
    let (at, m) = caught_with(&mut sync, |tick| {
        if tick == FROM {
            WIND.store(0.25f64.to_bits(), Ordering::Relaxed);
        }
    });
    // The check after the change re-runs ticks the first run ran with the old value.
    assert_eq!(at, FROM + 1, "{}", m.report(None));
    assert_eq!(m.tick, FROM + 2 - u64::from(K), "{}", m.report(None));
    assert_stage(&m, "integrate");
    assert_eq!(m.found_by, SyncFoundBy::StageHashes);
    assert_fields(&m, &["p.z", "mV.z"]);
}

#[test]
fn state_outside_the_world_without_stage_hashes_is_named_a_first_run_alone() {
    static OUTSIDE: AtomicU64 = AtomicU64::new(0);
    #[derive(Debug)]
    struct Setting;
    impl ForceTerm for Setting {
        fn name(&self) -> &str {
            "test/setting"
        }
        fn version(&self) -> u32 {
            1
        }
        fn force(&self, _: &ForceInput) -> DVec3 {
            DVec3::new(0.0, 0.0, f64::from_bits(OUTSIDE.load(Ordering::Relaxed)))
        }
    }
    let mut sync = sync_with(Setting);
    let (at, m) = caught_with(&mut sync, |tick| {
        if tick == FROM {
            OUTSIDE.store(0.25f64.to_bits(), Ordering::Relaxed);
        }
    });
    assert_eq!(at, FROM + 1);
    assert_eq!(m.found_by, SyncFoundBy::FirstRunAlone, "{}", m.report(None));
    assert_eq!(m.stage, None);
    assert_fields(&m, &["p.z", "mV.z"]);
    assert!(m.report(None).contains("--stage-hashes"));
}

/// Class 11: hidden state reached only by the contact solver: a counter bumped by evaluations off
/// the tick grid, which only the search for a bounce's time makes (semi-implicit Euler
/// evaluates at the step's start alone).
#[derive(Debug, Default)]
struct OffGrid(AtomicU64);

impl ForceTerm for OffGrid {
    fn name(&self) -> &str {
        "test/off-grid"
    }
    fn version(&self) -> u32 {
        1
    }
    fn force(&self, i: &ForceInput) -> DVec3 {
        let on_grid = ((i.t / H).round() * H - i.t).abs() < 1e-9;
        if on_grid || !acting(i.t) {
            return DVec3::ZERO;
        }
        let n = self.0.fetch_add(1, Ordering::Relaxed);
        DVec3::new(0.0, 0.0, 1e-4 * n as f64)
    }
}

#[test]
fn hidden_state_reached_by_the_contact_search_alone_is_caught_in_contacts() {
    let mut sync = sync_with(OffGrid::default());
    // The first tick after FROM whose step resolves a bounce (an event), stepped plainly.
    let mut plain = sync.world().clone();
    let bounce = loop {
        plain.step().expect("the scene steps");
        if plain.tick() > FROM && !plain.events().is_empty() {
            break plain.tick();
        }
    };
    let (at, m) = caught(&mut sync);
    assert_eq!((at, m.tick), (bounce, bounce), "{}", m.report(None));
    assert_stage(&m, "contacts");
    assert!(
        m.fields.iter().all(|d| d.body.is_some()),
        "{}",
        m.report(None)
    );
    assert!(
        m.fields.iter().any(|d| d.field == "mV.z"),
        "{}",
        m.report(None)
    );
    // The integrate stage agreed: the stage list shows it before the difference.
    let integrate = m
        .stages
        .iter()
        .find(|s| s.stage.name() == "integrate")
        .expect("the stages were hashed");
    assert_eq!(integrate.first, integrate.rerun);
}

/// Class 12: a command the first run applied outside the recorded commands (input that bypasses
/// the session): a body fired by the first run alone.
#[test]
fn an_unrecorded_command_is_caught_in_commands() {
    let once = AtomicBool::new(false);
    let mut sync = sync_with(Quiet).with_stage_hook(move |stage, world| {
        if stage == TickStage::Commands
            && world.tick() == FROM
            && !once.swap(true, Ordering::Relaxed)
        {
            world.apply(&Command::Fire).expect("room for a body");
        }
    });
    let (at, m) = caught(&mut sync);
    assert_eq!(at, FROM + 1);
    assert_stage(&m, "commands");
    let names: Vec<_> = m.fields.iter().map(|d| d.field.as_str()).collect();
    assert!(
        names.contains(&"next_id") && names.contains(&"body"),
        "{}",
        m.report(None)
    );
}
