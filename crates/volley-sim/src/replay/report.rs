//! What a replay reports when it parts from its recording: the first divergent tick, what
//! differed there, and every field that differs at the keyframe compared.

use crate::command::Stamped;
use crate::hash::hex;
use crate::world::Divergence;

use super::diff::FieldDiff;

/// What differed first.
#[derive(Clone, Debug, PartialEq)]
pub enum Mismatch {
    /// The stored state hash differs from the replay's.
    Hash {
        /// The recording's hash.
        recorded: u64,
        /// The replay's hash.
        replayed: u64,
    },
    /// Every hash agreed, but a keyframe differs in a field the hash does not cover and that
    /// decides the future (launcher, force toggles, integrator, energy caps, carried force).
    Fields,
    /// The replay's divergence guard stopped it where the recording went on.
    ReplayDiverged(Divergence),
    /// The recording ended in a divergence the replay did not reproduce.
    RecordingDiverged(Divergence),
    /// A recorded command could not be applied to the replayed world.
    Command {
        /// The command.
        command: Stamped,
        /// Why it failed.
        error: String,
    },
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Mismatch::Hash { recorded, replayed } => write!(
                f,
                "state hash recorded {} replayed {}",
                hex(*recorded),
                hex(*replayed)
            ),
            Mismatch::Fields => f.write_str("the hashes agree but keyframe fields differ"),
            Mismatch::ReplayDiverged(d) => write!(f, "the replay {d}; the recording did not"),
            Mismatch::RecordingDiverged(d) => write!(f, "the recording {d}; the replay did not"),
            Mismatch::Command { command, error } => {
                write!(f, "recorded command `{command}` failed on replay: {error}")
            }
        }
    }
}

/// Where a replay first parted from its recording, and every field that differs.
#[derive(Clone, Debug, PartialEq)]
pub struct FirstDivergence {
    /// The first checked tick that differs.
    pub tick: u64,
    /// The last tick before it whose stored hash matched, if any: the state first differed
    /// somewhere in `last_match + 1 ..= tick` (exactly `tick` when hashes are stored every tick).
    pub last_match: Option<u64>,
    /// What differed.
    pub mismatch: Mismatch,
    /// The keyframe tick `fields` were compared at: the first at or after `tick`, if any.
    pub compared_at: Option<u64>,
    /// Every field that differs at `compared_at`.
    pub fields: Vec<FieldDiff>,
}

impl FirstDivergence {
    /// The report as lines of text, listing at most `limit` fields (all for `None`).
    pub fn report(&self, limit: Option<usize>) -> String {
        let mut out = format!(
            "first divergence at tick {}: {}\n",
            self.tick, self.mismatch
        );
        match self.last_match {
            Some(m) if m + 1 == self.tick => out += &format!("the state matched at tick {m}\n"),
            Some(m) => {
                out += &format!(
                    "the state matched at tick {m} (the last stored hash before), so it first \
                     differed in ticks {}..={}\n",
                    m + 1,
                    self.tick
                )
            }
            None => {}
        }
        let t = self.tick;
        match self.compared_at {
            Some(k) if self.fields.is_empty() => {
                out += &format!("no field differs at tick {k}: the runs agree again there\n")
            }
            Some(k) if k == t => out += &format!("fields that differ at tick {k} (a keyframe):\n"),
            Some(k) => {
                out += &format!(
                    "fields that differ at tick {k}, the first keyframe at or after tick {t} \
                     (the recording holds no state at tick {t}; record with --keyframe-every 1 \
                     for it):\n"
                )
            }
            None => {
                out += &format!("the recording has no keyframe at or after tick {t} to compare\n")
            }
        }
        let shown = limit.unwrap_or(usize::MAX).min(self.fields.len());
        for d in &self.fields[..shown] {
            out += &format!("  {d}\n");
        }
        if shown < self.fields.len() {
            out += &format!("  ... and {} more\n", self.fields.len() - shown);
        }
        out
    }
}
