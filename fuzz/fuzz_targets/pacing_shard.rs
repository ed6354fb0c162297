//! cargo-fuzz target `pacing_shard`: see [`volley_fuzz::pacing_shard`] for the input and the
//! property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::pacing_shard(data));
