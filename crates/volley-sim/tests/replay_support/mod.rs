//! What the replay tests share: the coverage scene and script, recording into memory, and the
//! frame layout of the format (read here independently of the library, from its documented
//! layout, so the tests can edit a file the way a damaged or foreign one would look).
#![allow(dead_code)]

use std::io::Cursor;

use volley_sim::internals::clock::{FrameSource, VirtualClock};
use volley_sim::internals::replay::format::{self, Kind};
use volley_sim::internals::replay::{FlushPolicy, RecordOptions, Recorder, Recording, Replay};
use volley_sim::internals::scene;
use volley_sim::{Scene, SimLoop, Stamped, TickObserver, World};

/// The coverage scene (volley, contacts, spring, drag).
pub fn coverage_scene() -> Scene {
    scene::load(&crate::support::ws("tests/data/replay_scene.ron")).unwrap()
}

/// The reference's stiff spring (k/m = 1e4 at h = 1/60 s) under explicit Euler: it blows up
/// within a few ticks, so its recordings end in a divergence.
pub fn stiff_scene() -> Scene {
    scene::parse(
        "Scene(dt: 0.016666667, integrator: ExplicitEuler,
               forces: [Spring(anchor: (0, 0, 0), stiffness: 10000.0)],
               bodies: [(mass: 1, position: (1, 0, 0))])",
        "stiff.ron",
        "stiff",
    )
    .unwrap()
}

/// The script with every kind of command.
pub fn coverage_commands() -> Vec<Stamped> {
    let path = "tests/data/replay_commands.txt";
    let text = std::fs::read_to_string(crate::support::ws(path)).unwrap();
    volley_sim::internals::command::parse_script(&text, path).unwrap()
}

/// Options for in-memory recordings: keyframes every `keyframe_every`, no wall-clock flushes.
pub fn options(hash_every: u64, keyframe_every: u64) -> RecordOptions {
    RecordOptions {
        hash_every,
        keyframe_every,
        flush: FlushPolicy::OnFinish,
        scene_file: "tests/data/replay_scene.ron".into(),
    }
}

/// Records `ticks` ticks of `scene` with `commands`, frames from `source`.
pub fn record_from(
    scene: &Scene,
    ticks: u64,
    commands: &[Stamped],
    options: RecordOptions,
    source: &mut impl FrameSource,
) -> Vec<u8> {
    let mut sim = SimLoop::new(World::new(scene));
    sim.schedule(commands.iter().copied());
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options).unwrap();
    sim.run_until(ticks, source, &mut recorder).unwrap();
    recorder.finish(&sim.world).unwrap().0
}

/// Records at one tick per frame.
pub fn record(scene: &Scene, ticks: u64, commands: &[Stamped], options: RecordOptions) -> Vec<u8> {
    let mut source = VirtualClock::Steady(scene.timestep());
    record_from(scene, ticks, commands, options, &mut source)
}

/// Opens a recording held in memory.
pub fn open(
    bytes: &[u8],
) -> Result<Recording<Cursor<Vec<u8>>>, volley_sim::internals::replay::ReplayError> {
    Recording::from_reader(Cursor::new(bytes.to_vec()), "test.vrec")
}

/// Replays a recording to its end.
pub fn replay(bytes: &[u8], seek: Option<u64>) -> Replay<Cursor<Vec<u8>>> {
    let mut replay = Replay::start(open(bytes).unwrap(), seek).unwrap();
    replay.run_to(u64::MAX, &mut ()).unwrap();
    replay
}

/// An observer that keeps the canonical hash after every tick.
#[derive(Default)]
pub struct Hashes(pub Vec<(u64, u64)>);

impl TickObserver for Hashes {
    fn after_tick(
        &mut self,
        world: &World,
    ) -> Result<(), volley_sim::internals::sim_loop::ObserverError> {
        self.0
            .push((world.tick(), volley_sim::internals::hash::state_hash(world)));
        Ok(())
    }
}

/// One frame of a recording: kind tag and payload.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub kind: u8,
    pub payload: Vec<u8>,
}

/// Splits a complete recording into its frames (format v1: 12-byte preamble; per frame kind:u8,
/// len:u32, head check:u16, payload, crc:u32).
pub fn frames(bytes: &[u8]) -> Vec<Frame> {
    let mut out = Vec::new();
    let mut at = format::PREAMBLE_LEN;
    while at < bytes.len() {
        let len = u32::from_le_bytes(bytes[at + 1..at + 5].try_into().unwrap()) as usize;
        out.push(Frame {
            kind: bytes[at],
            payload: bytes[at + 7..at + 7 + len].to_vec(),
        });
        at += 7 + len + 4;
    }
    out
}

/// Reassembles frames with fresh head checks and CRCs.
pub fn assemble(frames: &[Frame]) -> Vec<u8> {
    let mut out = Vec::new();
    format::write_preamble(&mut out).unwrap();
    for f in frames {
        let kind = Kind::from_tag(f.kind).unwrap();
        format::write_frame(&mut out, kind, &f.payload).unwrap();
    }
    out
}

/// Byte offset where each frame starts.
pub fn frame_starts(bytes: &[u8]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut at = format::PREAMBLE_LEN;
    while at < bytes.len() {
        out.push(at);
        let len = u32::from_le_bytes(bytes[at + 1..at + 5].try_into().unwrap()) as usize;
        at += 7 + len + 4;
    }
    out
}
