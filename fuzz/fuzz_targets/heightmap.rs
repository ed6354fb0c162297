//! cargo-fuzz target `heightmap`: see [`volley_fuzz::heightmap`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::heightmap(data));
