//! cargo-fuzz target `recording`: see [`volley_fuzz::recording`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::recording(data));
