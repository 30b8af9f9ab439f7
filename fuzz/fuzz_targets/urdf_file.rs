//! Fuzz target: see [`gecaro_fuzz::urdf_file`] for the property checked.
#![no_main]

libfuzzer_sys::fuzz_target!(|input: &[u8]| gecaro_fuzz::urdf_file(input));
