//! The wall clock's `Instant`, in one place: std's, or the browser's with the `web` feature on
//! wasm32 (see the feature's note in Cargo.toml). Only what measures real time reads it (the
//! loop's `RealClock`, the recorder's flush timer, the study's timings); a tick never does.

#[cfg(not(all(target_arch = "wasm32", feature = "web")))]
pub use std::time::Instant;
#[cfg(all(target_arch = "wasm32", feature = "web"))]
pub use web_time::Instant;
