//! The command line's integration tests: the binary run as a user runs it.
//!
//! One test binary per crate (as ripgrep has): each file below was its own
//! binary, and linking them dominated the build of the tests.

mod build_profile;
mod cli;
mod customer_frames;
mod determinism;
mod errors;
mod front_ends;
mod hardening;
mod interchange;
mod iso9283_cli;
mod mistakes_cli;
mod named_frames;
mod parallel_cli;
mod region_cli;
mod robust_cli;
mod util;
