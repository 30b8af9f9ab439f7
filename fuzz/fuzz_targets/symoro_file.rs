//! Fuzz target: see [`gecaro_fuzz::symoro_file`] for the property checked.
#![no_main]

libfuzzer_sys::fuzz_target!(|input: &[u8]| gecaro_fuzz::symoro_file(input));
