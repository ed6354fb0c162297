//! Per-tick costs of the loop: the seed scene and the state hash (recording: [`crate::record`]).

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput};
use volley::hash::state_hash;
use volley::{Integrator, SimLoop, World};

use crate::scenes::{self, BenchScene};
use crate::{SIZES, sized};

/// Ticks of the seed scene's own run (t = 5.0 to 10.4 s).
pub const SEED_TICKS: u64 = 27;

/// Ticks run before the steady-state measurement, long after the projectile came to rest.
const SETTLE_TICKS: u64 = 1_000;

/// Benchmarks `seed/flight` (the scene's own 27 ticks from a fresh world, per tick) and
/// `seed/tick` (one tick of the long run, the body resting on the ground, as in the 1e6-tick
/// end-to-end run), both through [`SimLoop::frame`] with the scene's default guard.
pub fn bench_seed(c: &mut Criterion) {
    let scene = scenes::seed();
    let dt = scene.timestep();
    let mut group = c.benchmark_group("seed");
    sized(&mut group, 1);
    group.throughput(Throughput::Elements(SEED_TICKS));
    let fresh = World::new(&scene);
    group.bench_function("flight", |b| {
        b.iter_batched(
            || SimLoop::new(fresh.clone()),
            |mut sim| {
                for _ in 0..SEED_TICKS {
                    sim.frame(dt, &mut ()).expect("the seed scene runs");
                }
                sim
            },
            BatchSize::SmallInput,
        )
    });
    group.throughput(Throughput::Elements(1));
    let mut sim = SimLoop::new(World::new(&scene));
    for _ in 0..SETTLE_TICKS {
        sim.frame(dt, &mut ()).expect("the seed scene runs");
    }
    group.bench_function("tick", |b| {
        b.iter(|| sim.frame(dt, &mut ()).expect("the seed scene runs"))
    });
    group.finish();
}

/// Bytes the canonical hash reads per body: id and eight f64 fields.
pub const HASH_BYTES_PER_BODY: u64 = 72;

/// Benchmarks `hash/state/N`: [`state_hash`] of a world of N bodies.
pub fn bench_hash(c: &mut Criterion) {
    let mut group = c.benchmark_group("hash");
    for n in SIZES {
        sized(&mut group, n);
        group.throughput(Throughput::Elements(n));
        let mut world = None;
        group.bench_function(BenchmarkId::new("state", n), |b| {
            let world = world
                .get_or_insert_with(|| BenchScene::Gravity.world(n, Integrator::ExplicitEuler, 1));
            b.iter(|| state_hash(black_box(&*world)))
        });
    }
    group.finish();
}
