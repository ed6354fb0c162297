//! cargo-fuzz target `window_script`: see [`volley_fuzz::window_script`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::window_script(data));
