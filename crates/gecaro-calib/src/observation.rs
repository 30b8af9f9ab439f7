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

use std::borrow::Cow;

use faer::MatRef;

use crate::fold::{FoldKind, FoldedRows};
use crate::linalg::{LeastSquaresRows, NormalEquations, add_normal_sums, view};

use crate::parallel::{run_parts, scan_parts};

pub use crate::rows::{ColumnLayout, RowKind, RowWriter};
use crate::rows::{observation_sensor, sensor_weight, whole_weight};
pub use crate::states::{TerminalState, evaluate_poses, evaluate_states};

/// `values` as `len` zeros: fresh zeroed memory from the allocator when it
/// needs more room (its pages are then touched first by the threads that
/// write the rows, on all cores, not by a serial fill here), else its own.
fn zeroed<T: Copy + Default>(values: &mut Vec<T>, len: usize) {
    if values.capacity() < len {
        *values = vec![T::default(); len];
    } else {
        values.clear();
        values.resize(len, T::default());
    }
}

/// The rows `0..observations.len()` in the parts of a light pass
/// ([`scan_parts`]), each cut moved on to where the observation changes.
fn observation_parts(observations: &[u32]) -> Vec<std::ops::Range<usize>> {
    let rows = observations.len();
    let mut cuts: Vec<usize> = scan_parts(rows)
        .into_iter()
        .map(|part| {
            let mut cut = part.start;
            while cut > 0 && cut < rows && observations[cut] == observations[cut - 1] {
                cut += 1;
            }
            cut
        })
        .collect();
    cuts.push(rows);
    cuts.dedup();
    cuts.windows(2).map(|pair| pair[0]..pair[1]).collect()
}

/// `values[span]` for each of `spans` (in order, disjoint, within
/// `values`), apart.
fn split_spans<'a>(values: &'a mut [f64], spans: &[std::ops::Range<usize>]) -> Vec<&'a mut [f64]> {
    let mut rest = values;
    let mut at = 0;
    let mut parts = Vec::with_capacity(spans.len());
    for span in spans {
        let (_, after) = std::mem::take(&mut rest).split_at_mut(span.start - at);
        let (part, after) = after.split_at_mut(span.len());
        parts.push(part);
        rest = after;
        at = span.end;
    }
    parts
}

/// The rows a least-squares routine reads ([`ObservationSystem::solver_rows`]):
/// W (row-major) or its c × c stand-in, and the weighted right-hand sides.
pub(crate) struct SolverRows<'a> {
    matrix: Cow<'a, [f64]>,
    rows: usize,
    columns: usize,
    right: Vec<f64>,
}

impl LeastSquaresRows for SolverRows<'_> {
    /// The rows, as a matrix.
    fn matrix(&self) -> MatRef<'_, f64> {
        view(&self.matrix, self.rows, self.columns)
    }

    /// Their weighted right-hand sides.
    fn right(&self) -> &[f64] {
        &self.right
    }
}

/// The errors of a study's observations (configurations or pairs), in
/// observation order: each one's position-like error, the norm of its
/// length rows (m), and, when the data measure angles, its orientation
/// error, the norm of its angle rows (rad). Position data hold no angles:
/// 8 bytes an observation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObservationErrors {
    /// Each observation's position-like error (m).
    pub lengths: Vec<f64>,
    /// Each observation's orientation error (rad); empty when no row
    /// measures an angle.
    pub angles: Vec<f64>,
}

impl ObservationErrors {
    /// The number of observations.
    pub fn len(&self) -> usize {
        self.lengths.len()
    }

    /// Whether there are no observations.
    pub fn is_empty(&self) -> bool {
        self.lengths.is_empty()
    }

    /// Whether the data measure angles (then every observation has an
    /// orientation error).
    pub fn has_angles(&self) -> bool {
        !self.angles.is_empty()
    }

    /// Observation `index`'s position-like and orientation errors (the
    /// latter 0 when the data measure no angle).
    pub fn get(&self, index: usize) -> Option<(f64, f64)> {
        let length = *self.lengths.get(index)?;
        Some((length, self.angles.get(index).copied().unwrap_or(0.0)))
    }

    /// Every observation's errors, as [`get`](Self::get) gives them.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        (0..self.len()).filter_map(|index| self.get(index))
    }

    /// The errors of the observations `keep` says to keep, in order.
    pub fn retained(&self, mut keep: impl FnMut(usize) -> bool) -> Self {
        let has_angles = self.has_angles();
        let mut kept = Self::default();
        for index in 0..self.len() {
            if keep(index) {
                kept.lengths.push(self.lengths[index]);
                if has_angles {
                    kept.angles.push(self.angles[index]);
                }
            }
        }
        kept
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
    /// The sensor weights (1/σ) of each set's length and angle rows: a
    /// measured row's whole weight is its sensor weight × √(its
    /// observation's robust weight) ([`whole_weight`]), not stored per row.
    set_weights: Vec<[f64; 2]>,
    /// Each set's sensor weights per observation, when its data state a σ
    /// per row (empty otherwise; see [`RowWriter`]), and the number of the
    /// set's first observation in the whole system.
    set_sensors: Vec<(Vec<[f64; 2]>, usize)>,
    /// The weights of the appended rows, in order.
    appended_weights: Vec<f64>,
    /// What each measured row measures (appended rows have none).
    kinds: Vec<RowKind>,
    /// The observation (configuration, pair) each row belongs to, numbered
    /// across sets. 32 bits: a study of 2³² observations would hold a
    /// terabyte of samples; millions of rows keep 4 bytes each.
    observations: Vec<u32>,
    observation_count: usize,
    /// Robust weight of each observation (empty: all 1); kept by `reset`.
    observation_weights: Vec<f64>,
    /// The measured rows of each measurement set, in order.
    set_rows: Vec<std::ops::Range<usize>>,
    /// Whether the next writes fold the measured rows ([`crate::fold`]);
    /// kept by `reset`.
    fold: Option<FoldKind>,
    /// The measured rows, folded (`matrix` then holds the appended rows only).
    folded: Option<FoldedRows>,
}

impl ObservationSystem {
    /// Clears and sizes the system for `rows` rows in `layout`; their W is
    /// folded as it is written when [`set_folding`](Self::set_folding) asks
    /// for it and the writer can (`foldable`: every set's configurations
    /// are independent).
    pub(crate) fn reset(&mut self, rows: usize, layout: &ColumnLayout, foldable: bool) {
        self.rows = rows;
        self.columns = layout.columns();
        self.folded = self
            .fold
            .filter(|_| foldable)
            .map(|kind| FoldedRows::empty(self.columns, kind));
        let size = if self.folded.is_some() {
            0
        } else {
            rows * self.columns
        };
        zeroed(&mut self.matrix, size);
        zeroed(&mut self.residuals, rows);
        self.appended_weights.clear();
        self.set_weights.clear();
        self.set_sensors.clear();
        self.kinds.clear();
        self.kinds.resize(rows, RowKind::Length);
        zeroed(&mut self.observations, rows);
        self.set_rows.clear();
        self.observation_count = 0;
    }

    /// Folds the measured rows of the next writes (`Some`), or holds them
    /// (`None`, the default): see [`crate::fold`].
    pub(crate) fn set_folding(&mut self, fold: Option<FoldKind>) {
        self.fold = fold;
    }

    /// Whether the measured rows of W are folded rather than held: then
    /// [`matrix`](Self::matrix) holds the appended rows only, and the
    /// least-squares routines read a c × c stand-in for W.
    pub fn is_folded(&self) -> bool {
        self.folded.is_some()
    }

    /// The rows of W in `matrix`: all of them, or the appended ones of a folded system.
    fn held_rows(&self) -> std::ops::Range<usize> {
        if self.is_folded() {
            self.measured_rows()..self.rows
        } else {
            0..self.rows
        }
    }

    /// Each row's sensor weight and whole weight, in row order: a measured
    /// row's from its set's weights, its kind and its observation's robust
    /// weight, as [`RowWriter::push`] weighted it; an appended row's its own.
    fn row_weights(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        (0..self.set_rows.len())
            .flat_map(move |set| self.sensor_weights_of(set))
            .map(move |(row, sensor)| {
                let whole = whole_weight(
                    sensor,
                    &self.observation_weights,
                    self.observations[row] as usize,
                );
                (sensor, whole)
            })
            .chain(
                self.appended_weights
                    .iter()
                    .map(|weight| (*weight, *weight)),
            )
    }

    /// The whole weights of `rows`.
    fn weights_of(&self, rows: std::ops::Range<usize>) -> Vec<f64> {
        let measured = self.measured_rows();
        if rows.start >= measured {
            return self.appended_weights[rows.start - measured..rows.end - measured].to_vec();
        }
        self.row_weights()
            .skip(rows.start)
            .take(rows.len())
            .map(|(_, whole)| whole)
            .collect()
    }

    /// The weighted right-hand sides `w r` of `rows`.
    fn weighted_right(&self, rows: std::ops::Range<usize>) -> Vec<f64> {
        self.residuals[rows.clone()]
            .iter()
            .zip(self.weights_of(rows))
            .map(|(r, w)| r * w)
            .collect()
    }

    /// The weighted sum of squares of every row, `‖w r‖²` (prior and gauge rows included).
    pub(crate) fn weighted_cost(&self) -> f64 {
        self.weighted_terms(&self.residuals, |r, w| (r * w).powi(2))
            .sum()
    }

    /// `term(r, w)` of each of `residuals` (the first rows' residuals) and
    /// its row's whole weight, in row order. The weights are read by the
    /// iterator's own loop over each set's rows (a fold, where `zip` would
    /// step through the sets' chain row by row, twice as slow), the
    /// residuals beside them; a sum or collection of the terms is the one
    /// taken with `zip`, to the bit.
    fn weighted_terms<'a>(
        &'a self,
        residuals: &'a [f64],
        term: impl Fn(f64, f64) -> f64 + 'a,
    ) -> impl Iterator<Item = f64> + 'a {
        let mut residuals = residuals.iter();
        self.row_weights()
            .take(residuals.len())
            .map(move |(_, w)| term(residuals.next().copied().unwrap_or_default(), w))
    }

    /// The normal equations `WᵀW`, `Wᵀ(w r)` of every row.
    pub(crate) fn normal_equations(&self) -> NormalEquations {
        let held = self.held_rows();
        let right = self.weighted_right(held.clone());
        let matrix = view(&self.matrix, held.len(), self.columns);
        match &self.folded {
            None => NormalEquations::of(matrix, &right),
            Some(folded) => {
                debug_assert_eq!(folded.row_count(), self.measured_rows());
                let (mut gram, mut projected) = folded.normal_sums();
                add_normal_sums(
                    &mut gram,
                    &mut projected,
                    matrix,
                    MatRef::from_column_major_slice(&right, held.len(), 1),
                );
                NormalEquations::from_sums(gram, projected)
            }
        }
    }

    /// The rows every least-squares routine reads, with their weighted
    /// right-hand sides: W and `w r` as held, or a c × c stand-in of a
    /// folded system ([`FoldedRows::stand_in`]); `measured_only` leaves the
    /// appended rows out.
    pub(crate) fn solver_rows(&self, measured_only: bool) -> SolverRows<'_> {
        let end = if measured_only {
            self.measured_rows()
        } else {
            self.rows
        };
        match &self.folded {
            None => SolverRows {
                matrix: Cow::Borrowed(&self.matrix[..end * self.columns]),
                rows: end,
                columns: self.columns,
                right: self.weighted_right(0..end),
            },
            Some(folded) => {
                let appended = end - self.measured_rows();
                let (matrix, right) = if appended == 0 {
                    folded.stand_in()
                } else {
                    folded
                        .with_rows(
                            view(&self.matrix, appended, self.columns),
                            &self.weighted_right(self.measured_rows()..end),
                        )
                        .stand_in()
                };
                SolverRows {
                    matrix: Cow::Owned(matrix),
                    rows: self.columns,
                    columns: self.columns,
                    right,
                }
            }
        }
    }

    /// The column geometry of W (c × c: see [`FoldedRows::geometry`]) when
    /// its rows were folded and it is known from the fold, `None` otherwise.
    pub(crate) fn folded_geometry(&self) -> Option<faer::Mat<f64>> {
        self.folded.as_ref().and_then(FoldedRows::geometry)
    }

    /// Whether every entry of W is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.matrix.iter().all(|v| v.is_finite())
            && self.folded.as_ref().is_none_or(FoldedRows::is_finite)
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
        self.weighted_terms(&self.residuals[..rows], |r, w| (r * w).powi(2))
            .sum()
    }

    /// Number of observations (configurations, pairs) written.
    pub fn observation_count(&self) -> usize {
        self.observation_count
    }

    /// The observation each measured row belongs to.
    pub fn row_observations(&self) -> &[u32] {
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
        self.scaled_rows().map(|(_, scaled)| scaled).collect()
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
            self.appended_weights.push(weight);
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
        self.appended_weights.push(weight);
        self.rows += 1;
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// W, row-major (`rows × columns`), weighted; of a folded system
    /// ([`is_folded`](Self::is_folded)), its appended rows only.
    pub fn matrix(&self) -> &[f64] {
        &self.matrix
    }

    /// Row `row` of W (weighted).
    ///
    /// # Panics
    /// On a folded system, which holds no rows of W.
    pub fn row(&self, row: usize) -> &[f64] {
        assert!(!self.is_folded(), "a folded system holds no rows of W");
        &self.matrix[row * self.columns..(row + 1) * self.columns]
    }

    /// Column `column` of W (weighted), copied.
    ///
    /// # Panics
    /// On a folded system, which holds no rows of W.
    pub fn column(&self, column: usize) -> Vec<f64> {
        assert!(!self.is_folded(), "a folded system holds no rows of W");
        (0..self.rows)
            .map(|row| self.matrix[row * self.columns + column])
            .collect()
    }

    /// Δy, not weighted.
    pub fn residuals(&self) -> &[f64] {
        &self.residuals
    }

    /// An empty system for the residuals of the same sets elsewhere, with
    /// this one's robust observation weights (a set centred on its mean is
    /// centred on the weighted mean: [`RowWriter::observation_weight`]).
    pub(crate) fn for_residuals(&self) -> ObservationSystem {
        ObservationSystem {
            observation_weights: self.observation_weights.clone(),
            ..ObservationSystem::default()
        }
    }

    /// Replaces the measured rows' residuals (Δy, not weighted) by those of
    /// `other`, a system of the same sets written elsewhere
    /// ([`for_residuals`](Self::for_residuals)); W, its folded sums and the
    /// appended rows stay.
    pub(crate) fn take_measured_residuals(&mut self, other: &ObservationSystem) {
        let rows = self.measured_rows();
        debug_assert_eq!(other.measured_rows(), rows);
        self.residuals[..rows].copy_from_slice(&other.residuals[..rows]);
    }

    /// Δy multiplied by the row weights: the right-hand side that goes with [`Self::matrix`].
    pub fn weighted_residuals(&self) -> Vec<f64> {
        let mut weighted = Vec::with_capacity(self.residuals.len());
        self.weighted_terms(&self.residuals, |r, w| r * w)
            .for_each(|value| weighted.push(value));
        weighted
    }

    /// Updates the residuals for a small parameter step through the linear
    /// model: `Δy ← Δy − W·step` (columns of W in this system's layout).
    /// A folded system updates its appended rows and its folded sums
    /// ([`FoldedRows::apply_step`]); its measured rows' residuals, whose
    /// rows of W are not held, stay those at the system's parameters: off by
    /// nothing that counts for a negligible step (`‖W·step‖² ≤ 1e-12 ‖w r‖²`),
    /// evaluated anew after a larger one ([`take_measured_residuals`](Self::take_measured_residuals)).
    pub(crate) fn apply_linear_step(&mut self, step: &[f64]) {
        if let Some(folded) = &mut self.folded {
            folded.apply_step(step);
        }
        let held = self.held_rows();
        let weights = self.weights_of(held.clone());
        for ((index, row), weight) in held.enumerate().zip(weights) {
            let predicted: f64 = self.matrix[index * self.columns..(index + 1) * self.columns]
                .iter()
                .zip(step)
                .map(|(w, s)| w * s)
                .sum();
            // W is weighted; the stored residuals are not.
            if weight != 0.0 {
                self.residuals[row] -= predicted / weight;
            }
        }
    }

    /// What each row measures.
    pub fn kinds(&self) -> &[RowKind] {
        &self.kinds
    }

    /// Per observation (configuration or pair): the norm of its length rows
    /// (metres) and, when a row measures an angle, of its angle rows
    /// (radians).
    pub fn observation_errors(&self) -> ObservationErrors {
        let has_angles = self.kinds.contains(&RowKind::Angle);
        let count = self.observation_count;
        let mut lengths = vec![0.0; count];
        let mut angles = vec![0.0; if has_angles { count } else { 0 }];
        let rows = 0..self.measured_rows();
        // Parts of rows whose observations do not reach into another part
        // (the rows of an observation together, in order), each summed into
        // its own observations' errors: each sum is the one taken row after
        // row, to the bit.
        let observations = &self.observations[rows.clone()];
        let parts = observation_parts(observations);
        let spans: Vec<std::ops::Range<usize>> = parts
            .iter()
            .map(
                |part| match (observations.get(part.start), part.end.checked_sub(1)) {
                    (Some(first), Some(last)) => *first as usize..observations[last] as usize + 1,
                    _ => 0..0,
                },
            )
            .collect();
        let in_order = spans.iter().all(|span| span.start <= span.end)
            && spans.windows(2).all(|pair| pair[0].end <= pair[1].start);
        let summed = in_order && {
            let length_parts = split_spans(&mut lengths, &spans);
            let angle_parts = if has_angles {
                split_spans(&mut angles, &spans)
            } else {
                spans.iter().map(|_| &mut [][..]).collect()
            };
            let work: Vec<_> = parts
                .into_iter()
                .zip(spans.iter().map(|span| span.start))
                .zip(length_parts.into_iter().zip(angle_parts))
                .collect();
            run_parts(work, |((part, first), (lengths, angles))| {
                self.errors_within(part, first, lengths, angles)
            })
            .into_iter()
            .all(|summed| summed)
        };
        if !summed {
            lengths.fill(0.0);
            angles.fill(0.0);
            self.root_sums_of_squares(rows, 0, &mut lengths, &mut angles);
        }
        ObservationErrors { lengths, angles }
    }

    /// The errors of the observations `first..` of `rows` into `lengths` and
    /// `angles` (theirs only; `angles` empty without angle rows), when
    /// their observations do not decrease along them (else false, nothing
    /// written).
    fn errors_within(
        &self,
        rows: std::ops::Range<usize>,
        first: usize,
        lengths: &mut [f64],
        angles: &mut [f64],
    ) -> bool {
        if self.observations[rows.clone()]
            .windows(2)
            .any(|pair| pair[0] > pair[1])
        {
            return false;
        }
        self.root_sums_of_squares(rows, first, lengths, angles);
        true
    }

    /// Each observation's root sum of squares of its length rows and of
    /// its angle rows among `rows`, row after row, into `lengths` and
    /// `angles` (zeros on entry), indexed from observation `first`.
    fn root_sums_of_squares(
        &self,
        rows: std::ops::Range<usize>,
        first: usize,
        lengths: &mut [f64],
        angles: &mut [f64],
    ) {
        for row in rows {
            let squared = self.residuals[row] * self.residuals[row];
            let observation = self.observations[row] as usize - first;
            match self.kinds[row] {
                RowKind::Length => lengths[observation] += squared,
                RowKind::Angle => angles[observation] += squared,
            }
        }
        for error in lengths.iter_mut().chain(angles) {
            *error = error.sqrt();
        }
    }

    /// A writer for the rows `first_row..first_row + rows` of one measurement
    /// set, whose observations are numbered after those written so far.
    pub(crate) fn writer<'a>(
        &'a mut self,
        layout: &'a ColumnLayout,
        first_row: usize,
        rows: usize,
        auxiliary_offset: usize,
        (weights, sensors): ([f64; 2], Vec<[f64; 2]>),
    ) -> RowWriter<'a> {
        let range = first_row..first_row + rows;
        let set_base = self.observation_count;
        self.set_sensors.push((sensors, set_base));
        let columns = self.columns;
        let matrix = if self.folded.is_some() {
            &mut []
        } else {
            &mut self.matrix[range.start * columns..range.end * columns]
        };
        RowWriter {
            matrix,
            residuals: &mut self.residuals[range.clone()],
            observation_weights: &self.observation_weights,
            kinds: &mut self.kinds[range.clone()],
            observations: &mut self.observations[range],
            columns,
            layout,
            next_row: 0,
            auxiliary_offset,
            row_weights: weights,
            observation_sensors: &self.set_sensors[self.set_sensors.len() - 1].0,
            set_base,
            observation_base: set_base,
            observation_end: 0,
            fold: self.folded.as_ref().map(FoldedRows::kind),
            sink: self.folded.as_mut(),
        }
    }

    /// Records that rows `rows` belong to the next measurement set, whose
    /// length and angle rows have the sensor weights `weights` (those of
    /// its observations with a σ of their own given to its
    /// [`writer`](Self::writer)).
    pub(crate) fn record_set(&mut self, rows: std::ops::Range<usize>, weights: [f64; 2]) {
        self.set_rows.push(rows);
        self.set_weights.push(weights);
    }

    /// The measured rows of each measurement set, in order.
    pub fn set_rows(&self) -> &[std::ops::Range<usize>] {
        &self.set_rows
    }

    /// Each measurement set's measured rows with their residuals multiplied
    /// by their sensor weights only ([`scaled_residuals`](Self::scaled_residuals),
    /// without a vector of them), in order.
    pub(crate) fn scaled_rows(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.scaled_rows_within(0..usize::MAX)
    }

    /// [`scaled_rows`](Self::scaled_rows) of measurement set `set`.
    pub(crate) fn scaled_rows_of(&self, set: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.scaled_rows_of_within(set, self.set_rows[set].clone())
    }

    /// [`scaled_rows`](Self::scaled_rows) among `rows` (a part of the
    /// system's rows, read on its own).
    pub(crate) fn scaled_rows_within(
        &self,
        rows: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..self.set_rows.len()).flat_map(move |set| self.scaled_rows_of_within(set, rows.clone()))
    }

    /// [`scaled_rows_of`](Self::scaled_rows_of) among `rows`.
    pub(crate) fn scaled_rows_of_within(
        &self,
        set: usize,
        rows: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.sensor_weights_within(set, rows)
            .map(move |(row, sensor)| (row, self.residuals[row] * sensor))
    }

    /// The scaled residuals of the rows of kind `kind` of measurement set
    /// `set` among `rows`, in order: those of
    /// [`scaled_rows_of_within`](Self::scaled_rows_of_within) of that kind,
    /// the same values, read as slices (the robust σ̂ reads millions of
    /// rows several times).
    pub(crate) fn scaled_of_kind_within(
        &self,
        set: usize,
        kind: RowKind,
        rows: std::ops::Range<usize>,
    ) -> impl Iterator<Item = f64> + '_ {
        let within = self.set_rows_within(set, rows);
        let sensor = sensor_weight(self.set_weights[set], kind);
        // The set's one weight read as slices, or each observation's own.
        let (plain, own) = if self.has_observation_sensors(set) {
            (0..0, within)
        } else {
            (within, 0..0)
        };
        self.residuals[plain.clone()]
            .iter()
            .zip(&self.kinds[plain])
            .filter(move |(_, row)| **row == kind)
            .map(move |(residual, _)| residual * sensor)
            .chain(
                own.filter(move |row| self.kinds[*row] == kind)
                    .map(move |row| {
                        self.residuals[row] * sensor_weight(self.row_sensor(set, row), kind)
                    }),
            )
    }

    /// The rows of measurement set `set` with their sensor weights (1/σ).
    fn sensor_weights_of(&self, set: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.sensor_weights_within(set, self.set_rows[set].clone())
    }

    /// [`sensor_weights_of`](Self::sensor_weights_of) among `rows`.
    fn sensor_weights_within(
        &self,
        set: usize,
        rows: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.set_rows_within(set, rows).map(move |row| {
            (
                row,
                sensor_weight(self.row_sensor(set, row), self.kinds[row]),
            )
        })
    }

    /// Whether set `set`'s data state a σ per row (its observations then
    /// have sensor weights of their own).
    fn has_observation_sensors(&self, set: usize) -> bool {
        self.set_sensors
            .get(set)
            .is_some_and(|(sensors, _)| !sensors.is_empty())
    }

    /// The sensor weights of the length and angle rows of row `row`'s
    /// observation in set `set` ([`observation_sensor`], as the writer
    /// weighted it).
    fn row_sensor(&self, set: usize, row: usize) -> [f64; 2] {
        let (sensors, base) = self
            .set_sensors
            .get(set)
            .map_or((&[][..], 0), |(sensors, base)| (sensors.as_slice(), *base));
        observation_sensor(
            self.set_weights[set],
            sensors,
            (self.observations[row] as usize).wrapping_sub(base),
        )
    }

    /// The rows of measurement set `set` among `rows` (empty where they do
    /// not meet).
    fn set_rows_within(&self, set: usize, rows: std::ops::Range<usize>) -> std::ops::Range<usize> {
        let own = &self.set_rows[set];
        let start = own.start.max(rows.start);
        start..own.end.min(rows.end).max(start)
    }

    /// Records that observations up to `end` (exclusive) were written
    /// ([`RowWriter::observation_end`]).
    pub(crate) fn record_observations(&mut self, end: usize) {
        self.observation_count = self.observation_count.max(end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The errors summed row after row, as one thread does.
    fn row_after_row(system: &ObservationSystem) -> ObservationErrors {
        let has_angles = system.kinds.contains(&RowKind::Angle);
        let count = system.observation_count;
        let mut errors = ObservationErrors {
            lengths: vec![0.0; count],
            angles: vec![0.0; if has_angles { count } else { 0 }],
        };
        for row in 0..system.measured_rows() {
            let squared = system.residuals[row].powi(2);
            let observation = system.observations[row] as usize;
            match system.kinds[row] {
                RowKind::Length => errors.lengths[observation] += squared,
                RowKind::Angle => errors.angles[observation] += squared,
            }
        }
        for error in errors.lengths.iter_mut().chain(&mut errors.angles) {
            *error = error.sqrt();
        }
        errors
    }

    /// Rows of `observations` (1–7 rows each, lengths and angles mixed,
    /// some observations without rows), in order or shuffled.
    fn system(observations: usize, shuffled: bool, seed: u64) -> ObservationSystem {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut rows: Vec<(u32, RowKind, f64)> = Vec::new();
        for observation in 0..observations {
            if observation % 97 == 5 {
                continue;
            }
            for _ in 0..rng.random_range(1..8) {
                let kind = if rng.random_bool(0.4) {
                    RowKind::Angle
                } else {
                    RowKind::Length
                };
                rows.push((observation as u32, kind, rng.random_range(-1e-3..1e-3)));
            }
        }
        if shuffled {
            // Two far rows trade places: one observation's rows apart.
            let last = rows.len() - 1;
            rows.swap(3, last);
        }
        let layout = ColumnLayout::new(1, &[0], 0);
        let mut system = ObservationSystem::default();
        system.reset(rows.len(), &layout, false);
        for (row, (observation, kind, residual)) in rows.into_iter().enumerate() {
            system.observations[row] = observation;
            system.kinds[row] = kind;
            system.residuals[row] = residual;
        }
        system.observation_count = observations;
        system.set_rows.push(0..system.rows);
        system.set_weights.push([2.0, 3.0]);
        system
    }

    /// The scaled residuals of a kind, read as slices, are those of every
    /// row filtered by kind, bit for bit, for any range and both sets, the
    /// second with a σ per observation or not; each row's by its own σ.
    #[test]
    fn scaled_residuals_of_a_kind_are_those_of_every_row() {
        let mut system = system(300, false, 5);
        let middle = system.rows / 2;
        system.set_rows = vec![0..middle, middle..system.rows];
        system.set_weights = vec![[2.0, 3.0], [0.5, 7.0]];
        let base = system.observations[middle] as usize;
        let own: Vec<[f64; 2]> = (base..system.observation_count)
            .map(|observation| [1.0 + observation as f64, 0.25 * observation as f64])
            .collect();
        for sensors in [Vec::new(), own] {
            system.set_sensors = vec![(Vec::new(), 0), (sensors.clone(), base)];
            scaled_of_kind_are_every_row_s(&system, middle);
            let (row, scaled) = system.scaled_rows_of(1).nth(3).expect("a row");
            let weights = sensors
                .get(system.observations[row] as usize - base)
                .copied()
                .unwrap_or([0.5, 7.0]);
            assert_eq!(
                scaled,
                system.residuals[row] * sensor_weight(weights, system.kinds[row])
            );
        }
    }

    fn scaled_of_kind_are_every_row_s(system: &ObservationSystem, middle: usize) {
        let bits = |values: Vec<f64>| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for rows in [0..system.rows, 3..middle + 5, middle..middle, 7..usize::MAX] {
            for set in 0..2 {
                for kind in [RowKind::Length, RowKind::Angle] {
                    let every: Vec<f64> = system
                        .scaled_rows_of_within(set, rows.clone())
                        .filter(|(row, _)| system.kinds[*row] == kind)
                        .map(|(_, scaled)| scaled)
                        .collect();
                    let of_kind: Vec<f64> = system
                        .scaled_of_kind_within(set, kind, rows.clone())
                        .collect();
                    assert_eq!(bits(of_kind), bits(every), "{rows:?} {set} {kind:?}");
                }
            }
        }
        // Both sets have rows of both kinds over all rows.
        for set in 0..2 {
            for kind in [RowKind::Length, RowKind::Angle] {
                assert!(
                    system
                        .scaled_of_kind_within(set, kind, 0..usize::MAX)
                        .count()
                        > 10
                );
            }
        }
    }

    /// Summed in parts on all cores (cut where an observation ends) or on
    /// one, each observation's error has the bits of the sum row after row;
    /// rows out of order take the one-thread route.
    #[test]
    fn errors_in_parts_are_those_row_after_row() {
        let long = 2 * crate::parallel::PARALLEL_SCAN / 3;
        for (observations, shuffled) in [(50, false), (long, false), (long, true), (0, false)] {
            let system = system(observations, shuffled, 7);
            assert!(observations < 100 || system.measured_rows() > crate::parallel::PARALLEL_SCAN);
            let expected = row_after_row(&system);
            let errors = system.observation_errors();
            let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&errors.lengths),
                bits(&expected.lengths),
                "{observations}"
            );
            assert_eq!(
                bits(&errors.angles),
                bits(&expected.angles),
                "{observations}"
            );
        }
    }

    /// The weighted sums and residuals read the weights by their own loop:
    /// the bits of the same terms taken beside the weights with `zip`, with
    /// robust weights and appended rows.
    #[test]
    fn weighted_terms_are_those_beside_the_weights() {
        let mut system = system(3000, false, 11);
        let count = system.observation_count;
        system.set_observation_weights((0..count).map(|i| 0.25 + (i % 7) as f64 / 7.0).collect());
        system.append_rows(&[(0, 1e3, 1e-4), (0, 5e2, -2e-4)]);
        let zipped: Vec<f64> = system
            .residuals
            .iter()
            .zip(system.row_weights())
            .map(|(r, (_, w))| r * w)
            .collect();
        let cost: f64 = zipped.iter().map(|value| value.powi(2)).sum();
        let measured: f64 = zipped[..system.measured_rows()]
            .iter()
            .map(|value| value.powi(2))
            .sum();
        let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&system.weighted_residuals()), bits(&zipped));
        assert_eq!(system.weighted_cost().to_bits(), cost.to_bits());
        assert_eq!(system.measured_cost().to_bits(), measured.to_bits());
        assert!(system.measured_cost() < system.weighted_cost());
    }

    /// Parts end where an observation does, and cover every row once.
    #[test]
    fn parts_are_cut_between_observations() {
        let observations: Vec<u32> = (0..200_000u32).map(|row| row / 6).collect();
        let parts = observation_parts(&observations);
        assert_eq!(parts.first().map(|part| part.start), Some(0));
        assert_eq!(parts.last().map(|part| part.end), Some(observations.len()));
        for pair in parts.windows(2) {
            assert_eq!(pair[0].end, pair[1].start);
            let cut = pair[0].end;
            assert_ne!(observations[cut - 1], observations[cut]);
        }
        assert_eq!(observation_parts(&observations[..100]), vec![0..100]);
    }
}
