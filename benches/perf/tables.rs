//! The generated tables of BENCHMARKS.md, each from numbers measured in the same run.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::SystemTime;

use volley::Integrator;

use crate::e2e::E2e;
use crate::paired::{self, Pair, ROUNDS};
use crate::reference::{REFERENCE_DRAM_N, TRIAD_BYTES, TRIAD_LEN, TRIAD_MOVED};
use crate::scenes::BenchScene;
use crate::step::{BATCH_TICKS, PARALLEL_CASES, PARALLEL_N, parallel_name};
use crate::tick::{HASH_BYTES_PER_BODY, SEED_TICKS};
use crate::{SIZES, e2e, report};

/// Criterion's estimate of one iteration (ns) with its 95 % confidence interval.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// Point estimate (ns per iteration).
    pub ns: f64,
    /// Lower bound of the interval (ns).
    pub lower: f64,
    /// Upper bound of the interval (ns).
    pub upper: f64,
}

impl Estimate {
    /// Half-width of the interval relative to the estimate.
    fn spread(&self) -> f64 {
        0.5 * (self.upper - self.lower) / self.ns
    }
}

/// This run's estimates.
pub struct Results {
    /// Criterion's output directory.
    pub dir: PathBuf,
    /// Start of the run; older estimates are ignored.
    pub since: SystemTime,
    /// The interleaved comparisons.
    pub pairs: Vec<Pair>,
}

impl Results {
    pub fn pair(&self, name: &str) -> Option<&Pair> {
        self.pairs.iter().find(|p| p.name == name)
    }

    fn get(&self, id: &str) -> Option<Estimate> {
        report::read_estimate(&self.dir, id, self.since)
    }

    /// Nanoseconds per element of benchmark `id` that processes `n` elements per iteration.
    pub fn per(&self, id: &str, n: u64) -> Option<f64> {
        self.get(id).map(|e| e.ns / n as f64)
    }
}

/// Bytes one explicit-Euler gravity body-step of Volley moves at 1e6 bodies: reads p, mV (6 f64)
/// and m (a world that large recomputes 1/m, `step::STREAMING_MIN_BODIES`), writes p and mV back.
const VOLLEY_EULER_BYTES: f64 = 13.0 * 8.0;
/// Bytes one body-step of the reference kernel moves: reads and writes p and v (6 f64).
const REFERENCE_BYTES: f64 = 12.0 * 8.0;

/// `1.23`, `12.3`, `123`: three significant figures for times and rates.
pub fn sig(x: f64) -> String {
    match x.abs() {
        a if a < 10.0 => format!("{x:.2}"),
        a if a < 100.0 => format!("{x:.1}"),
        _ => format!("{x:.0}"),
    }
}

pub fn opt(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or_else(|| "-".into(), f)
}

pub fn size_name(n: u64) -> String {
    match n {
        1 => "1".into(),
        1_000 => "1e3".into(),
        100_000 => "1e5".into(),
        1_000_000 => "1e6".into(),
        4_000_000 => "4e6".into(),
        _ => n.to_string(),
    }
}

/// `0.93 (median 0.88)`: a paired ratio of best times, with the median of the rounds.
fn paired_cell(p: Option<&Pair>, suffix: &str) -> String {
    p.map_or_else(
        || "-".into(),
        |p| format!("{:.2}{suffix} (median {:.2}{suffix})", p.ratio, p.median),
    )
}

/// Writes every table; returns whether every number a complete report needs was there.
pub fn all(md: &mut String, r: &Results, e2e: Option<&Result<E2e, String>>) -> bool {
    let mut complete = reference(md, r);
    complete &= integrators(md, r);
    complete &= bandwidth(md, r);
    complete &= parallel(md, r);
    complete &= batched(md, r);
    complete &= seed(md, r, e2e);
    complete &= hashing(md, r);
    complete &= crate::record::table(md, r, e2e);
    complete &= peer(md, r);
    complete
}

fn reference(md: &mut String, r: &Results) -> bool {
    let level = volley::step::simd_level();
    let _ = writeln!(
        md,
        "\n### Reference kernel: Volley's full step against a hand-written loop\n"
    );
    let _ = writeln!(
        md,
        "Explicit Euler, gravity only, one thread. Reference: the plain SoA loop in \
         `benches/perf/reference.rs`, as `cargo build --release` compiles it (baseline x86-64, \
         SSE2), and the same loop compiled for the vector width Volley's kernel picked on this \
         CPU ({level:?}). Volley: `World::step` on `bench/gravity` (no contacts, guard off). \
         Ratios are throughputs, Volley / reference; the issue asks for at least 0.8 at 1e5 and \
         1e6 against the plain loop. `±` is criterion's 95 % interval. The paired column times \
         the plain loop and Volley interleaved ({ROUNDS} rounds) and gives the ratio of their \
         best rounds, with the median of the per-round ratios; the verdict uses it.\n"
    );
    let _ = writeln!(
        md,
        "| N | reference ns/body-step | reference, {level:?} build | Volley ns/body-step | Volley / reference | Volley / {level:?} reference | paired Volley / reference, best rounds | goal |\n|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let mut complete = true;
    for n in SIZES {
        let reference = r.get(&format!("reference/explicit-euler/{n}"));
        let widest = r.get(&format!("reference/explicit-euler-widest/{n}"));
        let volley = r.get(&format!("step-gravity/explicit-euler/{n}"));
        complete &= reference.is_some() && widest.is_some() && volley.is_some();
        let cell = |e: Option<Estimate>| match e {
            Some(e) => format!("{} ± {:.0} %", sig(e.ns / n as f64), 100.0 * e.spread()),
            None => "-".into(),
        };
        let ratio = |a: Option<Estimate>| a.zip(volley).map(|(a, b)| a.ns / b.ns);
        let pair = r.pair(&paired::reference_name(n));
        let verdict = pair.map(|p| p.ratio).or(ratio(reference));
        let goal = match (n >= 100_000, verdict) {
            (true, Some(x)) if x >= 0.8 => "≥ 0.8: met",
            (true, Some(_)) => "≥ 0.8: **missed**",
            _ => "",
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {goal} |",
            size_name(n),
            cell(reference),
            cell(widest),
            cell(volley),
            opt(ratio(reference), |x| format!("{x:.2}")),
            opt(ratio(widest), |x| format!("{x:.2}")),
            if n >= 100_000 {
                paired_cell(pair, "")
            } else {
                String::new()
            }
        );
    }
    let dram = r.per(
        &format!("reference/explicit-euler/{REFERENCE_DRAM_N}"),
        REFERENCE_DRAM_N,
    );
    let volley = r.per("step-gravity/explicit-euler/1000000", 1_000_000);
    let _ = writeln!(
        md,
        "| 1e6, against the reference at {} bodies (streaming from memory) | {} | | {} | {} | | {} | |",
        size_name(REFERENCE_DRAM_N),
        opt(dram, sig),
        opt(volley, sig),
        opt(dram.zip(volley).map(|(a, b)| a / b), |x| format!("{x:.2}")),
        paired_cell(r.pair(paired::REFERENCE_DRAM), "")
    );
    complete && dram.is_some()
}

fn integrators(md: &mut String, r: &Results) -> bool {
    let mut complete = true;
    for scene in BenchScene::ALL {
        let _ = writeln!(
            md,
            "\n### Every integrator, `bench/{}`: million body-steps per second (ns per body-step)\n",
            scene.name()
        );
        let _ = writeln!(
            md,
            "One thread, `World::step`. Last column: throughput relative to the reference kernel \
             at 1e6 bodies.\n"
        );
        let heads: Vec<String> = SIZES
            .iter()
            .map(|n| format!("N = {}", size_name(*n)))
            .collect();
        let _ = writeln!(
            md,
            "| integrator | {} | / reference at 1e6 |",
            heads.join(" | ")
        );
        let _ = writeln!(md, "|---|{}---:|", "---:|".repeat(SIZES.len()));
        let reference = r.per("reference/explicit-euler/1000000", 1_000_000);
        for integrator in Integrator::ALL {
            let cells: Vec<String> = SIZES
                .iter()
                .map(|&n| {
                    let per = r.per(&format!("step-{}/{integrator}/{n}", scene.name()), n);
                    complete &= per.is_some();
                    opt(per, |ns| format!("{} ({})", sig(1e3 / ns), sig(ns)))
                })
                .collect();
            let big = r.per(
                &format!("step-{}/{integrator}/1000000", scene.name()),
                1_000_000,
            );
            let ratio = reference.zip(big).map(|(a, b)| a / b);
            let _ = writeln!(
                md,
                "| {integrator} | {} | {} |",
                cells.join(" | "),
                opt(ratio, |x| format!("{x:.2}"))
            );
        }
    }
    complete
}

fn bandwidth(md: &mut String, r: &Results) -> bool {
    let _ = writeln!(md, "\n### Against the memory bandwidth limit\n");
    let _ = writeln!(
        md,
        "Triad `a = b + s c` over three arrays of {TRIAD_LEN} f64 (3 × 32 MiB). STREAM counts \
         {TRIAD_BYTES} bytes per element; the memory actually moves {TRIAD_MOVED} (the write \
         allocates its line first), and that is the figure to compare with in-place updates, \
         which need no write-allocate. At 1e6 bodies the step streams from memory: Volley's \
         explicit-Euler gravity step moves {VOLLEY_EULER_BYTES:.0} bytes per body (reads p, mV, \
         m, recomputing 1/m; writes p, mV back in place), the reference kernel {REFERENCE_BYTES:.0} (p and \
         v). Fractions near or above 1 mean the step runs at the memory's speed (the triad's \
         three streams and write-allocates are not the best case for the hardware prefetchers).\n"
    );
    let _ = writeln!(
        md,
        "| threads | triad GB/s (STREAM count) | triad GB/s moved | Volley GB/s at 1e6 | Volley / triad moved | reference GB/s at 1e6 | reference / triad moved |\n|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut complete = true;
    for threads in [1usize, 2] {
        let triad_ns = r.get(&format!("bandwidth/triad/{threads}")).map(|e| e.ns);
        let counted = triad_ns.map(|ns| (TRIAD_BYTES * TRIAD_LEN as u64) as f64 / ns);
        let moved = triad_ns.map(|ns| (TRIAD_MOVED * TRIAD_LEN as u64) as f64 / ns);
        let volley_id = if threads == 1 {
            "step-gravity/explicit-euler/1000000".to_string()
        } else {
            format!(
                "parallel/{}/2",
                parallel_name(BenchScene::Gravity, Integrator::ExplicitEuler)
            )
        };
        let volley = r
            .per(&volley_id, 1_000_000)
            .map(|ns| VOLLEY_EULER_BYTES / ns);
        let reference = (threads == 1)
            .then(|| r.per("reference/explicit-euler/1000000", 1_000_000))
            .flatten()
            .map(|ns| REFERENCE_BYTES / ns);
        complete &= triad_ns.is_some() && volley.is_some();
        let frac = |x: Option<f64>| opt(x.zip(moved).map(|(a, b)| a / b), |f| format!("{f:.2}"));
        let _ = writeln!(
            md,
            "| {threads} | {} | {} | {} | {} | {} | {} |",
            opt(counted, sig),
            opt(moved, sig),
            opt(volley, sig),
            frac(volley),
            opt(reference, sig),
            frac(reference)
        );
    }
    complete
}

/// The verdict on the 1.6× on 2 cores: from the paired ratio when there is one,
/// criterion's otherwise.
fn two_core_goal(pair: Option<&Pair>, speedup: Option<f64>) -> &'static str {
    match pair.map(|p| p.ratio).or(speedup) {
        Some(x) if x >= 1.6 => "≥ 1.6×: met",
        Some(_) => "≥ 1.6×: **missed**",
        None => "",
    }
}

/// The cells a one-against-two-threads row ends with, from `group/name/1` and `group/name/2`
/// at `per` body-steps each: both times, the speed-up, its paired measurement and the goal;
/// and whether both times were measured.
fn thread_cells(
    r: &Results,
    group: &str,
    name: &str,
    per: u64,
    pair: Option<&Pair>,
) -> (String, bool) {
    let one = r.per(&format!("{group}/{name}/1"), per);
    let two = r.per(&format!("{group}/{name}/2"), per);
    let speedup = one.zip(two).map(|(a, b)| a / b);
    let cells = format!(
        "{} | {} | {} | {} | {}",
        opt(one, sig),
        opt(two, sig),
        opt(speedup, |x| format!("{x:.2}×")),
        paired_cell(pair, "×"),
        two_core_goal(pair, speedup)
    );
    (cells, one.is_some() && two.is_some())
}

fn parallel(md: &mut String, r: &Results) -> bool {
    let _ = writeln!(md, "\n### Parallel stepping, N = 1e6\n");
    let _ = writeln!(
        md,
        "`World::set_threads`: contiguous chunks with `rayon::join`; the state is bit-identical \
         for every thread count (tests/parallel.rs). The issue asks for at least 1.6× on 2 cores. \
         A step that streams its bodies from memory cannot scale past the memory system, whose \
         1 → 2 thread scaling the triad row shows.\n"
    );
    let _ = writeln!(
        md,
        "| scene, integrator | 1 thread ns/body-step | 2 threads ns/body-step | speed-up | paired speed-up, best rounds | goal |\n|---|---:|---:|---:|---:|---|"
    );
    let mut complete = true;
    let triad = r
        .get("bandwidth/triad/1")
        .zip(r.get("bandwidth/triad/2"))
        .map(|(a, b)| a.ns / b.ns);
    let _ = writeln!(
        md,
        "| memory bound: the triad, 1 → 2 threads | | | {} | {} | |",
        opt(triad, |x| format!("{x:.2}×")),
        paired_cell(r.pair(paired::TRIAD_THREADS), "×")
    );
    for (scene, integrator) in PARALLEL_CASES {
        let name = parallel_name(scene, integrator);
        let pair = r.pair(&paired::threads_name(&name));
        let (cells, has) = thread_cells(r, "parallel", &name, PARALLEL_N, pair);
        complete &= has;
        let _ = writeln!(md, "| {}, {integrator} | {cells} |", scene.name());
    }
    complete
}

fn batched(md: &mut String, r: &Results) -> bool {
    let _ = writeln!(
        md,
        "\n### Batched stepping: ticks no observer needs, N = 1e6\n"
    );
    let _ = writeln!(
        md,
        "`World::step_ticks({BATCH_TICKS})`: a world without contacts runs each block of \
         {} bodies through all {BATCH_TICKS} ticks while it is in cache, so the state crosses \
         the memory bus once per batch instead of once per tick, with the same bits as \
         stepping tick by tick (tests/batch.rs). `volley headless` and `volley record` run \
         this way between the ticks they print or hash; with every tick observed (a window, \
         hashing every tick) the loop steps tick by tick as in the table above. Speed-ups on \
         2 cores are then bound by arithmetic, not memory.\n",
        volley::step::BATCH_BLOCK
    );
    let _ = writeln!(
        md,
        "| scene, integrator | tick by tick, 1 thread ns/body-step | batched, 1 thread | batched, 2 threads | speed-up | paired speed-up, best rounds | goal |\n|---|---:|---:|---:|---:|---:|---|"
    );
    let mut complete = true;
    let ticks = PARALLEL_N * BATCH_TICKS;
    for (scene, integrator) in PARALLEL_CASES {
        let name = parallel_name(scene, integrator);
        let per_tick = r.per(&format!("parallel/{name}/1"), PARALLEL_N);
        let pair = r.pair(&paired::batched_threads_name(&name));
        let (cells, has) = thread_cells(r, "batched", &name, ticks, pair);
        complete &= has;
        let _ = writeln!(
            md,
            "| {}, {integrator} | {} | {cells} |",
            scene.name(),
            opt(per_tick, sig)
        );
    }
    let reference = r.per("reference/explicit-euler/1000000", PARALLEL_N);
    let gravity = parallel_name(BenchScene::Gravity, Integrator::ExplicitEuler);
    let one = r.per(&format!("batched/{gravity}/1"), ticks);
    let _ = writeln!(
        md,
        "\nAgainst the reference kernel (the plain loop, one tick per pass over the bodies): \
         Volley batched, gravity, explicit Euler, one thread, {} ns/body-step against {} ns: \
         {} the reference's throughput; paired {}. A hand-written loop blocked the same way \
         would gain as much; the issue's yardstick is the plain loop.",
        opt(one, sig),
        opt(reference, sig),
        opt(reference.zip(one).map(|(a, b)| a / b), |x| format!(
            "{x:.2}×"
        )),
        paired_cell(r.pair(paired::REFERENCE_BATCHED), "×")
    );
    complete
}

fn seed(md: &mut String, r: &Results, e2e: Option<&Result<E2e, String>>) -> bool {
    let _ = writeln!(md, "\n### The seed scene, per tick and end to end\n");
    let flight = r.per("seed/flight", SEED_TICKS);
    let tick = r.get("seed/tick").map(|e| e.ns);
    let _ = writeln!(md, "| measurement | result |\n|---|---:|");
    let _ = writeln!(
        md,
        "| `SimLoop::frame`, the scene's own {SEED_TICKS} ticks from a fresh world | {} ns/tick |",
        opt(flight, sig)
    );
    let _ = writeln!(
        md,
        "| `SimLoop::frame`, one tick of the long run (body at rest on the ground) | {} ns/tick |",
        opt(tick, sig)
    );
    let command = format!("volley {}", e2e::ARGS.join(" "));
    let complete = match e2e {
        Some(Ok(e)) => {
            let _ = writeln!(
                md,
                "| `{command}`: process CPU time (user + system), median of {} (min) | {:.3} s ({:.3} s); goal ≤ 0.1 s: {} |",
                e.cpu.len(),
                e.cpu_median(),
                e.cpu[0],
                if e.cpu_median() <= 0.1 {
                    "met"
                } else {
                    "**missed**"
                }
            );
            let _ = writeln!(
                md,
                "| the same, wall clock, median | {:.3} s |\n| the same, lines printed | {} |",
                e.wall_median(),
                e.lines
            );
            let _ = writeln!(md, "\nIts last line: `{}`", e.summary);
            true
        }
        Some(Err(why)) => {
            let _ = writeln!(md, "| `{command}` | not measured: {why} |");
            false
        }
        None => false,
    };
    complete && flight.is_some() && tick.is_some()
}

fn hashing(md: &mut String, r: &Results) -> bool {
    let _ = writeln!(md, "\n### The canonical state hash (XXH3-64)\n");
    let _ = writeln!(
        md,
        "| N | ns/body | GB/s ({HASH_BYTES_PER_BODY} bytes/body) |\n|---:|---:|---:|"
    );
    let mut complete = true;
    for n in SIZES {
        let per = r.per(&format!("hash/state/{n}"), n);
        complete &= per.is_some();
        let _ = writeln!(
            md,
            "| {} | {} | {} |",
            size_name(n),
            opt(per, sig),
            opt(per, |ns| sig(HASH_BYTES_PER_BODY as f64 / ns))
        );
    }
    complete
}

#[cfg(not(feature = "peer"))]
fn peer(md: &mut String, _: &Results) -> bool {
    let _ = writeln!(
        md,
        "\n### Peer\n\nNot measured: run with `--features peer`."
    );
    false
}

#[cfg(feature = "peer")]
fn peer(md: &mut String, r: &Results) -> bool {
    crate::peer::table(md, r)
}
