//! Fuzz target: see [`gecaro_fuzz::web_api`] for the property checked.
#![no_main]

libfuzzer_sys::fuzz_target!(|input: &[u8]| gecaro_fuzz::web_api(input));
