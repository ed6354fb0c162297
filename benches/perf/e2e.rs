//! End to end: `volley headless seed --ticks 1000000 --no-table` as a process, timed by its
//! user + system CPU time (what the 0.1 s budget is about), read with
//! `getrusage(RUSAGE_CHILDREN)` around each run: microseconds, where `/usr/bin/time` prints
//! hundredths.
//!
//! Beside it, the same 1e6 ticks recorded: `volley record seed --ticks 1000000 -o FILE`, with
//! every tick hashed (the default) and with `--hash-every 10` and `100`, each writing a real
//! file (deleted after each run). The runs are interleaved, one of each per round in an order
//! that rotates, so a load change on the shared machine touches all of them alike; the
//! recording overhead is the ratio of CPU times, from the best runs and as the median of the
//! per-round ratios.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

/// The command line measured, after the binary.
pub const ARGS: [&str; 5] = ["headless", "seed", "--ticks", "1000000", "--no-table"];

/// The recording's command line, after the binary and before `-o FILE [--hash-every K]`.
pub const RECORD_ARGS: [&str; 4] = ["record", "seed", "--ticks", "1000000"];

/// `--hash-every` of the recording runs.
pub const RECORD_HASH_EVERY: [u64; 3] = [1, 10, 100];

/// Rounds; each runs the headless command and every recording once. The report gives the
/// minimum and the median.
const RUNS: usize = 11;

/// Process times of the end-to-end runs.
#[derive(Clone, Debug)]
pub struct E2e {
    /// User + system CPU seconds of each headless run, sorted.
    pub cpu: Vec<f64>,
    /// Wall-clock seconds of each headless run (spawn to reap), sorted.
    pub wall: Vec<f64>,
    /// The summary line the headless run printed (its hash shows what was run).
    pub summary: String,
    /// Lines the headless run printed in all (events and the summary).
    pub lines: usize,
    /// The recording runs, in the order of [`RECORD_HASH_EVERY`].
    pub record: Vec<RecordE2e>,
}

/// Process times of one recording command.
#[derive(Clone, Debug)]
pub struct RecordE2e {
    /// Its `--hash-every`.
    pub hash_every: u64,
    /// User + system CPU seconds of each run, sorted.
    pub cpu: Vec<f64>,
    /// Per round: this run's CPU time over the headless run's, sorted.
    pub ratios: Vec<f64>,
    /// Size of the recording written (bytes).
    pub bytes: u64,
    /// The line it printed.
    pub summary: String,
}

/// User + system CPU seconds of every child reaped so far.
fn children_cpu() -> f64 {
    // SAFETY: getrusage only writes the struct it is given, which is plain old data.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage
    };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

/// One run of the release binary: CPU seconds, wall seconds, what it printed.
fn run(args: &[String]) -> Result<(f64, f64, String), String> {
    let exe = env!("CARGO_BIN_EXE_volley");
    let before = children_cpu();
    let start = Instant::now();
    let out = Command::new(exe)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("cannot run {exe}: {e}"))?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = children_cpu() - before;
    if !out.status.success() {
        return Err(format!(
            "`volley {}` failed: {}",
            args.join(" "),
            out.status
        ));
    }
    Ok((cpu, wall, String::from_utf8_lossy(&out.stdout).into_owned()))
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

/// Times the release binary built for this bench run, writing recordings into `dir` (each
/// deleted after its run), or says why it could not.
pub fn measure(dir: &Path) -> Result<E2e, String> {
    let file = dir.join("e2e-record.vrec");
    let _ = std::fs::create_dir_all(dir);
    let headless: Vec<String> = ARGS.iter().map(|s| s.to_string()).collect();
    let recording = |k: u64| -> Vec<String> {
        let mut args: Vec<String> = RECORD_ARGS.iter().map(|s| s.to_string()).collect();
        args.extend(["-o".into(), file.display().to_string()]);
        args.extend(["--hash-every".into(), k.to_string()]);
        args
    };
    let commands: Vec<Vec<String>> = std::iter::once(headless)
        .chain(RECORD_HASH_EVERY.map(recording))
        .collect();
    let mut cpu = vec![Vec::new(); commands.len()];
    let mut wall = Vec::new();
    let mut printed = vec![String::new(); commands.len()];
    let mut bytes = vec![0; commands.len()];
    for round in 0..RUNS {
        for k in 0..commands.len() {
            let i = (k + round) % commands.len();
            let (c, w, out) = run(&commands[i])?;
            cpu[i].push(c);
            if i == 0 {
                wall.push(w);
            } else {
                bytes[i] = std::fs::metadata(&file).map_or(0, |m| m.len());
                let _ = std::fs::remove_file(&file);
            }
            printed[i] = out;
        }
    }
    let record = RECORD_HASH_EVERY
        .iter()
        .enumerate()
        .map(|(j, &hash_every)| {
            let i = j + 1;
            let ratios = cpu[i].iter().zip(&cpu[0]).map(|(r, h)| r / h).collect();
            RecordE2e {
                hash_every,
                cpu: sorted(cpu[i].clone()),
                ratios: sorted(ratios),
                bytes: bytes[i],
                summary: printed[i].lines().last().unwrap_or("").to_string(),
            }
        })
        .collect();
    Ok(E2e {
        cpu: sorted(cpu[0].clone()),
        wall: sorted(wall),
        summary: printed[0].lines().last().unwrap_or("").to_string(),
        lines: printed[0].lines().count(),
        record,
    })
}

impl E2e {
    /// Median CPU seconds.
    pub fn cpu_median(&self) -> f64 {
        self.cpu[self.cpu.len() / 2]
    }

    /// Median wall-clock seconds.
    pub fn wall_median(&self) -> f64 {
        self.wall[self.wall.len() / 2]
    }
}

impl RecordE2e {
    /// The recording's overhead over the headless run from the best runs of each:
    /// `min(record) / min(headless) - 1`.
    pub fn overhead(&self, headless: &E2e) -> f64 {
        self.cpu[0] / headless.cpu[0] - 1.0
    }

    /// The median over rounds of `record / headless - 1`.
    pub fn overhead_median(&self) -> f64 {
        self.ratios[self.ratios.len() / 2] - 1.0
    }
}
