//! The Python face of gecaro: `import gecaro`.
//!
//! This crate holds only conversions (numpy arrays, Python exceptions,
//! the GIL and Ctrl-C) and the Python classes; the calibration itself is the
//! library crates', so the Python package computes what the command line
//! computes, bit for bit. The Python package around this extension module
//! (`python/gecaro`) adds the exception classes and the type stubs.
//!
//! | module | Python |
//! |---|---|
//! | [`robot`] | `Robot` (files, table, parameters, fk / jacobian / ik), `Exported`, `ready_robots()` |
//! | [`methods`] | `Method`, `methods()` |
//! | [`data`] | `Data` (arrays ↔ data files) |
//! | [`study`] | `Study` (several sets, study files) |
//! | [`generation`] | `generate`, `Generation` |
//! | [`identifiability`] | `identifiable`, `Identifiability` |
//! | [`identification`] | `identify`, `evaluate`, `Identification`, `Parameter`, `ErrorSummary` |
//! | [`validation`] | `cross_validate` |
//! | [`compensation`] | `compensate`, `Compensation` |
//! | [`parallel`] | `parallel_generate`, `parallel_identifiable`, `parallel_identify`, `parallel_evaluate`, `parallel_compensate`, `parallel_plan`, `parallel_predict` |
//! | [`planning`] | `plan`, `Plan`, `plan_study`, `predict`, `accuracy_curve` |
//!
//! Every calibration function maps its arguments onto a request of the
//! application layer (`gecaro-app`, through [`source`]) and its result onto
//! Python objects: the same requests as the command line's and the web
//! page's, so the same numbers and the same messages (in Python's words).
//!
//! Units everywhere: metres and radians (file readers convert from mm and
//! degrees when told); a sensor's σ may carry its own unit ([`sigma`]).

// The modules are private (the crate's interface is Python's); their docs
// are for its developers: `cargo doc --document-private-items`.
#![allow(rustdoc::private_intra_doc_links)]
// A Python function's keyword arguments are its Rust function's parameters
// (pyo3 reads `#[pyo3(signature = …)]` from them): a Python call with ten
// keywords is a Rust function with ten parameters, which each function maps
// onto one request of the application layer at once.
#![allow(clippy::too_many_arguments)]

use pyo3::prelude::*;

mod arrays;
mod compensation;
mod data;
mod data_set;
mod documents;
mod errors;
mod files;
mod frames;
mod generation;
mod identifiability;
mod identification;
mod interrupt;
mod iso9283;
mod methods;
mod parallel;
mod planning;
mod robot;
mod robot_inputs;
mod sigma;
mod source;
mod study;
mod validation;
mod warnings;

#[pymodule]
fn _gecaro(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The defaults the functions' signatures state, from the constants the
    // command line and the page read (a test checks every signature
    // against them).
    let defaults = pyo3::types::PyDict::new(module.py());
    defaults.set_item(
        "max_iterations",
        gecaro_calib::identification::DEFAULT_MAX_ITERATIONS,
    )?;
    defaults.set_item("seed", gecaro_calib::simulation::DEFAULT_SEED)?;
    defaults.set_item(
        "outlier_threshold",
        gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD,
    )?;
    defaults.set_item("cycles", gecaro_calib::iso9283::DEFAULT_CYCLES)?;
    module.add("DEFAULTS", defaults)?;
    module.add_class::<robot::PyRobot>()?;
    module.add_class::<robot::Exported>()?;
    module.add_class::<methods::PyMethod>()?;
    module.add_class::<data::PyData>()?;
    module.add_class::<study::PyStudy>()?;
    module.add_class::<generation::Generation>()?;
    module.add_class::<identifiability::PyIdentifiability>()?;
    module.add_class::<identification::PyIdentification>()?;
    module.add_class::<identification::PyParameter>()?;
    module.add_class::<identification::PyErrorSummary>()?;
    module.add_class::<compensation::PyCompensation>()?;
    module.add_class::<planning::PyPlan>()?;
    module.add_function(wrap_pyfunction!(robot::ready_robots, module)?)?;
    module.add_function(wrap_pyfunction!(methods::methods, module)?)?;
    module.add_function(wrap_pyfunction!(generation::generate, module)?)?;
    module.add_function(wrap_pyfunction!(identifiability::identifiable, module)?)?;
    module.add_function(wrap_pyfunction!(identification::identify, module)?)?;
    module.add_function(wrap_pyfunction!(identification::evaluate, module)?)?;
    module.add_function(wrap_pyfunction!(validation::cross_validate, module)?)?;
    module.add_function(wrap_pyfunction!(compensation::compensate, module)?)?;
    module.add_function(wrap_pyfunction!(compensation::compensate_program, module)?)?;
    module.add_function(wrap_pyfunction!(frames::tool_point, module)?)?;
    module.add_function(wrap_pyfunction!(frames::user_frame, module)?)?;
    module.add_function(wrap_pyfunction!(frames::join, module)?)?;
    module.add_function(wrap_pyfunction!(iso9283::iso9283_plan, module)?)?;
    module.add_function(wrap_pyfunction!(iso9283::iso9283_evaluate, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_generate, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_identifiable, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_identify, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_evaluate, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_compensate, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_plan, module)?)?;
    module.add_function(wrap_pyfunction!(parallel::parallel_predict, module)?)?;
    module.add_function(wrap_pyfunction!(planning::plan, module)?)?;
    module.add_function(wrap_pyfunction!(planning::plan_study, module)?)?;
    module.add_function(wrap_pyfunction!(planning::predict, module)?)?;
    module.add_function(wrap_pyfunction!(planning::accuracy_curve, module)?)?;
    Ok(())
}
