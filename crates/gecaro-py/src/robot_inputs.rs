//! What Python hands a robot, read: poses (4×4 matrices or gecaro's seven
//! numbers), priority matrices, per-frame and per-joint columns, and room
//! for a batch's output within a bound.

use std::path::PathBuf;

use gecaro_core::{PriorityMatrix, Robot};
use gecaro_io::{pose_from_seven, read_priority_file};
use nalgebra::{DMatrix, IsometryMatrix3};
use pyo3::prelude::*;

use crate::arrays::Real;
use crate::errors::{IntoPyResult, input};

/// The most bytes a batch call returns (1 GiB): beyond it the caller is
/// told to split the batch, rather than the process aborted by a failed
/// allocation (issue 75: a Jacobian of 2·10⁶ configurations asked 4.1 GB).
pub(crate) const MAX_BATCH_BYTES: usize = 1 << 30;

/// Room for `count` rows of `width` values, or a `MemoryError` that says
/// how much was asked and how to split it.
pub(crate) fn batch_output(count: usize, width: usize) -> PyResult<Vec<f64>> {
    let values = count.checked_mul(width).filter(|values| {
        values
            .checked_mul(std::mem::size_of::<f64>())
            .is_some_and(|bytes| bytes <= MAX_BATCH_BYTES)
    });
    let too_large = || {
        pyo3::exceptions::PyMemoryError::new_err(format!(
            "qm: {count} configurations would give {:.2} GB ({width} values each), over the {} \
             GB a call returns: call it in batches of up to {} configurations",
            count as f64 * width as f64 * 8e-9,
            MAX_BATCH_BYTES as f64 * 1e-9,
            MAX_BATCH_BYTES / (8 * width.max(1))
        ))
    };
    let values = values.ok_or_else(too_large)?;
    let mut output = Vec::new();
    output.try_reserve_exact(values).map_err(|_| too_large())?;
    output.resize(values, 0.0);
    Ok(output)
}

/// The values of a homogeneous matrix, row by row.
pub(crate) fn homogeneous_rows(pose: &IsometryMatrix3<f64>, out: &mut [f64]) {
    let matrix = pose.to_homogeneous();
    for row in 0..4 {
        for column in 0..4 {
            out[4 * row + column] = matrix[(row, column)];
        }
    }
}

/// What [`pose`] takes.
const POSE: &str = "a 4×4 homogeneous matrix or [x, y, z, qw, qx, qy, qz]";

/// A rigid transform from a 4×4 homogeneous matrix or the seven numbers
/// `[x, y, z, qw, qx, qy, qz]` of gecaro's files and command line.
pub(crate) fn pose(value: &Bound<'_, PyAny>, what: &str) -> PyResult<IsometryMatrix3<f64>> {
    pose_of(&Real::new(value, what, POSE)?, what)
}

/// [`pose`] of values already read.
pub(crate) fn pose_of(array: &Real, what: &str) -> PyResult<IsometryMatrix3<f64>> {
    match array.shape[..] {
        [7] => pose_from_seven(&array.values).map_err(|message| input(format!("{what} {message}"))),
        [4, 4] => gecaro_io::pose_from_matrix(&array.values)
            .map_err(|message| input(format!("{what}: {message}"))),
        _ => Err(array.wrong_shape(what, POSE)),
    }
}

/// A priority matrix from an array of shape (n+2, 6) or a priority file.
pub(crate) fn priority_matrix(robot: &Robot, value: &Bound<'_, PyAny>) -> PyResult<PriorityMatrix> {
    if let Ok(path) = value.extract::<PathBuf>() {
        return read_priority_file(&path, robot).py();
    }
    let rows = robot.joint_count() + 2;
    let array = Real::shaped(value, "priority", &[Some(rows), Some(6)])?;
    let mut matrix = Vec::with_capacity(rows);
    for (frame, row) in array.values.chunks_exact(6).enumerate() {
        let mut out = [0u32; 6];
        for (column, value) in row.iter().enumerate() {
            if !(value.fract() == 0.0 && *value >= 0.0 && *value <= f64::from(u32::MAX)) {
                return Err(input(format!(
                    "priority: row {frame}, column {column} is {value}, not an integer ≥ 0"
                )));
            }
            out[column] = *value as u32;
        }
        matrix.push(out);
    }
    let matrix = PriorityMatrix::from_rows(matrix);
    matrix.validate(robot.parameters()).py()?;
    Ok(matrix)
}

/// Optional per-frame or per-joint values, `default` where not given.
pub(crate) fn column(
    value: Option<&Bound<'_, PyAny>>,
    what: &str,
    length: usize,
    default: impl Fn(usize) -> f64,
) -> PyResult<Vec<f64>> {
    match value {
        Some(value) => Ok(Real::shaped(value, what, &[Some(length)])?.values),
        None => Ok((0..length).map(default).collect()),
    }
}

pub(crate) fn square(
    value: Option<&Bound<'_, PyAny>>,
    what: &str,
    n: usize,
) -> PyResult<Option<DMatrix<f64>>> {
    value
        .map(|value| {
            let array = Real::shaped(value, what, &[Some(n), Some(n)])?;
            Ok(DMatrix::from_row_slice(n, n, &array.values))
        })
        .transpose()
}
