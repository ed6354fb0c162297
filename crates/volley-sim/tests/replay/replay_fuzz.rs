//! The recording reader against mutated files: it may refuse them, never panic.
//!
//! A seeded mutation loop over a corpus of valid recordings (a complete one with commands, one
//! started mid-run, one that ends in a divergence, one hashing every 3 ticks, a truncated one).
//! Half the cases mutate raw bytes (bit flips, byte overwrites with boundary values,
//! truncations, insertions, deletions, duplications, splices with another file); the other half
//! mutate inside frames and then recompute every head check and CRC, so the payload decoders
//! (JSON header, commands, keyframes, footer) and the record-order rules see damage the CRC
//! would otherwise stop. Each case opens the file, parses its scene, decodes and restores every
//! keyframe, and starts a replay and runs it a few ticks.
//!
//! CI runs `CI_CASES` in the dev profile (a few seconds). The full run, 1 000 000 cases:
//! `cargo test --release -p volley-sim --test replay replay_fuzz -- --ignored --nocapture`
//! (`VOLLEY_FUZZ_CASES=N` sets another count, `VOLLEY_FUZZ_SEED=S` another seed).

use std::io::Cursor;

use crate::replay_support::*;
use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::replay::{Recorder, Recording, Replay};
use volley_sim::internals::world::SplitMix64;
use volley_sim::{SimLoop, World};

/// Cases the dev-profile test run covers.
const CI_CASES: u64 = 20_000;

fn corpus() -> Vec<Vec<u8>> {
    let scene = coverage_scene();
    let commands = coverage_commands();
    let mut files = vec![record(&scene, 70, &commands, options(1, 20))];
    files.push(record(&scene, 40, &commands, options(3, 0)));
    // Started mid-run, at tick 50.
    let mut sim = SimLoop::new(World::new(&scene));
    sim.schedule(commands.iter().copied());
    let mut source = VirtualClock::Steady(scene.timestep());
    sim.run_until(50, &mut source, &mut ()).unwrap();
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 15)).unwrap();
    sim.run_until(75, &mut source, &mut recorder).unwrap();
    files.push(recorder.finish(&sim.world).unwrap().0);
    // Ends in a divergence.
    let stiff = stiff_scene();
    let mut sim = SimLoop::new(World::new(&stiff));
    let mut recorder = Recorder::start(Vec::new(), &sim.world, options(1, 5)).unwrap();
    let _ = sim.run_until(
        100,
        &mut VirtualClock::Steady(stiff.timestep()),
        &mut recorder,
    );
    files.push(recorder.finish(&sim.world).unwrap().0);
    // Truncated inside its last record.
    let mut cut = files[0].clone();
    cut.truncate(cut.len() - 30);
    files.push(cut);
    files
}

/// What the cases reached, so the test fails if the mutator stops reaching the decoders.
#[derive(Debug, Default)]
struct Reached {
    refused: u64,
    opened: u64,
    scenes: u64,
    keyframes: u64,
    replays: u64,
}

/// Everything a user's `volley replay` does with a file, short of running it to the end.
fn exercise(bytes: &[u8], reached: &mut Reached) {
    let Ok(mut rec) = Recording::from_reader(Cursor::new(bytes), "fuzz.vrec") else {
        reached.refused += 1;
        return;
    };
    reached.opened += 1;
    let _ = rec.build_warnings();
    let Ok(scene) = rec.scene() else {
        return;
    };
    reached.scenes += 1;
    // A mutated volley count or substep count would only measure allocation or patience.
    let bodies = scene.bodies().len() + scene.volley().map_or(0, |v| v.count as usize);
    if bodies > 1000 || scene.substeps() > 16 {
        return;
    }
    for i in 0..rec.keyframes().len() {
        if rec.world_at(i, &scene).is_ok() {
            reached.keyframes += 1;
        }
    }
    if let Ok(mut replay) = Replay::start(rec, None) {
        reached.replays += 1;
        let _ = replay.run_to(replay.started_at() + 3, &mut ());
    }
}

fn byte(rng: &mut SplitMix64) -> u8 {
    rng.next_u64() as u8
}

fn below(rng: &mut SplitMix64, n: usize) -> usize {
    (rng.next_u64() % n.max(1) as u64) as usize
}

/// One raw mutation of `b`; `other` is another corpus file for splices.
fn mutate_bytes(b: &mut Vec<u8>, other: &[u8], rng: &mut SplitMix64) {
    let at = below(rng, b.len());
    match rng.next_u64() % 8 {
        0 => {
            if let Some(x) = b.get_mut(at) {
                *x ^= 1 << (rng.next_u64() % 8);
            }
        }
        1 => {
            let values = [0x00, 0xff, 0x7f, 0x80, 0x01, 0xfe];
            let v = values[below(rng, values.len())];
            let n = [1, 2, 4, 8][below(rng, 4)];
            for x in b.iter_mut().skip(at).take(n) {
                *x = v;
            }
        }
        2 => b.truncate(at),
        3 => {
            let n = 1 + below(rng, 16);
            let bytes: Vec<u8> = (0..n).map(|_| byte(rng)).collect();
            b.splice(at..at, bytes);
        }
        4 => {
            let end = (at + 1 + below(rng, 64)).min(b.len());
            b.drain(at..end);
        }
        5 => {
            let end = (at + 1 + below(rng, 64)).min(b.len());
            let chunk = b[at..end].to_vec();
            let to = below(rng, b.len());
            b.splice(to..to, chunk);
        }
        6 => {
            let from = below(rng, other.len());
            b.truncate(at);
            b.extend_from_slice(&other[from..]);
        }
        _ => {
            if let Some(x) = b.get_mut(at) {
                *x = byte(rng);
            }
        }
    }
}

/// One mutation inside the frames, then every check and CRC made valid again.
fn mutate_frames(file: &[u8], other: &[u8], rng: &mut SplitMix64) -> Vec<u8> {
    let mut frames = frames(file_without_partial_tail(file));
    let i = below(rng, frames.len());
    match rng.next_u64() % 6 {
        0 => {
            frames.remove(i);
        }
        1 => {
            let f = frames[i].clone();
            frames.insert(below(rng, frames.len()), f);
        }
        2 => {
            let j = below(rng, frames.len());
            frames.swap(i, j);
        }
        _ => {
            let p = &mut frames[i].payload;
            for _ in 0..1 + below(rng, 3) {
                mutate_bytes(p, other, rng);
            }
        }
    }
    assemble(&frames)
}

/// The corpus' truncated file minus its partial record, so its frames can be split.
fn file_without_partial_tail(file: &[u8]) -> &[u8] {
    let mut end = 0;
    for start in frame_starts(file) {
        let len = u32::from_le_bytes(file[start + 1..start + 5].try_into().unwrap()) as usize;
        if start + 7 + len + 4 <= file.len() {
            end = start + 7 + len + 4;
        }
    }
    &file[..end]
}

fn fuzz(cases: u64, seed: u64) -> Reached {
    let corpus = corpus();
    let mut reached = Reached::default();
    for case in 0..cases {
        let mut rng = SplitMix64(seed ^ case.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let file = &corpus[below(&mut rng, corpus.len())];
        let other = &corpus[below(&mut rng, corpus.len())];
        let bytes = if rng.next_u64().is_multiple_of(2) {
            mutate_frames(file, other, &mut rng)
        } else {
            let mut b = file.clone();
            for _ in 0..1 + below(&mut rng, 3) {
                mutate_bytes(&mut b, other, &mut rng);
            }
            b
        };
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut r = Reached::default();
            exercise(&bytes, &mut r);
            r
        }));
        match outcome {
            Ok(r) => {
                reached.refused += r.refused;
                reached.opened += r.opened;
                reached.scenes += r.scenes;
                reached.keyframes += r.keyframes;
                reached.replays += r.replays;
            }
            Err(_) => {
                let path = std::env::temp_dir().join(format!("volley-fuzz-{seed}-{case}.vrec"));
                std::fs::write(&path, &bytes).unwrap();
                panic!(
                    "case {case} (seed {seed}) panicked; input saved to {}",
                    path.display()
                );
            }
        }
    }
    eprintln!("{cases} mutated recordings, seed {seed}: {reached:?}");
    reached
}

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn mutated_recordings_are_refused_or_replayed_never_a_panic() {
    let cases = env("VOLLEY_FUZZ_CASES", CI_CASES);
    let r = fuzz(cases, env("VOLLEY_FUZZ_SEED", 1));
    // The mutator reaches every stage: refusals, opened files, scenes, keyframes and replays.
    assert!(r.refused > 0 && r.opened > 0 && r.scenes > 0, "{r:?}");
    assert!(r.keyframes > 0 && r.replays > 0, "{r:?}");
}

#[test]
#[ignore = "a million cases: run in release, see the module doc"]
fn a_million_mutated_recordings_are_refused_or_replayed_never_a_panic() {
    let cases = env("VOLLEY_FUZZ_CASES", 1_000_000);
    let r = fuzz(cases, env("VOLLEY_FUZZ_SEED", 2));
    assert_eq!(r.refused + r.opened, cases);
}
