//! Recording format version 4: the preamble, the frame, and each record's payload.
//!
//! ```text
//! file      = preamble frame*
//! preamble  = MAGIC (8 bytes "\x89VOLLEY\n")  version:u32
//! frame     = kind:u8  len:u32  head_check:u16  payload[len]  crc:u32
//! ```
//!
//! All integers are little-endian, floats are their IEEE-754 bit patterns as `u64`. `head_check`
//! is the low 16 bits of the CRC-32 of `kind` and `len`, so a damaged length is caught before it
//! is trusted; `crc` is the CRC-32 (`crc32fast`, IEEE polynomial) of the head and the payload.
//! Payloads by kind:
//!
//! | kind | record | payload |
//! |---|---|---|
//! | 1 | header | JSON [`Header`]: build facts, the scene text verbatim, timestep, substeps, integrator, start tick, intervals |
//! | 2 | keyframe | a [`crate::world::Snapshot`]: see [`super::keyframe::encode_keyframe`] |
//! | 3 | command | `tick:u64` and the command in its script form (UTF-8), applied before the step from `tick` |
//! | 4 | hashes | `first_tick:u64  stride:u64  state_hash:u64 × n`, 1 ≤ n ≤ [`HASH_RUN_MAX`]: the canonical hashes (`crate::hash`) of ticks `first_tick + k·stride`, k = 0..n, stride ≥ 1 |
//! | 5 | footer | `final_tick:u64  final_hash:u64` and the divergence that ended the run, if one did |
//!
//! Order: the header, the keyframe at the start tick, then by tick: the hashes of hashed ticks
//! (every `hash_every` ticks), keyframes (every `keyframe_every` ticks) and the commands applied
//! before a tick's step; at the end a keyframe of the final state and the footer. Records never
//! go back in time.
//!
//! Hashes come in runs: the recorder collects the hashes of consecutive hashed ticks and writes
//! them as one record with one CRC ([`HashRun`]), 8 bytes a tick where a record per tick took 27
//! and a CRC each. A run is closed by a keyframe, a command, the footer, [`HASH_RUN_MAX`] hashes
//! and every flush, so records stay in tick order and a flush still hands every hash computed so
//! far to the file: a recording cut short keeps every tick flushed before the cut.
//!
//! Version 1 (never released outside this repository) had one 16-byte hash record per tick;
//! version 2 had an 8-bit force mask (8 kinds), no launcher spin and no launch columns in its
//! keyframes; version 3 (two commits of one session) always wrote the launch columns, with no
//! flag. This build refuses all three as other format versions.

use std::io::{self, Write};

use serde::{Deserialize, Serialize};

use crate::forces::ForceKind;
use crate::integrate::Integrator;
use crate::scene::Scene;
use crate::world::{BodyId, Divergence, DivergenceCause};

/// The first 8 bytes of every recording (PNG-style: a high byte, a name, a newline, so a text-
/// mode transfer that rewrites bytes is caught at once).
pub const MAGIC: [u8; 8] = *b"\x89VOLLEY\n";
/// The format version this build writes and the only one it reads.
pub const FORMAT_VERSION: u32 = 4;
/// Bytes before the first frame: magic and version.
pub const PREAMBLE_LEN: usize = 12;
/// Bytes of a frame head: kind, length, head check.
pub const HEAD_LEN: usize = 7;
/// Bytes of the CRC after a payload.
pub const CRC_LEN: usize = 4;
/// Most hashes one hash record holds: 8 KiB of hashes, one CRC.
pub const HASH_RUN_MAX: usize = 1024;
/// Bytes of a hash record's payload before its hashes: first tick and stride.
pub const HASH_RUN_FIXED: usize = 16;

/// What a frame holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Build facts and the run's settings, JSON.
    Header = 1,
    /// A full snapshot of the world.
    Keyframe = 2,
    /// A command applied at a tick boundary.
    Command = 3,
    /// The state hashes after a run of ticks.
    Hash = 4,
    /// The final tick and hash.
    Footer = 5,
}

impl Kind {
    /// The kind with this tag, if any.
    pub fn from_tag(tag: u8) -> Option<Kind> {
        [
            Kind::Header,
            Kind::Keyframe,
            Kind::Command,
            Kind::Hash,
            Kind::Footer,
        ]
        .into_iter()
        .find(|k| *k as u8 == tag)
    }

    /// The record's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Header => "header",
            Kind::Keyframe => "keyframe",
            Kind::Command => "command",
            Kind::Hash => "hashes",
            Kind::Footer => "footer",
        }
    }

    /// Payload lengths (bytes) a record of this kind may have.
    pub fn allowed_len(self) -> std::ops::RangeInclusive<u32> {
        match self {
            Kind::Header => 2..=(64 << 20),
            // A keyframe of the most bodies a world may hold, with a carried force and the
            // counts of the most events a scene may declare.
            Kind::Keyframe => {
                let most = super::keyframe::keyframe_len(crate::scene::MAX_BODIES, true, true)
                    .expect("fits a frame");
                let counts = (crate::scene::MAX_EVENTS as u32 + 1) * 8;
                let tallies = 16 + counts * (crate::scene::MAX_BODIES as u32 + 1);
                super::keyframe::KEYFRAME_FIXED as u32..=most + tallies
            }
            Kind::Command => 9..=4096,
            Kind::Hash => (HASH_RUN_FIXED + 8) as u32..=(HASH_RUN_FIXED + 8 * HASH_RUN_MAX) as u32,
            Kind::Footer => FOOTER_LEN as u32..=FOOTER_LEN as u32,
        }
    }
}

/// The head check of a frame: the low 16 bits of the CRC-32 of its kind and length.
pub fn head_check(kind: u8, len: u32) -> u16 {
    let l = len.to_le_bytes();
    crc32fast::hash(&[kind, l[0], l[1], l[2], l[3]]) as u16
}

/// The 7 head bytes of a frame.
pub fn frame_head(kind: Kind, len: u32) -> [u8; HEAD_LEN] {
    let mut head = [0u8; HEAD_LEN];
    head[0] = kind as u8;
    head[1..5].copy_from_slice(&len.to_le_bytes());
    head[5..7].copy_from_slice(&head_check(kind as u8, len).to_le_bytes());
    head
}

/// Writes the magic bytes and the format version.
pub fn write_preamble(out: &mut impl Write) -> io::Result<()> {
    out.write_all(&MAGIC)?;
    out.write_all(&FORMAT_VERSION.to_le_bytes())
}

/// Writes one whole frame; returns its length in bytes.
pub fn write_frame(out: &mut impl Write, kind: Kind, payload: &[u8]) -> io::Result<u64> {
    let len = u32::try_from(payload.len())
        .map_err(|_| io::Error::other(format!("{} record too large", kind.name())))?;
    let head = frame_head(kind, len);
    let mut crc = crc32fast::Hasher::new();
    crc.update(&head);
    crc.update(payload);
    out.write_all(&head)?;
    out.write_all(payload)?;
    out.write_all(&crc.finalize().to_le_bytes())?;
    Ok((HEAD_LEN + payload.len() + CRC_LEN) as u64)
}

/// The hashes of consecutive hashed ticks, collected into one hash record (kind 4).
///
/// The frame is built in place in a buffer allocated once: a push appends 8 bytes; closing
/// fills in the head, appends the CRC of the whole frame and writes it with one `write_all`.
#[derive(Clone, Debug)]
pub struct HashRun {
    /// The frame so far: head (filled in on closing), first tick, stride, the hashes.
    frame: Vec<u8>,
    /// Ticks between consecutive hashes.
    stride: u64,
    /// Hashes in the run.
    len: usize,
    /// The tick whose hash would continue the run.
    next: u64,
}

impl HashRun {
    /// An empty run of hashes `stride` ticks apart (at least 1).
    pub fn new(stride: u64) -> HashRun {
        HashRun {
            frame: Vec::with_capacity(HEAD_LEN + HASH_RUN_FIXED + 8 * HASH_RUN_MAX + CRC_LEN),
            stride: stride.max(1),
            len: 0,
            next: 0,
        }
    }

    /// Hashes in the run.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the run holds no hash (closing it writes nothing).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether the hash of `tick` can join the run: it is empty, or `tick` is the next one and
    /// the run is not full.
    #[inline]
    pub fn takes(&self, tick: u64) -> bool {
        self.len == 0 || (tick == self.next && self.len < HASH_RUN_MAX)
    }

    /// Adds the hash of `tick`, which the run must take (see [`HashRun::takes`]: close it
    /// first otherwise).
    #[inline]
    pub fn push(&mut self, tick: u64, hash: u64) {
        debug_assert!(self.takes(tick), "tick {tick} does not continue the run");
        if self.len == 0 {
            self.frame.clear();
            self.frame.extend_from_slice(&[0; HEAD_LEN]);
            self.frame.extend_from_slice(&tick.to_le_bytes());
            self.frame.extend_from_slice(&self.stride.to_le_bytes());
        }
        self.frame.extend_from_slice(&hash.to_le_bytes());
        self.len += 1;
        self.next = tick.saturating_add(self.stride);
    }

    /// Bytes closing the run now would write: its whole frame, 0 when empty.
    pub fn frame_len(&self) -> u64 {
        if self.len == 0 {
            0
        } else {
            (self.frame.len() + CRC_LEN) as u64
        }
    }

    /// Writes the run as one hash record and empties it; returns the bytes written (none for
    /// an empty run).
    pub fn close(&mut self, out: &mut impl Write) -> io::Result<u64> {
        if self.len == 0 {
            return Ok(0);
        }
        self.len = 0;
        let len = (self.frame.len() - HEAD_LEN) as u32;
        self.frame[..HEAD_LEN].copy_from_slice(&frame_head(Kind::Hash, len));
        let crc = crc32fast::hash(&self.frame);
        self.frame.extend_from_slice(&crc.to_le_bytes());
        out.write_all(&self.frame)?;
        Ok(self.frame.len() as u64)
    }
}

/// Facts about the build that wrote a recording; the ones that can change bits are compared.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Build {
    /// `std::env::consts::ARCH`, e.g. `x86_64`.
    pub target_arch: String,
    /// `std::env::consts::OS`.
    pub target_os: String,
    /// `little` or `big`.
    pub target_endian: String,
    /// `debug` (debug assertions on) or `release`; both give the same bits (tested).
    pub profile: String,
    /// Enabled target features among those that could matter to floating point.
    pub target_features: Vec<String>,
}

impl Build {
    /// This build.
    pub fn current() -> Build {
        let features = [
            ("sse2", cfg!(target_feature = "sse2")),
            ("sse4.1", cfg!(target_feature = "sse4.1")),
            ("avx", cfg!(target_feature = "avx")),
            ("avx2", cfg!(target_feature = "avx2")),
            ("fma", cfg!(target_feature = "fma")),
            ("avx512f", cfg!(target_feature = "avx512f")),
            ("neon", cfg!(target_feature = "neon")),
        ];
        Build {
            target_arch: std::env::consts::ARCH.into(),
            target_os: std::env::consts::OS.into(),
            target_endian: if cfg!(target_endian = "little") {
                "little"
            } else {
                "big"
            }
            .into(),
            profile: if cfg!(debug_assertions) {
                "debug"
            } else {
                "release"
            }
            .into(),
            target_features: features
                .iter()
                .filter(|(_, on)| *on)
                .map(|(name, _)| name.to_string())
                .collect(),
        }
    }
}

/// The header record: who wrote the file and everything needed to rebuild the run's world.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// `CARGO_PKG_VERSION` of the writer.
    pub volley_version: String,
    /// The writer's build.
    pub build: Build,
    /// The hash layout tag (`crate::hash::HASH_LAYOUT`) the stored hashes use.
    pub hash_layout: String,
    /// The scene's file as given to the writer (for messages only).
    pub scene_file: String,
    /// The scene's name.
    pub scene_name: String,
    /// The scene file's text, verbatim.
    pub scene_source: String,
    /// Timestep (ns) after any override; the physics step is exactly this.
    pub timestep_ns: u64,
    /// Integrator steps per tick after any override.
    pub substeps: u32,
    /// Integrator at the start tick.
    pub integrator: Integrator,
    /// The adaptive integrator's tolerance after any override; absent (older files, and the
    /// default) means [`crate::integrate::DEFAULT_TOLERANCE`], so files that never used it
    /// are byte-identical to before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The level files the scene read (meshes, then heightfields, as the scene lists them) and
    /// the xxh3 of each one's bytes: a replay refuses a level that changed. Absent for scenes
    /// without level files, so their recordings are byte-identical to before levels existed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub levels: Vec<LevelHash>,
    /// Tick of the first keyframe, where the recording starts.
    pub start_tick: u64,
    /// Hashes are stored at ticks that are multiples of this (and at the start and end).
    pub hash_every: u64,
    /// Keyframes are stored at ticks that are multiples of this (0: start and end only).
    pub keyframe_every: u64,
    /// Worker threads of the recording run; noted only, results do not depend on it.
    pub threads: usize,
}

/// A level file a recorded scene read, and its content hash.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LevelHash {
    /// The file as the scene names it.
    pub file: String,
    /// xxh3 of its bytes (with a glTF's external buffers), as 16 hex digits.
    pub xxh3: String,
}

impl LevelHash {
    /// The level files `scene` read, in its order (inline geometry is in the scene's source).
    pub fn of_scene(scene: &Scene) -> Vec<LevelHash> {
        use crate::contact::LevelSource;
        let files = scene
            .meshes
            .iter()
            .map(|m| (&m.source, m.content_hash))
            .chain(
                scene
                    .heightfields
                    .iter()
                    .map(|h| (&h.source, h.content_hash)),
            );
        files
            .filter_map(|(source, hash)| match source {
                LevelSource::File(f) => Some(LevelHash {
                    file: f.clone(),
                    xxh3: format!("{hash:016x}"),
                }),
                LevelSource::Inline => None,
            })
            .collect()
    }
}

/// The footer record: how the recorded run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footer {
    /// The last tick recorded.
    pub final_tick: u64,
    /// The state hash at that tick.
    pub final_hash: u64,
    /// The divergence that stopped the run at `final_tick`, if one did.
    pub diverged: Option<Divergence>,
}

const FOOTER_LEN: usize = 8 + 8 + 1 + 8 + 8 + 1 + 8 + 8;

/// The footer's payload.
pub fn encode_footer(f: &Footer) -> [u8; FOOTER_LEN] {
    let mut w = Words::default();
    w.u64(f.final_tick).u64(f.final_hash);
    match f.diverged {
        None => w.u8(0).u64(0).u64(0).u8(0).u64(0).u64(0),
        Some(d) => {
            let (cause, energy, bound) = match d.cause {
                DivergenceCause::NonFinite => (0, 0.0, 0.0),
                DivergenceCause::EnergyGrowth { energy, bound } => (1, energy, bound),
            };
            w.u8(1)
                .u64(d.tick)
                .u64(d.body.0)
                .u8(cause)
                .f64(energy)
                .f64(bound)
        }
    };
    w.bytes().try_into().expect("the footer has a fixed length")
}

/// Why a record's payload does not decode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// The payload ends before a field it should hold.
    Truncated {
        /// The payload's length (bytes).
        len: usize,
    },
    /// Bytes are left after the last field.
    TrailingBytes(usize),
    /// An array's declared length overflows.
    ArrayTooLong,
    /// The footer's divergence cause is no known tag.
    DivergenceCause(u8),
    /// The footer's divergence flag is neither 0 nor 1.
    DivergenceFlag(u8),
    /// A keyframe's integrator tag is no known integrator.
    IntegratorTag(u8),
    /// A keyframe's force mask has bits beyond the known terms, its carry flag is not 0 or 1,
    /// or its flags (has launch, has tallies) are past 3.
    MaskOrCarry {
        /// The force mask.
        mask: u16,
        /// The flags byte.
        launch: u8,
        /// The carry flag.
        carry: u8,
    },
    /// A keyframe marks a force term active that the scene does not declare.
    UndeclaredForce(ForceKind),
    /// A keyframe's body count does not match its length.
    BodyCount {
        /// The body count it declares.
        bodies: u64,
        /// The payload's length (bytes).
        len: usize,
    },
    /// A keyframe's body ids do not increase.
    IdsNotIncreasing,
    /// A keyframe's event count is past a u32.
    Tally(u64),
}

impl std::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DecodeError::Truncated { len } => write!(f, "payload ends at byte {len}"),
            DecodeError::TrailingBytes(n) => write!(f, "{n} unread bytes at the end"),
            DecodeError::ArrayTooLong => f.write_str("array too long"),
            DecodeError::DivergenceCause(c) => write!(f, "unknown divergence cause {c}"),
            DecodeError::DivergenceFlag(x) => write!(f, "divergence flag {x}, expected 0 or 1"),
            DecodeError::IntegratorTag(t) => write!(f, "unknown integrator tag {t}"),
            DecodeError::MaskOrCarry {
                mask,
                carry,
                launch,
            } => write!(
                f,
                "force mask {mask:#x}, carry flag {carry} or flags {launch} out of range"
            ),
            DecodeError::UndeclaredForce(kind) => {
                write!(f, "force term {} is active but not declared", kind.name())
            }
            DecodeError::BodyCount { bodies, len } => {
                write!(f, "{bodies} bodies do not fit a {len} byte keyframe")
            }
            DecodeError::IdsNotIncreasing => f.write_str("body ids are not increasing"),
            DecodeError::Tally(c) => write!(f, "an event count of {c}, past a u32"),
        }
    }
}

impl std::error::Error for DecodeError {}

/// Reads a footer's payload.
pub fn decode_footer(payload: &[u8]) -> Result<Footer, DecodeError> {
    let mut r = Reader::new(payload);
    let (final_tick, final_hash, flag) = (r.u64()?, r.u64()?, r.u8()?);
    let (tick, body, cause, energy, bound) = (r.u64()?, r.u64()?, r.u8()?, r.f64()?, r.f64()?);
    r.end()?;
    let cause = match cause {
        0 => DivergenceCause::NonFinite,
        1 => DivergenceCause::EnergyGrowth { energy, bound },
        c => return Err(DecodeError::DivergenceCause(c)),
    };
    let diverged = match flag {
        0 => None,
        1 => Some(Divergence {
            tick,
            body: BodyId(body),
            cause,
        }),
        f => return Err(DecodeError::DivergenceFlag(f)),
    };
    Ok(Footer {
        final_tick,
        final_hash,
        diverged,
    })
}

/// A little-endian field builder for the small fixed payloads, on the stack.
pub(crate) struct Words {
    buf: [u8; 128],
    len: usize,
}

impl Default for Words {
    fn default() -> Self {
        Words {
            buf: [0; 128],
            len: 0,
        }
    }
}

impl Words {
    pub(crate) fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
    pub(crate) fn u8(&mut self, x: u8) -> &mut Self {
        self.buf[self.len] = x;
        self.len += 1;
        self
    }
    pub(crate) fn u16(&mut self, x: u16) -> &mut Self {
        self.buf[self.len..self.len + 2].copy_from_slice(&x.to_le_bytes());
        self.len += 2;
        self
    }
    pub(crate) fn u64(&mut self, x: u64) -> &mut Self {
        self.buf[self.len..self.len + 8].copy_from_slice(&x.to_le_bytes());
        self.len += 8;
        self
    }
    pub(crate) fn f64(&mut self, x: f64) -> &mut Self {
        self.u64(x.to_bits())
    }
}

/// A bounds-checked little-endian reader over a payload; every read can fail, none panics.
pub(crate) struct Reader<'a> {
    buf: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(buf: &'a [u8]) -> Reader<'a> {
        Reader { buf, at: 0 }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.buf.len());
        let end = end.ok_or(DecodeError::Truncated {
            len: self.buf.len(),
        })?;
        let out = &self.buf[self.at..end];
        self.at = end;
        Ok(out)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.take(1)?[0])
    }

    pub(crate) fn u16(&mut self) -> Result<u16, DecodeError> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes(
            b.try_into().expect("take(2) gives 2 bytes"),
        ))
    }

    pub(crate) fn u64(&mut self) -> Result<u64, DecodeError> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(
            b.try_into().expect("take(8) gives 8 bytes"),
        ))
    }

    pub(crate) fn f64(&mut self) -> Result<f64, DecodeError> {
        self.u64().map(f64::from_bits)
    }

    pub(crate) fn take_u64s(
        &mut self,
        n: usize,
    ) -> Result<impl Iterator<Item = u64> + 'a, DecodeError> {
        let bytes = self.take(n.checked_mul(8).ok_or(DecodeError::ArrayTooLong)?)?;
        Ok(bytes
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().expect("chunks of 8"))))
    }

    /// The rest of the payload.
    pub(crate) fn rest(&mut self) -> &'a [u8] {
        let out = &self.buf[self.at..];
        self.at = self.buf.len();
        out
    }

    pub(crate) fn end(&self) -> Result<(), DecodeError> {
        if self.at == self.buf.len() {
            Ok(())
        } else {
            Err(DecodeError::TrailingBytes(self.buf.len() - self.at))
        }
    }
}

#[cfg(test)]
mod tests;
