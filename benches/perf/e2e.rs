//! End to end: `volley headless seed --ticks 1000000 --no-table` as a process, timed by its
//! user + system CPU time (what the 0.1 s budget is about), read with
//! `getrusage(RUSAGE_CHILDREN)` around each run: microseconds, where `/usr/bin/time` prints
//! hundredths.

use std::process::{Command, Stdio};
use std::time::Instant;

/// The command line measured, after the binary.
pub const ARGS: [&str; 5] = ["headless", "seed", "--ticks", "1000000", "--no-table"];

/// Runs of the process; the report gives the minimum and the median.
const RUNS: usize = 7;

/// Process times of the end-to-end run.
#[derive(Clone, Debug)]
pub struct E2e {
    /// User + system CPU seconds of each run, sorted.
    pub cpu: Vec<f64>,
    /// Wall-clock seconds of each run (spawn to reap), sorted.
    pub wall: Vec<f64>,
    /// The summary line the run printed (its hash shows what was run).
    pub summary: String,
    /// Lines the run printed in all (events and the summary).
    pub lines: usize,
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

/// Times the release binary built for this bench run, or says why it could not.
pub fn measure() -> Result<E2e, String> {
    let exe = env!("CARGO_BIN_EXE_volley");
    let (mut cpu, mut wall) = (Vec::new(), Vec::new());
    let (mut summary, mut lines) = (String::new(), 0);
    for _ in 0..RUNS {
        let before = children_cpu();
        let start = Instant::now();
        let out = Command::new(exe)
            .args(ARGS)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| format!("cannot run {exe}: {e}"))?;
        wall.push(start.elapsed().as_secs_f64());
        cpu.push(children_cpu() - before);
        if !out.status.success() {
            return Err(format!(
                "`volley {}` failed: {}",
                ARGS.join(" "),
                out.status
            ));
        }
        let stdout = String::from_utf8_lossy(&out.stdout);
        summary = stdout.lines().last().unwrap_or("").to_string();
        lines = stdout.lines().count();
    }
    cpu.sort_by(f64::total_cmp);
    wall.sort_by(f64::total_cmp);
    Ok(E2e {
        cpu,
        wall,
        summary,
        lines,
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
