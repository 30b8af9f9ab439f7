//! The calibration library against simulated truth, real data and Table 2.
//!
//! One test binary per crate (as ripgrep has): each file below was its own
//! binary, and linking them dominated the build of the tests.

mod change;
mod coarse;
mod frames;
mod identifiability;
mod identification;
mod iso9283;
mod parallel_robots;
mod planning;
mod prediction;
mod region;
mod robust;
mod row_sigma;
mod streaming;
mod util;
mod validation;
mod verdict;
