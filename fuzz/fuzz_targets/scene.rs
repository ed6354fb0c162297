//! cargo-fuzz target `scene`: see [`volley_fuzz::scene`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::scene(data));
