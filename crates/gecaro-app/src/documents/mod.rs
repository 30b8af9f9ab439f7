//! The results as JSON documents: what `gecaro … --json` prints and what the
//! web API answers, built from the library's result types so that both speak
//! the same shapes (documented in `docs/api.md`).
//!
//! Units: metres and radians everywhere, as in the robot model.

mod compensation;
mod errors;
mod identifiable;
mod identification;
mod plan;
mod prediction;
mod verdict;

pub use compensation::*;
pub use errors::*;
pub use identifiable::*;
pub use identification::*;
pub use plan::*;
pub use prediction::*;
pub use verdict::*;
