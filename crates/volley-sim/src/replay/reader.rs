//! Opening a recording: one checked pass over its frames, keyframes decoded on demand.
//!
//! The pass checks every frame's head and CRC and the order of the records, and keeps the
//! header, the commands, the hashes and where each keyframe is; keyframes are read again (and
//! checked again) only when asked for, so a long recording of many bodies opens in memory
//! proportional to its ticks, not its keyframes.
//!
//! A file that ends inside a frame, with no footer, is what an interrupted writer leaves: it
//! opens as truncated after the last complete tick. Anything else that is wrong (magic, version,
//! a head or CRC that does not check out on a complete frame, records out of order, bytes after
//! the footer, an undecodable payload) is an error naming the byte offset.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;
use std::time::Duration;

use crate::command::{Command, Stamped};
use crate::scene::{self, Scene};
use crate::world::{Snapshot, World};

use super::ReplayError;
use super::format::{self, CRC_LEN, FORMAT_VERSION, Footer, HEAD_LEN, Header, Kind, MAGIC};

/// Where a keyframe is in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyframeEntry {
    /// The tick it holds.
    pub tick: u64,
    /// Byte offset of its frame.
    offset: u64,
    /// Payload length.
    len: u32,
}

/// An open recording.
#[derive(Debug)]
pub struct Recording<R> {
    source: R,
    label: String,
    header: Header,
    commands: Vec<Stamped>,
    hashes: Vec<(u64, u64)>,
    keyframes: Vec<KeyframeEntry>,
    footer: Option<Footer>,
    truncated: Option<u64>,
    end_tick: u64,
    /// The program's own force terms, which the embedded scene's `Custom` terms resolve in.
    terms: crate::forces::ForceTerms,
}

impl Recording<BufReader<File>> {
    /// Opens and checks a recording file.
    pub fn open(path: &Path) -> Result<Self, ReplayError> {
        let label = path.display().to_string();
        let file = File::open(path).map_err(|e| ReplayError::input(&label, None, e))?;
        Recording::from_reader(BufReader::new(file), &label)
    }
}

/// Reads exactly `buf.len()` bytes at the reader's position.
fn read_at<R: Read>(r: &mut R, buf: &mut [u8], label: &str, at: u64) -> Result<(), ReplayError> {
    r.read_exact(buf)
        .map_err(|e| ReplayError::input(label, Some(at), format!("cannot read: {e}")))
}

/// What the checking pass collects.
#[derive(Default)]
struct Index {
    header: Option<Header>,
    commands: Vec<Stamped>,
    hashes: Vec<(u64, u64)>,
    keyframes: Vec<KeyframeEntry>,
    footer: Option<Footer>,
    /// Byte offset of the next frame.
    offset: u64,
    /// Highest tick of any record so far; records never go back in time.
    last_tick: Option<u64>,
    /// Highest tick with a hash or keyframe: how far a replay can be checked.
    checked_tick: Option<u64>,
}

impl<R: Read + Seek> Recording<R> {
    /// Checks a recording from any seekable reader; `label` names it in errors.
    pub fn from_reader(mut source: R, label: &str) -> Result<Self, ReplayError> {
        let err = |at: u64, m: String| ReplayError::input(label, Some(at), m);
        let total = source
            .seek(SeekFrom::End(0))
            .and_then(|t| source.seek(SeekFrom::Start(0)).map(|_| t))
            .map_err(|e| ReplayError::input(label, None, format!("cannot read: {e}")))?;
        let mut preamble = [0u8; format::PREAMBLE_LEN];
        let n = (total as usize).min(preamble.len());
        read_at(&mut source, &mut preamble[..n], label, 0)?;
        if n < MAGIC.len() || preamble[..8] != MAGIC {
            return Err(err(0, "not a Volley recording (wrong magic bytes)".into()));
        }
        if n < preamble.len() {
            return Err(err(8, "truncated inside the preamble".into()));
        }
        let version = u32::from_le_bytes(preamble[8..12].try_into().expect("4 bytes"));
        if version != FORMAT_VERSION {
            let age = if version > FORMAT_VERSION {
                "newer"
            } else {
                "older"
            };
            return Err(err(
                8,
                format!(
                    "recording format version {version} is {age} than the one this build \
                     reads ({FORMAT_VERSION}); use the Volley release that wrote it"
                ),
            ));
        }
        let mut index = Index {
            offset: format::PREAMBLE_LEN as u64,
            ..Index::default()
        };
        let mut payload = Vec::new();
        let mut truncated = None;
        while index.offset < total {
            let at = index.offset;
            if index.footer.is_some() {
                return Err(err(at, "bytes after the footer".into()));
            }
            let Some(kind) = next_frame(&mut source, label, total, at, &mut payload)? else {
                truncated = Some(at);
                break;
            };
            index.offset += (HEAD_LEN + payload.len() + CRC_LEN) as u64;
            index
                .take(kind, &payload, at)
                .map_err(|m| err(at, format!("{} record: {m}", kind.name())))?;
        }
        let what = if index.header.is_none() {
            "header"
        } else {
            "first keyframe"
        };
        let (Some(header), Some(checked)) = (index.header, index.checked_tick) else {
            return Err(err(
                index.offset,
                format!("ends before the {what}: nothing to replay"),
            ));
        };
        if index.footer.is_none() && truncated.is_none() {
            truncated = Some(total);
        }
        Ok(Recording {
            source,
            label: label.to_string(),
            header,
            commands: index.commands,
            hashes: index.hashes,
            keyframes: index.keyframes,
            end_tick: index.footer.map_or(checked, |f| f.final_tick),
            footer: index.footer,
            truncated,
            terms: crate::forces::ForceTerms::new(),
        })
    }

    /// The recording with the game's own force terms its scene may name: what
    /// [`Recording::scene`] and a [`super::Replay`] of it resolve them in. Without them a scene
    /// that names one is refused, naming the term.
    #[must_use]
    pub fn with_terms(mut self, terms: crate::forces::ForceTerms) -> Self {
        self.terms = terms;
        self
    }

    /// The file's name, as errors show it.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// The header record.
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Every recorded command, in order.
    pub fn commands(&self) -> &[Stamped] {
        &self.commands
    }

    /// Every stored `(tick, hash)`, ticks increasing; the footer's final hash included.
    pub fn hashes(&self) -> &[(u64, u64)] {
        &self.hashes
    }

    /// Every keyframe's tick and place, ticks increasing; the first is the start tick.
    pub fn keyframes(&self) -> &[KeyframeEntry] {
        &self.keyframes
    }

    /// The footer, or `None` for a truncated file.
    pub fn footer(&self) -> Option<&Footer> {
        self.footer.as_ref()
    }

    /// For a file without a footer: the byte offset where the incomplete part starts.
    pub fn truncated_at(&self) -> Option<u64> {
        self.truncated
    }

    /// The first tick of the recording.
    pub fn start_tick(&self) -> u64 {
        self.header.start_tick
    }

    /// The last tick a replay can check: the footer's, or for a truncated file the last tick
    /// with a hash or keyframe ("truncated after tick N").
    pub fn end_tick(&self) -> u64 {
        self.end_tick
    }

    /// Differences between the writer's build and this one that can change bits: Volley
    /// version, target arch, endianness. Empty when there are none.
    pub fn build_warnings(&self) -> Vec<String> {
        let (h, now) = (&self.header, format::Build::current());
        let mut out = Vec::new();
        let ours = env!("CARGO_PKG_VERSION");
        if h.volley_version != ours {
            out.push(format!(
                "recorded by Volley {}, this is {ours}",
                h.volley_version
            ));
        }
        if h.build.target_arch != now.target_arch || h.build.target_endian != now.target_endian {
            out.push(format!(
                "recorded on {} ({}-endian), this is {} ({}-endian)",
                h.build.target_arch, h.build.target_endian, now.target_arch, now.target_endian
            ));
        }
        out
    }

    /// The embedded scene with the recorded run's timestep, substeps and integrator, its own
    /// force terms resolved in the recording's ([`Recording::with_terms`]).
    pub fn scene(&self) -> Result<Scene, ReplayError> {
        self.scene_with(&self.terms)
    }

    /// [`Recording::scene`] with the game's own terms resolved in `terms`.
    pub fn scene_with(&self, terms: &crate::forces::ForceTerms) -> Result<Scene, ReplayError> {
        let h = &self.header;
        let fail = |m: String| ReplayError::input(&self.label, None, m);
        let file = format!("{} (embedded)", h.scene_file);
        let mut scene = scene::parse_with(&h.scene_source, &file, &h.scene_name, terms)
            .map_err(|e| fail(format!("the embedded scene no longer parses: {e}")))?;
        let now = super::format::LevelHash::of_scene(&scene);
        if now != h.levels {
            let changed = h.levels.iter().zip(&now).find(|(a, b)| a != b);
            return Err(fail(match changed {
                Some((then, now)) => format!(
                    "the level file {} changed since the recording (xxh3 {} now, {} recorded): refusing to replay against another level",
                    then.file, now.xxh3, then.xxh3
                ),
                None => format!(
                    "the scene reads {} level files now, the recording {}: refusing to replay against another level",
                    now.len(),
                    h.levels.len()
                ),
            }));
        }
        if !(1..=1_000_000_000_000).contains(&h.timestep_ns) {
            return Err(fail(format!("header: timestep of {} ns", h.timestep_ns)));
        }
        scene.timestep = Duration::from_nanos(h.timestep_ns);
        scene
            .set_substeps(h.substeps)
            .map_err(|e| fail(format!("header: {e}")))?;
        scene
            .set_integrator(h.integrator)
            .map_err(|e| fail(format!("header: {e}")))?;
        scene
            .set_tolerance(h.tolerance.unwrap_or(crate::integrate::DEFAULT_TOLERANCE))
            .map_err(|e| fail(format!("header: {e}")))?;
        Ok(scene)
    }

    /// Reads keyframe `index` into `out` (reusing its buffers), checking its CRC again.
    pub fn read_keyframe(
        &mut self,
        index: usize,
        scene: &Scene,
        out: &mut Snapshot,
    ) -> Result<(), ReplayError> {
        let k = self.keyframes[index];
        let err = |m: String| ReplayError::input(&self.label, Some(k.offset), m);
        self.source
            .seek(SeekFrom::Start(k.offset))
            .map_err(|e| err(format!("cannot read: {e}")))?;
        let mut frame = vec![0u8; HEAD_LEN + k.len as usize + CRC_LEN];
        read_at(&mut self.source, &mut frame, &self.label, k.offset)?;
        let (body, crc) = frame.split_at(HEAD_LEN + k.len as usize);
        if crc32fast::hash(body).to_le_bytes() != crc {
            return Err(err("keyframe changed since the file was opened".into()));
        }
        super::keyframe::decode_keyframe(&body[HEAD_LEN..], &scene.forces, out)
            .map_err(|m| err(format!("keyframe record: {m}")))
    }

    /// A world at keyframe `index`: built from `scene`, then restored.
    pub fn world_at(&mut self, index: usize, scene: &Scene) -> Result<World, ReplayError> {
        let mut world = World::new(scene);
        let mut snapshot = world.snapshot();
        self.read_keyframe(index, scene, &mut snapshot)?;
        let at = self.keyframes[index].offset;
        world.restore(&snapshot).map_err(|m| {
            let tick = snapshot.tick;
            ReplayError::input(
                &self.label,
                Some(at),
                format!("keyframe of tick {tick}: {m}"),
            )
        })?;
        Ok(world)
    }

    /// Index of the last keyframe at or before `tick` (the first keyframe if none is).
    pub fn keyframe_at_or_before(&self, tick: u64) -> usize {
        self.keyframes.partition_point(|k| k.tick <= tick).max(1) - 1
    }
}

impl Index {
    /// Takes one checked record into the index.
    fn take(&mut self, kind: Kind, payload: &[u8], at: u64) -> Result<(), String> {
        let first = self.header.is_none();
        if first != (kind == Kind::Header) {
            return Err(if first {
                "the first record must be the header".into()
            } else {
                "a second header".into()
            });
        }
        if kind != Kind::Header && kind != Kind::Keyframe && self.keyframes.is_empty() {
            return Err("the keyframe of the start tick must follow the header".into());
        }
        let mut r = format::Reader::new(payload);
        let tick = match kind {
            Kind::Header => {
                self.header = Some(parse_header(payload)?);
                return Ok(());
            }
            Kind::Footer => {
                let f = format::decode_footer(payload).map_err(|e| e.to_string())?;
                self.footer = Some(f);
                f.final_tick
            }
            _ => r.u64().map_err(|e| e.to_string())?,
        };
        if self.last_tick.is_some_and(|last| tick < last) {
            return Err(format!(
                "tick {tick} after tick {}",
                self.last_tick.unwrap_or(0)
            ));
        }
        let start = self.header.as_ref().map_or(0, |h| h.start_tick);
        if tick < start {
            return Err(format!("tick {tick} before the start tick {start}"));
        }
        self.last_tick = Some(tick);
        match kind {
            Kind::Command => {
                let text = std::str::from_utf8(r.rest()).map_err(|_| "text is not UTF-8")?;
                let command: Command = text.parse().map_err(|e| format!("`{text}`: {e}"))?;
                self.commands.push(Stamped { tick, command });
            }
            Kind::Hash => {
                if self.hashes.last().is_some_and(|&(t, _)| t == tick) {
                    return Err(format!("a second hash for tick {tick}"));
                }
                let last = self.take_hashes(tick, &mut r)?;
                self.last_tick = Some(last);
                self.checked_tick = Some(last);
            }
            Kind::Keyframe => {
                if self.keyframes.is_empty() && tick != start {
                    return Err(format!("the first keyframe is at tick {tick}, not {start}"));
                }
                if self.keyframes.last().is_some_and(|k| k.tick == tick) {
                    return Err(format!("a second keyframe for tick {tick}"));
                }
                self.keyframes.push(KeyframeEntry {
                    tick,
                    offset: at,
                    len: payload.len() as u32,
                });
                self.checked_tick = Some(tick);
            }
            Kind::Footer => {
                let hash = self.footer.map_or(0, |f| f.final_hash);
                match self.hashes.last() {
                    Some(&(t, h)) if t == tick && h != hash => {
                        return Err(format!("final hash differs from the hash of tick {tick}"));
                    }
                    Some(&(t, _)) if t == tick => {}
                    _ => self.hashes.push((tick, hash)),
                }
            }
            Kind::Header => unreachable!("handled above"),
        }
        Ok(())
    }
}

impl Index {
    /// Takes the hashes of a hash record whose first tick is `first` (read already); returns
    /// the tick of its last hash.
    fn take_hashes(&mut self, first: u64, r: &mut format::Reader) -> Result<u64, String> {
        let stride = r.u64().map_err(|e| e.to_string())?;
        if stride == 0 {
            return Err("stride 0 between hashed ticks".into());
        }
        let hashes = r.rest();
        if hashes.is_empty() || !hashes.len().is_multiple_of(8) {
            return Err(format!(
                "{} bytes of hashes, not a whole number of them",
                hashes.len()
            ));
        }
        let n = (hashes.len() / 8) as u64;
        let last = (n - 1)
            .checked_mul(stride)
            .and_then(|span| first.checked_add(span))
            .ok_or_else(|| {
                format!("{n} hashes from tick {first}, {stride} apart, pass the largest tick")
            })?;
        self.hashes
            .extend(hashes.chunks_exact(8).zip(0..).map(|(h, k)| {
                (
                    first + k * stride,
                    u64::from_le_bytes(h.try_into().expect("8 bytes")),
                )
            }));
        Ok(last)
    }
}

/// Reads the frame at byte `at` into `payload`; `None` if the file ends inside it.
fn next_frame<R: Read>(
    source: &mut R,
    label: &str,
    total: u64,
    at: u64,
    payload: &mut Vec<u8>,
) -> Result<Option<Kind>, ReplayError> {
    let err = |m: String| ReplayError::input(label, Some(at), m);
    if total - at < HEAD_LEN as u64 {
        return Ok(None);
    }
    let mut head = [0u8; HEAD_LEN];
    read_at(source, &mut head, label, at)?;
    let len = u32::from_le_bytes(head[1..5].try_into().expect("4 bytes"));
    if u16::from_le_bytes([head[5], head[6]]) != format::head_check(head[0], len) {
        return Err(err("frame head fails its check (damaged file)".into()));
    }
    let kind =
        Kind::from_tag(head[0]).ok_or_else(|| err(format!("unknown record kind {}", head[0])))?;
    if !kind.allowed_len().contains(&len) {
        return Err(err(format!("{} record of {len} bytes", kind.name())));
    }
    let end = at + (HEAD_LEN + CRC_LEN) as u64 + u64::from(len);
    if end > total {
        return Ok(None);
    }
    payload.resize(len as usize, 0);
    read_at(source, payload, label, at)?;
    let mut crc = [0u8; CRC_LEN];
    read_at(source, &mut crc, label, at)?;
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&head);
    hasher.update(payload);
    if hasher.finalize() != u32::from_le_bytes(crc) {
        return Err(err(format!(
            "{} record fails its CRC (damaged file)",
            kind.name()
        )));
    }
    Ok(Some(kind))
}

fn parse_header(payload: &[u8]) -> Result<Header, String> {
    let h: Header = serde_json::from_slice(payload).map_err(|e| e.to_string())?;
    if h.hash_layout.as_bytes() != crate::hash::HASH_LAYOUT {
        return Err(format!(
            "hashes use layout `{}`, this build hashes `{}`",
            h.hash_layout,
            String::from_utf8_lossy(crate::hash::HASH_LAYOUT)
        ));
    }
    if h.hash_every == 0 {
        return Err("hash_every must be at least 1".into());
    }
    Ok(h)
}
