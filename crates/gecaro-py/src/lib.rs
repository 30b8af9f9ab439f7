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
//! | [`calibration`] | `generate`, `identifiable`, `identify`, `evaluate` and their results |
//! | [`compensation`] | `compensate`, `Compensation` |
//!
//! Units everywhere: metres and radians (file readers convert from mm and
//! degrees when told).

use pyo3::prelude::*;

mod arrays;
mod calibration;
mod compensation;
mod data;
mod errors;
mod interrupt;
mod methods;
mod robot;
mod robust;
mod study;

#[pymodule]
fn _gecaro(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_class::<robot::PyRobot>()?;
    module.add_class::<robot::Exported>()?;
    module.add_class::<methods::PyMethod>()?;
    module.add_class::<data::PyData>()?;
    module.add_class::<study::PyStudy>()?;
    module.add_class::<calibration::Generation>()?;
    module.add_class::<calibration::PyIdentifiability>()?;
    module.add_class::<calibration::PyIdentification>()?;
    module.add_class::<calibration::PyParameter>()?;
    module.add_class::<calibration::PyErrorSummary>()?;
    module.add_class::<compensation::PyCompensation>()?;
    module.add_function(wrap_pyfunction!(robot::ready_robots, module)?)?;
    module.add_function(wrap_pyfunction!(methods::methods, module)?)?;
    module.add_function(wrap_pyfunction!(calibration::generate, module)?)?;
    module.add_function(wrap_pyfunction!(calibration::identifiable, module)?)?;
    module.add_function(wrap_pyfunction!(calibration::identify, module)?)?;
    module.add_function(wrap_pyfunction!(calibration::evaluate, module)?)?;
    module.add_function(wrap_pyfunction!(robust::cross_validate, module)?)?;
    module.add_function(wrap_pyfunction!(compensation::compensate, module)?)?;
    Ok(())
}
