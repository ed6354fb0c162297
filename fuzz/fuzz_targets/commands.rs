//! cargo-fuzz target `commands`: see [`volley_fuzz::commands`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::commands(data));
