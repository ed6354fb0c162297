//! Soak tests: memory that stays flat on long runs (docs/limits.md, "Memory on long runs").
//!
//! Their own test binary, so no other test allocates in the process they measure, and run one
//! at a time (a lock) for the same reason. Both run at full length in CI (a simulated hour of
//! the session, 10^7 ticks of `volley record`), each well under two minutes in the dev profile;
//! `VOLLEY_SOAK_SECONDS` and `VOLLEY_SOAK_RECORD_TICKS` change the lengths:
//!
//! ```text
//! VOLLEY_SOAK_SECONDS=36000 cargo test --release --test soak -- --nocapture
//! ```

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use volley::app::session::Session;
use volley::render::series::{BUCKETS, Bucket, Decimated};
use volley::replay::Recording;
use volley::{Command, Integrator, scene};

/// One soak at a time: each measures its own process's memory.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Simulated seconds of the session soak (an hour).
fn soak_seconds() -> u64 {
    env_u64("VOLLEY_SOAK_SECONDS", 3600)
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name).map_or(default, |v| {
        v.parse()
            .unwrap_or_else(|_| panic!("{name}: expected a count, got {v}"))
    })
}

/// Resident memory of this process (bytes), from `/proc/self/statm`.
fn resident() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").expect("Linux /proc");
    let pages: usize = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("volley-soak-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const MIB: usize = 1 << 20;

/// What the allocator may hold on top of the budgets: freed blocks it keeps, arenas, the page
/// granularity of resident memory.
const ALLOWANCE: usize = 4 * MIB;

/// The plots' budget for four lanes (docs/window.md, "Bounded memory"): three series of at most
/// `BUCKETS` buckets a lane, the per-body energy starts of the first 64 bodies, headers.
const PLOTS: usize = 4
    * (3 * BUCKETS * std::mem::size_of::<Bucket>()
        + 3 * std::mem::size_of::<Decimated>()
        + 4 * 64 * 24);

/// Each lane's timeline budget here: small, so the timelines fill and thin out early and the
/// rest of the run shows they stay within it.
const TIMELINE: usize = 256 << 10;

#[test]
fn the_window_session_in_four_lanes_recording_stays_within_its_memory_budgets() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/drag.ron");
    let lanes = vec![
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
    ];
    let mut session = Session::new(scene::load(&path).unwrap(), &path, lanes);
    session.set_history_budget(TIMELINE);
    session.restart(None, "soak").unwrap();
    let dir = scratch("session");
    let file = dir.join("soak.vrec");
    session.start_recording(Some(file.clone())).unwrap();
    let frame = session.scene().timestep();
    assert_eq!(frame, Duration::from_nanos(16_666_667), "60 Hz frames");
    let ticks = soak_seconds() * 60;
    // After the first 10 s: the one-time allocations (first frames, buffers) are made, and the
    // whole rest of the run (the timelines filling and thinning included) is measured.
    let warm_up = 600.min(ticks / 2);
    let (mut before, mut most) = (0, 0);
    let started = Instant::now();
    for n in 0..ticks {
        // A shot every 10 s, taken away again 5 s later: commands in the timeline and the
        // recording all along, with the body count bounded.
        if n % 600 == 0 {
            session.push(Command::Fire).unwrap();
        }
        if n % 600 == 300 {
            let ids = session.world().bodies().id.clone();
            if let Some(last) = ids.last().filter(|_| ids.len() > 1) {
                session.push(Command::Despawn(*last)).unwrap();
            }
        }
        session.frame(frame);
        if n + 1 == warm_up {
            before = resident();
        }
        if n >= warm_up && n % 3000 == 0 {
            most = most.max(resident());
        }
    }
    most = most.max(resident());
    assert_eq!(session.world().tick(), ticks);
    for lane in session.lanes() {
        let timeline = lane
            .history
            .timeline
            .as_ref()
            .expect("a timeline in every lane");
        assert!(
            timeline.bytes() <= TIMELINE,
            "{} > {TIMELINE}",
            timeline.bytes()
        );
        // Filled and thinned out: the budget, not the run's length, bounds it.
        assert!(timeline.bytes() > TIMELINE / 2, "{}", timeline.bytes());
        assert!(lane.history.series.bytes() <= PLOTS / 4);
        assert_eq!(lane.history.series.samples, ticks);
    }
    let growth = most.saturating_sub(before);
    let budget = 4 * TIMELINE + PLOTS + ALLOWANCE;
    let timeline = session.lanes()[0].history.timeline.as_ref().unwrap();
    eprintln!(
        "session soak: lane 0's timeline holds {} keyframes in {} bytes (budget {TIMELINE})",
        timeline.keyframes(),
        timeline.bytes()
    );
    eprintln!(
        "session soak: {ticks} ticks x 4 lanes in {:?}; resident {:.1} MiB after the warm-up, \
         at most {:.1} MiB after it (+{:.2} MiB, budget {:.1} MiB)",
        started.elapsed(),
        before as f64 / MIB as f64,
        most as f64 / MIB as f64,
        growth as f64 / MIB as f64,
        budget as f64 / MIB as f64
    );
    assert!(
        growth <= budget,
        "resident memory grew by {growth} bytes > {budget}"
    );
    // The recording holds the whole run: nothing recorded was lost to the long run.
    session.stop_recording("soak over");
    let recording = Recording::open(&file).unwrap();
    assert_eq!(recording.end_tick(), ticks);
    assert_eq!(recording.hashes().len() as u64, ticks + 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The peak resident memory (bytes) of process `pid` so far: `VmHWM` of `/proc/PID/status`,
/// which belongs to the program the process runs (a new one at exec), not to its parent.
fn peak_of(pid: u32) -> Option<usize> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Peak resident memory (bytes) of `volley record` of `ticks` ticks of a one-body scene, read
/// while it runs (`wait4`'s `ru_maxrss` would not do: a child started by `posix_spawn` shares
/// its parent's memory until exec, so it reports the test process's peak).
fn record_peak(dir: &std::path::Path, ticks: u64) -> usize {
    let out = dir.join(format!("run-{ticks}.vrec"));
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(["record", "seed", "--ticks", &ticks.to_string(), "-o"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut peak = 0;
    let status = loop {
        // Read before checking for the exit: a zombie's status file has no memory lines.
        if let Some(p) = peak_of(child.id()) {
            peak = peak.max(p);
        }
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status}");
    assert!(peak > 0, "the peak was read while it ran");
    let recording = Recording::open(&out).unwrap();
    assert_eq!(recording.end_tick(), ticks, "the whole run is recorded");
    let _ = std::fs::remove_file(&out);
    peak
}

#[test]
fn volley_record_memory_does_not_grow_with_the_tick_count() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let long = env_u64("VOLLEY_SOAK_RECORD_TICKS", 10_000_000);
    let short = long / 10;
    let dir = scratch("record");
    let started = Instant::now();
    let (a, b) = (record_peak(&dir, short), record_peak(&dir, long));
    eprintln!(
        "record soak: peak resident {:.1} MiB at {short} ticks, {:.1} MiB at {long} ticks ({:?})",
        a as f64 / MIB as f64,
        b as f64 / MIB as f64,
        started.elapsed()
    );
    // Ten times the ticks: the file grows by 8 bytes a tick, the memory by no more than the
    // allocator's allowance.
    assert!(b <= a + ALLOWANCE, "{b} > {a} + {ALLOWANCE}");
    let _ = std::fs::remove_dir_all(&dir);
}
