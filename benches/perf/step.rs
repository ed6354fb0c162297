//! `World::step` throughput: every integrator on both bench scenes, and on one and two threads.

use criterion::{BenchmarkId, Criterion, Throughput};
use volley::Integrator;

use crate::scenes::BenchScene;
use crate::{SIZES, sized};

/// Bodies in the parallel benchmark.
pub const PARALLEL_N: u64 = 1_000_000;

/// The (scene, integrator) pairs measured on one and two threads: the cheapest step and the
/// drag model's (both stream from memory at 1e6), the most arithmetic of the explicit methods,
/// and the closed form under drag (two `libm` calls per body: bound by arithmetic, not memory).
pub const PARALLEL_CASES: [(BenchScene, Integrator); 4] = [
    (BenchScene::Gravity, Integrator::ExplicitEuler),
    (BenchScene::Drag, Integrator::SemiImplicitEuler),
    (BenchScene::Drag, Integrator::Rk4),
    (BenchScene::Drag, Integrator::Exact),
];

/// Benchmarks `step-SCENE/INTEGRATOR/N`: one tick of the whole world, in body-steps.
pub fn bench(c: &mut Criterion) {
    for scene in BenchScene::ALL {
        let mut group = c.benchmark_group(format!("step-{}", scene.name()));
        for n in SIZES {
            sized(&mut group, n);
            group.throughput(Throughput::Elements(n));
            for integrator in Integrator::ALL {
                // Built on first use, so a filtered run does not build worlds it skips.
                let mut world = None;
                group.bench_function(BenchmarkId::new(integrator.name(), n), |b| {
                    let world = world.get_or_insert_with(|| scene.world(n, integrator, 1));
                    b.iter(|| world.step().expect("the bench scenes do not diverge"))
                });
            }
        }
        group.finish();
    }
}

/// The benchmark function name of a parallel case.
pub fn parallel_name(scene: BenchScene, integrator: Integrator) -> String {
    format!("{}-{}", scene.name(), integrator.name())
}

/// Ticks per iteration of the batched benchmark: one batch of [`volley::step::BATCH_MAX_TICKS`].
pub const BATCH_TICKS: u64 = volley::step::BATCH_MAX_TICKS;

/// Benchmarks `batched/SCENE-INTEGRATOR/THREADS`: [`BATCH_TICKS`] ticks in one
/// `World::step_ticks` at [`PARALLEL_N`] bodies, in body-steps (what `volley headless` and
/// `volley record` run between the ticks they observe).
pub fn bench_batched(c: &mut Criterion) {
    bench_threads(c, "batched", BATCH_TICKS, |world| {
        world
            .step_ticks(BATCH_TICKS)
            .expect("the bench scenes do not diverge")
    });
}

/// Benchmarks `parallel/SCENE-INTEGRATOR/THREADS` at [`PARALLEL_N`] bodies.
pub fn bench_parallel(c: &mut Criterion) {
    bench_threads(c, "parallel", 1, |world| {
        world.step().expect("the bench scenes do not diverge")
    });
}

/// Every parallel case on one and two threads at [`PARALLEL_N`] bodies, `run` advancing the
/// world by `ticks` ticks per iteration.
fn bench_threads(c: &mut Criterion, name: &str, ticks: u64, run: fn(&mut volley::World)) {
    let mut group = c.benchmark_group(name);
    sized(&mut group, PARALLEL_N * ticks);
    group.throughput(Throughput::Elements(PARALLEL_N * ticks));
    for (scene, integrator) in PARALLEL_CASES {
        for threads in [1usize, 2] {
            let mut world = None;
            let id = BenchmarkId::new(parallel_name(scene, integrator), threads);
            group.bench_function(id, |b| {
                let world =
                    world.get_or_insert_with(|| scene.world(PARALLEL_N, integrator, threads));
                b.iter(|| run(world))
            });
        }
    }
    group.finish();
}
