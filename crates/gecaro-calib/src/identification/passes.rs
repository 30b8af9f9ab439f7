//! The tests behind the second pass of an identification (see
//! [`super::second_pass`]): the score test of the parameters outside the base
//! set at the first pass's solution, and the F test that keeps a second pass.
//! Both compare residual sums of squares of nested least-squares models:
//! `F = (gain/k) / (rest/ν)` against the F(k, ν) quantile at
//! [`SECOND_PASS_LEVEL`].

use super::result::Identification;
use crate::Error;
use crate::linalg::{NormalEquations, view};
use crate::observation::ObservationSystem;
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

/// Significance level of the F test that keeps a second pass.
pub const SECOND_PASS_LEVEL: f64 = 0.01;

/// Whether adding `candidates` (vocabulary indices) to the base set of
/// `current` can explain the data significantly better: the score test of
/// these columns at `current`'s solution, before any iteration. One system
/// over the auxiliary unknowns, the base set and the candidates, written at
/// the calibrated robot (`states` hold its poses); the part of the sum of
/// squares that a least-squares step over all these columns explains, beyond
/// the one over the base set alone, is tested as in [`significantly_better`]
/// (k the rank the candidates add). It costs one system and its normal
/// equations, and keeps the structural analysis and the second pass from
/// running where the first pass's residual is noise.
pub(super) fn promising(
    current: &Identification,
    study: &Study,
    candidates: &[usize],
) -> Result<bool, Error> {
    const EIGENVALUE_FLOOR: f64 = 1e-12;
    let robot = &current.calibrated;
    let thinned = thinned(study, SCORE_TEST_OBSERVATIONS);
    let study = thinned.as_ref().unwrap_or(study);
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let states = &mut states;
    let auxiliary = study.initial_auxiliary(states)?;
    let base = &current.rank.base_parameters;
    let wide: Vec<usize> = base.iter().chain(candidates).copied().collect();
    let layout = ColumnLayout::new(robot.parameters().len(), &wide, auxiliary.len());
    let mut system = ObservationSystem::default();
    study.linearise(robot, &auxiliary, &layout, states, &mut system)?;
    let rows = system.measured_rows();
    let columns = layout.columns();
    let right = &system.weighted_residuals()[..rows];
    let matrix = view(&system.matrix()[..rows * columns], rows, columns);
    let normal = NormalEquations::of(matrix, right);
    if !normal.is_finite() {
        return Ok(false);
    }
    let all: Vec<usize> = (0..columns).collect();
    let (wide_explained, wide_rank) = normal.explained(&all, EIGENVALUE_FLOOR);
    let (narrow_explained, narrow_rank) =
        normal.explained(&all[..auxiliary.len() + base.len()], EIGENVALUE_FLOOR);
    let total: f64 = right.iter().map(|r| r * r).sum();
    let added = wide_rank.saturating_sub(narrow_rank);
    let freedom = rows.saturating_sub(wide_rank).max(1) as f64;
    let (gain, rest) = (wide_explained - narrow_explained, total - wide_explained);
    if added == 0 || !(gain.is_finite() && rest.is_finite()) || gain <= 0.0 {
        return Ok(false);
    }
    Ok(f_test(gain / added as f64, rest / freedom, added, freedom))
}

/// The score test reads at most this many observations (configurations,
/// pairs), evenly spread over the data: enough to see structure that
/// matters, and a bounded cost on large data sets (the test is valid on any
/// subset, since it compares the base set and the wider one on the same rows).
const SCORE_TEST_OBSERVATIONS: usize = 500;

/// `study` with every k-th unit (configuration, set, pair) of each set, so
/// that about `limit` units remain; `None` when it has no more than `limit`.
fn thinned(study: &Study, limit: usize) -> Option<Study> {
    let units: Vec<Vec<Vec<usize>>> = study
        .sets
        .iter()
        .map(|set| crate::methods::units(set.method.as_ref(), &set.samples))
        .collect();
    let total: usize = units.iter().map(Vec::len).sum();
    if total <= limit {
        return None;
    }
    let stride = total.div_ceil(limit);
    Some(Study {
        sets: study
            .sets
            .iter()
            .zip(&units)
            .map(|(set, units)| {
                let samples = units
                    .iter()
                    .step_by(stride)
                    .flat_map(|unit| unit.iter().map(|index| set.samples[*index].clone()))
                    .collect();
                set.with_samples(samples)
            })
            .collect(),
        frames: study.frames.clone(),
    })
}

/// Whether the variance ratio `explained / residual` exceeds the F(k, ν)
/// quantile at [`SECOND_PASS_LEVEL`].
fn f_test(explained: f64, residual: f64, k: usize, freedom: f64) -> bool {
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    if residual <= f64::MIN_POSITIVE {
        return explained > 0.0;
    }
    FisherSnedecor::new(k as f64, freedom)
        .map(|f| explained / residual > f.inverse_cdf(1.0 - SECOND_PASS_LEVEL))
        .unwrap_or(false)
}

/// Whether `second` (with `added` more unknowns) explains the data
/// significantly better than `first`: F = ((S₁ − S₂)/k) / (S₂/(n − b₂)) above
/// the F(k, n − b₂) quantile at [`SECOND_PASS_LEVEL`] (S the data's residual
/// sum of squares, prior rows excluded).
pub(super) fn significantly_better(
    first: &Identification,
    second: &Identification,
    added: usize,
) -> bool {
    let (s1, s2) = (first.data_cost, second.data_cost);
    let freedom = second.degrees_of_freedom.max(1) as f64;
    s2 < s1 && f_test((s1 - s2) / added as f64, s2 / freedom, added, freedom)
}
