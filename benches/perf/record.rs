//! Recording overhead: a tick of [`SimLoop::frame`] with and without a [`Recorder`], per tick
//! with criterion and paired, interleaved, for the 5 % budget; the end-to-end runs are
//! in [`crate::e2e`].
//!
//! Each side steps its own `SimLoop` of the same world, one tick per iteration, as `volley
//! record` runs:
//! - `off`: no observer;
//! - `memory`: a recorder hashing every tick into `io::sink()`, flushing only when its buffer
//!   fills: all of recording but the I/O;
//! - `file`: what `volley record` does, default options (a hash every tick, a keyframe every 600
//!   ticks, flushed every 50 ms) into a real file;
//! - `file-every-10`, `file-every-100`: the same with `--hash-every 10` and `100`;
//! - `hash`: the state hash alone, what every hashed tick pays at least;
//! - `read`: every word the hash covers read once and XOR-folded ([`read_once`]): not a hash, the
//!   least any per-tick check of the whole state can cost, against which the 5 % budget is
//!   judged.
//!
//! The worlds span the cost of a tick: the seed (one body), a gravity-only volley of 1e3 bodies
//! (the cheapest step per body) and the bundled `wind` scene (200 bodies, RK4, drag, contacts).
//!
//! The files live in criterion's output directory and start over every [`ROLL_BYTES`], so a
//! benchmark that records tens of millions of ticks does not fill the disk; every write still
//! goes through the page cache as a recording's does. They are deleted at the end.

use std::fmt::Write as _;
use std::fs::File;
use std::hint::black_box;
use std::io::{self, Seek, Write};
use std::path::PathBuf;

use criterion::{BenchmarkId, Criterion, Throughput};
use volley::hash::state_hash;
use volley::replay::{FlushPolicy, RecordOptions, Recorder};
use volley::step::{SimdLevel, simd_level};
use volley::{Integrator, SimLoop, World};

use crate::e2e::{self, E2e};
use crate::paired::{self, Pair};
use crate::scenes::{self, BenchScene};
use crate::sized;
use crate::tables::{Results, opt, sig};

/// Bodies in the recording benchmark's second world.
pub const RECORD_VOLLEY: u64 = 1_000;

/// A bench file starts over once it holds this many bytes.
const ROLL_BYTES: u64 = 64 << 20;

/// The budget: recording costs at most this fraction over not recording.
const BUDGET: f64 = 0.05;

/// How a recording side writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Every tick hashed, bytes discarded.
    Memory,
    /// `volley record`'s options with this `--hash-every`, into a file.
    File(u64),
}

/// The recording sides, in report order.
pub const SIDES: [Side; 4] = [Side::Memory, Side::File(1), Side::File(10), Side::File(100)];

impl Side {
    /// The benchmark function name.
    pub fn name(self) -> String {
        match self {
            Side::Memory => "memory".into(),
            Side::File(1) => "file".into(),
            Side::File(k) => format!("file-every-{k}"),
        }
    }

    fn heading(self) -> String {
        match self {
            Side::Memory => "every tick, no I/O".into(),
            Side::File(1) => "every tick, to a file (`volley record`)".into(),
            Side::File(k) => format!("`--hash-every {k}`, to a file"),
        }
    }

    /// A recorder for `sim`'s world writing where this side writes; `world` names the file.
    fn recorder(self, sim: &SimLoop, world: &str) -> Recorder<Sink> {
        let (sink, options) = match self {
            Side::Memory => (
                Sink::Discard,
                RecordOptions {
                    flush: FlushPolicy::OnFinish,
                    ..RecordOptions::default()
                },
            ),
            Side::File(k) => {
                let dir = crate::report::output_dir();
                let _ = std::fs::create_dir_all(&dir);
                let path = dir.join(format!("record-bench-{world}-{}.vrec", self.name()));
                let file = File::create(&path).expect("the bench can write its output directory");
                let options = RecordOptions {
                    hash_every: k,
                    ..RecordOptions::default()
                };
                (
                    Sink::File {
                        file,
                        path,
                        written: 0,
                    },
                    options,
                )
            }
        };
        Recorder::start(sink, &sim.world, options).expect("the recording starts")
    }
}

/// Where a recording side's bytes go.
enum Sink {
    Discard,
    File {
        file: File,
        path: PathBuf,
        written: u64,
    },
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let Sink::File { file, written, .. } = self else {
            return Ok(buf.len());
        };
        if *written >= ROLL_BYTES {
            file.set_len(0)?;
            file.rewind()?;
            *written = 0;
        }
        let n = file.write(buf)?;
        *written += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        match self {
            Sink::Discard => Ok(()),
            Sink::File { file, .. } => file.flush(),
        }
    }
}

impl Drop for Sink {
    fn drop(&mut self) {
        if let Sink::File { path, .. } = self {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// The worlds: the seed scene (one body, contacts, events, the energy guard: the cheapest
/// tick there is), a volley of [`RECORD_VOLLEY`] bodies under gravity alone (semi-implicit
/// Euler, no contacts: the cheapest step per body), and the bundled `wind` scene (200 balls,
/// RK4, gravity, crosswind and quadratic drag, ground and a target: a typical sandbox scene).
fn worlds() -> [(String, World); 3] {
    let wind = volley::scene::load(std::path::Path::new("assets/scenes/wind.ron"))
        .expect("the wind scene is valid");
    [
        ("seed".into(), World::new(&scenes::seed())),
        (
            format!("volley-{RECORD_VOLLEY}"),
            BenchScene::Gravity.world(RECORD_VOLLEY, Integrator::SemiImplicitEuler, 1),
        ),
        ("wind".into(), World::new(&wind)),
    ]
}

/// The cheapest conceivable pass over what the state hash covers (tick, generator state, every
/// body's id, position, momentum, mass and radius): each word read once and folded with one XOR,
/// no mixing and no canonicalisation, built for Volley's vector width. It is not a hash (a
/// swap of two bodies leaves it unchanged); it is a floor: any hash of the whole state reads at
/// least these words and does at least this much with each.
pub fn read_once(world: &World) -> u64 {
    #[cfg(target_arch = "x86_64")]
    match simd_level() {
        // SAFETY: `simd_level` only reports instruction sets the CPU has.
        SimdLevel::Avx512 => return unsafe { read_once_avx512(world) },
        SimdLevel::Avx2 => return unsafe { read_once_avx2(world) },
        SimdLevel::Baseline => {}
    }
    read_once_body(world)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx2")]
fn read_once_avx2(world: &World) -> u64 {
    read_once_body(world)
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx512f")]
fn read_once_avx512(world: &World) -> u64 {
    read_once_body(world)
}

#[inline(always)]
fn read_once_body(world: &World) -> u64 {
    let b = world.bodies();
    let (p, mv) = (b.positions(), b.momenta());
    let fold = |s: &[f64]| s.iter().fold(0u64, |acc, x| acc ^ x.to_bits());
    let fields = [
        &p.x[..],
        &p.y[..],
        &p.z[..],
        &mv.x[..],
        &mv.y[..],
        &mv.z[..],
        b.masses(),
        b.radii(),
    ];
    let ids = b.ids().iter().fold(0u64, |acc, id| acc ^ id.0);
    fields
        .iter()
        .fold(world.tick() ^ world.rng().0 ^ ids, |acc, f| acc ^ fold(f))
}

fn tick(sim: &mut SimLoop, observer: &mut impl volley::TickObserver) {
    let dt = sim.world.scene().timestep();
    sim.frame(dt, observer).expect("the scene runs");
}

/// Benchmarks `record/off/WORLD` and `record/SIDE/WORLD` for every side, one tick per
/// iteration, `record/hash/WORLD`: the state hash alone, and `record/read/WORLD`: the floor
/// ([`read_once`]), both of the world as `off` left it.
pub fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("record");
    sized(&mut group, 1);
    group.throughput(Throughput::Elements(1));
    for (name, world) in worlds() {
        let mut sim = SimLoop::new(world.clone());
        group.bench_function(BenchmarkId::new("off", &name), |b| {
            b.iter(|| tick(&mut sim, &mut ()))
        });
        group.bench_function(BenchmarkId::new("hash", &name), |b| {
            b.iter(|| state_hash(black_box(&sim.world)))
        });
        group.bench_function(BenchmarkId::new("read", &name), |b| {
            b.iter(|| read_once(black_box(&sim.world)))
        });
        for side in SIDES {
            let mut sim = SimLoop::new(world.clone());
            let mut recorder = None;
            group.bench_function(BenchmarkId::new(side.name(), &name), |b| {
                let recorder = recorder.get_or_insert_with(|| side.recorder(&sim, &name));
                b.iter(|| tick(&mut sim, recorder))
            });
        }
    }
    group.finish();
}

/// Name of the paired comparison of `side` against `off` on `world`.
pub fn pair_name(side: Side, world: &str) -> String {
    format!("record/{}/{world}", side.name())
}

/// Every side against `off`, interleaved: the ratio is time(on) / time(off).
pub fn paired() -> Vec<Pair> {
    let mut out = Vec::new();
    for (name, world) in worlds() {
        for side in SIDES {
            let mut off = SimLoop::new(world.clone());
            let mut on = SimLoop::new(world.clone());
            let mut recorder = side.recorder(&on, &name);
            out.push(paired::compare(
                &pair_name(side, &name),
                || tick(&mut on, &mut recorder),
                || tick(&mut off, &mut ()),
            ));
        }
    }
    out
}

fn percent(x: f64) -> String {
    format!("{:+.1} %", 100.0 * x)
}

fn verdict(x: f64) -> &'static str {
    if x <= BUDGET {
        "≤ 5 %: met"
    } else {
        "≤ 5 %: **missed**"
    }
}

/// Writes the recording tables; returns whether every number was there.
pub fn table(md: &mut String, r: &Results, e2e: Option<&Result<E2e, String>>) -> bool {
    let _ = writeln!(md, "\n### Recording overhead\n");
    let _ = writeln!(
        md,
        "`SimLoop::frame` per tick, one tick per frame (so no tick is batched: the cost of \
         stepping and recording tick by tick), without an \
         observer (off) and with a `Recorder`: hashing every tick into `io::sink()` (no I/O), \
         and with `volley record`'s options into a real file, hashing every tick, every 10th and \
         every 100th (keyframes every 600 ticks and the 50 ms flush in all three). `volley record` itself feeds the loop frames of 65 \
         ticks (a 64-tick batch and the frame's last tick), so with `--hash-every K` a world without contacts runs the unhashed ticks as \
         batches, faster than this table's 'off'. The issue's budget: recording every tick \
         costs at most 5 % over not recording. The last two columns are the state hash alone \
         and the floor under any hash of the whole state: every word the hash covers read once \
         and XOR-folded, at Volley's vector width (`read_once` in benches/perf/record.rs), each \
         with its cost as a fraction of off: where the floor alone passes 5 %, no recorder \
         that checks the whole state every tick can meet the budget.\n"
    );
    let heads: Vec<String> = SIDES.iter().map(|s| s.heading()).collect();
    let _ = writeln!(
        md,
        "| world | off ns/tick | {} | the state hash alone | reading the state once (floor) |\n|---|---:|{}---:|---:|",
        heads.join(" | "),
        "---:|".repeat(SIDES.len())
    );
    let mut complete = true;
    for (name, _) in worlds() {
        let off = r.per(&format!("record/off/{name}"), 1);
        let cells: Vec<String> = SIDES
            .iter()
            .map(|side| {
                let on = r.per(&format!("record/{}/{name}", side.name()), 1);
                complete &= on.is_some();
                let over = on.zip(off).map(|(a, b)| a / b - 1.0);
                format!("{} ({})", opt(on, sig), opt(over, percent))
            })
            .collect();
        let alone = |what: &str| {
            let t = r.per(&format!("record/{what}/{name}"), 1);
            let of_off = t.zip(off).map(|(a, b)| a / b);
            (
                t.is_some(),
                format!("{} ({})", opt(t, sig), opt(of_off, percent)),
            )
        };
        let ((has_hash, hash), (has_read, read)) = (alone("hash"), alone("read"));
        complete &= off.is_some() && has_hash && has_read;
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {hash} | {read} |",
            opt(off, sig),
            cells.join(" | "),
        );
    }
    let _ = writeln!(
        md,
        "\nThe same, paired: each recording side against off, interleaved ({} rounds); the \
         overhead from each side's best round, with the median of the per-round overheads. The \
         verdict is on recording every tick into a file.\n",
        paired::ROUNDS
    );
    let _ = writeln!(
        md,
        "| world | {} | goal |\n|---|{}---|",
        heads.join(" | "),
        "---:|".repeat(SIDES.len())
    );
    for (name, _) in worlds() {
        let pairs: Vec<Option<&Pair>> = SIDES
            .iter()
            .map(|s| r.pair(&pair_name(*s, &name)))
            .collect();
        complete &= pairs.iter().all(Option::is_some);
        let cells: Vec<String> = pairs
            .iter()
            .map(|p| {
                p.map_or_else(
                    || "-".into(),
                    |p| {
                        format!(
                            "{} (median {})",
                            percent(p.ratio - 1.0),
                            percent(p.median - 1.0)
                        )
                    },
                )
            })
            .collect();
        let goal = pairs[1].map_or("", |p| verdict(p.ratio - 1.0));
        let _ = writeln!(md, "| {name} | {} | {goal} |", cells.join(" | "));
    }
    complete & end_to_end(md, e2e)
}

fn end_to_end(md: &mut String, e2e: Option<&Result<E2e, String>>) -> bool {
    let Some(Ok(e)) = e2e else {
        let _ = writeln!(md, "\nEnd to end: not measured in this run.");
        return false;
    };
    let _ = writeln!(
        md,
        "\nEnd to end: `volley {} -o FILE [--hash-every K]` against `volley {}`, process CPU \
         time (user + system), {} rounds each running every command once, in rotating order. \
         Overhead from the best runs, with the median of the per-round overheads.\n",
        e2e::RECORD_ARGS.join(" "),
        e2e::ARGS.join(" "),
        e.cpu.len()
    );
    let _ = writeln!(
        md,
        "| command | CPU s, median (min) | overhead | file | goal |\n|---|---:|---:|---:|---|"
    );
    let _ = writeln!(
        md,
        "| `volley {}` | {:.3} ({:.3}) | | | |",
        e2e::ARGS.join(" "),
        e.cpu_median(),
        e.cpu[0]
    );
    for rec in &e.record {
        let flag = match rec.hash_every {
            1 => String::new(),
            k => format!(" --hash-every {k}"),
        };
        let over = rec.overhead(e);
        let _ = writeln!(
            md,
            "| `volley {} -o FILE{flag}` | {:.3} ({:.3}) | {} (median {}) | {:.1} MB | {} |",
            e2e::RECORD_ARGS.join(" "),
            rec.cpu[rec.cpu.len() / 2],
            rec.cpu[0],
            percent(over),
            percent(rec.overhead_median()),
            rec.bytes as f64 / 1e6,
            if rec.hash_every == 1 {
                verdict(over)
            } else {
                ""
            }
        );
    }
    if let Some(rec) = e.record.first() {
        let _ = writeln!(md, "\nThe recording's line: `` {} ``", rec.summary);
    }
    true
}
