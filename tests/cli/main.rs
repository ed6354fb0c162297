//! Tests that run the `volley` binary (or need the whole sandbox crate): bad input and exit
//! codes, pinned hashes in both profiles, batched and vector-width equivalence end to end,
//! divergence reports, `--frames`, the study's files, and replays from the command line.

#[path = "../support/mod.rs"]
mod support;

#[path = "../../crates/volley-sim/tests/replay_support/mod.rs"]
mod replay_support;

mod aim;
mod bad_input;
mod batch;
mod determinism;
mod divergence;
mod first_run;
mod headless_frames;
mod manual;
mod pacing;
mod range;
mod replay_cli;
mod simd;
mod study;
mod synctest;
