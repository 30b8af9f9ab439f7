//! Fuzz target: see [`gecaro_fuzz::web_api`] for the property checked.
//!
//! `cargo fuzz` builds it with `--cfg fuzzing`, which brings in libFuzzer
//! (fuzz/Cargo.toml); every other build of the workspace makes it an empty
//! program, so that `cargo test` neither compiles libFuzzer's C++ nor links
//! the libraries into six programs it never runs.
#![cfg_attr(fuzzing, no_main)]

#[cfg(fuzzing)]
libfuzzer_sys::fuzz_target!(|input: &[u8]| gecaro_fuzz::web_api(input));

#[cfg(not(fuzzing))]
fn main() {}
