//! Hash records hold runs of hashes: where the recorder closes a run, and what the reader
//! refuses in one. (Format version 2; `src/replay/format.rs` has the layout.)

use crate::replay_support::*;
use volley_sim::internals::replay::format::HASH_RUN_MAX;
use volley_sim::internals::scene;
use volley_sim::{Scene, Stamped};

/// One body thrown under gravity, no contacts: cheap to run for thousands of ticks.
fn throw() -> Scene {
    scene::parse(
        "Scene(dt: 0.01, integrator: SemiImplicitEuler, forces: [Gravity((0, 0, -9.81))],
               bodies: [(mass: 1, position: (0, 0, 1), launch: Velocity((3, 0, 40)))])",
        "throw.ron",
        "throw",
    )
    .unwrap()
}

fn commands(script: &str) -> Vec<Stamped> {
    volley_sim::internals::command::parse_script(script, "inline").unwrap()
}

const HEADER: u8 = 1;
const KEYFRAME: u8 = 2;
const COMMAND: u8 = 3;
const HASHES: u8 = 4;
const FOOTER: u8 = 5;

/// A hash record's first tick, stride and number of hashes.
fn run_of(f: &Frame) -> (u64, u64, usize) {
    let word = |k: usize| u64::from_le_bytes(f.payload[8 * k..8 * k + 8].try_into().unwrap());
    (word(0), word(1), (f.payload.len() - 16) / 8)
}

#[test]
fn runs_are_closed_by_the_start_a_command_their_size_a_keyframe_and_the_end() {
    let script = commands("500: fire");
    let bytes = record(&throw(), 3000, &script, options(1, 2000));
    let frames = frames(&bytes);
    let kinds: Vec<u8> = frames.iter().map(|f| f.kind).collect();
    assert_eq!(
        kinds,
        [
            HEADER, KEYFRAME, HASHES, HASHES, COMMAND, HASHES, HASHES, KEYFRAME, HASHES, KEYFRAME,
            FOOTER,
        ]
    );
    let runs: Vec<_> = frames
        .iter()
        .filter(|f| f.kind == HASHES)
        .map(run_of)
        .collect();
    assert_eq!(
        runs,
        [
            (0, 1, 1),              // the start tick, flushed by `start`
            (1, 1, 500),            // up to the command applied before tick 500's step
            (501, 1, HASH_RUN_MAX), // full
            (501 + HASH_RUN_MAX as u64, 1, 2000 - 500 - HASH_RUN_MAX), // up to the keyframe
            (2001, 1, 1000),        // up to the final keyframe
        ]
    );
    let rec = open(&bytes).unwrap();
    let ticks: Vec<u64> = rec.hashes().iter().map(|h| h.0).collect();
    assert_eq!(ticks, (0..=3000).collect::<Vec<_>>());
}

#[test]
fn with_a_hash_every_k_ticks_a_run_has_stride_k() {
    let bytes = record(&throw(), 100, &[], options(3, 0));
    let runs: Vec<_> = frames(&bytes)
        .iter()
        .filter(|f| f.kind == HASHES)
        .map(run_of)
        .collect();
    assert_eq!(runs, [(0, 3, 1), (3, 3, 33)]);
    let rec = open(&bytes).unwrap();
    let ticks: Vec<u64> = rec.hashes().iter().map(|h| h.0).collect();
    let expected: Vec<u64> = (0..=99).step_by(3).chain([100]).collect();
    assert_eq!(
        ticks, expected,
        "every third tick, and the footer's final tick"
    );
    assert!(replay(&bytes, None).first_divergence().is_none());
}

/// The recording of [`runs_are_closed_by_the_start_a_command_their_size_a_keyframe_and_the_end`]
/// with `edit` applied to its second hash record (ticks 1 to 500), CRCs made valid again.
fn edited(edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let bytes = record(&throw(), 3000, &commands("500: fire"), options(1, 2000));
    let mut frames = frames(&bytes);
    let second = frames.iter().filter(|f| f.kind == HASHES).nth(1).unwrap();
    let i = frames.iter().position(|f| f == second).unwrap();
    edit(&mut frames[i].payload);
    assemble(&frames)
}

#[test]
fn a_run_with_stride_0_a_partial_hash_or_ticks_past_the_next_record_is_refused() {
    let set = |k: usize, x: u64| {
        move |p: &mut Vec<u8>| p[8 * k..8 * k + 8].copy_from_slice(&x.to_le_bytes())
    };
    let cases: [(Vec<u8>, &str); 5] = [
        (
            edited(set(1, 0)),
            "hashes record: stride 0 between hashed ticks",
        ),
        (
            edited(|p| p.extend_from_slice(&[0; 4])),
            "hashes record: 4004 bytes of hashes, not a whole number of them",
        ),
        // Ticks 1, 3, ..., 999 run past the command at tick 500.
        (edited(set(1, 2)), "command record: tick 500 after tick 999"),
        (edited(set(0, 0)), "hashes record: a second hash for tick 0"),
        (
            edited(set(0, u64::MAX - 10)),
            "hashes record: 500 hashes from tick 18446744073709551605, 1 apart, pass the largest tick",
        ),
    ];
    for (bytes, expected) in cases {
        let e = open(&bytes).unwrap_err().to_string();
        assert!(
            e.starts_with("test.vrec: byte ") && e.ends_with(expected),
            "{e}"
        );
    }
}

#[test]
fn a_run_longer_than_the_cap_is_refused_by_its_length() {
    let bytes = edited(|p| p.extend_from_slice(&vec![0; 8 * HASH_RUN_MAX]));
    let e = open(&bytes).unwrap_err().to_string();
    let len = 16 + 8 * (500 + HASH_RUN_MAX);
    assert!(e.ends_with(&format!("hashes record of {len} bytes")), "{e}");
}
