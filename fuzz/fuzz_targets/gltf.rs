//! cargo-fuzz target `gltf`: see [`volley_fuzz::gltf`] for the input and the property.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| volley_fuzz::gltf(data));
