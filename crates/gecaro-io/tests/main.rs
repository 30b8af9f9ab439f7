//! The file formats: lines, tables and URDF read as users write them.
//!
//! One test binary per crate (as ripgrep has): each file below was its own
//! binary, and linking them dominated the build of the tests.

mod lines;
mod tables;
mod urdf;
