//! Recording, reading, verifying and seeking replays, and the reader under a mutating fuzzer.
//! One binary, no GPU stack.

#[path = "../support/mod.rs"]
mod support;

#[path = "../replay_support/mod.rs"]
mod replay_support;

mod columns;
mod edited;
mod levels;
mod replay;
mod replay_fuzz;
mod replay_hash_runs;
mod timeline;
