//! What a failed check reports: the tick, the stage, every field with both values and their
//! bit patterns, and how the place was found.

use crate::hash::hex;
use crate::replay::diff::{FieldDiff, Value};
use crate::step::Stage;

/// One stage's hash in the two runs compared (`None` where a run has no hash for it: it
/// stopped before, or the stage was found without hashing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StageHashes {
    /// The stage.
    pub stage: Stage,
    /// The first run's hash after it.
    pub first: Option<u64>,
    /// The re-run's hash after it.
    pub rerun: Option<u64>,
}

impl StageHashes {
    /// A stage named without hashes (a restore compared field by field, a command that failed).
    pub(super) fn unhashed(stage: Stage) -> StageHashes {
        StageHashes {
            stage,
            first: None,
            rerun: None,
        }
    }
}

/// How a mismatch's place was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FoundBy {
    /// Every run was hashed stage by stage as it ran ([`crate::SyncTest::with_stage_hashes`]):
    /// the stage is where the first run and the re-run that disagree first parted.
    StageHashes,
    /// The failing window was searched: the restore done again and compared with the saved
    /// state, then each tick run twice more from the first run's state, stage by stage, once
    /// as the first run ran and once as the re-runs ran; the stage is where those two parted.
    ReExecuted,
    /// Two more runs of the tick agree at every stage but not with the first run: the first
    /// run saw something no later run sees (a one-off input, state outside the world that
    /// changed since). Stage hashes on every run name its stage.
    FirstRunAlone,
    /// The re-run itself stopped: a command the first run applied failed, or it diverged
    /// where the first run did not.
    ReRun,
    /// Only the failing re-run parted; every tick run again agrees with the first run, so the
    /// stage is unknown (a fault that does not repeat: stage hashes on every run name it).
    NotReproduced,
}

/// Where a re-run parted from the first run.
#[derive(Clone, Debug, PartialEq)]
pub struct SyncMismatch {
    /// The first tick whose state differs, as far as the checks could see.
    pub tick: u64,
    /// The first run's tick the failing check checked (the sync test stopped there).
    pub checked: u64,
    /// The tick the failing check restored and re-ran from.
    pub restored_from: u64,
    /// The sync test's check distance.
    pub check_distance: u32,
    /// Integrator steps per tick (the stages that repeat per substep name theirs).
    pub substeps: u32,
    /// The first stage that differs, with both runs' hashes after it, if it was found.
    pub stage: Option<StageHashes>,
    /// Every stage of the tick's step that both runs hashed, in order.
    pub stages: Vec<StageHashes>,
    /// How the stage was found.
    pub found_by: FoundBy,
    /// Every field that differs at `tick`: `recorded` is the first run's value (the saved
    /// state's, for the restore stage), `replayed` the re-run's (the restored one's).
    pub fields: Vec<FieldDiff>,
    /// What else the check knows: a command that failed, a divergence, a restore's refusal.
    pub note: Option<String>,
}

/// A field's value with its bit pattern.
fn with_bits(v: &Value) -> String {
    match v {
        Value::F64(x) => format!("{x:?} ({:#018x})", x.to_bits()),
        Value::U64(x) => format!("{x} ({x:#018x})"),
        Value::Text(t) => t.clone(),
        Value::Absent => "absent".into(),
    }
}

fn hash_or_none(h: Option<u64>) -> String {
    h.map_or_else(|| "-".into(), hex)
}

impl SyncMismatch {
    /// Which stage, as the report names it: with `substep k of n` when a tick has several.
    pub fn stage_name(&self) -> Option<String> {
        let s = self.stage?.stage;
        Some(match s.substep() {
            Some(k) if self.substeps > 1 => {
                format!("{} (substep {} of {})", s.name(), k + 1, self.substeps)
            }
            _ => s.name().to_string(),
        })
    }

    /// The two sides' names in the field lines.
    fn sides(&self) -> (&'static str, &'static str) {
        match self.stage.map(|s| s.stage) {
            Some(Stage::Restore) => ("saved", "restored"),
            _ => ("first run", "re-run"),
        }
    }

    /// One field as a line: body, field, both values with their bit patterns, their distance.
    pub fn field_line(&self, d: &FieldDiff) -> String {
        let (a, b) = self.sides();
        let mut line = match d.body {
            Some(id) => format!("body {id} {}", d.field),
            None => d.field.clone(),
        };
        line += &format!(
            ": {a} {}, {b} {}",
            with_bits(&d.recorded),
            with_bits(&d.replayed)
        );
        match d.ulps() {
            Some(1) => line += " (1 ulp apart)",
            Some(n) => line += &format!(" ({n} ulps apart)"),
            None => {}
        }
        line
    }

    /// The mismatch in one line: tick, stage, the first field.
    pub fn headline(&self) -> String {
        let mut out = format!("sync test mismatch at tick {}", self.tick);
        if let Some(stage) = self.stage_name() {
            out += &format!(", stage {stage}");
        }
        match self.fields.first() {
            Some(d) => out += &format!(": {}", self.field_line(d)),
            None => {
                if let Some(note) = &self.note {
                    out += &format!(": {note}");
                }
            }
        }
        out
    }

    /// The report as lines of text, listing at most `limit` fields (all for `None`).
    pub fn report(&self, limit: Option<usize>) -> String {
        let t = self.tick;
        let ran = self.checked - self.restored_from;
        let mut out = format!(
            "sync test mismatch at tick {t}: the check of tick {}, which restored tick {} and \
             re-ran {ran} tick{} (check distance {}), parts from the first run\n",
            self.checked,
            self.restored_from,
            if ran == 1 { "" } else { "s" },
            self.check_distance
        );
        if let Some(note) = &self.note {
            out += &format!("{note}\n");
        }
        match (self.stage, self.stage_name()) {
            (Some(s), Some(name)) if s.first.is_some() || s.rerun.is_some() => {
                out += &format!(
                    "first differing stage: {name} (stage hash {} in the first run, {} in the \
                     re-run)\n",
                    hash_or_none(s.first),
                    hash_or_none(s.rerun)
                );
            }
            (Some(_), Some(name)) => out += &format!("first differing stage: {name}\n"),
            _ => out += "first differing stage: not found\n",
        }
        out += match self.found_by {
            FoundBy::StageHashes => {
                "found by: the stage hashes of the first run and of the re-run, as they ran\n"
            }
            FoundBy::ReExecuted => {
                "found by: doing the restore again and running each tick twice more from the \
                 first run's state, stage by stage, as the first run ran and as the re-runs ran\n"
            }
            FoundBy::FirstRunAlone => {
                "found by: two more runs of the tick, which agree at every stage with each other \
                 but not with the first run: the first run saw something no later run sees (a \
                 one-off input, state outside the world changed since); stage hashes on every \
                 run (--stage-hashes) name its stage\n"
            }
            FoundBy::ReRun => "found by: the re-run, which stopped there\n",
            FoundBy::NotReproduced => {
                "not reproduced: every tick run again agrees with the first run, only the \
                 failing re-run differs; stage hashes on every run (--stage-hashes) name its \
                 stage\n"
            }
        };
        if !self.stages.is_empty() {
            out += &format!("stage hashes of the step to tick {t} (first run, re-run):\n");
            let first = self.stage.map(|s| s.stage);
            for s in &self.stages {
                let mark = if Some(s.stage) == first && s.first != s.rerun {
                    "  <- first difference"
                } else {
                    ""
                };
                out += &format!(
                    "  {:<24} {} {}{mark}\n",
                    s.stage.to_string(),
                    hash_or_none(s.first),
                    hash_or_none(s.rerun)
                );
            }
        }
        if self.fields.is_empty() {
            out += &format!("no field differs at tick {t} as the state hash compares them\n");
        } else {
            out += &format!("fields that differ at tick {t}:\n");
        }
        let shown = limit.unwrap_or(usize::MAX).min(self.fields.len());
        for d in &self.fields[..shown] {
            out += &format!("  {}\n", self.field_line(d));
        }
        if shown < self.fields.len() {
            out += &format!("  ... and {} more\n", self.fields.len() - shown);
        }
        out
    }
}
