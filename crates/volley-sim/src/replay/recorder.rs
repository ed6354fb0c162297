//! The recorder: a [`TickObserver`] that writes a recording as the loop runs.
//!
//! Per hashed tick it hashes the world ([`state_hash`], nearly all of the cost) and appends the
//! 8-byte hash to the open run of hashes ([`format::HashRun`]), which becomes one hash record
//! with one CRC when it is closed: by a keyframe, a command, 1024 hashes, a flush or the end.
//! Whether a hash or keyframe is due is a comparison with the next due tick (no division per
//! tick). Keyframes stream the world's arrays through the CRC from a snapshot buffer that is
//! reused; commands are formatted into a reused string; nothing allocates per tick.
//!
//! Records reach the file through a 64 KiB buffer by the [`FlushPolicy`]: by default once at
//! least 50 ms of wall time passed, so a run killed by Ctrl-C or a crash loses only its last
//! moments and the file still opens, as truncated. A flush first closes the open run, so it
//! hands over every hash computed so far. The wall clock is read after a tick, by the observer,
//! never inside one; and only every so many ticks when ticks are fast (see
//! [`FlushPolicy::Interval`]). A recorder dropped without [`Recorder::finish`] (an error path, a
//! panic) closes its run and hands its buffer over, like a flush.
//!
//! Starting and stopping from another observer (the window's record toggle): hold an
//! `Option<Recorder<W>>`, forward the [`TickObserver`] calls to it while it is `Some`, create it
//! with [`Recorder::start`] between frames and end it with [`Recorder::finish`]. A recording
//! may start at any tick: its first keyframe is the state it starts from.

use std::io::{self, BufWriter, Write};
use std::time::Duration;

use crate::instant::Instant;

use crate::command::Stamped;
use crate::hash::state_hash;
use crate::sim_loop::{ObserverError, TickObserver, next_multiple};
use crate::world::{Snapshot, World};

use super::format::{self, Build, Footer, Header, Kind};

/// When the recorder hands its buffer to the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlushPolicy {
    /// After every tick: nothing is lost to a kill, at one write call per tick.
    EveryTick,
    /// After a tick, once at least this much wall time passed since the last flush. The clock is
    /// read every tick while ticks take a millisecond or more (real time), and every 2, 4, ...
    /// up to 1024 ticks while they are faster (a headless run), so the extra delay past the
    /// interval stays within a few milliseconds of ticks. ("Ticks" here are the ticks the
    /// recorder sees: with `hash_every` above 1 the loop may batch the ones between, and a batch
    /// counts as one.)
    Interval(Duration),
    /// Only when the buffer fills and at [`Recorder::finish`] (benchmarks, in-memory writers).
    /// Runs of hashes are then closed only by keyframes, commands and their size, so the file's
    /// bytes do not depend on timing.
    OnFinish,
}

/// What to record and how often.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordOptions {
    /// Store the state hash at ticks that are multiples of this (at least 1; default 1).
    pub hash_every: u64,
    /// Store a keyframe at ticks that are multiples of this; 0 keeps only the start and end
    /// keyframes. Default 600 (10 s at 60 Hz): a seek re-simulates at most 599 ticks.
    pub keyframe_every: u64,
    /// Flushing; default every 50 ms of wall time.
    pub flush: FlushPolicy,
    /// The scene's file as the user named it, kept in the header for messages.
    pub scene_file: String,
}

impl Default for RecordOptions {
    fn default() -> Self {
        RecordOptions {
            hash_every: 1,
            keyframe_every: 600,
            flush: FlushPolicy::Interval(Duration::from_millis(50)),
            scene_file: String::new(),
        }
    }
}

/// What a recorder wrote so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordStats {
    /// Tick of the first keyframe.
    pub start_tick: u64,
    /// The last tick seen.
    pub last_tick: u64,
    /// Bytes written (buffered or not), the open run of hashes included as the record it
    /// becomes.
    pub bytes: u64,
    /// Stored hashes: the hashed ticks, and the footer's final hash when the last tick was
    /// not one of them (what `volley replay --verify` compares).
    pub hashes: u64,
    /// Keyframes, the start and final ones included.
    pub keyframes: u64,
    /// Commands.
    pub commands: u64,
}

/// Writes a recording of the world it observes to any [`Write`].
pub struct Recorder<W: Write> {
    /// The file behind its buffer; `None` only once [`Recorder::finish`] took it.
    out: Option<BufWriter<W>>,
    options: RecordOptions,
    snapshot: Snapshot,
    text: String,
    payload: Vec<u8>,
    /// The hashes not yet written as a record.
    run: format::HashRun,
    /// The next tick due a hash, and a keyframe (`u64::MAX`: none).
    next_hash: u64,
    next_keyframe: u64,
    last_flush: Instant,
    /// Clock reads for the flush policy: the last one, ticks between reads, ticks until the next.
    last_read: Instant,
    read_every: u32,
    until_read: u32,
    last_keyframe: u64,
    /// The last tick whose hash went into a run.
    last_hashed: Option<u64>,
    stats: RecordStats,
}

impl<W: Write> Recorder<W> {
    /// Starts a recording of `world` as it is now: writes the preamble, the header, the keyframe
    /// and the hash of the current tick.
    pub fn start(out: W, world: &World, options: RecordOptions) -> io::Result<Recorder<W>> {
        if options.hash_every == 0 {
            return Err(io::Error::other("hash_every must be at least 1"));
        }
        let scene = world.scene();
        let header = Header {
            volley_version: env!("CARGO_PKG_VERSION").into(),
            build: Build::current(),
            hash_layout: String::from_utf8_lossy(crate::hash::HASH_LAYOUT).into_owned(),
            scene_file: options.scene_file.clone(),
            scene_name: scene.name.clone(),
            scene_source: scene.source.clone(),
            timestep_ns: scene.timestep.as_nanos() as u64,
            substeps: world.substeps(),
            integrator: world.integrator(),
            tolerance: (world.params().tolerance != crate::integrate::DEFAULT_TOLERANCE)
                .then_some(world.params().tolerance),
            levels: format::LevelHash::of_scene(scene),
            start_tick: world.tick(),
            hash_every: options.hash_every,
            keyframe_every: options.keyframe_every,
            threads: world.threads(),
        };
        let json = serde_json::to_vec(&header).map_err(io::Error::other)?;
        let mut out = BufWriter::with_capacity(64 * 1024, out);
        format::write_preamble(&mut out)?;
        let mut bytes = format::PREAMBLE_LEN as u64;
        bytes += format::write_frame(&mut out, Kind::Header, &json)?;
        let tick = world.tick();
        let mut recorder = Recorder {
            out: Some(out),
            snapshot: world.snapshot(),
            text: String::with_capacity(256),
            payload: Vec::with_capacity(256),
            run: format::HashRun::new(options.hash_every),
            next_hash: next_multiple(tick, options.hash_every),
            next_keyframe: match options.keyframe_every {
                0 => u64::MAX,
                every => next_multiple(tick, every),
            },
            options,
            last_flush: Instant::now(),
            last_read: Instant::now(),
            read_every: 1,
            until_read: 1,
            last_keyframe: tick,
            last_hashed: None,
            stats: RecordStats {
                start_tick: tick,
                last_tick: tick,
                bytes,
                ..RecordStats::default()
            },
        };
        let out = recorder.out.as_mut().expect("the writer is set");
        recorder.stats.bytes += super::keyframe::encode_keyframe(out, &recorder.snapshot)?;
        recorder.stats.keyframes = 1;
        recorder.write_hash(world)?;
        recorder.flush()?;
        Ok(recorder)
    }

    /// What was written so far.
    pub fn stats(&self) -> RecordStats {
        RecordStats {
            bytes: self.stats.bytes + self.run.frame_len(),
            ..self.stats
        }
    }

    /// Ends the recording at the world's current tick: a keyframe of the final state (unless
    /// one was just written), the footer with the final tick, hash and divergence if the run
    /// stopped on one; flushes and returns the writer and the final counts.
    pub fn finish(mut self, world: &World) -> io::Result<(W, RecordStats)> {
        let tick = world.tick();
        if tick != self.last_keyframe {
            self.write_keyframe(world)?;
        }
        self.close_run()?;
        let footer = Footer {
            final_tick: tick,
            final_hash: state_hash(world),
            diverged: world.divergence(),
        };
        if self.last_hashed != Some(tick) {
            self.stats.hashes += 1;
        }
        let payload = format::encode_footer(&footer);
        self.stats.bytes += format::write_frame(self.out(), Kind::Footer, &payload)?;
        self.stats.last_tick = tick;
        self.out().flush()?;
        let out = self.out.take().expect("finish takes the writer once");
        let out = out.into_inner().map_err(|e| e.into_error())?;
        Ok((out, self.stats))
    }

    /// The buffered writer.
    fn out(&mut self) -> &mut BufWriter<W> {
        self.out.as_mut().expect("only finish takes the writer")
    }

    /// Writes the open run of hashes as a record.
    fn close_run(&mut self) -> io::Result<()> {
        let Some(out) = self.out.as_mut() else {
            return Ok(());
        };
        self.stats.bytes += self.run.close(out)?;
        Ok(())
    }

    /// Closes the open run and hands everything to the file.
    fn flush(&mut self) -> io::Result<()> {
        self.close_run()?;
        self.out().flush()?;
        self.last_flush = Instant::now();
        Ok(())
    }

    fn write_hash(&mut self, world: &World) -> io::Result<()> {
        let tick = world.tick();
        if !self.run.takes(tick) {
            self.close_run()?;
        }
        self.run.push(tick, state_hash(world));
        self.stats.hashes += 1;
        self.last_hashed = Some(tick);
        Ok(())
    }

    fn write_keyframe(&mut self, world: &World) -> io::Result<()> {
        self.close_run()?;
        world.snapshot_into(&mut self.snapshot);
        let out = self.out.as_mut().expect("only finish takes the writer");
        self.stats.bytes += super::keyframe::encode_keyframe(out, &self.snapshot)?;
        self.stats.keyframes += 1;
        self.last_keyframe = world.tick();
        Ok(())
    }

    fn tick(&mut self, world: &World) -> io::Result<()> {
        let tick = world.tick();
        self.stats.last_tick = tick;
        if tick >= self.next_hash {
            let every = self.options.hash_every;
            if every == 1 || tick.is_multiple_of(every) {
                self.write_hash(world)?;
            }
            self.next_hash = next_multiple(tick, every);
        }
        if tick >= self.next_keyframe {
            let every = self.options.keyframe_every;
            if tick.is_multiple_of(every) {
                self.write_keyframe(world)?;
            }
            self.next_keyframe = next_multiple(tick, every);
        }
        let due = match self.options.flush {
            FlushPolicy::EveryTick => true,
            FlushPolicy::Interval(d) => self.read_clock().is_some_and(|t| t - self.last_flush >= d),
            FlushPolicy::OnFinish => false,
        };
        if due {
            self.flush()?;
        }
        Ok(())
    }

    /// The wall clock, when a read is due: every tick while ticks are slower than 1 ms
    /// (`read_every` halves back to 1), every `read_every` ticks while they are faster
    /// (doubling up to 1024), so fast runs read it about a thousand times a second at most.
    fn read_clock(&mut self) -> Option<Instant> {
        self.until_read -= 1;
        if self.until_read > 0 {
            return None;
        }
        let now = Instant::now();
        let since = now - self.last_read;
        if since < Duration::from_millis(1) {
            self.read_every = (self.read_every * 2).min(1024);
        } else if since > Duration::from_millis(4) {
            self.read_every = (self.read_every / 2).max(1);
        }
        (self.last_read, self.until_read) = (now, self.read_every);
        Some(now)
    }

    fn command(&mut self, stamped: &Stamped) -> io::Result<()> {
        use std::fmt::Write as _;
        self.close_run()?;
        self.text.clear();
        write!(self.text, "{}", stamped.command).map_err(io::Error::other)?;
        self.payload.clear();
        self.payload.extend_from_slice(&stamped.tick.to_le_bytes());
        self.payload.extend_from_slice(self.text.as_bytes());
        let out = self.out.as_mut().expect("only finish takes the writer");
        self.stats.bytes += format::write_frame(out, Kind::Command, &self.payload)?;
        self.stats.commands += 1;
        Ok(())
    }
}

impl<W: Write> Drop for Recorder<W> {
    /// Closes the open run of hashes into the buffer, which the buffer's own drop then hands
    /// to the file: a recording dropped without [`Recorder::finish`] ends truncated after the
    /// last tick it saw. Errors are ignored here, as `BufWriter` ignores them on drop.
    fn drop(&mut self) {
        let _ = self.close_run();
    }
}

fn observer_error(e: io::Error) -> ObserverError {
    ObserverError(format!("cannot write the recording: {e}"))
}

impl<W: Write> TickObserver for Recorder<W> {
    fn on_command(&mut self, _world: &World, stamped: &Stamped) -> Result<(), ObserverError> {
        self.command(stamped).map_err(observer_error)
    }

    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.tick(world).map_err(observer_error)
    }

    /// The next tick due a hash or a keyframe: with `hash_every` above 1 the loop may run the
    /// ticks between as a batch.
    fn next_needed_tick(&self, _tick: u64) -> u64 {
        self.next_hash.min(self.next_keyframe)
    }
}
