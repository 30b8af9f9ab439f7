//! The linearised calibration equations `Δy = W Δη` (eq. 6, 8) as methods
//! write them, row by row.
//!
//! A method sees the current end-effector pose and parameter Jacobian of every
//! configuration ([`TerminalState`]) and pushes rows through a [`RowWriter`]:
//! the residual Δy (what the model misses; zero at the real parameters), the
//! coefficients of the Np robot parameters (vocabulary order) and of its own
//! auxiliary unknowns. The [`ObservationSystem`] keeps only the columns a
//! [`ColumnLayout`] asks for, row by row (each row is written contiguously).
//!
//! ## Weights
//!
//! Rows are multiplied by their set's sensor weight (1/σ of the sensor) when
//! several measurement sets are stacked, and by `√w_i` for the robust weight
//! `w_i` of their observation ([`ObservationSystem::set_observation_weights`],
//! iteratively reweighted least squares, see [`crate::identification::Loss`]). Methods that
//! centre a set on its mean centre it on the weighted mean
//! ([`RowWriter::observation_weight`]), which makes the centred rows the
//! weighted least-squares problem with the set's point eliminated. A prior adds
//! rows that belong to no observation ([`ObservationSystem::append_rows`]).

use gecaro_core::{Error as ModelError, JacobianRows, KinematicModel};

use crate::frames::SetFrames;

use crate::method::CalibrationMethod;
use crate::parallel::run_parts;
use crate::sample::Sample;
use crate::states::{BLOCK, evaluate_chunk, part_size};

pub use crate::rows::{ColumnLayout, RowKind, RowWriter};
pub use crate::states::{TerminalState, evaluate_poses, evaluate_states};

/// Has `method` write its rows for `samples` (whose states are `states`)
/// into `writer` and returns one past the largest observation written,
/// numbered in the whole system (0 when nothing was written).
pub(crate) fn write_rows(
    mut writer: RowWriter<'_>,
    method: &dyn CalibrationMethod,
    samples: &[Sample],
    states: &[TerminalState],
    auxiliary: &[f64],
) -> usize {
    method.linearise(samples, states, auxiliary, &mut writer);
    writer.finish(method.name())
}

/// Evaluates and linearises a set of `method`, whose configurations are
/// independent ([`CalibrationMethod::independent_configurations`]), into
/// `writer`: block by block, so that each block's states are still in cache
/// when the method reads them, and large sets over all cores. The rows are
/// those of [`evaluate_states`](crate::states::evaluate_states) followed by [`CalibrationMethod::linearise`]
/// on the whole set, bit for bit; with the set's named `frames`, each state
/// is that of the measured pose ([`crate::frames`]). Returns the end of the observations
/// written (see [`RowWriter::observation_end`]).
///
/// # Errors
/// When a sample's configuration does not fit the robot (the first such sample).
pub(crate) fn linearise_independent(
    model: &KinematicModel,
    method: &dyn CalibrationMethod,
    samples: &[Sample],
    auxiliary: &[f64],
    frames: Option<&SetFrames<'_>>,
    mut writer: RowWriter<'_>,
) -> Result<usize, ModelError> {
    let rows = method.jacobian_rows();
    // A named tool moves the point with the flange's rotation: all six rows.
    let evaluated = if frames.is_some() {
        JacobianRows::Full
    } else {
        rows
    };
    // No column reads the Jacobian (the errors alone, as `evaluate` asks):
    // its rows are empty, the kinematics poses only.
    let jacobian = (frames.is_some() || writer.layout.maps_parameters()).then_some(evaluated);
    let parts: Vec<(&[Sample], RowWriter<'_>)> = samples
        .chunks(part_size(samples.len()))
        .map(|chunk| {
            (
                chunk,
                writer.split_front(method.row_count(chunk), chunk.len()),
            )
        })
        .collect();
    let ends = run_parts(parts, |(chunk, mut part)| {
        let mut states: Vec<TerminalState> = Vec::with_capacity(BLOCK);
        let mut end = 0;
        for block in chunk.chunks(BLOCK) {
            states.resize_with(block.len(), || TerminalState::empty(model));
            evaluate_chunk(model, block, jacobian, &mut states[..block.len()])?;
            if jacobian.is_none() {
                for state in &mut states[..block.len()] {
                    state.with_empty_jacobian(evaluated);
                }
            }
            if let Some(frames) = frames {
                for state in &mut states[..block.len()] {
                    frames.apply(state, rows.count());
                }
            }
            let block_rows = part.split_front(method.row_count(block), block.len());
            end = end.max(write_rows(
                block_rows,
                method,
                block,
                &states[..block.len()],
                auxiliary,
            ));
        }
        Ok(end)
    });
    ends.into_iter()
        .try_fold(0, |end, part: Result<usize, ModelError>| Ok(end.max(part?)))
}

/// The stacked, weighted linear system of all measurement sets.
#[derive(Clone, Debug, Default)]
pub struct ObservationSystem {
    rows: usize,
    columns: usize,
    /// W, row-major (each row written contiguously), rows already weighted.
    matrix: Vec<f64>,
    /// Δy, not weighted (metres or radians).
    residuals: Vec<f64>,
    /// Each row's whole weight: sensor weight × √(robust weight).
    weights: Vec<f64>,
    /// Each row's sensor weight (1/σ).
    sensor_weights: Vec<f64>,
    /// What each measured row measures (appended rows have none).
    kinds: Vec<RowKind>,
    /// The observation (configuration, pair) each row belongs to, numbered across sets.
    observations: Vec<usize>,
    observation_count: usize,
    /// Robust weight of each observation (empty: all 1); kept by `reset`.
    observation_weights: Vec<f64>,
    /// The measured rows of each measurement set, in order.
    set_rows: Vec<std::ops::Range<usize>>,
}

impl ObservationSystem {
    /// Clears and sizes the system for `rows` rows in `layout`.
    pub(crate) fn reset(&mut self, rows: usize, layout: &ColumnLayout) {
        self.rows = rows;
        self.columns = layout.columns();
        let size = rows * self.columns;
        if self.matrix.capacity() < size {
            // Fresh zeroed memory from the allocator (calloc): its pages are
            // touched first by the threads that write the rows, on all cores,
            // instead of by a serial fill here.
            self.matrix = vec![0.0; size];
        } else {
            self.matrix.clear();
            self.matrix.resize(size, 0.0);
        }
        for buffer in [
            &mut self.residuals,
            &mut self.weights,
            &mut self.sensor_weights,
        ] {
            buffer.clear();
            buffer.resize(rows, 0.0);
        }
        self.kinds.clear();
        self.kinds.resize(rows, RowKind::Length);
        self.observations.clear();
        self.observations.resize(rows, 0);
        self.set_rows.clear();
        self.observation_count = 0;
    }

    /// Number of rows: the measured rows, then any appended ones.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of rows written by the measurement sets (before appended rows).
    pub fn measured_rows(&self) -> usize {
        self.kinds.len()
    }

    /// The measured rows' weighted sum of squares `Σ (w r)²` (the appended
    /// prior and gauge rows left out).
    pub fn measured_cost(&self) -> f64 {
        let rows = self.measured_rows();
        self.residuals[..rows]
            .iter()
            .zip(&self.weights[..rows])
            .map(|(r, w)| (r * w).powi(2))
            .sum()
    }

    /// Number of observations (configurations, pairs) written.
    pub fn observation_count(&self) -> usize {
        self.observation_count
    }

    /// The observation each measured row belongs to.
    pub fn row_observations(&self) -> &[usize] {
        &self.observations
    }

    /// Sets the robust weight `w_i ≥ 0` of every observation (one per
    /// observation, numbered across sets; empty for all 1), used by the next
    /// writes: rows are multiplied by `√w_i`, sets centred on weighted means.
    pub fn set_observation_weights(&mut self, weights: Vec<f64>) {
        self.observation_weights = weights;
    }

    /// The measured rows' residuals multiplied by their sensor weights only
    /// (not by robust weights): in units of the sensor's σ.
    pub fn scaled_residuals(&self) -> Vec<f64> {
        (0..self.measured_rows())
            .map(|row| self.residuals[row] * self.sensor_weights[row])
            .collect()
    }

    /// Appends rows `weight · Δη_column = weight · residual`, each with one
    /// non-zero coefficient (a prior's pseudo-observations). They belong to no
    /// observation and have no [`RowKind`].
    pub fn append_rows(&mut self, rows: &[(usize, f64, f64)]) {
        for &(column, weight, residual) in rows {
            let start = self.matrix.len();
            self.matrix.resize(start + self.columns, 0.0);
            self.matrix[start + column] = weight;
            self.residuals.push(residual);
            self.weights.push(weight);
            self.sensor_weights.push(weight);
            self.rows += 1;
        }
    }

    /// Appends one row `weight · Σ c_k Δη_k = weight · residual` with the
    /// coefficients `c_k` of `entries` (column, coefficient): a constraint
    /// held by a heavy weight (the gauge of an unobserved scale). It belongs
    /// to no observation and has no [`RowKind`].
    pub(crate) fn append_row(&mut self, entries: &[(usize, f64)], weight: f64, residual: f64) {
        let start = self.matrix.len();
        self.matrix.resize(start + self.columns, 0.0);
        for &(column, coefficient) in entries {
            self.matrix[start + column] += weight * coefficient;
        }
        self.residuals.push(residual);
        self.weights.push(weight);
        self.sensor_weights.push(weight);
        self.rows += 1;
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// W, row-major (`rows × columns`), weighted.
    pub fn matrix(&self) -> &[f64] {
        &self.matrix
    }

    /// Row `row` of W (weighted).
    pub fn row(&self, row: usize) -> &[f64] {
        &self.matrix[row * self.columns..(row + 1) * self.columns]
    }

    /// Column `column` of W (weighted), copied.
    pub fn column(&self, column: usize) -> Vec<f64> {
        (0..self.rows)
            .map(|row| self.matrix[row * self.columns + column])
            .collect()
    }

    /// Δy, not weighted.
    pub fn residuals(&self) -> &[f64] {
        &self.residuals
    }

    /// Δy multiplied by the row weights: the right-hand side that goes with [`Self::matrix`].
    pub fn weighted_residuals(&self) -> Vec<f64> {
        self.residuals
            .iter()
            .zip(&self.weights)
            .map(|(r, w)| r * w)
            .collect()
    }

    /// Updates the residuals for a small parameter step through the linear
    /// model: `Δy ← Δy − W·step` (columns of W in this system's layout).
    pub(crate) fn apply_linear_step(&mut self, step: &[f64]) {
        for row in 0..self.rows {
            let predicted: f64 = self.matrix[row * self.columns..(row + 1) * self.columns]
                .iter()
                .zip(step)
                .map(|(w, s)| w * s)
                .sum();
            // W is weighted; the stored residuals are not.
            if self.weights[row] != 0.0 {
                self.residuals[row] -= predicted / self.weights[row];
            }
        }
    }

    /// What each row measures.
    pub fn kinds(&self) -> &[RowKind] {
        &self.kinds
    }

    /// Per observation (configuration or pair): the norm of its length rows
    /// (metres) and of its angle rows (radians).
    pub fn observation_errors(&self) -> Vec<(f64, f64)> {
        let mut errors = vec![(0.0, 0.0); self.observation_count];
        for row in 0..self.measured_rows() {
            let squared = self.residuals[row] * self.residuals[row];
            let error = &mut errors[self.observations[row]];
            match self.kinds[row] {
                RowKind::Length => error.0 += squared,
                RowKind::Angle => error.1 += squared,
            }
        }
        errors
            .into_iter()
            .map(|(l, a)| (l.sqrt(), a.sqrt()))
            .collect()
    }

    /// A writer for the rows `first_row..first_row + rows` of one measurement
    /// set, whose observations are numbered after those written so far.
    pub(crate) fn writer<'a>(
        &'a mut self,
        layout: &'a ColumnLayout,
        first_row: usize,
        rows: usize,
        auxiliary_offset: usize,
        weights: [f64; 2],
    ) -> RowWriter<'a> {
        let range = first_row..first_row + rows;
        let columns = self.columns;
        RowWriter {
            matrix: &mut self.matrix[range.start * columns..range.end * columns],
            residuals: &mut self.residuals[range.clone()],
            weights: &mut self.weights[range.clone()],
            sensor_weights: &mut self.sensor_weights[range.clone()],
            observation_weights: &self.observation_weights,
            kinds: &mut self.kinds[range.clone()],
            observations: &mut self.observations[range],
            columns,
            layout,
            next_row: 0,
            auxiliary_offset,
            row_weights: weights,
            observation_base: self.observation_count,
            observation_end: 0,
        }
    }

    /// Records that rows `rows` belong to the next measurement set.
    pub(crate) fn record_set(&mut self, rows: std::ops::Range<usize>) {
        self.set_rows.push(rows);
    }

    /// The measured rows of each measurement set, in order.
    pub fn set_rows(&self) -> &[std::ops::Range<usize>] {
        &self.set_rows
    }

    /// Records that observations up to `end` (exclusive) were written
    /// ([`RowWriter::observation_end`]).
    pub(crate) fn record_observations(&mut self, end: usize) {
        self.observation_count = self.observation_count.max(end);
    }
}
