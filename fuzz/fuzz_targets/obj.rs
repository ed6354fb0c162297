//! cargo-fuzz target `obj`: see [`volley_fuzz::obj`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::obj(data));
