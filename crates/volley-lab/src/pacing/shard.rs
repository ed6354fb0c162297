//! A loop-lab sweep split over machines, as a study is ([`crate::study::shard`]): each shard
//! runs a fixed share of the sweep's jobs and writes them; the merge checks the shards are one
//! complete sweep and gives back its rows, equal to the one-machine run's.
//!
//! The partition is round-robin over [`Sweep::jobs`]: job `k` belongs to shard `k mod n`,
//! shards numbered from 0 (`SLURM_ARRAY_TASK_ID`, `JOB_COMPLETION_INDEX`). A shard carries what
//! identifies the sweep ([`SweepIdentity`]: every display's name, kind and present count, the
//! rates, policies, integrators, subjects and phases) and its rows with their job numbers. The
//! reader checks that every row is the job its number says (display, rate, policy, integrator,
//! subject, phase); the merge refuses shards of another sweep, another shard count, duplicates
//! and gaps, with the study's words.
//!
//! The file is JSON (`serde_json` with `float_roundtrip`, so every float reads back to the bit)
//! with a fixed `format` tag and a [`VERSION`] that a reader of another version refuses.

use serde::{Deserialize, Serialize};

use crate::study::shard::{self as study_shard, MergeError, Shard, Shards, at};
use volley_sim::internals::clock::LoopPolicy;
use volley_sim::internals::integrate::Integrator;

use super::lab::Subject;
use super::metrics::Metrics;
use super::sweep::{Row, Sweep};

/// The `format` field of every pacing shard file.
pub const FORMAT: &str = "volley-pacing-shard";
/// The version of the file layout this build reads and writes.
pub const VERSION: u32 = 2;

/// One display of the sweep as a shard names it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DisplayIdentity {
    /// Its name in the tables.
    pub name: String,
    /// Whether it is a capture.
    pub capture: bool,
    /// How many presents its timing holds (a capture of another length is another sweep).
    pub presents: usize,
}

/// What makes two shards parts of the same sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepIdentity {
    /// The displays, in order.
    pub displays: Vec<DisplayIdentity>,
    /// Tick rates (Hz).
    pub rates: Vec<f64>,
    /// Loop policy names.
    pub policies: Vec<String>,
    /// Integrators.
    pub integrators: Vec<Integrator>,
    /// Subjects.
    pub subjects: Vec<Subject>,
    /// Phases.
    pub phases: Vec<f64>,
}

impl SweepIdentity {
    /// The identity of `sweep`.
    pub fn of(sweep: &Sweep) -> SweepIdentity {
        SweepIdentity {
            displays: sweep
                .displays
                .iter()
                .map(|d| DisplayIdentity {
                    name: d.name.clone(),
                    capture: d.capture,
                    presents: d.timing.presents.len(),
                })
                .collect(),
            rates: sweep.rates.clone(),
            policies: sweep.policies.iter().map(|p| p.to_string()).collect(),
            integrators: sweep.integrators.clone(),
            subjects: sweep.subjects.clone(),
            phases: sweep.phases.clone(),
        }
    }

    /// How many jobs the sweep has.
    pub fn jobs(&self) -> usize {
        self.displays.len()
            * self.rates.len()
            * self.policies.len()
            * self.integrators.len()
            * self.subjects.len()
            * self.phases.len()
    }

    /// Job `k`'s display index, rate, policy, integrator, subject and phase, in
    /// [`Sweep::jobs`] order (the phase varying fastest).
    fn job(&self, k: usize) -> (usize, f64, &str, Integrator, Subject, f64) {
        let mut k = k;
        let mut take = |n: usize| {
            let i = k % n;
            k /= n;
            i
        };
        let phase = take(self.phases.len());
        let subject = take(self.subjects.len());
        let integrator = take(self.integrators.len());
        let policy = take(self.policies.len());
        let rate = take(self.rates.len());
        let display = take(self.displays.len());
        (
            display,
            self.rates[rate],
            &self.policies[policy],
            self.integrators[integrator],
            self.subjects[subject],
            self.phases[phase],
        )
    }
}

/// One row as a shard file holds it (the policy by name).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RowRecord {
    /// Display name.
    pub display: String,
    /// Whether the display is a capture.
    pub capture: bool,
    /// Tick rate (Hz).
    pub rate: f64,
    /// Policy name.
    pub policy: String,
    /// Integrator.
    pub integrator: Integrator,
    /// Subject.
    pub subject: Subject,
    /// Phase.
    pub phase: f64,
    /// What it measured.
    pub metrics: Metrics,
}

impl RowRecord {
    fn of(row: &Row) -> RowRecord {
        RowRecord {
            display: row.display.clone(),
            capture: row.capture,
            rate: row.rate,
            policy: row.policy.to_string(),
            integrator: row.integrator,
            subject: row.subject,
            phase: row.phase,
            metrics: row.metrics.clone(),
        }
    }

    /// The row, its policy named from [`LoopPolicy::NAMES`] (the reader checked it is one).
    fn row(&self) -> Row {
        let policy = LoopPolicy::NAMES
            .into_iter()
            .find(|p| *p == self.policy)
            .unwrap_or(LoopPolicy::NAMES[0]);
        Row {
            display: self.display.clone(),
            capture: self.capture,
            rate: self.rate,
            policy,
            integrator: self.integrator,
            subject: self.subject,
            phase: self.phase,
            metrics: self.metrics.clone(),
        }
    }
}

/// The rows of one shard, as written to its file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PacingShard {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`] of the writer.
    pub version: u32,
    /// Which shard this is.
    pub shard: Shard,
    /// The sweep it is a part of.
    pub sweep: SweepIdentity,
    /// Its rows by job number, in that order.
    pub rows: Vec<(usize, RowRecord)>,
}

impl PacingShard {
    /// Runs the jobs of `sweep` that `shard` owns.
    pub fn run(
        sweep: &Sweep,
        shard: Shard,
    ) -> Result<PacingShard, volley_sim::internals::sim_loop::LoopError> {
        let rows = sweep
            .run_shard(shard)?
            .iter()
            .map(|(k, row)| (*k, RowRecord::of(row)))
            .collect();
        Ok(PacingShard {
            format: FORMAT.to_string(),
            version: VERSION,
            shard,
            sweep: SweepIdentity::of(sweep),
            rows,
        })
    }

    /// The file's text: pretty JSON with a trailing newline.
    pub fn to_json(&self) -> String {
        study_shard::to_json(self)
    }

    /// Reads a shard file's text; `file` labels the errors. Refuses another format or version
    /// before reading the rest, and a file whose rows are not the jobs its shard owns.
    pub fn from_json(text: &str, file: &str) -> Result<PacingShard, MergeError> {
        let part: PacingShard = study_shard::from_json(text, file, FORMAT, VERSION, "pacing")?;
        part.check(file)?;
        Ok(part)
    }

    /// Whether the file is consistent with itself: a valid shard of a non-empty sweep of known
    /// policies, holding exactly its jobs, each the job its number says.
    fn check(&self, file: &str) -> Result<(), MergeError> {
        let Shard { index, count } = self.shard.checked(file)?;
        let sweep = &self.sweep;
        if let Some(p) = sweep
            .policies
            .iter()
            .find(|p| !LoopPolicy::NAMES.contains(&p.as_str()))
        {
            return Err(at(
                file,
                format!(
                    "sweep.policies: unknown `{p}`, expected one of {}",
                    LoopPolicy::NAMES.join(", ")
                ),
            ));
        }
        // Checked before the product, which could overflow for a forged file.
        let lens = [
            sweep.displays.len(),
            sweep.rates.len(),
            sweep.policies.len(),
            sweep.integrators.len(),
            sweep.subjects.len(),
            sweep.phases.len(),
        ];
        let total = lens.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
        // A shard of `count` holds at most ceil(total / count) jobs, so a sweep past
        // (rows + 1) x count jobs cannot be the one its rows are of.
        let most = (self.rows.len() + 1).saturating_mul(count as usize);
        let Some(total) = total.filter(|&t| t > 0 && t <= most) else {
            return Err(at(
                file,
                format!(
                    "the sweep of {lens:?} displays, rates, policies, integrators, subjects and \
                     phases is empty or more than its {count} shards' rows can hold"
                ),
            ));
        };
        let owned = (0..total).filter(|&k| self.shard.owns(k));
        let held = self.rows.iter().map(|(k, _)| *k);
        if !owned.clone().eq(held) {
            return Err(at(
                file,
                format!(
                    "shard {index}/{count} of a sweep of {total} jobs should hold jobs {}, it \
                     holds {} rows",
                    ranges(owned.collect()),
                    self.rows.len()
                ),
            ));
        }
        for (k, r) in &self.rows {
            let (d, rate, policy, integrator, subject, phase) = sweep.job(*k);
            let display = &sweep.displays[d];
            let same = r.display == display.name
                && r.capture == display.capture
                && r.rate.to_bits() == rate.to_bits()
                && r.policy == policy
                && r.integrator == integrator
                && r.subject == subject
                && r.phase.to_bits() == phase.to_bits();
            if !same {
                return Err(at(
                    file,
                    format!(
                        "rows: job {k} should be {} at {rate} Hz, {policy}, {}, {}, phase \
                         {phase}; it holds {} at {} Hz, {}, {}, {}, phase {}",
                        display.name,
                        integrator.name(),
                        subject.name(),
                        r.display,
                        r.rate,
                        r.policy,
                        r.integrator.name(),
                        r.subject.name(),
                        r.phase
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// `[0, 3, 6]` as `0, 3, 6` and long lists cut short.
fn ranges(jobs: Vec<usize>) -> String {
    let shown: Vec<String> = jobs.iter().take(8).map(usize::to_string).collect();
    if jobs.len() > 8 {
        format!("{}, ... ({} in all)", shown.join(", "), jobs.len())
    } else {
        shown.join(", ")
    }
}

/// Merges the shards `(file label, shard)` of one sweep into its rows, in the sweep's order.
/// Refuses (naming the file) a shard of another sweep or shard count, a shard given twice and
/// a missing shard.
pub fn merge(parts: &[(String, PacingShard)]) -> Result<Vec<Row>, MergeError> {
    let Some((first_file, first)) = parts.first() else {
        return Err(MergeError {
            file: None,
            message: "expected at least one shard file".into(),
        });
    };
    let mut shards = Shards::new(first_file, first.shard.count, "sweep");
    for (file, part) in parts {
        part.check(file)?;
        if part.sweep != first.sweep {
            return Err(at(
                file,
                format!(
                    "the sweep (displays, rates, policies, integrators, subjects, phases) \
                     differs from {first_file}'s: not a shard of the same sweep"
                ),
            ));
        }
        shards.add(file, part.shard)?;
    }
    shards.finish()?;
    let mut rows: Vec<(usize, Row)> = parts
        .iter()
        .flat_map(|(_, p)| p.rows.iter().map(|(k, r)| (*k, r.row())))
        .collect();
    // Every shard is present and holds exactly its jobs (checked above): sorted by job, the
    // rows are the sweep's, each once.
    rows.sort_by_key(|(k, _)| *k);
    Ok(rows.into_iter().map(|(_, r)| r).collect())
}
