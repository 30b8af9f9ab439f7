//! The tests behind the second pass and the damped descent of an
//! identification (see [`super::second_pass`]): the score tests at a pass's
//! solution, and the F test that keeps a pass.
//! Both compare residual sums of squares of nested least-squares models:
//! `F = (gain/k) / (rest/ν)` against the F(k, ν) quantile at
//! [`SECOND_PASS_LEVEL`].

use super::gauge::Gauge;
use super::outliers::outlier_samples;
use super::result::Identification;
use super::subsample::spread_subsample;
use crate::Error;
use crate::fold::FoldKind;
use crate::observation::ObservationSystem;
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

/// Significance level of the F test that keeps a second pass.
pub const SECOND_PASS_LEVEL: f64 = 0.01;

/// What a least-squares step from `current`'s solution could still explain
/// ([`score_tests`]): the rank that a test finds significant, or `None`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ScoreTests {
    /// Adding the candidates to the base set: the part of the sum of squares
    /// a step over the base set and the candidates explains beyond the one
    /// over the base set alone (k the rank the candidates add).
    pub(super) outside: Option<usize>,
    /// A step over all of them: the part of the sum of squares it explains
    /// (k its rank). Where the base set was fitted by plain least squares its
    /// own step explains nothing, and this test is the weaker of the two;
    /// after a second pass, whose added parameters a prior holds, it also
    /// sees what the prior keeps from the data.
    pub(super) whole: Option<usize>,
}

/// The score tests of `candidates` (vocabulary indices, outside the base set
/// of `current`) at `current`'s solution, before any iteration: one system
/// over the auxiliary unknowns, the base set and the candidates, written at
/// the calibrated robot, and the parts of its sum of squares that
/// least-squares steps would explain, tested as in [`significantly_lower`].
/// It costs one system and its normal equations, and keeps the structural
/// analysis, the second pass and the damped descent from running where the
/// residual is noise. For a study that does not observe the scale, a
/// [`Gauge`] row (with the σ of `gauge`) holds it: the step that shrinks
/// the robot would explain residuals in metres too.
pub(super) fn score_tests(
    current: &Identification,
    study: &Study,
    candidates: &[usize],
    gauge: Option<&crate::prior::Prior>,
    streamed_rows: usize,
) -> Result<ScoreTests, Error> {
    const EIGENVALUE_FLOOR: f64 = 1e-12;
    let robot = &current.calibrated;
    // The tests assume Gaussian residuals, and gross errors would pass for
    // structure: they read the observations within the outlier threshold.
    // (A model that misses structure makes outliers of its own; the
    // inliers show that structure still.)
    let dropped = outlier_samples(study, &current.outliers);
    let tested = spread_subsample(study, &dropped, SCORE_TEST_OBSERVATIONS);
    let study: &Study = &tested;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let states = &mut states;
    let auxiliary = study.initial_auxiliary(states)?;
    let base = &current.rank.base_parameters;
    let wide: Vec<usize> = base.iter().chain(candidates).copied().collect();
    let layout = ColumnLayout::new(robot.parameters().len(), &wide, auxiliary.len());
    // The tests read the normal equations only: tall data are folded into
    // them as they are written, no W is held ([`crate::fold`]).
    let mut system = ObservationSystem::default();
    system.set_folding(study.is_streamed(streamed_rows).then_some(FoldKind::Gram));
    study.linearise(robot, &auxiliary, &layout, states, &mut system)?;
    let rows = system.measured_rows();
    if let Some(prior) = gauge {
        Gauge::new(robot, &layout, prior, rows).append_to(&mut system, robot);
    }
    let columns = layout.columns();
    let weighted = system.weighted_residuals();
    let right = &weighted[..rows];
    let normal = system.normal_equations();
    if !normal.is_finite() {
        return Ok(ScoreTests::default());
    }
    let all: Vec<usize> = (0..columns).collect();
    // The two spectra on two cores.
    let ((wide_explained, wide_rank), (narrow_explained, narrow_rank)) =
        crate::parallel::beside_if_free(
            || normal.explained(&all, EIGENVALUE_FLOOR),
            || normal.explained(&all[..auxiliary.len() + base.len()], EIGENVALUE_FLOOR),
        );
    let total: f64 = right.iter().map(|r| r * r).sum();
    let freedom = rows.saturating_sub(wide_rank).max(1) as f64;
    let rest = total - wide_explained;
    let test = |gain: f64, k: usize| {
        let valid = k > 0 && gain.is_finite() && rest.is_finite() && gain > 0.0;
        (valid && f_test(gain / k as f64, rest / freedom, k, freedom)).then_some(k)
    };
    Ok(ScoreTests {
        outside: test(
            wide_explained - narrow_explained,
            wide_rank.saturating_sub(narrow_rank),
        ),
        whole: test(wide_explained, wide_rank),
    })
}

/// The score test reads at most this many observations (configurations,
/// pairs), spread over the data ([`spread_subsample`]): enough to see structure that
/// matters, and a bounded cost on large data sets (the test is valid on any
/// subset, since it compares the base set and the wider one on the same rows).
const SCORE_TEST_OBSERVATIONS: usize = 500;

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

/// Whether a sum of squares `s2`, with `added` more unknowns and `freedom`
/// degrees of freedom left, is significantly lower than `s1`: F =
/// ((s1 − s2)/k) / (s2/freedom) above the F(k, freedom) quantile at
/// [`SECOND_PASS_LEVEL`] (the data's residual sums of squares, prior rows
/// excluded).
pub(super) fn significantly_lower(s1: f64, s2: f64, added: usize, freedom: usize) -> bool {
    let freedom = freedom.max(1) as f64;
    added > 0 && s2 < s1 && f_test((s1 - s2) / added as f64, s2 / freedom, added, freedom)
}
