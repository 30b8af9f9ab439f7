//! The linearised calibration equations `Δy = W Δη` (eq. 6, 8) as methods
//! write them, row by row.
//!
//! A method sees the current end-effector pose and parameter Jacobian of every
//! configuration ([`TerminalState`]) and pushes rows through a [`RowWriter`]:
//! the residual Δy (what the model misses; zero at the real parameters), the
//! coefficients of the Np robot parameters (vocabulary order) and of its own
//! auxiliary unknowns. The [`ObservationSystem`] keeps only the columns a
//! [`ColumnLayout`] asks for, row by row (each row is written contiguously). Rows are multiplied by a per-set weight (1/σ of the sensor)
//! when several measurement sets are stacked.

use std::sync::OnceLock;

use gecaro_core::{ChainBuffer, Error as ModelError, KinematicModel, Robot};
use nalgebra::IsometryMatrix3;

use crate::sample::Sample;

/// The end-effector pose and parameter Jacobian at one configuration.
#[derive(Clone, Debug)]
pub struct TerminalState {
    /// `(−1)T(n+1)` (eq. 1).
    pub pose: IsometryMatrix3<f64>,
    /// The 6×Np Jacobian of Appendix II, row-major: `jacobian[axis * Np + k]`.
    jacobian: Vec<f64>,
    parameters: usize,
}

impl TerminalState {
    /// Number of parameters Np (length of a Jacobian row).
    pub fn parameter_count(&self) -> usize {
        self.parameters
    }

    /// Row `axis` of the Jacobian (0–2 position, 3–5 rotation), Np entries.
    pub fn jacobian_row(&self, axis: usize) -> &[f64] {
        &self.jacobian[axis * self.parameters..(axis + 1) * self.parameters]
    }

    /// Adds `scale ×` row `axis` of the Jacobian to `out`.
    pub fn add_jacobian_row(&self, axis: usize, scale: f64, out: &mut [f64]) {
        for (value, coefficient) in out.iter_mut().zip(self.jacobian_row(axis)) {
            *value += scale * coefficient;
        }
    }
}

/// Below this many samples, states are evaluated on one thread.
const PARALLEL_MINIMUM: usize = 1024;

/// Evaluates the pose and Jacobian of every sample, reusing `states`' storage.
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
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    let model = KinematicModel::new(robot);
    states.truncate(samples.len());
    states.resize_with(samples.len(), || TerminalState {
        pose: IsometryMatrix3::identity(),
        jacobian: Vec::new(),
        parameters: model.parameter_count(),
    });
    if samples.len() < PARALLEL_MINIMUM {
        return evaluate_chunk(&model, samples, states);
    }
    let threads = available_threads();
    if threads < 2 {
        return evaluate_chunk(&model, samples, states);
    }
    let chunk = samples.len().div_ceil(threads);
    let results: Vec<Result<(), ModelError>> = std::thread::scope(|scope| {
        let workers: Vec<_> = samples
            .chunks(chunk)
            .zip(states.chunks_mut(chunk))
            .map(|(samples, states)| scope.spawn(|| evaluate_chunk(&model, samples, states)))
            .collect();
        workers
            .into_iter()
            .map(|worker| worker.join().expect("evaluating kinematics does not panic"))
            .collect()
    });
    results.into_iter().collect()
}

/// The cores this process may use, asked once: the standard library reads
/// the cgroup quota files on every call, which costs more than evaluating
/// a hundred configurations.
fn available_threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get))
}

fn evaluate_chunk(
    model: &KinematicModel,
    samples: &[Sample],
    states: &mut [TerminalState],
) -> Result<(), ModelError> {
    let mut chain = ChainBuffer::default();
    for (sample, state) in samples.iter().zip(states) {
        model.forward(&sample.motor_positions, &mut chain)?;
        state.pose = *chain.world_from_tool();
        state.parameters = model.parameter_count();
        model.jacobian_rows(&chain, &mut state.jacobian);
    }
    Ok(())
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
    weights: Vec<f64>,
    kinds: Vec<RowKind>,
    /// The observation (configuration, pair) each row belongs to, numbered across sets.
    observations: Vec<usize>,
    observation_count: usize,
}

impl ObservationSystem {
    /// Clears and sizes the system for `rows` rows in `layout`.
    pub(crate) fn reset(&mut self, rows: usize, layout: &ColumnLayout) {
        self.rows = rows;
        self.columns = layout.columns();
        self.matrix.clear();
        self.matrix.resize(rows * self.columns, 0.0);
        for buffer in [&mut self.residuals, &mut self.weights] {
            buffer.clear();
            buffer.resize(rows, 0.0);
        }
        self.kinds.clear();
        self.kinds.resize(rows, RowKind::Length);
        self.observations.clear();
        self.observations.resize(rows, 0);
        self.observation_count = 0;
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
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
        for row in 0..self.rows {
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

    /// A writer for the rows `first_row..first_row + rows` of one measurement set.
    pub(crate) fn writer<'a>(
        &'a mut self,
        layout: &'a ColumnLayout,
        first_row: usize,
        rows: usize,
        auxiliary_offset: usize,
        weights: [f64; 2],
    ) -> RowWriter<'a> {
        let observation_base = self.observation_count;
        RowWriter {
            system: self,
            layout,
            next_row: first_row,
            end_row: first_row + rows,
            auxiliary_offset,
            weights,
            observation_base,
        }
    }
}

/// Writes the rows of one measurement set; see the module docs.
#[derive(Debug)]
pub struct RowWriter<'a> {
    system: &'a mut ObservationSystem,
    layout: &'a ColumnLayout,
    next_row: usize,
    end_row: usize,
    auxiliary_offset: usize,
    /// Row weights of length and angle rows (1/σ of the sensor).
    weights: [f64; 2],
    observation_base: usize,
}

impl RowWriter<'_> {
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
        assert!(
            self.next_row < self.end_row,
            "a method wrote more rows than its row_count"
        );
        let row = self.next_row;
        let weight = match kind {
            RowKind::Length => self.weights[0],
            RowKind::Angle => self.weights[1],
        };
        let columns = self.system.columns;
        let target = &mut self.system.matrix[row * columns..(row + 1) * columns];
        for (index, column) in &self.layout.mapped {
            target[*column] = weight * parameters[*index];
        }
        for (index, value) in auxiliary.iter().enumerate() {
            if let Some(column) = self.layout.auxiliary_columns[self.auxiliary_offset + index] {
                target[column] = weight * value;
            }
        }
        self.system.residuals[row] = residual;
        self.system.weights[row] = weight;
        self.system.kinds[row] = kind;
        let observation = self.observation_base + observation;
        self.system.observations[row] = observation;
        self.system.observation_count = self.system.observation_count.max(observation + 1);
        self.next_row += 1;
    }

    /// Whether every promised row was written.
    pub(crate) fn is_complete(&self) -> bool {
        self.next_row == self.end_row
    }
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
        let mut parallel = Vec::new();
        evaluate_states(&robot, &samples, &mut parallel).expect("states");
        let model = KinematicModel::new(&robot);
        let mut serial: Vec<TerminalState> = samples
            .iter()
            .map(|_| TerminalState {
                pose: IsometryMatrix3::identity(),
                jacobian: Vec::new(),
                parameters: model.parameter_count(),
            })
            .collect();
        evaluate_chunk(&model, &samples, &mut serial).expect("states");
        for (a, b) in parallel.iter().zip(&serial) {
            assert_eq!(a.pose, b.pose);
            let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
            assert_eq!(bits(&a.jacobian), bits(&b.jacobian));
        }
    }
}
