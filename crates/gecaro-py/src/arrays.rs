//! numpy arrays in and out.
//!
//! Inputs are any array-like of real numbers (numpy arrays of any real dtype,
//! lists, tuples): integers are converted to float64; other dtypes (complex,
//! strings, objects) and wrong shapes are an `InputError` (a `ValueError`)
//! naming the argument and the shape it needs. Inputs are copied into Rust
//! memory before any work, so the GIL can be released without Python code
//! changing them underneath — the large columns of a `Data` too
//! ([`column_of`]; docs/python.md). Outputs are new C-ordered float64
//! arrays.

use gecaro_calib::study::Column as SampleColumn;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{
    Element, IntoPyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::input;

/// The dimensions of an array, as Python writes them: `(3, 4)`, `(6,)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// `value` as a numpy array of `dtype` (`float64` or `int64`), accepting the
/// dtype kinds in `kinds` (`"fiu"`: float, signed, unsigned integers).
fn converted<'py>(
    value: &Bound<'py, PyAny>,
    what: &str,
    expected: &str,
    dtype: &str,
    kinds: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = value.py().import("numpy")?;
    let array = numpy
        .call_method1("asarray", (value,))
        .map_err(|error| input(format!("{what}: expected {expected}; {error}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if !kinds.contains(kind.as_str()) {
        let dtype_name: String = array.getattr("dtype")?.str()?.extract()?;
        return Err(input(format!(
            "{what}: expected {expected} of real numbers, got an array of dtype {dtype_name}"
        )));
    }
    array.call_method1("astype", (dtype,))
}

/// Whether `value` (a numpy array) sits at an address its dtype can be
/// read at (numpy's `flags.aligned`); false for what is not an array.
fn aligned(value: &Bound<'_, PyAny>) -> bool {
    value
        .getattr("flags")
        .and_then(|flags| flags.getattr("aligned"))
        .and_then(|aligned| aligned.extract::<bool>())
        .unwrap_or(false)
}

/// A float64 array with its shape, copied.
pub(crate) struct Real {
    /// The shape.
    pub(crate) shape: Vec<usize>,
    /// The values in C order.
    pub(crate) values: Vec<f64>,
}

impl Real {
    /// `value` as float64 values; `expected` describes the shape in messages.
    pub(crate) fn new(value: &Bound<'_, PyAny>, what: &str, expected: &str) -> PyResult<Self> {
        let read = |array: PyReadonlyArrayDyn<'_, f64>| Real {
            shape: array.shape().to_vec(),
            values: array.as_array().iter().copied().collect(),
        };
        // A float64 array at an odd address (a view into a byte buffer)
        // cannot be read as one: it is converted (issue 75: it panicked).
        if let Ok(array) = value.extract::<PyReadonlyArrayDyn<'_, f64>>()
            && aligned(value)
        {
            return Ok(read(array));
        }
        let array = converted(value, what, expected, "float64", "fiu")?;
        Ok(read(array.extract::<PyReadonlyArrayDyn<'_, f64>>()?))
    }

    /// The error of a shape other than `expected`.
    pub(crate) fn wrong_shape(&self, what: &str, expected: &str) -> PyErr {
        input(format!(
            "{what}: expected {expected}, got an array of shape {}",
            shape_text(&self.shape)
        ))
    }

    /// `value` of exactly this shape (`None`: any length on that axis).
    pub(crate) fn shaped(
        value: &Bound<'_, PyAny>,
        what: &str,
        shape: &[Option<usize>],
    ) -> PyResult<Self> {
        let expected = expected_shape(shape);
        let array = Real::new(value, what, &expected)?;
        if fits(&array.shape, shape) {
            Ok(array)
        } else {
            Err(array.wrong_shape(what, &expected))
        }
    }

    /// Rows of `row_length` values: `(k,)` is one row, `(m, k)` is m rows.
    /// Returns the rows and whether the input was a single row.
    pub(crate) fn rows(
        value: &Bound<'_, PyAny>,
        what: &str,
        row_length: usize,
    ) -> PyResult<(Vec<f64>, bool)> {
        let expected = format!("an array of shape ({row_length},) or (m, {row_length})");
        let array = Real::new(value, what, &expected)?;
        match array.shape[..] {
            [k] if k == row_length => Ok((array.values, true)),
            [_, k] if k == row_length => Ok((array.values, false)),
            _ => Err(array.wrong_shape(what, &expected)),
        }
    }
}

/// The words of a shape in messages: `an array of shape (m, 3)`.
fn expected_shape(shape: &[Option<usize>]) -> String {
    format!(
        "an array of shape ({})",
        shape
            .iter()
            .enumerate()
            .map(|(axis, length)| length
                .map_or_else(|| ["m", "k"][axis.min(1)].to_owned(), |n| n.to_string()))
            .collect::<Vec<_>>()
            .join(", ")
            + if shape.len() == 1 { "," } else { "" }
    )
}

/// Whether `found` is `shape` (`None`: any length on that axis).
fn fits(found: &[usize], shape: &[Option<usize>]) -> bool {
    found.len() == shape.len()
        && found
            .iter()
            .zip(shape)
            .all(|(found, wanted)| wanted.is_none_or(|wanted| *found == wanted))
}

/// `value` of exactly this shape as one column of values, copied into
/// Rust memory (one pass over a C-ordered float64 array; other arrays
/// converted by numpy's `ascontiguousarray` first). Returns the shape and
/// the column.
///
/// Why a copy, not the array's memory read in place (issue 75): numpy frees
/// an array's memory on `resize(…, refcheck=False)` and `__setstate__`
/// whatever references or buffer exports it has, and a calibration that
/// read it afterwards — or while another thread did it, the GIL released —
/// read freed memory. The copy costs one pass (72 MB and ~30 ms for 10⁶
/// rows of a 6-joint robot with positions) and no crash is left to a
/// caller's care.
pub(crate) fn column_of(
    value: &Bound<'_, PyAny>,
    what: &str,
    shape: &[Option<usize>],
) -> PyResult<(Vec<usize>, SampleColumn<f64>)> {
    let expected = expected_shape(shape);
    // A float64 array at an odd address (a view into a byte buffer) is
    // converted, not refused (issue 75).
    let array = match value.cast::<PyArrayDyn<f64>>() {
        Ok(array) if array.is_c_contiguous() && aligned(value) => array.clone(),
        _ => {
            let converted = converted(value, what, &expected, "float64", "fiu")?;
            let numpy = value.py().import("numpy")?;
            numpy
                .call_method1("ascontiguousarray", (converted,))?
                .cast_into::<PyArrayDyn<f64>>()?
        }
    };
    let found = array.shape().to_vec();
    if !fits(&found, shape) {
        return Err(input(format!(
            "{what}: expected {expected}, got an array of shape {}",
            shape_text(&found)
        )));
    }
    let read = array
        .try_readonly()
        .map_err(|error| input(format!("{what}: {error}")))?;
    let values = read
        .as_slice()
        .map_err(|error| input(format!("{what}: {error}")))?
        .to_vec();
    Ok((found, SampleColumn::from(values)))
}

/// `value` as m non-negative integers (set or pair ids).
pub(crate) fn identifiers(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<u64>> {
    let expected = "an array of shape (m,) of integers ≥ 0";
    let array = converted(value, what, expected, "int64", "iu")?;
    let array = array.extract::<PyReadonlyArrayDyn<'_, i64>>()?;
    if array.ndim() != 1 {
        return Err(input(format!(
            "{what}: expected {expected}, got an array of shape {}",
            shape_text(array.shape())
        )));
    }
    array
        .as_array()
        .iter()
        .enumerate()
        .map(|(row, id)| {
            u64::try_from(*id).map_err(|_| input(format!("{what}: row {row} is {id}, not ≥ 0")))
        })
        .collect()
}

/// A new array of this shape (float64 or int64).
pub(crate) fn array<'py, T: Element>(
    py: Python<'py>,
    shape: &[usize],
    values: Vec<T>,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    Ok(ArrayD::from_shape_vec(IxDyn(shape), values)
        .map_err(|error| pyo3::exceptions::PyRuntimeError::new_err(error.to_string()))?
        .into_pyarray(py))
}

/// A named field of a record, for [`columns`].
pub(crate) type Column<T> = (&'static str, fn(&T) -> f64);

/// A dict of one (len,) array per named field of `records`.
pub(crate) fn columns<'py, T>(
    py: Python<'py>,
    records: &[T],
    fields: &[Column<T>],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, value) in fields {
        dict.set_item(
            key,
            array(py, &[records.len()], records.iter().map(value).collect())?,
        )?;
    }
    Ok(dict)
}

/// A priority matrix's rows (α, d, θ, r, β, K per frame) as an (n+2, 6) int64 array.
pub(crate) fn priority_array<'py>(
    py: Python<'py>,
    rows: &[[u32; 6]],
) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
    let values = rows.iter().flatten().map(|v| i64::from(*v)).collect();
    array(py, &[rows.len(), 6], values)
}

/// The rows of an (N, 3) array `what` (N = `count` when given) as points.
pub(crate) fn points(
    array: &Bound<'_, PyAny>,
    what: &str,
    count: Option<usize>,
) -> PyResult<Vec<nalgebra::Vector3<f64>>> {
    Ok(Real::shaped(array, what, &[count, Some(3)])?
        .values
        .chunks_exact(3)
        .map(nalgebra::Vector3::from_column_slice)
        .collect())
}

/// Measured points (an (N, 3) array, `measured`) and their names (`names`,
/// else `row i`).
///
/// # Errors
/// An array of another shape, or names of another count.
pub(crate) fn named_points(
    measured: &Bound<'_, PyAny>,
    names: Option<Vec<String>>,
) -> PyResult<(Vec<String>, Vec<nalgebra::Vector3<f64>>)> {
    let measured = points(measured, "measured", None)?;
    let count = measured.len();
    let names = match names {
        Some(names) if names.len() != count => {
            return Err(input(format!("names: {} for {count} points", names.len())));
        }
        Some(names) => names,
        None => (0..count).map(|i| format!("row {i}")).collect(),
    };
    Ok((names, measured))
}
