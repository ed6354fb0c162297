//! cargo-fuzz target `capture`: see [`volley_fuzz::capture`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::capture(data));
