//! What the numbers were measured on: CPU, caches, memory, compiler, commit, and the load.

use std::fmt::Write as _;
use std::process::Command;

fn read(path: &str) -> Option<String> {
    std::fs::read_to_string(path)
        .ok()
        .map(|s| s.trim().to_string())
}

fn command(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn cpu_model() -> String {
    read("/proc/cpuinfo")
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// Cache sizes of CPU 0 as `L1d 48K, L2 1024K, L3 32768K`.
fn caches() -> String {
    (0..8)
        .filter_map(|i| {
            let base = format!("/sys/devices/system/cpu/cpu0/cache/index{i}");
            let kind = read(&format!("{base}/type"))?;
            if kind == "Instruction" {
                return None;
            }
            let level = read(&format!("{base}/level"))?;
            let size = read(&format!("{base}/size"))?;
            let d = if kind == "Data" { "d" } else { "" };
            Some(format!("L{level}{d} {size}"))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn memory() -> String {
    read("/proc/meminfo")
        .and_then(|s| {
            let kb: f64 = s.lines().next()?.split_whitespace().nth(1)?.parse().ok()?;
            Some(format!("{:.0} GiB", kb / (1024.0 * 1024.0)))
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Writes the "Run" subsection.
pub fn section(md: &mut String, load_before: &str) {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let date = command("date", &["-u", "+%Y-%m-%d %H:%M UTC"]).unwrap_or_default();
    let rustc = command("rustc", &["-V"]).unwrap_or_else(|| "rustc (unknown)".into());
    let commit = command("git", &["rev-parse", "--short", "HEAD"]).unwrap_or_default();
    let dirty = command("git", &["status", "--porcelain", "--untracked-files=no"])
        .is_some_and(|s| !s.is_empty());
    let kernel = read("/proc/sys/kernel/osrelease").unwrap_or_default();
    let _ = writeln!(md, "\n### Run\n");
    let _ = writeln!(md, "| | |\n|---|---|");
    let _ = writeln!(md, "| date | {date} |");
    let _ = writeln!(
        md,
        "| CPU | {} ({cores} cores; {}) |",
        cpu_model(),
        caches()
    );
    let _ = writeln!(md, "| memory | {} |", memory());
    let _ = writeln!(md, "| OS | Linux {kernel} |");
    let _ = writeln!(
        md,
        "| compiler | {rustc}, `bench` profile (= release), no target-cpu flags |"
    );
    let dirty = if dirty {
        " (with uncommitted changes)"
    } else {
        ""
    };
    let _ = writeln!(md, "| commit | {commit}{dirty} |");
    let _ = writeln!(
        md,
        "| load average (1, 5, 15 min) | {load_before} before, {} after |",
        crate::report::load_average()
    );
}
