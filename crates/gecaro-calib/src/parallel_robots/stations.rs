//! Several sets measured from several stations: each set's frame an
//! unknown of the fit beside the robot's parameters.
//!
//! A tracker moved between two sets measures the second in another frame.
//! Each set is first registered in closed form on the nominal robot
//! ([`super::measurement_frame`]) and brought into the base frame; the
//! first set's frame then defines the base frame (as one set's does), and
//! every later set `s` keeps a small rigid correction `δ_s`, identified
//! with the parameters: its measurements are `δ_s·m` (a point `m` moved to
//! `t_s + exp(r_s)·m`, a pose `(p, R)` to `(t_s + exp(r_s)·p, exp(r_s)·R)`).
//! The closed-form registration carries the nominal robot's errors — a
//! millimetre between two sets that see the platform's errors from two
//! sides — which the correction takes up.
//!
//! # The columns of a correction
//! Six unknowns a station, `[t_x, t_y, t_z, r_x, r_y, r_z]` (m, rad), after
//! the robot's parameters, in station order. For a measured pose, the
//! closure equation `Fᵢ` changes with the pose as `∂Fᵢ/∂x = [g_p; g_r]`
//! (`δp`, then `ω` with `R ← exp(ω)·R`), so with the correction
//! `∂Fᵢ/∂t = g_p` and `∂Fᵢ/∂r = g_r + p × g_p`. For a measured point `m`
//! the residual `δ_s·m − y(ξ)` gives the columns `[−I, [m]×]` in the
//! system `∂y/∂ξ·Δξ − ∂(δ_s·m)/∂δ·Δδ = δ_s·m − y`. Distances have no frame.
//! The rotation's columns are those at `r = 0` for every `r` (its
//! parameterisation's derivative is left out): they differ from the exact
//! ones by an invertible factor `I + O(‖r‖)`, so the fit's minimum is the
//! same and the robot's covariance (the correction's Schur complement)
//! too; only the corrections' own σ carry the `O(‖r‖)` — a mrad's
//! thousandth.

use nalgebra::{Isometry3, Matrix3, SMatrix, Translation3, UnitQuaternion, Vector3};

/// Unknowns of one station's correction.
pub(super) const STATION_UNKNOWNS: usize = 6;

/// Which station measured each sample, and each station's correction
/// (station 0's is the identity, not an unknown).
#[derive(Clone, Debug, Default)]
pub(super) struct StationFrames {
    /// Each sample's station (empty: all station 0).
    of_sample: Vec<usize>,
    /// Each station's correction `δ_s` (the first the identity).
    corrections: Vec<Isometry3<f64>>,
}

impl StationFrames {
    /// One station: no unknowns.
    pub(super) fn single() -> Self {
        Self::default()
    }

    /// `of_sample[i]` the station of sample i (stations numbered from 0 in
    /// order), their corrections the identity.
    pub(super) fn new(of_sample: Vec<usize>) -> Self {
        let stations = of_sample.iter().max().map_or(1, |last| last + 1);
        Self {
            of_sample,
            corrections: vec![Isometry3::identity(); stations],
        }
    }

    /// The unknowns of the corrections (six a station after the first).
    pub(super) fn unknowns(&self) -> usize {
        STATION_UNKNOWNS * self.corrections.len().saturating_sub(1)
    }

    /// The stations after the first, which have unknowns.
    pub(super) fn corrected(&self) -> usize {
        self.corrections.len().saturating_sub(1)
    }

    /// Each station's samples among `count`, as ranges: a station's
    /// samples follow each other (its set's, the sets in order).
    pub(super) fn ranges(&self, count: usize) -> Vec<std::ops::Range<usize>> {
        if self.of_sample.is_empty() {
            return std::iter::once(0..count).collect();
        }
        let mut ranges: Vec<std::ops::Range<usize>> = Vec::new();
        for (index, station) in self.of_sample.iter().enumerate().take(count) {
            match ranges.get_mut(*station) {
                Some(range) => range.end = index + 1,
                None => {
                    ranges.resize(*station, 0..0);
                    ranges.push(index..index + 1);
                }
            }
        }
        ranges
    }

    /// Sample `index`'s station.
    pub(super) fn station_of(&self, index: usize) -> usize {
        self.of_sample.get(index).copied().unwrap_or(0)
    }

    /// The stations of the samples kept by `keep` (their indices).
    pub(super) fn kept(&self, keep: impl Fn(usize) -> bool) -> Self {
        if self.of_sample.is_empty() {
            return self.clone();
        }
        Self {
            of_sample: (0..self.of_sample.len())
                .filter(|index| keep(*index))
                .map(|index| self.of_sample[index])
                .collect(),
            corrections: self.corrections.clone(),
        }
    }

    /// The same stations with the corrections `values` (the unknowns, six a
    /// station after the first: see the module docs).
    pub(super) fn at(&self, values: &[f64]) -> Self {
        let mut corrections = vec![Isometry3::identity()];
        corrections.extend(values.chunks_exact(STATION_UNKNOWNS).map(|unknowns| {
            Isometry3::from_parts(
                Translation3::new(unknowns[0], unknowns[1], unknowns[2]),
                UnitQuaternion::from_scaled_axis(Vector3::new(
                    unknowns[3],
                    unknowns[4],
                    unknowns[5],
                )),
            )
        }));
        corrections.truncate(self.corrections.len().max(1));
        Self {
            of_sample: self.of_sample.clone(),
            corrections,
        }
    }

    /// Station `station`'s correction.
    pub(super) fn correction(&self, station: usize) -> &Isometry3<f64> {
        &self.corrections[station]
    }

    /// Sample `index`'s measurement `measured` (a pose, or a point as a
    /// pose's translation) corrected by its station's `δ_s`.
    pub(super) fn corrected_measurement(
        &self,
        index: usize,
        measured: &Isometry3<f64>,
    ) -> Isometry3<f64> {
        match self.station_of(index) {
            0 => *measured,
            station => self.corrections[station] * measured,
        }
    }

    /// The first column of sample `index`'s station's correction among
    /// `parameters` + unknowns, or `None` for station 0.
    pub(super) fn first_column(&self, index: usize, parameters: usize) -> Option<usize> {
        match self.station_of(index) {
            0 => None,
            station => Some(parameters + STATION_UNKNOWNS * (station - 1)),
        }
    }
}

/// A closure equation's coefficients on its station's correction, from its
/// row `by_pose` of `∂F/∂x` at the corrected pose whose position is `p`
/// (module docs): `[g_p, g_r + p × g_p]`; a platform that only translates
/// (`by_pose` of three) has `g_r = 0`.
pub(super) fn pose_columns(by_pose: &[f64], position: &Vector3<f64>) -> [f64; STATION_UNKNOWNS] {
    let translation = Vector3::new(by_pose[0], by_pose[1], by_pose[2]);
    let turn = match by_pose.get(3..6) {
        Some(turn) => Vector3::new(turn[0], turn[1], turn[2]),
        None => Vector3::zeros(),
    } + position.cross(&translation);
    [
        translation.x,
        translation.y,
        translation.z,
        turn.x,
        turn.y,
        turn.z,
    ]
}

/// A measured point's three rows on its station's correction, the point
/// `measured` as corrected (module docs): `[−I, [m]×]`.
pub(super) fn point_columns(measured: &Vector3<f64>) -> SMatrix<f64, 3, STATION_UNKNOWNS> {
    let mut columns = SMatrix::<f64, 3, STATION_UNKNOWNS>::zeros();
    columns
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(-Matrix3::identity()));
    columns
        .fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&measured.cross_matrix());
    columns
}
