//! The application layer's requests as the front ends send them.
//!
//! One test binary per crate (as ripgrep has): each file below was its own
//! binary, and linking them dominated the build of the tests.

mod cell;
mod documents;
mod elastic;
mod iso9283;
mod model_check;
mod parallel;
mod real_data;
mod wording;
