//! The JSON API on its own (docs/api.md): every route, through the router,
//! without a network.
//!
//! One binary, its tests in files by job: the page, robot files, the
//! calibration functions, the work in the cell, studies, and the server
//! under stress; `util` holds what they share.

mod calibration;
mod cell;
mod page;
mod parallel;
mod robots;
mod robustness;
mod studies;
mod util;
