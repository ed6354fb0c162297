//! Paired ratios: the comparisons the issue sets goals for, timed interleaved.
//!
//! Criterion measures one benchmark after another, a few seconds each, so a compile starting on
//! the shared machine between two of them moves their ratio. Here the two sides of a comparison
//! alternate within each round (A then B, then B then A), for [`ROUNDS`] rounds of a few
//! milliseconds each. Another process can only add time to a round (by taking the core or the
//! memory bandwidth), so the headline is the ratio of each side's best round; the median of the
//! per-round ratios is given beside it, and the two agree when the machine was quiet.

use std::hint::black_box;
use std::time::Instant;

use volley::Integrator;

use crate::reference::{REFERENCE_DRAM_N, Soa, TRIAD_LEN};
use crate::scenes::BenchScene;
use crate::step::{BATCH_TICKS, PARALLEL_CASES, PARALLEL_N, parallel_name};

/// Rounds per comparison (odd, so the median is one of them).
pub const ROUNDS: usize = 101;

/// Shortest timed stretch of one side in a round (ns): long enough for the timer, short enough
/// for many rounds.
const MIN_STRETCH_NS: f64 = 3e6;

/// One paired comparison.
#[derive(Clone, Debug)]
pub struct Pair {
    /// What is compared, as the report names it.
    pub name: String,
    /// Best time of A over best time of B: B's throughput relative to A's.
    pub ratio: f64,
    /// Median over rounds of time(A) / time(B).
    pub median: f64,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn timed(k: usize, f: &mut impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..k {
        f();
    }
    start.elapsed().as_nanos() as f64 / k as f64
}

/// Times `a` and `b` interleaved over [`ROUNDS`] rounds.
pub fn compare(name: &str, mut a: impl FnMut(), mut b: impl FnMut()) -> Pair {
    for _ in 0..3 {
        a();
        b();
    }
    // Each side repeats enough calls to fill its stretch, so one cold first call (after the other
    // side evicted its data from the caches) does not decide its time.
    let reps = |once: f64| (MIN_STRETCH_NS / once.max(1.0)).ceil() as usize;
    let (ka, kb) = (reps(timed(1, &mut a)), reps(timed(1, &mut b)));
    let (mut best_a, mut best_b, mut ratios) = (f64::INFINITY, f64::INFINITY, Vec::new());
    for round in 0..ROUNDS {
        let (x, y) = if round % 2 == 0 {
            let x = timed(ka, &mut a);
            (x, timed(kb, &mut b))
        } else {
            let y = timed(kb, &mut b);
            (timed(ka, &mut a), y)
        };
        best_a = best_a.min(x);
        best_b = best_b.min(y);
        ratios.push(x / y);
    }
    Pair {
        name: name.to_string(),
        ratio: best_a / best_b,
        median: median(&mut ratios),
    }
}

/// Name of the reference-against-Volley pair at `n` bodies.
pub fn reference_name(n: u64) -> String {
    format!("reference-vs-volley/{n}")
}

/// Name of the pair of the reference at [`REFERENCE_DRAM_N`] bodies against Volley at 1e6,
/// per body-step.
pub const REFERENCE_DRAM: &str = "reference-dram-vs-volley/1000000";

/// Name of the one-against-two-threads pair of a parallel case.
pub fn threads_name(case: &str) -> String {
    format!("threads/{case}")
}

/// Name of the one-against-two-threads pair of a parallel case, batched.
pub fn batched_threads_name(case: &str) -> String {
    format!("batched-threads/{case}")
}

/// Name of the pair of the reference (per tick) against Volley's batched step, one thread,
/// explicit Euler on gravity at 1e6 bodies, per body-step.
pub const REFERENCE_BATCHED: &str = "reference-vs-volley-batched/1000000";

/// Name of the triad's one-against-two-threads pair.
pub const TRIAD_THREADS: &str = "threads/triad";

fn step(world: &mut volley::World) {
    world.step().expect("the bench scenes do not diverge");
}

fn step_batch(world: &mut volley::World) {
    world
        .step_ticks(BATCH_TICKS)
        .expect("the bench scenes do not diverge");
}

/// Every paired comparison the report uses.
pub fn all() -> Vec<Pair> {
    let mut out = Vec::new();
    for n in [100_000u64, 1_000_000] {
        let mut soa = Soa::new(n as usize);
        let mut world = BenchScene::Gravity.world(n, Integrator::ExplicitEuler, 1);
        let (h, g) = (black_box(0.016_666_667), black_box([0.0, 0.0, -9.81]));
        out.push(compare(
            &reference_name(n),
            || soa.step(h, g),
            || step(&mut world),
        ));
    }
    {
        let mut soa = Soa::new(REFERENCE_DRAM_N as usize);
        let mut world = BenchScene::Gravity.world(1_000_000, Integrator::ExplicitEuler, 1);
        let (h, g) = (black_box(0.016_666_667), black_box([0.0, 0.0, -9.81]));
        let mut pair = compare(REFERENCE_DRAM, || soa.step(h, g), || step(&mut world));
        // Per body-step: the reference side steps REFERENCE_DRAM_N bodies per call.
        let per_body = 1e6 / REFERENCE_DRAM_N as f64;
        pair.ratio *= per_body;
        pair.median *= per_body;
        out.push(pair);
    }
    for (scene, integrator) in PARALLEL_CASES {
        let mut one = scene.world(PARALLEL_N, integrator, 1);
        let mut two = scene.world(PARALLEL_N, integrator, 2);
        let name = threads_name(&parallel_name(scene, integrator));
        out.push(compare(&name, || step(&mut one), || step(&mut two)));
    }
    // The closed form under drag is left out: a batch of it takes over a second, and it is
    // bound by arithmetic either way (criterion's rows show it).
    for (scene, integrator) in PARALLEL_CASES {
        if integrator == Integrator::Exact {
            continue;
        }
        let mut one = scene.world(PARALLEL_N, integrator, 1);
        let mut two = scene.world(PARALLEL_N, integrator, 2);
        let name = batched_threads_name(&parallel_name(scene, integrator));
        out.push(compare(
            &name,
            || step_batch(&mut one),
            || step_batch(&mut two),
        ));
    }
    {
        let mut soa = Soa::new(PARALLEL_N as usize);
        let mut world = BenchScene::Gravity.world(PARALLEL_N, Integrator::ExplicitEuler, 1);
        let (h, g) = (black_box(0.016_666_667), black_box([0.0, 0.0, -9.81]));
        let mut pair = compare(
            REFERENCE_BATCHED,
            || soa.step(h, g),
            || step_batch(&mut world),
        );
        // Per body-step: the Volley side runs BATCH_TICKS ticks per call.
        pair.ratio *= BATCH_TICKS as f64;
        pair.median *= BATCH_TICKS as f64;
        out.push(pair);
    }
    let mut a = vec![0.5; TRIAD_LEN];
    let (b, c) = (vec![1.0; TRIAD_LEN], vec![2.0; TRIAD_LEN]);
    let mut a2 = a.clone();
    out.push(compare(
        TRIAD_THREADS,
        || crate::reference::triad(&mut a, &b, &c, black_box(0.5), 1),
        || crate::reference::triad(&mut a2, &b, &c, black_box(0.5), 2),
    ));
    out
}
