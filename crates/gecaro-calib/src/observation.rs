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
//! iteratively reweighted least squares, see [`crate::Loss`]). Methods that
//! centre a set on its mean centre it on the weighted mean
//! ([`RowWriter::observation_weight`]), which makes the centred rows the
//! weighted least-squares problem with the set's point eliminated. A prior adds
//! rows that belong to no observation ([`ObservationSystem::append_rows`]).

use gecaro_core::{ChainBuffer, Error as ModelError, JacobianRows, KinematicModel, Robot};
use nalgebra::IsometryMatrix3;

use crate::methods::CalibrationMethod;
use crate::parallel::{available_threads, run_parts};
use crate::sample::Sample;

/// The end-effector pose and parameter Jacobian at one configuration.
#[derive(Clone, Debug)]
pub struct TerminalState {
    /// `(−1)T(n+1)` (eq. 1).
    pub pose: IsometryMatrix3<f64>,
    /// The Jacobian of Appendix II, row-major: `jacobian[axis * Np + k]`;
    /// rows 0–2 (position) and, when evaluated, 3–5 (rotation).
    jacobian: Vec<f64>,
    parameters: usize,
    /// Rows of the Jacobian held: 3 or 6.
    rows: usize,
}

impl TerminalState {
    fn empty(model: &KinematicModel) -> Self {
        TerminalState {
            pose: IsometryMatrix3::identity(),
            jacobian: Vec::new(),
            parameters: model.parameter_count(),
            rows: 0,
        }
    }

    /// Number of parameters Np (length of a Jacobian row).
    pub fn parameter_count(&self) -> usize {
        self.parameters
    }

    /// Row `axis` of the Jacobian (0–2 position, 3–5 rotation), Np entries.
    ///
    /// # Panics
    /// For a row that was not evaluated: a rotation row of a state evaluated
    /// with [`JacobianRows::Position`] (a method that reads rotation rows must
    /// say so in [`CalibrationMethod::jacobian_rows`]), or any row of a state
    /// from [`evaluate_poses`].
    pub fn jacobian_row(&self, axis: usize) -> &[f64] {
        assert!(
            axis < self.rows,
            "Jacobian row {axis} was not evaluated (the method asks for {} rows)",
            self.rows
        );
        &self.jacobian[axis * self.parameters..(axis + 1) * self.parameters]
    }

    /// Adds `scale ×` row `axis` of the Jacobian to `out`.
    pub fn add_jacobian_row(&self, axis: usize, scale: f64, out: &mut [f64]) {
        for (value, coefficient) in out.iter_mut().zip(self.jacobian_row(axis)) {
            *value += scale * coefficient;
        }
    }
}

/// Below this many samples, a set is evaluated on one thread.
const PARALLEL_MINIMUM: usize = 1024;

/// Configurations evaluated and linearised together by
/// [`linearise_independent`]: their states (2 kB each for 43 parameters)
/// stay in the core's cache between the model and the method.
const BLOCK: usize = 32;

/// Evaluates the pose and the `rows` of the Jacobian of every sample,
/// reusing `states`' storage.
///
/// Large data sets are split over the available cores. Each state depends
/// only on its own configuration, so the result is the same, bit for bit,
/// whatever the number of threads.
///
/// # Errors
/// When a sample's configuration does not fit the robot (the first such sample).
pub fn evaluate_states(
    robot: &Robot,
    samples: &[Sample],
    rows: JacobianRows,
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    evaluate_into(robot, samples, Some(rows), states)
}

/// The poses of every sample only, as [`evaluate_states`] does (the states
/// hold no Jacobian rows): what initial auxiliary values and data-like
/// random configurations need.
///
/// # Errors
/// As [`evaluate_states`].
pub fn evaluate_poses(
    robot: &Robot,
    samples: &[Sample],
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    evaluate_into(robot, samples, None, states)
}

fn evaluate_into(
    robot: &Robot,
    samples: &[Sample],
    rows: Option<JacobianRows>,
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    let model = KinematicModel::new(robot);
    states.truncate(samples.len());
    states.resize_with(samples.len(), || TerminalState::empty(&model));
    let part = part_size(samples.len());
    let parts = samples.chunks(part).zip(states.chunks_mut(part)).collect();
    run_parts(parts, |(samples, states)| {
        evaluate_chunk(&model, samples, rows, states)
    })
    .into_iter()
    .collect()
}

/// Samples per thread: all of them below [`PARALLEL_MINIMUM`], else an even share.
fn part_size(samples: usize) -> usize {
    if samples < PARALLEL_MINIMUM {
        samples.max(1)
    } else {
        samples.div_ceil(available_threads())
    }
}

/// The poses and, unless `rows` is `None`, those Jacobian rows of `samples`.
fn evaluate_chunk(
    model: &KinematicModel,
    samples: &[Sample],
    rows: Option<JacobianRows>,
    states: &mut [TerminalState],
) -> Result<(), ModelError> {
    let mut chain = ChainBuffer::default();
    for (sample, state) in samples.iter().zip(states) {
        model.forward(&sample.motor_positions, &mut chain)?;
        state.pose = *chain.world_from_tool();
        state.parameters = model.parameter_count();
        match rows {
            Some(rows) => {
                state.rows = rows.count();
                model.jacobian_rows(&chain, &mut state.jacobian, rows);
            }
            None => {
                state.rows = 0;
                state.jacobian.clear();
            }
        }
    }
    Ok(())
}

/// Evaluates and linearises a set of `method`, whose configurations are
/// independent ([`CalibrationMethod::independent_configurations`]), into
/// `writer`: block by block, so that each block's states are still in cache
/// when the method reads them, and large sets over all cores. The rows are
/// those of [`evaluate_states`] followed by [`CalibrationMethod::linearise`]
/// on the whole set, bit for bit. Returns the end of the observations
/// written (see [`RowWriter::observation_end`]).
///
/// # Errors
/// When a sample's configuration does not fit the robot (the first such sample).
pub(crate) fn linearise_independent(
    model: &KinematicModel,
    method: &dyn CalibrationMethod,
    samples: &[Sample],
    auxiliary: &[f64],
    mut writer: RowWriter<'_>,
) -> Result<usize, ModelError> {
    let rows = method.jacobian_rows();
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
            evaluate_chunk(model, block, Some(rows), &mut states[..block.len()])?;
            let block_rows = part.split_front(method.row_count(block), block.len());
            end = end.max(block_rows.write(method, block, &states[..block.len()], auxiliary));
        }
        Ok(end)
    });
    ends.into_iter()
        .try_fold(0, |end, part: Result<usize, ModelError>| Ok(end.max(part?)))
}

/// What a row measures, so that errors are reported in the right unit.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum RowKind {
    /// A length (metres): positions, distances, distances to a plane.
    Length,
    /// An angle (radians): orientation differences.
    Angle,
}

/// Which columns of W to build, in which order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColumnLayout {
    /// For each robot parameter (vocabulary order), its column in W, if kept.
    parameter_columns: Vec<Option<usize>>,
    /// The kept (parameter, column) pairs.
    mapped: Vec<(usize, usize)>,
    /// For each auxiliary unknown (all sets, in order), its column in W, if kept.
    auxiliary_columns: Vec<Option<usize>>,
    columns: usize,
}

impl ColumnLayout {
    /// Auxiliary unknowns first (in order), then the listed robot parameters in
    /// the order given (`parameters` holds vocabulary indices).
    pub fn new(parameter_count: usize, parameters: &[usize], auxiliary_count: usize) -> Self {
        let mut parameter_columns = vec![None; parameter_count];
        for (position, index) in parameters.iter().enumerate() {
            parameter_columns[*index] = Some(auxiliary_count + position);
        }
        ColumnLayout {
            mapped: parameters
                .iter()
                .enumerate()
                .map(|(position, index)| (*index, auxiliary_count + position))
                .collect(),
            parameter_columns,
            auxiliary_columns: (0..auxiliary_count).map(Some).collect(),
            columns: auxiliary_count + parameters.len(),
        }
    }

    /// Auxiliary unknowns first (only those listed in `auxiliary`, indices
    /// into all auxiliary unknowns), then the listed robot parameters.
    pub fn with_auxiliary(
        parameter_count: usize,
        parameters: &[usize],
        auxiliary_count: usize,
        auxiliary: &[usize],
    ) -> Self {
        let mut layout = ColumnLayout::new(parameter_count, parameters, auxiliary.len());
        layout.auxiliary_columns = vec![None; auxiliary_count];
        debug_assert!(
            layout
                .mapped
                .iter()
                .all(|(_, column)| *column >= auxiliary.len())
        );
        for (column, index) in auxiliary.iter().enumerate() {
            layout.auxiliary_columns[*index] = Some(column);
        }
        layout
    }

    /// Number of columns of W.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Number of auxiliary columns (they come first).
    pub fn auxiliary_count(&self) -> usize {
        self.auxiliary_columns.iter().flatten().count()
    }
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
        self.matrix.clear();
        self.matrix.resize(rows * self.columns, 0.0);
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

/// Writes rows of one measurement set into the rows of the system it was
/// made for; see the module docs.
#[derive(Debug)]
pub struct RowWriter<'a> {
    /// The writer's rows of W (row-major), Δy, weights, kinds and observations.
    matrix: &'a mut [f64],
    residuals: &'a mut [f64],
    weights: &'a mut [f64],
    sensor_weights: &'a mut [f64],
    /// Robust weights of the whole system's observations (empty: all 1).
    observation_weights: &'a [f64],
    kinds: &'a mut [RowKind],
    observations: &'a mut [usize],
    columns: usize,
    layout: &'a ColumnLayout,
    next_row: usize,
    auxiliary_offset: usize,
    /// Row weights of length and angle rows (1/σ of the sensor).
    row_weights: [f64; 2],
    /// Number, in the whole system, of this writer's observation 0.
    observation_base: usize,
    /// One past the largest observation written (in the whole system's numbering).
    observation_end: usize,
}

impl<'a> RowWriter<'a> {
    /// The robust weight of `observation` (0-based within this set; 1 unless
    /// the identification reweights, see the module docs).
    pub fn observation_weight(&self, observation: usize) -> f64 {
        self.observation_weights
            .get(self.observation_base + observation)
            .copied()
            .unwrap_or(1.0)
    }

    /// Appends one row: `Σ parameters[k]·Δη_k + Σ auxiliary[k]·Δaux_k = residual`.
    ///
    /// `observation` numbers the configuration or pair the row belongs to
    /// (0-based within this set); `parameters` has Np entries, `auxiliary` one
    /// per auxiliary unknown of the method.
    ///
    /// # Panics
    /// When the method pushes more rows than its `row_count` promised (a bug in the method).
    pub fn push(
        &mut self,
        kind: RowKind,
        observation: usize,
        residual: f64,
        parameters: &[f64],
        auxiliary: &[f64],
    ) {
        let row = self.next_row;
        assert!(
            row < self.residuals.len(),
            "a method wrote more rows than its row_count"
        );
        let sensor_weight = match kind {
            RowKind::Length => self.row_weights[0],
            RowKind::Angle => self.row_weights[1],
        };
        let weight = if self.observation_weights.is_empty() {
            sensor_weight
        } else {
            sensor_weight * self.observation_weight(observation).sqrt()
        };
        let target = &mut self.matrix[row * self.columns..(row + 1) * self.columns];
        for (index, column) in &self.layout.mapped {
            target[*column] = weight * parameters[*index];
        }
        for (index, value) in auxiliary.iter().enumerate() {
            if let Some(column) = self.layout.auxiliary_columns[self.auxiliary_offset + index] {
                target[column] = weight * value;
            }
        }
        self.residuals[row] = residual;
        self.weights[row] = weight;
        self.sensor_weights[row] = sensor_weight;
        self.kinds[row] = kind;
        let observation = self.observation_base + observation;
        self.observations[row] = observation;
        self.observation_end = self.observation_end.max(observation + 1);
        self.next_row += 1;
    }

    /// Has `method` write its rows for `samples` (whose states are `states`)
    /// and returns one past the largest observation written, numbered in the
    /// whole system (0 when nothing was written).
    pub(crate) fn write(
        mut self,
        method: &dyn CalibrationMethod,
        samples: &[Sample],
        states: &[TerminalState],
        auxiliary: &[f64],
    ) -> usize {
        method.linearise(samples, states, auxiliary, &mut self);
        debug_assert!(
            self.next_row == self.residuals.len(),
            "{} wrote fewer rows than promised",
            method.name()
        );
        self.observation_end
    }

    /// A writer for this writer's first `rows` rows, numbering observations
    /// from this writer's; this writer keeps the remaining rows and numbers
    /// its observations `observations` further on. Lets independent blocks of
    /// a set be written separately (on separate threads).
    ///
    /// # Panics
    /// When rows were written already, or fewer than `rows` remain.
    pub(crate) fn split_front(&mut self, rows: usize, observations: usize) -> RowWriter<'a> {
        assert!(
            self.next_row == 0 && rows <= self.residuals.len(),
            "a writer is split before it writes, within its rows"
        );
        let front = RowWriter {
            matrix: take_front(&mut self.matrix, rows * self.columns),
            residuals: take_front(&mut self.residuals, rows),
            weights: take_front(&mut self.weights, rows),
            sensor_weights: take_front(&mut self.sensor_weights, rows),
            observation_weights: self.observation_weights,
            kinds: take_front(&mut self.kinds, rows),
            observations: take_front(&mut self.observations, rows),
            columns: self.columns,
            layout: self.layout,
            next_row: 0,
            auxiliary_offset: self.auxiliary_offset,
            row_weights: self.row_weights,
            observation_base: self.observation_base,
            observation_end: 0,
        };
        self.observation_base += observations;
        front
    }
}

/// The first `count` entries of `slice`, which keeps the rest.
fn take_front<'a, T>(slice: &mut &'a mut [T], count: usize) -> &'a mut [T] {
    let (front, rest) = std::mem::take(slice).split_at_mut(count);
    *slice = rest;
    front
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Sampler;

    #[test]
    fn parallel_evaluation_is_bit_identical_to_serial() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut sampler = Sampler::new(9);
        let samples: Vec<Sample> = (0..PARALLEL_MINIMUM * 2 + 17)
            .map(|_| Sample::new(sampler.configuration(&robot)))
            .collect();
        let model = KinematicModel::new(&robot);
        for rows in [JacobianRows::Full, JacobianRows::Position] {
            let mut parallel = Vec::new();
            evaluate_states(&robot, &samples, rows, &mut parallel).expect("states");
            let mut serial: Vec<TerminalState> = samples
                .iter()
                .map(|_| TerminalState::empty(&model))
                .collect();
            evaluate_chunk(&model, &samples, Some(rows), &mut serial).expect("states");
            for (a, b) in parallel.iter().zip(&serial) {
                assert_eq!(a.pose, b.pose);
                let bits =
                    |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
                assert_eq!(bits(&a.jacobian), bits(&b.jacobian));
                assert_eq!(a.jacobian.len(), rows.count() * model.parameter_count());
            }
        }
    }

    #[test]
    #[should_panic(expected = "Jacobian row 3 was not evaluated")]
    fn rotation_rows_of_a_position_state_are_refused() {
        let robot = Robot::template("arm", "RRR").expect("template");
        let samples = [Sample::new(vec![0.1, 0.2, 0.3])];
        let mut states = Vec::new();
        evaluate_states(&robot, &samples, JacobianRows::Position, &mut states).expect("states");
        assert_eq!(states[0].jacobian_row(2).len(), robot.parameters().len());
        let _ = states[0].jacobian_row(3);
    }
}
