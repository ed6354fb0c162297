//! No allocation per tick after warm-up: a counting global allocator watches `SimLoop::frame`,
//! with and without a recorder, and a sync test's ticks (`SyncTest::advance`).
//!
//! The allocator counts only on threads that opted in (a thread-local pointer to a per-test
//! counter), so the test harness's own threads and other tests running at the same time are not
//! counted. Each measurement runs inside its own two-thread rayon pool whose workers opt in, so
//! the chunks stepped on the other worker are counted too.
//!
//! Buffers (events, per-chunk event lists, the Verlet force carry, the declared events' search
//! and due bodies, kept per thread) grow to the largest tick they have seen and are reused. The warm-up covers the first tick with the most events of these
//! scenes (every body is identical, so a tick has no events or one per body), after which no
//! tick may allocate.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use volley_sim::internals::replay::{FlushPolicy, RecordOptions, Recorder};
use volley_sim::internals::scene::{self, Scene};
use volley_sim::internals::step::PARALLEL_MIN_CHUNK;
use volley_sim::{Integrator, SimLoop, World};

struct Counting;

thread_local! {
    static COUNTER: Cell<Option<&'static AtomicU64>> = const { Cell::new(None) };
}

fn count() {
    // `try_with`: a thread being torn down has no thread-locals left, and is not counted.
    let _ = COUNTER.try_with(|c| {
        if let Some(counter) = c.get() {
            counter.fetch_add(1, Ordering::Relaxed);
        }
    });
}

// SAFETY: every call is forwarded to the system allocator unchanged; counting has no effect on
// the memory handed out.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

const WARM_UP_TICKS: u64 = 45;
const MEASURED_TICKS: u64 = 60;

/// A two-thread pool whose workers count their allocations into the returned counter.
fn counting_pool() -> (&'static AtomicU64, rayon::ThreadPool) {
    let counter: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(0)));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .start_handler(move |_| COUNTER.with(|c| c.set(Some(counter))))
        .build()
        .expect("a two-thread pool");
    // Both workers have started (and opted in) once each has run a broadcast job.
    pool.broadcast(|_| ());
    (counter, pool)
}

/// Allocations made while `scene` runs ticks `WARM_UP_TICKS..WARM_UP_TICKS + MEASURED_TICKS`
/// on `threads` threads, one tick per frame; with `record`, a recorder started at tick 0 hashes
/// every tick and keeps a keyframe every 100 ticks (into `io::sink()`, no wall-clock flushes):
/// its run of hashes grows past anything the warm-up saw, to the keyframe at tick 100.
fn allocations_after_warm_up(scene: &Scene, threads: usize, record: bool) -> u64 {
    let (counter, pool) = counting_pool();
    pool.install(|| {
        let mut world = World::new(scene);
        world.set_threads(threads);
        let mut sim = SimLoop::new(world);
        let dt = scene.timestep();
        let options = RecordOptions {
            keyframe_every: 100,
            flush: FlushPolicy::OnFinish,
            ..RecordOptions::default()
        };
        let mut recorder = record.then(|| {
            Recorder::start(std::io::sink(), &sim.world, options).expect("a sink takes anything")
        });
        let mut tick = |sim: &mut SimLoop| {
            match recorder.as_mut() {
                Some(recorder) => sim.frame(dt, recorder),
                None => sim.frame(dt, &mut ()),
            }
            .expect("the test scenes run");
        };
        let mut events = 0;
        for _ in 0..WARM_UP_TICKS {
            tick(&mut sim);
        }
        let before = counter.load(Ordering::SeqCst);
        for _ in 0..MEASURED_TICKS {
            tick(&mut sim);
            events += sim.world.events().len();
        }
        let allocations = counter.load(Ordering::SeqCst) - before;
        assert!(events > 0, "the measured ticks must have events");
        allocations
    })
}

/// Identical bodies thrown straight up from the ground (so each tick has no events or one per
/// body): they bounce on the ground every 2.05 s (41 ticks of 0.1 s, impacts mid-tick) and pass
/// through a target at 2.36 m on the way up and down; a wall stands beside them. Gravity alone
/// runs the constant-field model; with `drag` every integrator takes its velocity-dependent path.
fn bouncing(bodies: u32, integrator: Integrator, drag: bool) -> Scene {
    let forces = if drag {
        "Gravity((0.0, 0.0, -9.81)), LinearDrag(0.001)"
    } else {
        "Gravity((0.0, 0.0, -9.81))"
    };
    let text = format!(
        "Scene(dt: 0.1, integrator: ExplicitEuler, forces: [{forces}],
               ground: (height: 0.0, restitution: 1.0),
               walls: [(point: (5.0, 0.0, 0.0), normal: (1.0, 0.0, 0.0), thickness: 0.1)],
               targets: [(center: (0.0, 0.0, 2.357), radius: 0.5)],
               launcher: (position: (0.0, 0.0, 0.1), speed: 10.05525, elevation_deg: 90.0,
                          azimuth_deg: 0.0, mass: 1.0, radius: 0.1),
               volley: (count: {bodies}))"
    );
    let mut scene = scene::parse(&text, "alloc.ron", "alloc").expect("the test scene is valid");
    scene
        .set_integrator(integrator)
        .expect("gravity and drag have closed forms");
    scene
}

#[test]
fn ticks_allocate_nothing_for_any_integrator_on_one_thread() {
    for drag in [false, true] {
        for integrator in Integrator::ALL {
            let scene = bouncing(64, integrator, drag);
            let n = allocations_after_warm_up(&scene, 1, false);
            assert_eq!(n, 0, "{integrator}, drag {drag}");
        }
    }
}

#[test]
fn ticks_allocate_nothing_for_any_integrator_on_two_threads() {
    // Enough bodies for two chunks.
    let bodies = 2 * PARALLEL_MIN_CHUNK as u32 + 3;
    for integrator in Integrator::ALL {
        let scene = bouncing(bodies, integrator, true);
        let n = allocations_after_warm_up(&scene, 2, false);
        assert_eq!(n, 0, "{integrator}");
    }
}

/// Identical bodies thrown straight up at 60 m/s under gravity alone, nothing to hit, with
/// declared events: the step keeps horizons and searches the due bodies after the vectorised
/// loop. The warm-up sees crossings of an altitude (tick 5) and a speed (tick 31); the measured
/// ticks see another altitude up (tick 48) and down (tick 75), the apex (tick 62) and the speed
/// again (tick 92).
fn thrown_up_with_events(bodies: u32) -> Scene {
    let text = format!(
        "Scene(dt: 0.1, integrator: Rk4, forces: [Gravity((0.0, 0.0, -9.81))],
               launcher: (position: (0.0, 0.0, 0.1), speed: 60.0, elevation_deg: 90.0,
                          azimuth_deg: 0.0, mass: 1.0, radius: 0.1),
               volley: (count: {bodies}),
               events: [(when: Altitude(20.0)), (when: Altitude(175.0)), (when: Apex),
                        (when: Speed(30.0))])"
    );
    scene::parse(&text, "alloc.ron", "alloc").expect("the test scene is valid")
}

#[test]
fn declared_events_with_horizons_allocate_nothing() {
    for (bodies, threads) in [(64, 1), (2 * PARALLEL_MIN_CHUNK as u32 + 3, 2)] {
        let n = allocations_after_warm_up(&thrown_up_with_events(bodies), threads, false);
        assert_eq!(n, 0, "{bodies} bodies on {threads} threads");
    }
}

#[test]
fn recording_every_tick_allocates_nothing() {
    // 64 bodies hash from one stack buffer, 200 stream in blocks; velocity Verlet's keyframes
    // carry its force.
    for bodies in [64, 200] {
        let scene = bouncing(bodies, Integrator::VelocityVerlet, true);
        let n = allocations_after_warm_up(&scene, 1, true);
        assert_eq!(n, 0, "{bodies} bodies");
    }
}

#[test]
fn the_counter_sees_an_allocation_inside_the_loop() {
    // The counting itself works: a tick that spawns a body (a command) allocates.
    let scene = bouncing(1, Integrator::ExplicitEuler, false);
    let counter: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(0)));
    COUNTER.with(|c| c.set(Some(counter)));
    let mut sim = SimLoop::new(World::new(&scene));
    sim.push(volley_sim::Command::Fire);
    sim.frame(Duration::from_millis(100), &mut ())
        .expect("the test scene runs");
    COUNTER.with(|c| c.set(None));
    assert!(counter.load(Ordering::SeqCst) > 0);
}

#[test]
fn batched_ticks_allocate_nothing_after_the_first_batch() {
    // `World::step_ticks` saves the state before each batch into a buffer that grows once.
    let bodies = 2 * PARALLEL_MIN_CHUNK as u32 + 3;
    let text = format!(
        "Scene(dt: 0.01, integrator: VelocityVerlet,
               forces: [Spring(anchor: (0.0, 0.0, 5.0), stiffness: 4.0)],
               launcher: (position: (0.0, 0.0, 1.0), speed: 10.0, elevation_deg: 60.0, azimuth_deg: 0.0),
               volley: (count: {bodies}, speed_spread: 2.0, angle_spread_deg: 10.0))"
    );
    let scene = scene::parse(&text, "alloc.ron", "alloc").expect("the test scene is valid");
    let (counter, pool) = counting_pool();
    let allocations = pool.install(|| {
        let mut world = World::new(&scene);
        world.set_threads(2);
        world.step_ticks(10).expect("the spring is stable");
        let before = counter.load(Ordering::SeqCst);
        world.step_ticks(70).expect("the spring is stable");
        counter.load(Ordering::SeqCst) - before
    });
    assert_eq!(allocations, 0);
}

/// Allocations of a sync test at K = 7 over the measured ticks after the warm-up (which fills
/// its ring of frames), on one thread; with `events`, the measured ticks must have some.
fn sync_test_allocations(scene: &Scene, events_needed: bool) -> u64 {
    let (counter, pool) = counting_pool();
    pool.install(|| {
        let mut sync = volley_sim::SyncTest::new(World::new(scene), 7).expect("7 is in range");
        for _ in 0..WARM_UP_TICKS {
            sync.advance(&[]).expect("the test scenes pass");
        }
        let before = counter.load(Ordering::SeqCst);
        let mut events = 0;
        for _ in 0..MEASURED_TICKS {
            sync.advance(&[]).expect("the test scenes pass");
            events += sync.world().events().len();
        }
        let allocations = counter.load(Ordering::SeqCst) - before;
        assert!(
            events > 0 || !events_needed,
            "the measured ticks must have events"
        );
        allocations
    })
}

#[test]
fn sync_test_ticks_allocate_nothing_for_any_integrator() {
    // Velocity Verlet and Forest-Ruth carry their force through the frames.
    for drag in [false, true] {
        for integrator in Integrator::ALL {
            let scene = bouncing(64, integrator, drag);
            assert_eq!(
                sync_test_allocations(&scene, true),
                0,
                "{integrator}, drag {drag}"
            );
        }
    }
}

#[test]
fn sync_test_ticks_of_a_burning_motor_allocate_nothing() {
    // The frames keep the masses while the motor burns.
    let scene = scene::bundled("model_rocket").expect("bundled scenes parse");
    assert_eq!(sync_test_allocations(&scene, false), 0);
}
