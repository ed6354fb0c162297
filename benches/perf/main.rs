//! Volley's performance benchmarks, side by side with what they are judged against.
//!
//! One run measures, with criterion:
//! - `reference`: a plain structure-of-arrays explicit-Euler gravity loop written here, the
//!   yardstick for "a scene pays only for what it declares";
//! - `bandwidth`: a STREAM-triad-like loop on one and two threads, the memory limit;
//! - `step-gravity`, `step-drag`: [`volley::World::step`] for every integrator at N = 1, 1e3,
//!   1e5 and 1e6 bodies on the bench scenes (`assets/scenes/bench/`: no contacts, guard off);
//! - `parallel`: the same step at N = 1e6 on one and two threads;
//! - `batched`: 64 ticks in one `World::step_ticks` at N = 1e6, on one and two threads;
//! - `seed`: the seed scene through [`volley::SimLoop`], per tick;
//! - `hash`: the canonical state hash;
//! - `record`: a tick with and without a [`volley::replay::Recorder`], in memory and into a
//!   file, hashing every tick, every 10th and every 100th ([`record`]);
//! - `peer` (with `--features peer`): rapier3d-f64 stepping free bodies at the same dt.
//!
//! After criterion, the run times `volley headless seed --ticks 1000000 --no-table` as a process
//! and `volley record` of the same ticks beside it ([`e2e`]), times the comparisons the issue
//! sets goals for once more interleaved ([`paired`], [`record::paired`]), and prints every ratio
//! computed from this run's numbers ([`report`]). With
//! `VOLLEY_BENCH_WRITE=BENCHMARKS.md` it also rewrites the generated block of that file;
//! `scripts/bench` does exactly that.

use std::time::{Duration, SystemTime};

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion};

mod e2e;
mod machine;
mod paired;
#[cfg(feature = "peer")]
mod peer;
mod record;
mod reference;
mod report;
mod scenes;
#[path = "../common/splice.rs"]
mod splice;
mod step;
mod tables;
mod tick;

/// Body counts of the throughput benchmarks.
pub const SIZES: [u64; 4] = [1, 1_000, 100_000, 1_000_000];

/// Sampling for a benchmark whose iteration steps `n` bodies: large worlds take fewer, longer
/// samples so a run stays within a few minutes.
pub fn sized(group: &mut BenchmarkGroup<'_, WallTime>, n: u64) {
    if n >= 100_000 {
        group
            .sample_size(20)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(3));
    } else {
        group
            .sample_size(40)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_millis(1500));
    }
}

/// The font criterion's plots are drawn with. The crate's `plotters` renders text with
/// `ab_glyph` (for `volley study`'s plots), which finds no system fonts: a family must be
/// registered, or criterion's first plot panics.
static PLOT_FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

fn main() {
    use plotters::style::FontStyle;
    for style in [FontStyle::Normal, FontStyle::Bold] {
        if plotters::style::register_font("sans-serif", style, PLOT_FONT).is_err() {
            eprintln!("cannot load the plot font: criterion's plots may fail");
        }
    }
    let started = SystemTime::now();
    let load_before = report::load_average();
    let dir = report::output_dir();
    let mut c = Criterion::default()
        .output_directory(&dir)
        .configure_from_args();
    reference::bench(&mut c);
    step::bench(&mut c);
    step::bench_parallel(&mut c);
    step::bench_batched(&mut c);
    tick::bench_seed(&mut c);
    tick::bench_hash(&mut c);
    record::bench(&mut c);
    #[cfg(feature = "peer")]
    peer::bench(&mut c);
    c.final_summary();
    // `cargo bench` passes `--bench`; `cargo test --benches` runs each benchmark once without it,
    // and then there is nothing worth reporting. A filter (a bare argument) measures a subset:
    // the report shows what it has and the end-to-end run is left out.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let profiling = args.iter().any(|a| a == "--profile-time");
    if args.iter().any(|a| a == "--bench") && !profiling {
        let filtered = args
            .iter()
            .any(|a| !a.starts_with('-') && a.parse::<f64>().is_err());
        let e2e = (!filtered).then(|| e2e::measure(&dir));
        let pairs = if filtered {
            Vec::new()
        } else {
            #[cfg(feature = "peer")]
            let peer_pairs = peer::paired();
            #[cfg(not(feature = "peer"))]
            let peer_pairs = Vec::new();
            paired::all()
                .into_iter()
                .chain(record::paired())
                .chain(peer_pairs)
                .collect()
        };
        report::run(&dir, started, load_before, e2e, &pairs);
    }
}
