//! Speed against error: sweep integrators and timesteps over one scene and measure what each
//! setting costs and what it buys.
//!
//! For every (integrator, dt) the scene runs through the ordinary [`SimLoop`] and
//! [`World::step`], and the study records:
//!
//! - **cost**: force evaluations per simulated second ([`World::force_evals`], which counts every
//!   stage, the start-up force of Verlet and every evaluation of the contact root searches), and
//!   wall time per tick, the median of repeated runs with no observer (meaningful only in a
//!   release build; the report says which build made it);
//! - **error** of the positions against a reference ([`mod@reference`]): at the final tick, the
//!   largest over the trajectory, and the RMS over every sampled (tick, body) pair; the largest
//!   velocity error at the final tick; and the error of event times (impacts, target hits), the
//!   k-th event of a body on a surface or target matched with the reference's k-th;
//! - **energy drift** per time window for conservative scenes (no drag, restitution 1);
//! - the **stability pre-check**'s verdict ([`crate::stability`]), beside what happened;
//! - per integrator, the **observed order**: the least-squares slope of log(max error) against
//!   log(dt) over the completed runs whose error is above the rounding floor.
//!
//! With a tolerance the study names the cheapest setting (fewest force evaluations per simulated
//! second) whose largest trajectory error meets it. [`output`] writes the markdown table and the
//! CSV; the `volley` package's `plot` module draws the work-precision diagram. Every report
//! names the reference of each dt and that reference's own error estimate.
//!
//! The error runs (every point's measured run, and the references) run on all cores, the
//! points of one dt in parallel after its reference, and are collected in point order, so the
//! report is the one a serial run gives. The timed runs follow, one at a time, so no two timed
//! runs share the machine with each other or with an error run.
//!
//! A study can also be split over machines: [`run_shard`] measures one [`Shard`] of the points
//! (point `k` of the dt-major list belongs to shard `k mod n`) and returns a [`ShardResult`]
//! that serialises to JSON; [`shard::merge`] checks that a set of them is one complete study
//! and builds the report, the observed orders and the cheapest setting over all points, equal
//! to the one-machine run's.
//!
//! ```
//! use volley_lab::study::{self, StudyConfig};
//! use volley_sim::Integrator;
//! let scene = volley_sim::bundled_scene("seed").unwrap();
//! let config = StudyConfig {
//!     integrators: vec![Integrator::ExplicitEuler, Integrator::Rk4],
//!     dts: vec![0.2, 0.1],
//!     timing: false,
//!     ..StudyConfig::for_scene(&scene)
//! };
//! let report = study::run(&scene, &config, &mut |_| {}).unwrap();
//! let euler = &report.points[0];
//! // Explicit Euler ends g T h / 2 high under gravity: about 5 m after 5.4 s at h = 0.2.
//! assert!(euler.errors.unwrap().final_position > 4.0);
//! ```

pub mod fit;
mod measure;
pub mod output;

pub mod reference;
pub mod shard;

use std::sync::Mutex;
use std::time::Duration;

use volley_sim::internals::instant::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::stability;
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::exact::ExtrapolationError;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::scene::{IntegratorError, InvalidValue, Scene};
use volley_sim::internals::sim_loop::{LoopError, SimLoop};
use volley_sim::internals::world::{Divergence, World};

pub use fit::OrderFit;
pub use measure::{EnergyDrift, Errors, EventErrors};
pub use reference::{Reference, ReferenceKind};
pub use shard::{MergeError, Shard, ShardResult};

/// What to sweep and how to measure it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyConfig {
    /// Integrators, in table order.
    pub integrators: Vec<Integrator>,
    /// Tick lengths (s); each is rounded to whole nanoseconds like a scene's `dt`.
    pub dts: Vec<f64>,
    /// Sim time (s) every run reaches: the first tick at or after it is the final tick.
    pub until: f64,
    /// Largest acceptable trajectory position error (m), to name the cheapest setting meeting it.
    pub tolerance: Option<f64>,
    /// Whether to measure wall time (repeated untimed-observer runs). Tests turn it off.
    pub timing: bool,
    /// Fewest timed repeats per point (the median is reported).
    pub min_repeats: u32,
    /// Keep repeating (up to 25 runs) until this much wall time was spent on a point.
    pub timing_budget: Duration,
    /// Windows the run is split into for the energy drift.
    pub energy_windows: usize,
    /// Most sampled ticks per run for the trajectory errors (evenly strided, final tick always).
    pub max_samples: u64,
}

impl StudyConfig {
    /// Defaults for `scene`: every integrator it allows except `exact` (no force evaluations, so
    /// it has no place on a cost axis), six steps halving from the scene's `dt`, until the end
    /// of the scene's duration, 10 energy windows.
    pub fn for_scene(scene: &Scene) -> StudyConfig {
        StudyConfig {
            integrators: Integrator::ALL
                .into_iter()
                .filter(|i| *i != Integrator::Exact)
                .collect(),
            dts: (0..6).map(|k| scene.dt() / f64::from(1u32 << k)).collect(),
            until: scene.start_time() + scene.duration(),
            tolerance: None,
            timing: true,
            min_repeats: 3,
            timing_budget: Duration::from_millis(200),
            energy_windows: 10,
            max_samples: 20_000,
        }
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Outcome {
    /// Reached the final tick.
    Completed,
    /// Stopped by the divergence guard.
    Diverged(Divergence),
}

/// The measurements of one (integrator, dt).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyPoint {
    /// Integrator.
    pub integrator: Integrator,
    /// Tick length (s), after rounding to nanoseconds.
    pub dt: f64,
    /// Integrator steps per tick (the scene's).
    pub substeps: u32,
    /// Ticks to the final tick.
    pub ticks: u64,
    /// Force evaluations of the run (to the divergence, if it diverged).
    pub force_evals: u64,
    /// Force evaluations per simulated second.
    pub evals_per_second: f64,
    /// Median wall time per tick (None without timing or when the run diverged).
    pub wall_per_tick: Option<Duration>,
    /// Timed samples behind the median (each sample is one or more back-to-back runs).
    pub repeats: u32,
    /// Completed or diverged.
    pub outcome: Outcome,
    /// Position and velocity errors (None when the run diverged).
    pub errors: Option<Errors>,
    /// Event-time errors.
    pub events: EventErrors,
    /// Energy drift per window, for conservative scenes.
    pub energy: Option<EnergyDrift>,
    /// The pre-check's growth factor per step (1 = neutral) and whether it called the step
    /// stable.
    pub precheck: stability::Growth,
}

impl StudyPoint {
    /// Wall time (s) per simulated second, if measured.
    pub fn wall_per_sim_second(&self) -> Option<f64> {
        self.wall_per_tick.map(|w| w.as_secs_f64() / self.dt)
    }
}

/// Everything a study found.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyReport {
    /// Scene name.
    pub scene: String,
    /// Sim time of tick 0 (s).
    pub start_time: f64,
    /// Sim time (s) the runs reach.
    pub until: f64,
    /// Whether this binary is a release build (wall times mean something only then).
    pub release: bool,
    /// The reference used for each dt, in `dts` order: what it was and its own error estimate.
    pub references: Vec<Reference>,
    /// One point per (dt, integrator), dt-major in the order given.
    pub points: Vec<StudyPoint>,
    /// Observed order per integrator, in the order given.
    pub orders: Vec<(Integrator, OrderFit)>,
    /// The tolerance asked for (m), and the index in `points` of the cheapest setting meeting
    /// it (None if none does).
    pub cheapest: Option<(f64, Option<usize>)>,
    /// Pre-check warning lines ([`precheck_lines`]).
    pub warnings: Vec<String>,
}

/// Progress of a study, for a progress bar.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// Runs finished.
    pub done: u64,
    /// Runs in all (references included).
    pub total: u64,
    /// What runs next.
    pub message: String,
}

/// Why a study could not run.
#[derive(Clone, Debug, PartialEq)]
pub enum StudyError {
    /// The integrator list is empty.
    NoIntegrators,
    /// The step list is empty.
    NoSteps,
    /// A step (or a reference's substep count) the scene refuses; names the field.
    Value(InvalidValue),
    /// An integrator of the list the scene's forces refuse.
    Integrator(IntegratorError),
    /// The final time is not finite or not after the scene's start.
    Until {
        /// The scene's start time (s).
        start: f64,
        /// The final time asked for (s).
        until: f64,
    },
    /// The tolerance is not a finite number > 0.
    Tolerance(f64),
    /// No energy window or no sample asked for.
    NoSamples,
    /// The run of a reference failed.
    Reference {
        /// The reference's integrator.
        integrator: Integrator,
        /// Its substeps per tick.
        substeps: u32,
        /// The step it serves (s).
        dt: f64,
        /// Why it stopped.
        error: Box<LoopError>,
    },
    /// The extrapolation reference could not follow a body.
    Extrapolation {
        /// The body's id.
        body: u64,
        /// Why it stopped.
        error: ExtrapolationError,
    },
    /// The shard is not one of its count (`index < count`, `count >= 1`).
    Shard(Shard),
    /// A timed repeat of a run failed where the measured run did not.
    TimedRun(Box<LoopError>),
    /// A measured run stopped for another reason than divergence (a divergence is an outcome).
    Run(Box<LoopError>),
}

impl std::fmt::Display for StudyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StudyError::NoIntegrators => f.write_str("integrators: expected at least one"),
            StudyError::NoSteps => f.write_str("dt: expected at least one step"),
            StudyError::Value(e) => write!(f, "{e}"),
            StudyError::Integrator(e) => write!(f, "integrators: {e}"),
            StudyError::Until { start, until } => write!(
                f,
                "until: expected a finite time after the scene's start {start} s, got {until}"
            ),
            StudyError::Tolerance(t) => {
                write!(f, "tolerance: expected a finite number > 0 (m), got {t}")
            }
            StudyError::NoSamples => f.write_str("energy windows and samples: expected at least 1"),
            StudyError::Reference {
                integrator,
                substeps,
                dt,
                error,
            } => write!(
                f,
                "the {integrator} reference ({substeps} substeps per tick at dt = {dt} s) failed: \
                 {error}; study smaller steps"
            ),
            StudyError::Extrapolation { body, error } => write!(
                f,
                "the extrapolation reference failed on body {body}: {error}; study a shorter span"
            ),
            StudyError::Shard(s) => write!(
                f,
                "shard: expected I/N with 0 <= I < N, got {}/{}",
                s.index, s.count
            ),
            StudyError::TimedRun(e) => {
                write!(f, "a timed run failed where the measured one did not: {e}")
            }
            StudyError::Run(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for StudyError {}

/// Validates `config` against `scene`: non-empty lists, valid steps, integrators the scene
/// allows, a final time after the start.
pub fn validate(scene: &Scene, config: &StudyConfig) -> Result<(), StudyError> {
    if config.integrators.is_empty() {
        return Err(StudyError::NoIntegrators);
    }
    if config.dts.is_empty() {
        return Err(StudyError::NoSteps);
    }
    for &dt in &config.dts {
        scene.clone().set_dt(dt).map_err(StudyError::Value)?;
    }
    for &i in &config.integrators {
        volley_sim::internals::scene::check_integrator(i, scene.forces())
            .map_err(StudyError::Integrator)?;
    }
    if !(config.until.is_finite() && config.until > scene.start_time()) {
        return Err(StudyError::Until {
            start: scene.start_time(),
            until: config.until,
        });
    }
    if let Some(t) = config.tolerance
        && !(t.is_finite() && t > 0.0)
    {
        return Err(StudyError::Tolerance(t));
    }
    if config.energy_windows == 0 || config.max_samples == 0 {
        return Err(StudyError::NoSamples);
    }
    Ok(())
}

/// Runs the study on this machine: every point of every dt. `progress` is called before each
/// run, from whichever thread runs it.
pub fn run(
    scene: &Scene,
    config: &StudyConfig,
    progress: &mut (dyn FnMut(Progress) + Send),
) -> Result<StudyReport, StudyError> {
    let whole = run_shard(scene, config, Shard::WHOLE, progress)?;
    let references = whole.references.into_iter().map(|(_, r)| r).collect();
    let points = whole.points.into_iter().map(|(_, p)| p).collect();
    Ok(report(&whole.study, whole.header, references, points))
}

/// What [`run`] tells `progress`, shared by the threads of the error runs.
struct Tally<'a> {
    progress: &'a mut (dyn FnMut(Progress) + Send),
    done: u64,
    total: u64,
}

impl Tally<'_> {
    fn tell(cell: &Mutex<Tally<'_>>, message: String) {
        // A poisoned lock means a progress callback panicked; the count is still usable.
        let mut t = cell.lock().unwrap_or_else(|e| e.into_inner());
        let progress = Progress {
            done: t.done,
            total: t.total,
            message,
        };
        (t.progress)(progress);
        t.done += 1;
    }
}

/// Measures the points of `shard` (point `k` of the dt-major (dt, integrator) list belongs to
/// shard `k mod count`) and the references they need. The error runs of one dt run in
/// parallel after its reference; the timed runs follow, serially, in point order.
pub fn run_shard(
    scene: &Scene,
    config: &StudyConfig,
    shard: Shard,
    progress: &mut (dyn FnMut(Progress) + Send),
) -> Result<ShardResult, StudyError> {
    validate(scene, config)?;
    if !shard.is_valid() {
        return Err(StudyError::Shard(shard));
    }
    let per_dt = config.integrators.len();
    let owned: Vec<usize> = (0..config.dts.len() * per_dt)
        .filter(|&k| shard.owns(k))
        .collect();
    let mut needed: Vec<usize> = owned.iter().map(|k| k / per_dt).collect();
    needed.dedup();
    let tally = Mutex::new(Tally {
        progress,
        done: 0,
        total: (needed.len() + owned.len()) as u64,
    });
    let finest = config.dts.iter().copied().fold(f64::INFINITY, f64::min);
    let (mut references, mut measured) = (Vec::new(), Vec::new());
    for &d in &needed {
        let mut at_dt = scene.clone();
        at_dt.set_dt(config.dts[d]).map_err(StudyError::Value)?;
        let ticks = at_dt.ticks_until(config.until).max(1);
        let stride = ticks.div_ceil(config.max_samples).max(1);
        let dt_text = output::sci(at_dt.dt());
        Tally::tell(&tally, format!("reference at dt = {dt_text}"));
        let trajectory = reference::build(&at_dt, ticks, stride, finest)?;
        let check = stability::check_at(&at_dt, at_dt.dt(), at_dt.substeps(), at_dt.integrator());
        let here: Vec<usize> = owned.iter().copied().filter(|k| k / per_dt == d).collect();
        let one = |k: usize| -> Result<(usize, StudyPoint, Scene), StudyError> {
            let integrator = config.integrators[k % per_dt];
            Tally::tell(&tally, format!("{integrator} at dt = {dt_text}"));
            let mut run_scene = at_dt.clone();
            run_scene
                .set_integrator(integrator)
                .map_err(StudyError::Integrator)?;
            let mut point = measure::run_point(&run_scene, ticks, stride, &trajectory, config)?;
            point.precheck = precheck_of(&check, integrator);
            Ok((k, point, run_scene))
        };
        // Collected in point order, and the first error in that order wins, whatever the
        // scheduling.
        let results: Vec<_> = here.into_par_iter().map(one).collect();
        for result in results {
            measured.push(result?);
        }
        references.push((d, trajectory.reference));
    }
    if config.timing {
        let completed = measured
            .iter()
            .filter(|(_, p, _)| p.outcome == Outcome::Completed)
            .count();
        tally.lock().unwrap_or_else(|e| e.into_inner()).total += completed as u64;
        for (_, point, run_scene) in &mut measured {
            if point.outcome != Outcome::Completed {
                continue;
            }
            let message = format!(
                "timing {} at dt = {}",
                point.integrator,
                output::sci(point.dt)
            );
            Tally::tell(&tally, message);
            let (wall, repeats) = time_runs(run_scene, point.ticks, config)?;
            (point.wall_per_tick, point.repeats) = (Some(wall), repeats);
        }
    }
    Ok(ShardResult {
        format: shard::FORMAT.into(),
        version: shard::VERSION,
        shard,
        study: shard::StudyIdentity {
            scene: scene.name().to_string(),
            source: scene.source().to_string(),
            substeps: scene.substeps(),
            config: config.clone(),
        },
        header: shard::Header {
            start_time: scene.start_time(),
            release: !cfg!(debug_assertions),
            warnings: precheck_lines(scene, config),
        },
        references,
        points: measured.into_iter().map(|(k, p, _)| (k, p)).collect(),
    })
}

/// The report of a complete set of points (dt-major) and references (in `dts` order): the
/// observed orders and the cheapest setting are fitted over all of them.
pub(crate) fn report(
    study: &shard::StudyIdentity,
    header: shard::Header,
    references: Vec<Reference>,
    points: Vec<StudyPoint>,
) -> StudyReport {
    let config = &study.config;
    let orders = config
        .integrators
        .iter()
        .map(|&i| (i, fit::observed_order(&points, i, &references)))
        .collect();
    let cheapest = config.tolerance.map(|t| (t, fit::cheapest(&points, t)));
    StudyReport {
        scene: study.scene.clone(),
        start_time: header.start_time,
        until: config.until,
        release: header.release,
        references,
        points,
        orders,
        cheapest,
        warnings: header.warnings,
    }
}

/// The pre-check of a whole study, as warning lines: the stiffness once, then for each
/// integrator outside its linear stability region at some studied dt, which dts, and the fixes
/// at the largest of them. Empty when every point is stable.
pub fn precheck_lines(scene: &Scene, config: &StudyConfig) -> Vec<String> {
    let mut lines = Vec::new();
    for &integrator in &config.integrators {
        let mut unstable = Vec::new();
        for &dt in &config.dts {
            let mut at_dt = scene.clone();
            if at_dt.set_dt(dt).is_err() {
                continue;
            }
            let report = stability::check_at(&at_dt, at_dt.dt(), at_dt.substeps(), integrator);
            if report.verdict(integrator).is_some_and(|v| !v.stable) {
                unstable.push(report);
            }
        }
        let Some(largest) = unstable.iter().max_by(|a, b| a.dt.total_cmp(&b.dt)) else {
            continue;
        };
        if lines.is_empty()
            && let Some(first) = largest.warnings().into_iter().next()
        {
            lines.push(first);
        }
        let dts: Vec<String> = unstable.iter().map(|r| output::sci(r.dt)).collect();
        let worst = unstable
            .iter()
            .filter_map(|r| r.verdict(integrator).map(|v| v.growth))
            .fold(1.0, f64::max);
        lines.push(format!(
            "pre-check: {integrator} is outside its linear stability region at dt = {} \
             (amplitude up to {} per step): expect those runs to grow without bound",
            dts.join(", "),
            stability::growth_text(worst)
        ));
        if let Some(v) = largest.verdict(integrator) {
            lines.push(format!(
                "  fix at dt = {}: {}",
                output::sci(largest.dt),
                largest.fixes(v).join(", or ")
            ));
        }
    }
    lines
}

fn precheck_of(check: &stability::StabilityReport, integrator: Integrator) -> stability::Growth {
    check.verdict(integrator).map_or(
        stability::Growth {
            rho: 1.0,
            stable: true,
        },
        |v| stability::Growth {
            rho: v.growth,
            stable: v.stable,
        },
    )
}

/// Median wall time per tick over repeated samples, and the number of samples. A sample is
/// `k` back-to-back runs with no observer, `k` chosen so one sample lasts at least a
/// millisecond (a 27-tick run alone is too short for the clock to time).
fn time_runs(
    scene: &Scene,
    ticks: u64,
    config: &StudyConfig,
) -> Result<(Duration, u32), StudyError> {
    let once = || -> Result<Duration, StudyError> {
        let mut sim = SimLoop::new(World::new(scene));
        let mut clock = VirtualClock::Steady(scene.timestep());
        let t0 = Instant::now();
        let result = sim.run_until(ticks, &mut clock, &mut ());
        let elapsed = t0.elapsed();
        result.map_err(|e| StudyError::TimedRun(Box::new(e)))?;
        Ok(elapsed)
    };
    let first = once()?.max(Duration::from_nanos(1));
    let k = (Duration::from_millis(1).as_nanos() / first.as_nanos()).clamp(1, 10_000) as u32;
    let mut samples = Vec::new();
    let started = Instant::now();
    while samples.len() < config.min_repeats.max(1) as usize
        || (started.elapsed() < config.timing_budget && samples.len() < 25)
    {
        let mut total = Duration::ZERO;
        for _ in 0..k {
            total += once()?;
        }
        let runs_ticks = u128::from(k) * u128::from(ticks);
        samples.push(Duration::from_nanos((total.as_nanos() / runs_ticks) as u64));
    }
    samples.sort();
    Ok((samples[samples.len() / 2], samples.len() as u32))
}

/// The loop error of a run, as a study error (divergence is an outcome, not an error).
pub(crate) fn loop_error(e: LoopError) -> Result<Divergence, StudyError> {
    match e {
        LoopError::Diverged(d) => Ok(d),
        other => Err(StudyError::Run(Box::new(other))),
    }
}

#[cfg(test)]
mod tests;
