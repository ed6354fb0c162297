//! A study split over machines: each shard measures a fixed share of the points and writes a
//! partial result; the merge checks the shards are one complete study and builds its report.
//!
//! The partition is round-robin over the dt-major (dt, integrator) list: point `k` (dt index
//! `k / integrators`, integrator index `k mod integrators`) belongs to shard `k mod n`, shards
//! numbered from 0 like `SLURM_ARRAY_TASK_ID` and `JOB_COMPLETION_INDEX`. Round-robin spreads
//! the expensive small dts over every shard. A shard carries only the references its points
//! need ([`super::Reference`], not the trajectory), its points with their indices, and what
//! identifies the study: the scene's name, verbatim text and substeps, and the whole
//! [`StudyConfig`]. The merge refuses shards of another study, another shard count, another
//! build profile, duplicates and gaps, and fits the observed orders and the cheapest setting
//! over all points, so its report equals the one-machine run's.
//!
//! The file is JSON (`serde_json` with `float_roundtrip`, so every float reads back to the bit)
//! with a fixed `format` tag and a [`VERSION`] that a reader of another version refuses.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{Reference, StudyConfig, StudyPoint, StudyReport};

/// The `format` field of every shard file.
pub const FORMAT: &str = "volley-study-shard";
/// The version of the shard file layout this build reads and writes.
pub const VERSION: u32 = 1;

/// Which share of a study's points a run measures: point `k` belongs to shard `k mod count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard's number, from 0.
    pub index: u32,
    /// How many shards the study is split into (at least 1).
    pub count: u32,
}

impl Shard {
    /// The whole study as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Whether `index < count` (so `count >= 1`).
    pub fn is_valid(self) -> bool {
        self.index < self.count
    }

    /// The shard itself if `index < count`, else the error naming `file`.
    pub(crate) fn checked(self, file: &str) -> Result<Shard, MergeError> {
        if self.is_valid() {
            Ok(self)
        } else {
            Err(at(
                file,
                format!(
                    "shard {}/{}: expected 0 <= index < count",
                    self.index, self.count
                ),
            ))
        }
    }

    /// Whether point `k` of the dt-major list is this shard's.
    pub fn owns(self, k: usize) -> bool {
        k % self.count as usize == self.index as usize
    }
}

/// What makes two shards parts of the same study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyIdentity {
    /// Scene name.
    pub scene: String,
    /// The scene file's text, verbatim.
    pub source: String,
    /// Integrator steps per tick the runs used (the scene's, or the command line's).
    pub substeps: u32,
    /// The study's configuration.
    pub config: StudyConfig,
}

/// What the report takes from the run itself rather than from the points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Sim time of tick 0 (s).
    pub start_time: f64,
    /// Whether a release build measured it.
    pub release: bool,
    /// The study's pre-check warning lines.
    pub warnings: Vec<String>,
}

/// The partial result of one shard, as written to its file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardResult {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`] of the writer.
    pub version: u32,
    /// Which shard this is.
    pub shard: Shard,
    /// The study it is a part of.
    pub study: StudyIdentity,
    /// Start time, build profile and pre-check lines.
    pub header: Header,
    /// The references its points need, by dt index, in `dts` order.
    pub references: Vec<(usize, Reference)>,
    /// Its points by index in the dt-major list, in that order.
    pub points: Vec<(usize, StudyPoint)>,
}

/// Why shard files could not be merged: one line, naming the file where one is to blame.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeError {
    /// The file at fault, if one is.
    pub file: Option<String>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl std::fmt::Display for MergeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.file {
            Some(file) => write!(f, "{file}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for MergeError {}

pub(crate) fn at(file: &str, message: impl Into<String>) -> MergeError {
    MergeError {
        file: Some(file.to_string()),
        message: message.into(),
    }
}

/// A shard file's text: pretty JSON with a trailing newline (the study's and the loop lab's).
pub(crate) fn to_json<T: Serialize>(value: &T) -> String {
    // Every key is a string and every value serialisable, so this cannot fail.
    let mut text = serde_json::to_string_pretty(value)
        .expect("a shard has string keys and serialisable values");
    text.push('\n');
    text
}

/// Reads a shard file of `format` at `version` (`what` names it in errors: "study", "pacing"),
/// refusing another format or version before reading the rest.
pub(crate) fn from_json<T: serde::de::DeserializeOwned>(
    text: &str,
    file: &str,
    format: &str,
    version: u32,
    what: &str,
) -> Result<T, MergeError> {
    let tag: Tag = serde_json::from_str(text).map_err(|e| {
        at(
            file,
            format!("expected a {what} shard file (JSON with format \"{format}\"): {e}"),
        )
    })?;
    if tag.format != format {
        return Err(at(
            file,
            format!("expected format \"{format}\", got \"{}\"", tag.format),
        ));
    }
    if tag.version != version {
        let label = if what == "study" {
            "shard"
        } else {
            "pacing shard"
        };
        return Err(at(
            file,
            format!(
                "{label} file version {}, this volley reads version {version}",
                tag.version
            ),
        ));
    }
    serde_json::from_str(text).map_err(|e| at(file, format!("not a valid {what} shard file: {e}")))
}

/// Whether the shards given are one complete set: one shard count, each index once, none
/// missing. Fed file by file ([`Shards::add`]) so the first file at fault is the one named.
pub(crate) struct Shards<'a> {
    first: &'a str,
    count: u32,
    what: &'a str,
    by_index: BTreeMap<u32, &'a str>,
}

impl<'a> Shards<'a> {
    /// A set whose first file, `first`, is one of `count` shards of a `what` ("study").
    pub(crate) fn new(first: &'a str, count: u32, what: &'a str) -> Shards<'a> {
        Shards {
            first,
            count,
            what,
            by_index: BTreeMap::new(),
        }
    }

    /// One more file: refused if it is of another shard count or given twice.
    pub(crate) fn add(&mut self, file: &'a str, shard: Shard) -> Result<(), MergeError> {
        let (count, first, what) = (self.count, self.first, self.what);
        if shard.count != count {
            return Err(at(
                file,
                format!(
                    "one of {} shards, {first} is one of {count}: not a shard of the same \
                     {what}",
                    shard.count
                ),
            ));
        }
        if let Some(other) = self.by_index.insert(shard.index, file) {
            return Err(at(
                file,
                format!("shard {}/{count} given twice (also {other})", shard.index),
            ));
        }
        Ok(())
    }

    /// Refused if a shard is missing.
    pub(crate) fn finish(&self) -> Result<(), MergeError> {
        let count = self.count;
        match (0..count).find(|i| !self.by_index.contains_key(i)) {
            None => Ok(()),
            Some(missing) => {
                let have: Vec<String> = self.by_index.keys().map(u32::to_string).collect();
                Err(MergeError {
                    file: None,
                    message: format!(
                        "missing shard {missing}/{count}: the files given hold shards {} of \
                         {count} (numbered from 0)",
                        have.join(", ")
                    ),
                })
            }
        }
    }
}

/// Just the fields that say what a file is, read before the rest.
#[derive(Deserialize)]
struct Tag {
    format: String,
    version: u32,
}

impl ShardResult {
    /// The file's text: pretty JSON with a trailing newline.
    pub fn to_json(&self) -> String {
        to_json(self)
    }

    /// Reads a shard file's text; `file` labels the errors. Refuses another format or version
    /// before reading the rest.
    pub fn from_json(text: &str, file: &str) -> Result<ShardResult, MergeError> {
        let result: ShardResult = from_json(text, file, FORMAT, VERSION, "study")?;
        result.check(file)?;
        Ok(result)
    }

    /// Whether the file is consistent with itself: a valid shard of a non-empty study, holding
    /// exactly its points and the references they need.
    fn check(&self, file: &str) -> Result<(), MergeError> {
        let Shard { index, count } = self.shard.checked(file)?;
        let config = &self.study.config;
        let per_dt = config.integrators.len();
        if per_dt == 0 || config.dts.is_empty() {
            return Err(at(file, "expected at least one integrator and one dt"));
        }
        let owned: Vec<usize> = (0..config.dts.len() * per_dt)
            .filter(|&k| self.shard.owns(k))
            .collect();
        let held: Vec<usize> = self.points.iter().map(|(k, _)| *k).collect();
        if held != owned {
            return Err(at(
                file,
                format!(
                    "shard {index}/{count} should hold points {owned:?} of the dt-major list, \
                     it holds {held:?}"
                ),
            ));
        }
        let mut needed: Vec<usize> = owned.iter().map(|k| k / per_dt).collect();
        needed.dedup();
        let refs: Vec<usize> = self.references.iter().map(|(d, _)| *d).collect();
        if refs != needed {
            return Err(at(
                file,
                format!("expected the references of dts {needed:?}, it holds {refs:?}"),
            ));
        }
        Ok(())
    }
}

/// Merges the shards `(file label, result)` of one study into its report. Refuses (naming the
/// file) a shard of another scene, configuration, shard count or build profile, a shard given
/// twice, a missing shard, and references that disagree between shards.
pub fn merge(parts: &[(String, ShardResult)]) -> Result<StudyReport, MergeError> {
    let Some((first_file, first)) = parts.first() else {
        return Err(MergeError {
            file: None,
            message: "expected at least one shard file".into(),
        });
    };
    let mut shards = Shards::new(first_file, first.shard.count, "study");
    for (file, part) in parts {
        part.check(file)?;
        let differs = |what: &str| {
            at(
                file,
                format!("{what} differs from {first_file}'s: not a shard of the same study"),
            )
        };
        if part.study.scene != first.study.scene || part.study.source != first.study.source {
            return Err(differs("the scene"));
        }
        if part.study.substeps != first.study.substeps {
            return Err(differs("the substeps per tick"));
        }
        if part.study.config != first.study.config {
            return Err(differs(
                "the study configuration (integrators, dts, until, options)",
            ));
        }
        if part.shard.count != first.shard.count {
            shards.add(file, part.shard)?;
        }
        if part.header != first.header {
            return Err(differs("the build profile, start time or pre-check"));
        }
        shards.add(file, part.shard)?;
    }
    shards.finish()?;
    let config = &first.study.config;
    let mut references: Vec<Option<(&str, Reference)>> = vec![None; config.dts.len()];
    let mut points: Vec<Option<StudyPoint>> =
        vec![None; config.dts.len() * config.integrators.len()];
    for (file, part) in parts {
        for (d, r) in &part.references {
            match references[*d] {
                Some((other, known)) if known != *r => {
                    return Err(at(
                        file,
                        format!(
                            "its reference at dt = {} differs from {other}'s",
                            super::output::sci(r.dt)
                        ),
                    ));
                }
                Some(_) => {}
                None => references[*d] = Some((file, *r)),
            }
        }
        for (k, p) in &part.points {
            points[*k] = Some(p.clone());
        }
    }
    // Every shard is present and holds exactly its points and their references (checked
    // above), so every slot is filled.
    let references = references
        .into_iter()
        .map(|r| {
            r.map(|(_, r)| r)
                .expect("every dt has a point, held by a present shard")
        })
        .collect();
    let points = points
        .into_iter()
        .map(|p| p.expect("every point belongs to a present shard"))
        .collect();
    Ok(super::report(
        &first.study,
        first.header.clone(),
        references,
        points,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::{self, run_shard};
    use volley_sim::internals::integrate::Integrator;

    /// Quadratic drag with no ground: the extrapolation reference, and no exact point.
    fn scene() -> volley_sim::internals::scene::Scene {
        let text = "Scene(dt: 0.1, duration: 2.0, integrator: Rk4, forces: [Gravity((0, 0, \
                    -9.81)), QuadraticDrag(0.05)], bodies: [(mass: 1, position: (0, 0, 1), \
                    launch: Velocity((12.0, 0, 15.0)))])";
        volley_sim::internals::scene::parse(text, "air.ron", "air").unwrap()
    }

    fn config(scene: &volley_sim::internals::scene::Scene) -> StudyConfig {
        StudyConfig {
            integrators: vec![Integrator::ExplicitEuler, Integrator::Rk4],
            dts: vec![0.1, 0.05, 0.025],
            timing: false,
            tolerance: Some(1e-3),
            ..StudyConfig::for_scene(scene)
        }
    }

    /// The three shards' files of the study, read back from JSON, labelled `s0.json`, ...
    fn shards(count: u32) -> Vec<(String, ShardResult)> {
        let (scene, config) = (scene(), config(&scene()));
        (0..count)
            .map(|index| {
                let part = run_shard(&scene, &config, Shard { index, count }, &mut |_| {}).unwrap();
                let label = format!("s{index}.json");
                let read = ShardResult::from_json(&part.to_json(), &label).unwrap();
                assert_eq!(read, part, "JSON reads back to the bit");
                (label, read)
            })
            .collect()
    }

    #[test]
    fn three_shards_merge_to_the_one_machine_report() {
        let (scene, config) = (scene(), config(&scene()));
        let whole = study::run(&scene, &config, &mut |_| {}).unwrap();
        let parts = shards(3);
        // Round-robin: shard 1 of 3 holds points 1 and 4 of the six.
        let held: Vec<usize> = parts[1].1.points.iter().map(|(k, _)| *k).collect();
        assert_eq!(held, [1, 4]);
        let merged = merge(&parts).unwrap();
        assert_eq!(merged, whole);
        // The fit is over every dt: no shard holds more than one dt of an integrator, so a fit
        // per shard would have too few points.
        assert!(matches!(
            merged.orders[1].1,
            study::OrderFit::Fitted { points: 3, .. }
        ));
        let mut reversed = parts.clone();
        reversed.reverse();
        assert_eq!(
            merge(&reversed).unwrap(),
            whole,
            "file order does not matter"
        );
    }

    #[test]
    fn bad_merges_name_the_file_and_what_is_wrong() {
        let parts = shards(3);
        let message = |p: &[(String, ShardResult)]| merge(p).unwrap_err().to_string();
        assert_eq!(
            message(&parts[..2]),
            "missing shard 2/3: the files given hold shards 0, 1 of 3 (numbered from 0)"
        );
        let twice = [parts[0].clone(), parts[1].clone(), parts[1].clone()];
        assert_eq!(
            message(&twice),
            "s1.json: shard 1/3 given twice (also s1.json)"
        );
        let mut other = parts.clone();
        other[2].1.study.config.until = 1.5;
        assert_eq!(
            message(&other),
            "s2.json: the study configuration (integrators, dts, until, options) differs from \
             s0.json's: not a shard of the same study"
        );
        let mut other = parts.clone();
        other[1].1.study.source.push(' ');
        assert_eq!(
            message(&other),
            "s1.json: the scene differs from s0.json's: not a shard of the same study"
        );
        let halves = shards(2);
        let mixed = [parts[0].clone(), halves[1].clone()];
        assert_eq!(
            message(&mixed),
            "s1.json: one of 2 shards, s0.json is one of 3: not a shard of the same study"
        );
        assert_eq!(message(&[]), "expected at least one shard file");
    }

    #[test]
    fn a_file_of_another_version_or_kind_is_refused() {
        let text = shards(1)[0].1.to_json();
        let newer = text.replace("\"version\": 1,", "\"version\": 2,");
        assert_eq!(
            ShardResult::from_json(&newer, "new.json")
                .unwrap_err()
                .to_string(),
            "new.json: shard file version 2, this volley reads version 1"
        );
        let e = ShardResult::from_json("{}", "empty.json").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("empty.json: expected a study shard file"),
            "{e}"
        );
        let cut = &text[..text.len() / 2];
        let e = ShardResult::from_json(cut, "cut.json").unwrap_err();
        assert!(e.to_string().starts_with("cut.json: "), "{e}");
        let mut lost = shards(1)[0].1.clone();
        lost.points.pop();
        let e = ShardResult::from_json(&lost.to_json(), "lost.json").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("lost.json: shard 0/1 should hold points [0, 1, 2, 3, 4, 5]"),
            "{e}"
        );
    }
}
