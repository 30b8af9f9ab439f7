//! The rows of the linearised calibration equations `Δy = W Δη` (eq. 6, 8)
//! as methods write them.
//!
//! A method sees the current end-effector pose and parameter Jacobian of every
//! configuration ([`TerminalState`](crate::states::TerminalState)) and pushes
//! rows through a [`RowWriter`]: the residual Δy (what the model misses; zero
//! at the real parameters), the coefficients of the Np robot parameters
//! (vocabulary order) and of its own auxiliary unknowns. Only the columns a
//! [`ColumnLayout`] asks for are kept, row by row (each row is written
//! contiguously).
//!
//! Rows are multiplied by their set's sensor weight (1/σ of the sensor) and by
//! `√w_i` for the robust weight `w_i` of their observation (see
//! [`crate::observation`]). Methods that centre a set on its mean centre it on
//! the weighted mean ([`RowWriter::observation_weight`]).

use crate::fold::{FoldKind, FoldedRows};

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
    /// `(c, k)` when the kept parameters are the first k of a Jacobian row,
    /// in columns c, c+1, …, c+k−1 of W: a row's coefficients are then
    /// copied whole (see [`for_selected`](Self::for_selected)).
    run: Option<(usize, usize)>,
}

impl ColumnLayout {
    /// Whether some column holds a robot parameter (else the rows need no
    /// parameter Jacobian: an evaluation of the errors alone).
    pub(crate) fn maps_parameters(&self) -> bool {
        !self.mapped.is_empty()
    }

    /// Auxiliary unknowns first (in order), then the listed robot parameters in
    /// the order given (`parameters` holds vocabulary indices).
    pub fn new(parameter_count: usize, parameters: &[usize], auxiliary_count: usize) -> Self {
        let mut parameter_columns = vec![None; parameter_count];
        for (position, index) in parameters.iter().enumerate() {
            parameter_columns[*index] = Some(auxiliary_count + position);
        }
        let mapped: Vec<(usize, usize)> = parameters
            .iter()
            .enumerate()
            .map(|(position, index)| (*index, auxiliary_count + position))
            .collect();
        ColumnLayout {
            run: run_of(&mapped),
            mapped,
            parameter_columns,
            auxiliary_columns: (0..auxiliary_count).map(Some).collect(),
            columns: auxiliary_count + parameters.len(),
        }
    }

    /// The kept robot parameters (vocabulary indices), in the order of
    /// their columns: what a model [`selecting`] them computes.
    ///
    /// [`selecting`]: gecaro_core::KinematicModel::selecting
    pub(crate) fn kept_parameters(&self) -> Vec<usize> {
        self.mapped.iter().map(|(index, _)| *index).collect()
    }

    /// This layout for Jacobian rows of `width` columns whose first ones
    /// are the [`kept_parameters`](Self::kept_parameters) in order (a
    /// model [`selecting`] them; the columns after them are read by none):
    /// the same columns of W, auxiliary unknowns and all.
    ///
    /// [`selecting`]: gecaro_core::KinematicModel::selecting
    pub(crate) fn for_selected(&self, width: usize) -> ColumnLayout {
        debug_assert!(width >= self.mapped.len());
        let mapped: Vec<(usize, usize)> = self
            .mapped
            .iter()
            .enumerate()
            .map(|(position, (_, column))| (position, *column))
            .collect();
        let mut parameter_columns = vec![None; width];
        for (position, column) in &mapped {
            parameter_columns[*position] = Some(*column);
        }
        ColumnLayout {
            run: run_of(&mapped),
            mapped,
            parameter_columns,
            auxiliary_columns: self.auxiliary_columns.clone(),
            columns: self.columns,
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

    /// Whether [`RowWriter::push`] writes every entry of a row: the robot
    /// parameters' columns are all of W's, in one run (no auxiliary or frame
    /// column, none left unwritten). A block of such rows needs no zeroing
    /// before it is written.
    pub(crate) fn writes_every_column(&self) -> bool {
        self.run == Some((0, self.columns))
    }

    /// Number of columns of W.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// The kept robot parameters: (vocabulary index, column of W).
    pub(crate) fn parameter_columns(&self) -> &[(usize, usize)] {
        &self.mapped
    }

    /// Number of auxiliary columns (they come first).
    pub fn auxiliary_count(&self) -> usize {
        self.auxiliary_columns.iter().flatten().count()
    }
}

/// `(c, k)` when `mapped` sends parameters 0, 1, …, k−1 to columns c, c+1,
/// …, c+k−1 (see [`ColumnLayout::run`]).
fn run_of(mapped: &[(usize, usize)]) -> Option<(usize, usize)> {
    let (_, first) = *mapped.first()?;
    mapped
        .iter()
        .enumerate()
        .all(|(position, (index, column))| *index == position && *column == first + position)
        .then_some((first, mapped.len()))
}

/// Writes rows of one measurement set into the rows of the system it was
/// made for; see the module docs.
#[derive(Debug)]
pub struct RowWriter<'a> {
    /// The writer's rows of W (row-major), Δy, weights, kinds and observations.
    pub(crate) matrix: &'a mut [f64],
    pub(crate) residuals: &'a mut [f64],
    /// Robust weights of the whole system's observations (empty: all 1).
    pub(crate) observation_weights: &'a [f64],
    pub(crate) kinds: &'a mut [RowKind],
    pub(crate) observations: &'a mut [u32],
    pub(crate) columns: usize,
    pub(crate) layout: &'a ColumnLayout,
    pub(crate) next_row: usize,
    pub(crate) auxiliary_offset: usize,
    /// Row weights of length and angle rows (1/σ of the sensor).
    pub(crate) row_weights: [f64; 2],
    /// The sensor weights of each of the set's observations when its data
    /// state a σ per row ([`crate::study::RowSigma`]; empty: `row_weights`
    /// for every row), the set's observation 0 being `set_base` in the
    /// whole system.
    pub(crate) observation_sensors: &'a [[f64; 2]],
    pub(crate) set_base: usize,
    /// Number, in the whole system, of this writer's observation 0.
    pub(crate) observation_base: usize,
    /// One past the largest observation written (in the whole system's numbering).
    pub(crate) observation_end: usize,
    /// Rows folded as they are written ([`crate::fold`]): `matrix` is then
    /// empty, and the writer of a whole set hands its folded rows to `sink`.
    pub(crate) fold: Option<FoldKind>,
    pub(crate) sink: Option<&'a mut FoldedRows>,
}

impl<'a> RowWriter<'a> {
    /// The robust weight of `observation` (0-based within this set; 1 unless
    /// the identification reweights, see the module docs).
    pub fn observation_weight(&self, observation: usize) -> f64 {
        robust_weight(
            self.observation_weights,
            self.observation_base + observation,
        )
    }

    /// Appends one row: `Σ parameters[k]·Δη_k + Σ auxiliary[k]·Δaux_k = residual`.
    ///
    /// `observation` numbers the configuration or pair the row belongs to
    /// (0-based within this set); `parameters` has the length of a state's
    /// Jacobian row (Np in vocabulary order; more for a set with named
    /// frames, whose unknowns follow; the selected columns when the states
    /// are a [`selecting`] model's), `auxiliary` one per auxiliary unknown
    /// of the method.
    ///
    /// [`selecting`]: gecaro_core::KinematicModel::selecting
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
        let weight = self.weight(kind, self.observation_base + observation);
        let target = &mut self.matrix[row * self.columns..(row + 1) * self.columns];
        match self.layout.run {
            Some((first, count)) => {
                for (value, coefficient) in target[first..first + count]
                    .iter_mut()
                    .zip(&parameters[..count])
                {
                    *value = weight * coefficient;
                }
            }
            None => {
                for (index, column) in &self.layout.mapped {
                    target[*column] = weight * parameters[*index];
                }
            }
        }
        // Columns beyond the robot's parameters: the study's named frames,
        // its first auxiliary unknowns (crate::frames).
        let robot_parameters = self.layout.parameter_columns.len();
        if let Some(frames) = parameters.get(robot_parameters..) {
            for (index, value) in frames.iter().enumerate() {
                if let Some(column) = self.layout.auxiliary_columns[index] {
                    target[column] = weight * value;
                }
            }
        }
        for (index, value) in auxiliary.iter().enumerate() {
            if let Some(column) = self.layout.auxiliary_columns[self.auxiliary_offset + index] {
                target[column] = weight * value;
            }
        }
        self.residuals[row] = residual;
        self.kinds[row] = kind;
        let observation = self.observation_base + observation;
        debug_assert!(u32::try_from(observation).is_ok());
        self.observations[row] = observation as u32;
        self.observation_end = self.observation_end.max(observation + 1);
        self.next_row += 1;
    }

    /// Checks, after a method wrote its rows, that it wrote all it promised,
    /// and returns one past the largest observation written, numbered in the
    /// whole system (0 when nothing was written).
    pub(crate) fn finish(self, method: &str) -> usize {
        debug_assert!(
            self.next_row == self.residuals.len(),
            "{method} wrote fewer rows than promised"
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
        let matrix = if self.fold.is_some() {
            &mut []
        } else {
            take_front(&mut self.matrix, rows * self.columns)
        };
        let front = RowWriter {
            matrix,
            residuals: take_front(&mut self.residuals, rows),
            observation_weights: self.observation_weights,
            kinds: take_front(&mut self.kinds, rows),
            observations: take_front(&mut self.observations, rows),
            columns: self.columns,
            layout: self.layout,
            next_row: 0,
            auxiliary_offset: self.auxiliary_offset,
            row_weights: self.row_weights,
            observation_sensors: self.observation_sensors,
            set_base: self.set_base,
            observation_base: self.observation_base,
            observation_end: 0,
            fold: self.fold,
            sink: None,
        };
        self.observation_base += observations;
        front
    }

    /// [`split_front`](Self::split_front) for a folding writer: the front
    /// rows of W are written into `matrix` (zeroed here, unless every entry
    /// of a row is written: [`ColumnLayout::writes_every_column`]), a block
    /// to fold.
    pub(crate) fn split_front_into<'b>(
        &'b mut self,
        rows: usize,
        observations: usize,
        matrix: &'b mut [f64],
    ) -> RowWriter<'b> {
        debug_assert!(self.fold.is_some() && matrix.len() == rows * self.columns);
        if !self.layout.writes_every_column() {
            matrix.fill(0.0);
        }
        let mut front = self.split_front(rows, observations);
        front.matrix = matrix;
        front
    }

    /// The rows written so far: their weighted right-hand sides `w r`.
    pub(crate) fn weighted_residuals(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.next_row).map(|row| {
            self.residuals[row] * self.weight(self.kinds[row], self.observations[row] as usize)
        })
    }

    /// The whole weight of a row of `kind` of `observation` (numbered in
    /// the whole system): its sensor weight × √(the observation's robust weight).
    fn weight(&self, kind: RowKind, observation: usize) -> f64 {
        let weights = observation_sensor(
            self.row_weights,
            self.observation_sensors,
            observation - self.set_base,
        );
        whole_weight(
            sensor_weight(weights, kind),
            self.observation_weights,
            observation,
        )
    }
}

/// The sensor weight (1/σ) of a row of `kind` of a set whose length and
/// angle rows have the sensor weights `weights`.
pub(crate) fn sensor_weight(weights: [f64; 2], kind: RowKind) -> f64 {
    match kind {
        RowKind::Length => weights[0],
        RowKind::Angle => weights[1],
    }
}

/// The sensor weights (1/σ) of the length and angle rows of a set's
/// `observation` (numbered within the set): its own when the set's data
/// state a σ per row (`sensors`, one per observation), else the set's
/// `weights`.
pub(crate) fn observation_sensor(
    weights: [f64; 2],
    sensors: &[[f64; 2]],
    observation: usize,
) -> [f64; 2] {
    sensors.get(observation).copied().unwrap_or(weights)
}

/// The whole weight of a measured row: its `sensor` weight (1/σ) × √(the
/// robust weight of its `observation`, numbered in the whole system;
/// `observation_weights` empty: all 1).
pub(crate) fn whole_weight(sensor: f64, observation_weights: &[f64], observation: usize) -> f64 {
    if observation_weights.is_empty() {
        sensor
    } else {
        sensor * robust_weight(observation_weights, observation).sqrt()
    }
}

/// The robust weight of `observation` (numbered in the whole system) among
/// `observation_weights`: 1 where there are none (the identification has
/// not reweighted).
pub(crate) fn robust_weight(observation_weights: &[f64], observation: usize) -> f64 {
    observation_weights.get(observation).copied().unwrap_or(1.0)
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

    /// Rows pushed through a writer of `layout` into a block first filled
    /// with NaN, a robot parameter Jacobian of `parameters` entries and
    /// `auxiliary` auxiliary coefficients a row: the block as written.
    fn written(layout: &ColumnLayout, parameters: usize, auxiliary: usize) -> Vec<f64> {
        let rows = 3;
        let mut matrix = vec![f64::NAN; rows * layout.columns()];
        let mut residuals = vec![0.0; rows];
        let mut kinds = vec![RowKind::Length; rows];
        let mut observations = vec![0; rows];
        let mut writer = RowWriter {
            matrix: &mut matrix,
            residuals: &mut residuals,
            observation_weights: &[],
            kinds: &mut kinds,
            observations: &mut observations,
            columns: layout.columns(),
            layout,
            next_row: 0,
            auxiliary_offset: 0,
            row_weights: [2.0, 3.0],
            observation_sensors: &[],
            set_base: 0,
            observation_base: 0,
            observation_end: 0,
            fold: Some(FoldKind::Gram),
            sink: None,
        };
        for row in 0..rows {
            let coefficients: Vec<f64> = (0..parameters).map(|k| (row + k) as f64).collect();
            let extra: Vec<f64> = (0..auxiliary).map(|k| -(k as f64)).collect();
            writer.push(RowKind::Length, row, 0.5, &coefficients, &extra);
        }
        writer.finish("test");
        matrix
    }

    /// A layout that says its rows are written whole leaves no entry of a
    /// block unwritten (the block needs no zeroing); where it does not say
    /// so, a row may leave some (another set's auxiliary unknowns).
    #[test]
    fn rows_written_whole_are_those_the_layout_says() {
        let cases = [
            // Every parameter, in order: written whole.
            (ColumnLayout::new(5, &[0, 1, 2, 3, 4], 0), 5, 0, true),
            // The kept parameters, as a selecting model's Jacobian writes them.
            (
                ColumnLayout::new(5, &[0, 2, 4], 0).for_selected(3),
                3,
                0,
                true,
            ),
            // Auxiliary unknowns of which none is kept.
            (
                ColumnLayout::with_auxiliary(3, &[0, 1, 2], 2, &[]),
                3,
                2,
                true,
            ),
            // Some parameters of the whole Jacobian (not a run).
            (ColumnLayout::new(5, &[0, 2, 4], 0), 5, 0, false),
            // Auxiliary columns before the parameters'.
            (ColumnLayout::new(4, &[0, 1, 2, 3], 2), 4, 2, false),
        ];
        for (index, (layout, parameters, auxiliary, whole)) in cases.into_iter().enumerate() {
            assert_eq!(layout.writes_every_column(), whole, "case {index}");
            if whole {
                let block = written(&layout, parameters, auxiliary);
                assert!(block.iter().all(|value| !value.is_nan()), "case {index}");
            }
        }
        // Rows of a set with one of the system's two auxiliary unknowns
        // leave the other's column unwritten: such a layout is not whole.
        let shared = ColumnLayout::new(4, &[0, 1, 2, 3], 2);
        assert!(!shared.writes_every_column());
        assert!(written(&shared, 4, 1).iter().any(|value| value.is_nan()));
    }
}
