//! The loop lab's sweep: every loop policy x display x tick rate x integrator x subject x phase,
//! each run measuring every draw mode, on all cores, reported in a fixed order.

use std::collections::BTreeMap;
use std::time::Duration;

use rayon::prelude::*;

use crate::study::shard::Shard;
use volley_sim::internals::clock::LoopPolicy;
use volley_sim::internals::integrate::Integrator;
use volley_sim::internals::sim_loop::LoopError;

use super::lab::{DrawMode, RunConfig, Subject, run};
use super::metrics::Metrics;
use super::{DisplayModel, DisplayTiming};

/// A display the sweep runs under, or the window emulates: its timing and the refresh interval
/// a game believes in.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepDisplay {
    /// The name the tables use.
    pub name: String,
    /// Its presents.
    pub timing: DisplayTiming,
    /// The refresh interval the snapping and quantising policies are given.
    pub refresh: Duration,
    /// Whether it is a capture (the default is chosen over the models only).
    pub capture: bool,
}

impl SweepDisplay {
    /// A bundled model, `seconds` long.
    pub fn model(name: &str, model: &DisplayModel, seconds: f64) -> SweepDisplay {
        SweepDisplay {
            name: name.to_string(),
            timing: model.timing(name, seconds),
            refresh: model.believed_refresh(),
            capture: false,
        }
    }

    /// A capture: the refresh believed is its median display interval rounded to whole hertz.
    pub fn capture(name: &str, timing: DisplayTiming) -> SweepDisplay {
        let interval = timing
            .median_display_interval()
            .unwrap_or(Duration::from_nanos(16_666_667));
        let hz = 1e9 / interval.as_nanos().max(1) as f64;
        SweepDisplay {
            name: name.to_string(),
            timing,
            refresh: super::display::believed_refresh(hz),
            capture: true,
        }
    }
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The displays.
    pub displays: Vec<SweepDisplay>,
    /// Tick rates (Hz).
    pub rates: Vec<f64>,
    /// Loop policies by name ([`LoopPolicy::NAMES`]).
    pub policies: Vec<&'static str>,
    /// Integrators.
    pub integrators: Vec<Integrator>,
    /// Subjects.
    pub subjects: Vec<Subject>,
    /// Starting phases of the tick grid against the frames (see [`RunConfig::phase`]).
    pub phases: Vec<f64>,
}

/// Tick rates the bundled sweep runs: 30, 60, Bevy's 64 and 120 Hz.
pub const RATES: [f64; 4] = [30.0, 60.0, 64.0, 120.0];
/// Phases the bundled sweep runs: on a tick boundary and midway.
pub const PHASES: [f64; 2] = [0.0, 0.5];
/// Seconds of display timing the bundled models produce: enough for three and a half beats of
/// a 60 Hz loop on a 59.94 Hz display (one every 16.7 s).
pub const SECONDS: f64 = 60.0;

impl Sweep {
    /// The bundled sweep over `displays`: every policy, [`RATES`], velocity Verlet and the
    /// exact integrator, both subjects, [`PHASES`].
    pub fn bundled(displays: Vec<SweepDisplay>) -> Sweep {
        Sweep {
            displays,
            rates: RATES.to_vec(),
            policies: LoopPolicy::NAMES.to_vec(),
            integrators: vec![Integrator::VelocityVerlet, Integrator::Exact],
            subjects: Subject::ALL.to_vec(),
            phases: PHASES.to_vec(),
        }
    }

    /// The bundled display models, `seconds` long.
    pub fn bundled_displays(seconds: f64) -> Vec<SweepDisplay> {
        DisplayModel::bundled()
            .iter()
            .map(|(n, m)| SweepDisplay::model(n, m, seconds))
            .collect()
    }

    /// Every combination, in the sweep's own order (display, rate, policy, integrator,
    /// subject, phase, the last varying fastest): job `k` of this list is the one shards
    /// number.
    pub fn jobs(&self) -> Vec<Job> {
        let mut jobs = Vec::new();
        for d in 0..self.displays.len() {
            for &rate in &self.rates {
                for &policy in &self.policies {
                    for &integrator in &self.integrators {
                        for &subject in &self.subjects {
                            for &phase in &self.phases {
                                jobs.push(Job {
                                    display: d,
                                    rate,
                                    policy,
                                    integrator,
                                    subject,
                                    phase,
                                });
                            }
                        }
                    }
                }
            }
        }
        jobs
    }

    /// Runs every combination, on all cores; the rows come back in the sweep's own order
    /// ([`Sweep::jobs`]), whatever the scheduling.
    pub fn run(&self) -> Result<Vec<Row>, LoopError> {
        Ok(self
            .run_shard(Shard::WHOLE)?
            .into_iter()
            .map(|(_, row)| row)
            .collect())
    }

    /// Runs the jobs `shard` owns (job `k` when `k mod count == index`), on all cores: each
    /// with its job number, in order.
    pub fn run_shard(&self, shard: Shard) -> Result<Vec<(usize, Row)>, LoopError> {
        let jobs: Vec<(usize, Job)> = self
            .jobs()
            .into_iter()
            .enumerate()
            .filter(|(k, _)| shard.owns(*k))
            .collect();
        jobs.par_iter()
            .map(|(k, job)| self.run_job(job).map(|row| (*k, row)))
            .collect()
    }

    fn run_job(&self, job: &Job) -> Result<Row, LoopError> {
        let display = &self.displays[job.display];
        let policy = LoopPolicy::from_name(job.policy, display.refresh)
            .expect("sweep policies are named from LoopPolicy::NAMES");
        let config = RunConfig {
            subject: job.subject,
            rate: job.rate,
            integrator: job.integrator,
            policy,
            phase: job.phase,
        };
        run(&config, &display.timing).map(|metrics| Row {
            display: display.name.clone(),
            capture: display.capture,
            rate: job.rate,
            policy: job.policy,
            integrator: job.integrator,
            subject: job.subject,
            phase: job.phase,
            metrics,
        })
    }
}

/// One combination of the sweep: which display (by index), rate, policy, integrator, subject
/// and phase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Job {
    /// Index into [`Sweep::displays`].
    pub display: usize,
    /// Tick rate (Hz).
    pub rate: f64,
    /// Policy name.
    pub policy: &'static str,
    /// Integrator.
    pub integrator: Integrator,
    /// Subject.
    pub subject: Subject,
    /// Phase.
    pub phase: f64,
}

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Display name.
    pub display: String,
    /// Whether the display is a capture.
    pub capture: bool,
    /// Tick rate (Hz).
    pub rate: f64,
    /// Policy name.
    pub policy: &'static str,
    /// Integrator.
    pub integrator: Integrator,
    /// Subject.
    pub subject: Subject,
    /// Phase.
    pub phase: f64,
    /// What it measured.
    pub metrics: Metrics,
}

/// One cell of the summary: a display, rate, policy and draw mode, with the metrics of the
/// worse phase (a game cannot choose when it starts): the row whose p99 display error is the
/// larger, and the larger latency and drift of the phases, each taken on its own (the phase
/// that is worse for error need not be worse for latency).
#[derive(Clone, Debug)]
pub struct Cell<'a> {
    /// The row of the phase with the larger p99 display error.
    pub row: &'a Row,
    /// The draw mode.
    pub mode: DrawMode,
    /// The larger median latency of the phases (ms).
    pub latency: f64,
    /// The larger |drift growth| of the phases (ms).
    pub drift_growth: f64,
    /// The larger worst |drift| of the phases (ms).
    pub drift_worst: f64,
    /// The larger worst |drift + dropped| of the phases (ms): see [`Metrics::drift_kept`].
    pub drift_kept: f64,
    /// The more frames drawn inside a surface of the phases.
    pub inside_frames: u64,
    /// The deeper of the phases' deepest (m).
    pub inside_depth: f64,
}

impl Cell<'_> {
    /// The draw mode's metrics in that row.
    pub fn metrics(&self) -> &super::metrics::ModeMetrics {
        self.row.metrics.mode(self.mode)
    }
}

/// The summary cells of `rows` for one subject and integrator: per display, rate, policy and
/// draw mode, the phase with the larger p99 display error.
pub fn cells(rows: &[Row], subject: Subject, integrator: Integrator) -> Vec<Cell<'_>> {
    let mut out: Vec<Cell<'_>> = Vec::new();
    // Where each (display, rate, policy, draw mode) cell is in `out`, so a sweep of thousands of
    // rows is one pass, in the order cells first appear.
    let mut at: BTreeMap<(&str, u64, &str, DrawMode), usize> = BTreeMap::new();
    for row in rows
        .iter()
        .filter(|r| r.subject == subject && r.integrator == integrator)
    {
        for mode in DrawMode::ALL {
            let key = (row.display.as_str(), row.rate.to_bits(), row.policy, mode);
            let same = at.get(&key).map(|&k| &mut out[k]);
            let m = &row.metrics;
            match same {
                Some(c) => {
                    if m.mode(mode).error.p99 > c.metrics().error.p99 {
                        c.row = row;
                    }
                    c.latency = c.latency.max(m.mode(mode).latency.median);
                    c.drift_growth = c.drift_growth.max(m.drift_growth.abs());
                    c.drift_worst = c.drift_worst.max(m.drift_worst);
                    c.drift_kept = c.drift_kept.max(m.drift_kept);
                    c.inside_frames = c.inside_frames.max(m.mode(mode).inside_frames);
                    c.inside_depth = c.inside_depth.max(m.mode(mode).inside_depth);
                }
                None => {
                    at.insert(key, out.len());
                    out.push(Cell {
                        row,
                        mode,
                        latency: m.mode(mode).latency.median,
                        drift_growth: m.drift_growth.abs(),
                        drift_worst: m.drift_worst,
                        drift_kept: m.drift_kept,
                        inside_frames: m.mode(mode).inside_frames,
                        inside_depth: m.mode(mode).inside_depth,
                    });
                }
            }
        }
    }
    out
}

/// A candidate default: a policy and a draw mode, scored over the display models at one rate.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// Policy name.
    pub policy: &'static str,
    /// Draw mode.
    pub mode: DrawMode,
    /// Mean over the display models of the p99 display error (m).
    pub p99_error: f64,
    /// Mean over the display models of the median latency (ms).
    pub latency: f64,
    /// Largest |game time + dropped - wall time| over the models (ms): the drift the policy
    /// causes ([`Metrics::drift_kept`]).
    pub drift: f64,
    /// Whether it meets the constraints: latency no more than the plain accumulator with
    /// interpolation, and the drift the policy causes within one tick on every model.
    pub admissible: bool,
}

/// Every policy x draw mode scored at `rate` on `subject` under `integrator`, best admissible
/// first: the lowest mean p99 display error over the display models (captures excluded), at no
/// more mean median latency than the plain accumulator with interpolation (today's window), and
/// with the drift the policy causes ([`Metrics::drift_kept`]) within one tick on every model.
/// Latency and drift are each the worse of the phases, as the error is.
pub fn choose(rows: &[Row], rate: f64, subject: Subject, integrator: Integrator) -> Vec<Choice> {
    let cells = cells(rows, subject, integrator);
    let at = |policy: &str, mode: DrawMode| -> Vec<&Cell<'_>> {
        cells
            .iter()
            .filter(|c| {
                c.row.rate == rate && !c.row.capture && c.row.policy == policy && c.mode == mode
            })
            .collect()
    };
    let mean = |v: &[&Cell<'_>], f: &dyn Fn(&Cell<'_>) -> f64| {
        v.iter().map(|c| f(c)).sum::<f64>() / v.len().max(1) as f64
    };
    let baseline = at("accumulator", DrawMode::Interpolate);
    let base_latency = mean(&baseline, &|c| c.latency);
    let tick_ms = 1e3 / rate;
    let mut out = Vec::new();
    for policy in LoopPolicy::NAMES {
        for mode in DrawMode::ALL {
            let v = at(policy, mode);
            if v.is_empty() {
                continue;
            }
            let latency = mean(&v, &|c| c.latency);
            let drift = v.iter().map(|c| c.drift_kept).fold(0.0, f64::max);
            out.push(Choice {
                policy,
                mode,
                p99_error: mean(&v, &|c| c.metrics().error.p99),
                latency,
                drift,
                // A hundredth of a millisecond of slack: latencies are display times, equal in
                // exact arithmetic for policies that run the same ticks.
                admissible: latency <= base_latency + 0.01 && drift <= tick_ms,
            });
        }
    }
    out.sort_by(|a, b| {
        b.admissible
            .cmp(&a.admissible)
            .then(a.p99_error.total_cmp(&b.p99_error))
    });
    out
}

/// A candidate default scored over every subject of the sweep: see [`choose_all`].
#[derive(Clone, Debug, PartialEq)]
pub struct OverallChoice {
    /// Policy name.
    pub policy: &'static str,
    /// Draw mode.
    pub mode: DrawMode,
    /// Mean over the subjects of its mean-over-models p99 display error divided by
    /// `accumulator + predict`'s on the same subject (1 is predict's, lower is better).
    pub score: f64,
    /// Its score on each subject, in the sweep's subject order: `(subject, p99 ratio)`.
    pub per_subject: Vec<(Subject, f64)>,
    /// Most frames drawn inside a surface on any display, model or capture, and subject (the
    /// worse phase).
    pub inside_frames: u64,
    /// Whether it is admissible on every subject ([`choose`]'s latency and drift limits) and
    /// draws no frame inside a surface on any model.
    pub admissible: bool,
}

/// Every policy x draw mode scored at `rate` under `integrator` over every subject in `rows`,
/// best admissible first: the mean over subjects of its mean p99 display error over the display
/// models as a ratio to `accumulator + predict`'s on that subject (the subjects' scales differ
/// tenfold, so a plain mean would rank on the fastest one). Admissible: [`choose`]'s limits on
/// every subject, and not one frame drawn inside a surface on any display (captures too) and
/// subject.
pub fn choose_all(rows: &[Row], rate: f64, integrator: Integrator) -> Vec<OverallChoice> {
    let mut subjects: Vec<Subject> = Vec::new();
    for r in rows {
        if r.integrator == integrator && r.rate == rate && !subjects.contains(&r.subject) {
            subjects.push(r.subject);
        }
    }
    let per: Vec<(Subject, Vec<Choice>, Vec<Cell<'_>>)> = subjects
        .iter()
        .map(|&s| {
            (
                s,
                choose(rows, rate, s, integrator),
                cells(rows, s, integrator),
            )
        })
        .collect();
    let mut out = Vec::new();
    for policy in LoopPolicy::NAMES {
        for mode in DrawMode::ALL {
            let mut per_subject = Vec::new();
            let mut admissible = true;
            let mut inside_frames = 0;
            for (subject, ranking, cells) in &per {
                let find =
                    |p: &str, m: DrawMode| ranking.iter().find(|c| c.policy == p && c.mode == m);
                let (Some(c), Some(base)) =
                    (find(policy, mode), find("accumulator", DrawMode::Predict))
                else {
                    continue;
                };
                per_subject.push((
                    *subject,
                    c.p99_error / base.p99_error.max(f64::MIN_POSITIVE),
                ));
                admissible &= c.admissible;
                inside_frames = cells
                    .iter()
                    .filter(|k| k.row.rate == rate && k.row.policy == policy && k.mode == mode)
                    .map(|k| k.inside_frames)
                    .fold(inside_frames, u64::max);
            }
            if per_subject.is_empty() {
                continue;
            }
            let score = per_subject.iter().map(|(_, r)| r).sum::<f64>() / per_subject.len() as f64;
            out.push(OverallChoice {
                policy,
                mode,
                score,
                per_subject,
                inside_frames,
                admissible: admissible && inside_frames == 0,
            });
        }
    }
    out.sort_by(|a, b| {
        b.admissible
            .cmp(&a.admissible)
            .then(a.score.total_cmp(&b.score))
    });
    out
}
