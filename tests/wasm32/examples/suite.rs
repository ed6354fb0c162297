//! Prints the determinism suite's report ([`volley_wasm32::suite`]), one line per run: the
//! program `scripts/aarch64` builds for aarch64-unknown-linux-gnu and `tests/same_bits.rs` runs
//! under qemu-aarch64, comparing its lines with this machine's.

use std::io::Write;

fn main() {
    let mut out = std::io::stdout().lock();
    for line in volley_wasm32::suite() {
        writeln!(out, "{line}").expect("stdout is writable");
    }
}
