//! cargo-fuzz target `shard`: see [`volley_fuzz::shard`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::shard(data));
