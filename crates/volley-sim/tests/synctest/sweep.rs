//! No false positives: every bundled scene under every integrator it allows passes the sync
//! test, with commands of every kind the scene takes, and ends where plain stepping ends.
//!
//! The dev-profile tests cover 300 ticks of each pair (30 for the worlds of a thousand bodies
//! or more, 4 for the 10 000-body volley) at K = 7, and a shorter run with stage hashes and the
//! re-runs on another thread count. The full sweep, 100 000 ticks of every pair, is the ignored
//! test below, run in release:
//!
//! ```text
//! cargo test --release -p volley-sim --test synctest -- --ignored --nocapture
//! ```
//!
//! `VOLLEY_SYNC_TICKS` changes its length. It takes hours on two cores (a run stopped by a
//! 6000 s timeout had not finished), so it can run in parts: with `VOLLEY_SYNC_LOG=FILE`, each
//! pair it finishes is appended to FILE as one line, and a pair already there (for the same
//! length) is not run again; start it again after a stop and it goes on. With
//! `VOLLEY_BENCH_WRITE=BENCHMARKS.md` it writes what it ran (pairs, ticks stepped, the pairs
//! that ended early on a divergence plain stepping met at the same tick, and the time the
//! pairs took) into that file's "sync test sweep" block.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use volley_sim::internals::scene::BUNDLED;
use volley_sim::{
    Command, Integrator, Scene, SyncError, SyncTest, World, bundled_scene, state_hash,
};

/// The commands of tick `tick` for `world`: a fire, a launcher change, another fire, the
/// first fired body despawned, a reset; each where the scene takes it.
fn commands_at(tick: u64, world: &World, fired: &mut Option<volley_sim::BodyId>) -> Vec<Command> {
    match tick {
        2 | 6 => vec![Command::Fire],
        4 => vec![Command::SetLaunch {
            speed: Some(world.launcher().speed + 1.0),
            elevation_deg: None,
            azimuth_deg: Some(5.0),
            position: None,
        }],
        9 => fired.take().map(Command::Despawn).into_iter().collect(),
        15 => vec![Command::Reset],
        _ => Vec::new(),
    }
}

/// How a pair ended: the ticks both sides stepped, and whether they stopped there on the same
/// divergence (a scene that blows up under an integrator, as it should, alike on both sides).
#[derive(Clone, Debug, Default, PartialEq)]
struct Ran {
    label: String,
    ticks: u64,
    diverged: bool,
    /// The pair's time (s), both sides.
    seconds: f64,
}

impl Ran {
    /// Its line in a sweep's log: the length asked for, the label, the ticks run, whether it
    /// stopped on a divergence, the time, tab-separated.
    fn line(&self, asked: u64) -> String {
        format!(
            "{asked}\t{}\t{}\t{}\t{:.3}\n",
            self.label, self.ticks, self.diverged, self.seconds
        )
    }

    /// A log line's run, if it is one of `asked` ticks.
    fn parse(line: &str, asked: u64) -> Option<Ran> {
        let mut f = line.split('\t');
        (f.next()?.parse::<u64>().ok()? == asked).then_some(())?;
        let ran = Ran {
            label: f.next()?.to_string(),
            ticks: f.next()?.parse().ok()?,
            diverged: f.next()?.parse().ok()?,
            seconds: f.next()?.parse().ok()?,
        };
        f.next().is_none().then_some(ran)
    }
}

#[test]
fn a_sweep_log_line_reads_back() {
    let ran = Ran {
        label: "hard/stiff_spring under Rk4".into(),
        ticks: 812,
        diverged: true,
        seconds: 1.25,
    };
    let line = ran.line(100_000);
    assert_eq!(Ran::parse(line.trim_end(), 100_000), Some(ran));
    assert_eq!(Ran::parse(line.trim_end(), 300), None, "another length");
    assert_eq!(Ran::parse("100000\tx\t5", 100_000), None, "a cut line");
}

/// Runs `scene` for `ticks` under a sync test (`setup` configures it) and under plain
/// stepping with the same commands; both must end on the same state, or diverge alike.
fn run_pair(
    scene: &Scene,
    ticks: u64,
    setup: impl Fn(SyncTest) -> SyncTest,
) -> Result<Ran, String> {
    let label = label(scene);
    let start = std::time::Instant::now();
    let mut sync = setup(SyncTest::new(World::new(scene), 7).expect("7 is in range"));
    let mut plain = World::new(scene);
    let mut fired = None;
    for tick in 0..ticks {
        let commands = commands_at(tick, &plain, &mut fired);
        for c in &commands {
            plain
                .apply(c)
                .map_err(|e| format!("{label}: the test's command {c} failed: {e}"))?;
        }
        if tick == 2 {
            fired = plain.bodies().ids().last().copied();
        }
        let stepped = plain.step();
        match sync.advance(&commands) {
            Ok(()) => {}
            Err(SyncError::Diverged(d)) if stepped == Err(d) => {
                return Ok(Ran {
                    label,
                    ticks: tick + 1,
                    diverged: true,
                    seconds: start.elapsed().as_secs_f64(),
                });
            }
            Err(SyncError::Mismatch(m)) => {
                return Err(format!("{label}: false positive\n{}", m.report(Some(8))));
            }
            Err(e) => return Err(format!("{label}: {e} (plain stepping: {stepped:?})")),
        }
        if let Err(d) = stepped {
            return Err(format!(
                "{label}: plain stepping {d}, the sync test did not"
            ));
        }
    }
    if state_hash(&plain) != state_hash(sync.world()) || plain.snapshot() != sync.world().snapshot()
    {
        return Err(format!(
            "{label}: the sync test's world ends elsewhere than plain stepping"
        ));
    }
    Ok(Ran {
        label,
        ticks,
        diverged: false,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// A pair's name in reports and the sweep's log: `scene under integrator`.
fn label(scene: &Scene) -> String {
    format!("{} under {}", scene.name(), scene.integrator())
}

/// Every bundled scene under every integrator it allows.
fn pairs() -> Vec<Scene> {
    let mut out = Vec::new();
    for (name, _) in BUNDLED {
        let base = bundled_scene(name).expect("bundled scenes parse");
        for integrator in Integrator::ALL {
            let mut scene = base.clone();
            if scene.set_integrator(integrator).is_ok() {
                out.push(scene);
            }
        }
    }
    out
}

/// Ticks for a scene: `ticks`, fewer for large worlds.
fn length(scene: &Scene, ticks: u64, big: u64, huge: u64) -> u64 {
    match World::new(scene).bodies().len() {
        0..1000 => ticks,
        1000..5000 => big,
        _ => huge,
    }
}

/// Runs every pair on one plain thread per core (not rayon's workers: a worker waiting for
/// the re-runs' pool would run another pair on top of its stack). With a `log` (a file, and
/// the one length every pair runs), pairs it holds are not run again, and each pair run is
/// appended to it.
fn sweep(
    ticks: u64,
    big: u64,
    huge: u64,
    setup: impl Fn(SyncTest) -> SyncTest + Sync,
    log: Option<&std::path::Path>,
) -> Vec<Ran> {
    let pairs = pairs();
    assert!(pairs.len() > 150, "{} pairs", pairs.len());
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let mut done = vec![None; pairs.len()];
    if let Some(path) = log {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let logged: Vec<Ran> = text.lines().filter_map(|l| Ran::parse(l, ticks)).collect();
        for (k, scene) in pairs.iter().enumerate() {
            let label = label(scene);
            done[k] = logged.iter().find(|r| r.label == label).cloned();
        }
    }
    let file = log.map(|path| {
        Mutex::new(
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(path)
                .unwrap_or_else(|e| panic!("cannot open the log {}: {e}", path.display())),
        )
    });
    let ran = Mutex::new(done.clone());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..cores {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(scene) = pairs.get(k) else { break };
                    if done[k].is_some() {
                        continue;
                    }
                    match run_pair(scene, length(scene, ticks, big, huge), &setup) {
                        Ok(r) => {
                            if let Some(f) = &file {
                                use std::io::Write as _;
                                let mut f = f.lock().expect("not poisoned");
                                f.write_all(r.line(ticks).as_bytes())
                                    .and_then(|()| f.flush())
                                    .expect("the log takes a line");
                            }
                            ran.lock().expect("not poisoned")[k] = Some(r);
                        }
                        Err(e) => failures.lock().expect("not poisoned").push(e),
                    }
                }
            });
        }
    });
    let failures = failures.into_inner().expect("not poisoned");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    ran.into_inner()
        .expect("not poisoned")
        .into_iter()
        .map(|r| r.expect("every pair ran or failed"))
        .collect()
}

#[test]
fn every_bundled_scene_under_every_integrator_passes() {
    let ran = sweep(300, 30, 4, |s| s, None);
    assert!(ran.iter().all(|r| r.ticks > 0));
}

#[test]
fn every_bundled_scene_passes_with_stage_hashes_and_other_threads() {
    sweep(
        40,
        4,
        2,
        |s| {
            s.with_stage_hashes(true)
                .with_rerun_threads(3)
                .expect("three threads")
        },
        None,
    );
}

#[test]
#[ignore = "the full sweep: hours in release (see the module doc)"]
fn every_bundled_scene_under_every_integrator_passes_for_1e5_ticks() {
    let ticks = std::env::var("VOLLEY_SYNC_TICKS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(100_000);
    let log = std::env::var_os("VOLLEY_SYNC_LOG").map(std::path::PathBuf::from);
    let ran = sweep(ticks, ticks, ticks, |s| s, log.as_deref());
    let seconds: f64 = ran.iter().map(|r| r.seconds).sum();
    let early: Vec<String> = ran
        .iter()
        .filter(|r| r.diverged)
        .map(|r| format!("{} (tick {})", r.label, r.ticks))
        .collect();
    let mut slowest: Vec<&Ran> = ran.iter().collect();
    slowest.sort_by(|a, b| b.seconds.total_cmp(&a.seconds));
    let slowest: Vec<String> = slowest
        .iter()
        .take(3)
        .map(|r| format!("{} {:.0} s", r.label, r.seconds))
        .collect();
    let block = format!(
        "{BEGIN}\n\n`cargo test --release -p volley-sim --test synctest -- --ignored` (K = 7, \
         the commands of every kind each scene takes, one pair per thread on {} threads, \
         `VOLLEY_SYNC_LOG` to run it in parts): {} pairs of a bundled \
         scene and an integrator it allows, {ticks} ticks each, {} ticks stepped under the \
         sync test in all, 0 false positives, and every pair's world at the end equal to plain \
         stepping's, byte for byte. {} pairs stopped early, at a divergence plain stepping met \
         at the same tick with the same cause (a scene that blows up under an integrator too \
         crude for it, or a guard's stop): {}. Time: {seconds:.0} s, the pairs' own times \
         summed (both sides of each pair); the slowest: {}.\n\n{END}\n",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        ran.len(),
        ran.iter().map(|r| r.ticks).sum::<u64>(),
        early.len(),
        early.join(", "),
        slowest.join(", "),
    );
    eprint!("{block}");
    crate::splice::write_if_asked(&block, BEGIN, END);
}

const BEGIN: &str =
    "<!-- BEGIN synctest sweep: generated by the ignored sweep test, do not edit by hand -->";
const END: &str = "<!-- END synctest sweep -->";
