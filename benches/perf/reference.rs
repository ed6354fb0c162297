//! The yardsticks: a hand-written SoA explicit-Euler gravity loop, and a STREAM-triad-like loop.
//!
//! The reference kernel is what a programmer writes for "projectiles under gravity" with no
//! engine at all: six arrays, `p += h v; v += h g`, nothing else. Volley's full step on the
//! gravity scene does the same physics through its general machinery (the world, the declared
//! force model, momentum state, the non-finite check), and the ratio of the two throughputs is
//! the cost of that machinery. Both are compiled with the same flags in the same binary.
//!
//! The triad `a = b + s c` over arrays much larger than the last-level cache measures the memory
//! bandwidth one and two threads can reach; it counts 24 bytes per element, as STREAM does.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput};
use volley::step::{SimdLevel, simd_level};

use crate::{SIZES, sized};

/// Positions and velocities, one array per component.
pub struct Soa {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    vz: Vec<f64>,
}

impl Soa {
    /// `n` bodies at 1 m height with distinct launch velocities.
    pub fn new(n: usize) -> Soa {
        let spread = |i: usize, k: f64| 1.0 + ((i as f64) * k).sin();
        Soa {
            x: vec![0.0; n],
            y: vec![0.0; n],
            z: vec![1.0; n],
            vx: (0..n).map(|i| 14.0 * spread(i, 0.37)).collect(),
            vy: (0..n).map(|i| 0.5 * spread(i, 0.11)).collect(),
            vz: (0..n).map(|i| 14.0 * spread(i, 0.23)).collect(),
        }
    }

    /// One explicit-Euler step of every body, `p += h v; v += h g`, compiled for the target's
    /// baseline (SSE2 on x86-64): the loop exactly as `cargo build --release` builds it.
    #[inline(never)]
    pub fn step(&mut self, h: f64, g: [f64; 3]) {
        self.step_body(h, g);
    }

    /// The same loop compiled for the vector width Volley's kernel runs at
    /// ([`volley::step::simd_level`]), so the two can also be compared instruction set for
    /// instruction set.
    pub fn step_widest(&mut self, h: f64, g: [f64; 3]) {
        #[cfg(target_arch = "x86_64")]
        match simd_level() {
            // SAFETY: `simd_level` only reports instruction sets the CPU has.
            SimdLevel::Avx512 => return unsafe { self.step_avx512(h, g) },
            SimdLevel::Avx2 => return unsafe { self.step_avx2(h, g) },
            SimdLevel::Baseline => {}
        }
        self.step(h, g);
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(never)]
    #[target_feature(enable = "avx2")]
    fn step_avx2(&mut self, h: f64, g: [f64; 3]) {
        self.step_body(h, g);
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(never)]
    #[target_feature(enable = "avx512f")]
    fn step_avx512(&mut self, h: f64, g: [f64; 3]) {
        self.step_body(h, g);
    }

    #[inline(always)]
    fn step_body(&mut self, h: f64, g: [f64; 3]) {
        let n = self.x.len();
        let (x, y, z) = (&mut self.x[..n], &mut self.y[..n], &mut self.z[..n]);
        let (vx, vy, vz) = (&mut self.vx[..n], &mut self.vy[..n], &mut self.vz[..n]);
        for i in 0..n {
            x[i] += h * vx[i];
            y[i] += h * vy[i];
            z[i] += h * vz[i];
            vx[i] += h * g[0];
            vy[i] += h * g[1];
            vz[i] += h * g[2];
        }
    }
}

/// Bodies of the reference run that streams from memory: 192 MB, six times the last-level
/// cache. At 1e6 bodies the reference's 48 MB still partly fits the 32 MB L3 of the machine this
/// was tuned on, where Volley's 112 MB does not.
pub const REFERENCE_DRAM_N: u64 = 4_000_000;

/// Elements per triad array: 3 arrays of 32 MiB, three times the last-level cache of the
/// machine this was tuned on, and about the footprint of a 1e6-body world.
pub const TRIAD_LEN: usize = 1 << 22;

/// Bytes a triad element moves, by STREAM's count (two reads, one write).
pub const TRIAD_BYTES: u64 = 24;

/// Bytes a triad element really moves: STREAM's count plus the read of the line the write
/// allocates.
pub const TRIAD_MOVED: u64 = 32;

/// `a = b + s c`, split into `chunks` contiguous pieces run with `rayon::join`.
pub fn triad(a: &mut [f64], b: &[f64], c: &[f64], s: f64, chunks: usize) {
    if chunks <= 1 {
        for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
            *a = b + s * c;
        }
        return;
    }
    let half = chunks / 2;
    let mid = a.len() * half / chunks;
    let (a0, a1) = a.split_at_mut(mid);
    let ((b0, b1), (c0, c1)) = (b.split_at(mid), c.split_at(mid));
    rayon::join(
        || triad(a0, b0, c0, s, half),
        || triad(a1, b1, c1, s, chunks - half),
    );
}

/// Benchmarks `reference/explicit-euler/N` (baseline build), `reference/explicit-euler-widest/N`
/// (built for Volley's vector width) and `bandwidth/triad/THREADS`.
pub fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("reference");
    for n in SIZES.into_iter().chain([REFERENCE_DRAM_N]) {
        sized(&mut group, n);
        group.throughput(Throughput::Elements(n));
        let mut soa = Soa::new(n as usize);
        let h = black_box(0.016_666_667);
        let g = black_box([0.0, 0.0, -9.81]);
        group.bench_function(BenchmarkId::new("explicit-euler", n), |b| {
            b.iter(|| soa.step(h, g))
        });
        group.bench_function(BenchmarkId::new("explicit-euler-widest", n), |b| {
            b.iter(|| soa.step_widest(h, g))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("bandwidth");
    sized(&mut group, TRIAD_LEN as u64);
    group.throughput(Throughput::Bytes(TRIAD_BYTES * TRIAD_LEN as u64));
    let mut a = vec![0.5; TRIAD_LEN];
    let b = vec![1.0; TRIAD_LEN];
    let cc = vec![2.0; TRIAD_LEN];
    let s = black_box(0.5);
    for threads in [1usize, 2] {
        group.bench_function(BenchmarkId::new("triad", threads), |bench| {
            bench.iter(|| triad(&mut a, &b, &cc, s, threads))
        });
    }
    group.finish();
}
