//! What an identification gives: the identified parameters with their σ,
//! the errors before and after, how it got there and why it stopped.

use gecaro_core::Robot;

use super::outliers::Outlier;
use super::parameter::IdentifiedParameter;
use super::verdict::{Outcome, StopReason, Verdict};
use super::warnings::Warning;
use super::words;
use crate::frames::NamedFrame;
use crate::identifiability::RankReport;
use crate::observability::Observability;
use crate::observation::ObservationErrors;
use crate::prior::Prior;
use crate::progress::IterationRecord;
use crate::robust::Loss;

/// Which route produced the solution (see the module docs).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Route {
    /// Plain Gauss–Newton on the base parameters (the paper).
    GaussNewton,
    /// Minimum-norm steps on all parameters, then continuation to the base set.
    MinimumNorm,
    /// Levenberg–Marquardt on the base parameters.
    LevenbergMarquardt,
}

impl Route {
    /// `gauss-newton`, `minimum-norm` or `levenberg-marquardt`.
    pub fn as_str(self) -> &'static str {
        match self {
            Route::GaussNewton => "gauss-newton",
            Route::MinimumNorm => "minimum-norm",
            Route::LevenbergMarquardt => "levenberg-marquardt",
        }
    }
}

/// Statistics of the per-observation errors (configuration, or pair) of a study.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ErrorSummary {
    /// Number of observations.
    pub count: usize,
    /// RMS of the position-like errors (metres).
    pub rms: f64,
    /// Mean (metres).
    pub mean: f64,
    /// Largest (metres).
    pub max: f64,
    /// RMS of the orientation errors (radians), for data with orientations.
    pub rms_rotation: Option<f64>,
    /// Largest orientation error (radians).
    pub max_rotation: Option<f64>,
}

impl ErrorSummary {
    /// The summary of per-observation errors (position-like in metres,
    /// orientation in radians), with orientation statistics when they
    /// measure angles.
    pub fn of_errors(errors: &ObservationErrors) -> Self {
        let count = errors.len();
        let rms = |squares: f64| (squares / count.max(1) as f64).sqrt();
        // One pass over each, nothing copied (a million observations).
        let (mut squares, mut sum, mut max) = (0.0, 0.0, 0.0_f64);
        for &length in &errors.lengths {
            squares += length * length;
            sum += length;
            max = max.max(length);
        }
        let rotation = errors.has_angles().then(|| {
            let (squares, max) = errors
                .angles
                .iter()
                .fold((0.0, 0.0_f64), |(squares, max), &angle| {
                    (squares + angle * angle, max.max(angle))
                });
            (rms(squares), max)
        });
        ErrorSummary {
            count,
            rms: rms(squares),
            mean: sum / count.max(1) as f64,
            max,
            rms_rotation: rotation.map(|(rms, _)| rms),
            max_rotation: rotation.map(|(_, max)| max),
        }
    }
}

/// The result of [`identify`](super::identify).
#[derive(Clone, Debug)]
pub struct Identification {
    /// The robot with the identified parameters (the best iterate).
    pub calibrated: Robot,
    /// The structural identifiable parameters (random data like these, Appendix III).
    pub rank: RankReport,
    /// Entry 0 is the starting point; then one entry per accepted update of the route taken.
    pub history: Vec<IterationRecord>,
    /// The route that produced the solution.
    pub route: Route,
    /// Errors of the observations at the nominal parameters.
    pub before: ErrorSummary,
    /// Errors of the observations at the identified parameters.
    pub after: ErrorSummary,
    /// Per observation (configuration or pair): the position-like error (m)
    /// and the orientation error (rad) at the nominal parameters.
    pub errors_before: ObservationErrors,
    /// The same at the identified parameters.
    pub errors_after: ObservationErrors,
    /// Condition number of W_b at the solution.
    pub condition_number: f64,
    /// Appendix III on the data at the nominal robot (the excitation check):
    /// the base set they excite, and their W_b's condition number and
    /// observability indices, computed when first read.
    pub excitation: RankReport,
    /// The identified base parameters, in column (priority) order.
    pub parameters: Vec<IdentifiedParameter>,
    /// The identified auxiliary unknowns (named frames' unknowns, plane
    /// coefficients).
    pub auxiliary: Vec<IdentifiedParameter>,
    /// The study's named tools and stations at their identified poses (an
    /// unknown the data do not determine keeps its stated value): with
    /// [`Study::with_frames`](crate::study::Study::with_frames), what a
    /// held-out evaluation of the calibrated robot needs.
    pub frames: Vec<NamedFrame>,
    /// The posterior covariance of the identified unknowns, `σ² (W_bᵀW_b)⁻¹`
    /// (eq. 11, the prior's rows in W_b; σ² of the residuals as measured, of
    /// the observations within the outlier threshold with a robust loss):
    /// rows and columns in the order of
    /// [`auxiliary`](Self::auxiliary), then [`parameters`](Self::parameters);
    /// in their units (metres, radians). `None` when W_bᵀW_b is not
    /// numerically positive definite.
    pub covariance: Option<nalgebra::DMatrix<f64>>,
    /// The a-posteriori residual standard deviation σ (units of the weighted rows).
    pub residual_sigma: f64,
    /// Why the iteration stopped.
    pub stop_reason: StopReason,
    /// Structural base parameters the data do not excite: not identified, left at nominal.
    pub not_excited: Vec<String>,
    /// Parameters outside the base set that the minimum-norm route had to move
    /// (their `std` is NaN): with them at nominal, the base set — chosen at the
    /// nominal geometry, where its regroupings hold to first order — cannot
    /// reproduce these data. Empty on the paper's route.
    pub moved: Vec<IdentifiedParameter>,
    /// Things a user should know about these results ([`Warning`]: each
    /// says itself in words).
    pub warnings: Vec<Warning>,
    /// The loss minimised.
    pub loss: Loss,
    /// The prior, if one was given.
    pub prior: Option<Prior>,
    /// Outer iterations of the reweighted phase (0 in plain least squares).
    pub reweightings: usize,
    /// The robust σ̂ of the residuals at the solution, in units of the
    /// sensors' σ (the rows' weights; metres for an unweighted set).
    pub robust_sigma: f64,
    /// Per observation: its standardised residual at the solution (units of σ̂).
    pub standardized: Vec<f64>,
    /// Per observation: its weight in the final fit (all 1 in least squares).
    pub observation_weights: Vec<f64>,
    /// The outlier threshold used (robust σ̂).
    pub outlier_threshold: f64,
    /// Observations beyond the outlier threshold at the solution, worst first.
    pub outliers: Vec<Outlier>,
    /// Whether the result can be trusted ([`Verdict`]).
    pub verdict: Verdict,
    /// Pairs of identified parameters whose estimates are strongly
    /// correlated, `(a, b, ρ)` with |ρ| above
    /// [`STRONG_CORRELATION`](super::STRONG_CORRELATION), strongest first:
    /// the data tell them apart poorly.
    pub correlated: Vec<(String, String, f64)>,
    /// Parameters outside the base set chosen at the nominal robot that the
    /// second pass identified (identifiable at the calibrated robot; see the
    /// module docs): empty when the paper's base set sufficed.
    pub second_pass: Vec<String>,
    /// Parameters outside the base set that the data set (the closed-form
    /// start, the continuation or the damped descent moved them) and a
    /// base parameter absorbs: identified beside the base set, held by the
    /// second pass's weak prior, so that their values and σ, and those of
    /// the base parameters they regroup with, are the data's rather than
    /// the route's (see the module docs of `tied`).
    pub joined: Vec<String>,
    /// The data's residual sum of squares at the solution (rows scaled by
    /// their sensor σ and robust weights; prior rows excluded).
    pub data_cost: f64,
    /// Degrees of freedom of the residuals: independent equations of the
    /// observations with a weight, minus the identified unknowns.
    pub degrees_of_freedom: usize,
    /// Observations dropped before this fit ([`IdentificationOptions::reject`](super::IdentificationOptions::reject)):
    /// the outliers of the first fit, located in the original data.
    pub rejected: Vec<Outlier>,
}

impl Identification {
    /// The names of the unknowns in the order of
    /// [`covariance`](Self::covariance): the auxiliary unknowns, then the
    /// base parameters.
    pub fn unknown_names(&self) -> Vec<&str> {
        self.auxiliary
            .iter()
            .chain(&self.parameters)
            .map(|p| p.name.as_str())
            .collect()
    }

    /// The correlation matrix of the unknowns, `ρ_ij = C_ij / √(C_ii C_jj)`
    /// of [`covariance`](Self::covariance) (its order, 1 on the diagonal;
    /// 0 beside an unknown of no variance); `None` without a covariance.
    pub fn correlation(&self) -> Option<nalgebra::DMatrix<f64>> {
        let covariance = self.covariance.as_ref()?;
        let scale: Vec<f64> = covariance
            .diagonal()
            .iter()
            .map(|v| v.max(0.0).sqrt())
            .collect();
        Some(nalgebra::DMatrix::from_fn(
            covariance.nrows(),
            covariance.ncols(),
            |i, j| {
                let denominator = scale[i] * scale[j];
                if denominator > 0.0 {
                    (covariance[(i, j)] / denominator).clamp(-1.0, 1.0)
                } else {
                    0.0
                }
            },
        ))
    }

    /// The covariance (m²) of named frame `frame`'s identified origin, its
    /// unknowns `FRAME.x`, `FRAME.y`, `FRAME.z`; `None` when one of them
    /// was not identified or there is no covariance.
    pub fn frame_position_covariance(&self, frame: &str) -> Option<nalgebra::Matrix3<f64>> {
        let covariance = self.covariance.as_ref()?;
        let index = |axis: &str| {
            let name = format!("{frame}.{axis}");
            self.auxiliary.iter().position(|p| p.name == name)
        };
        let indices = [index("x")?, index("y")?, index("z")?];
        Some(nalgebra::Matrix3::from_fn(|i, j| {
            covariance[(indices[i], indices[j])]
        }))
    }

    /// The observations beyond the outlier threshold, numbered across sets
    /// as [`Identification::errors_after`] (for plots).
    pub fn outlier_observations(&self) -> Vec<usize> {
        self.standardized
            .iter()
            .enumerate()
            .filter(|(_, u)| **u > self.outlier_threshold)
            .map(|(index, _)| index)
            .collect()
    }

    /// The errors at the solution of the observations that are not
    /// outliers: what a robust fit achieves on the data it believes (`None`
    /// when nothing is an outlier; then [`Identification::after`] says it).
    pub fn after_inliers(&self) -> Option<ErrorSummary> {
        if self.outliers.is_empty() {
            return None;
        }
        let outliers = self.outlier_observations();
        let kept = self
            .errors_after
            .retained(|index| outliers.binary_search(&index).is_err());
        Some(ErrorSummary::of_errors(&kept))
    }

    /// The robust σ̂ of the residuals in words: in units of the stated σ
    /// when every set states one (`1.04× the stated σ`), else in
    /// millimetres (the rows are then metres).
    pub fn robust_sigma_words(&self) -> String {
        if self.verdict.noise_test.is_some() {
            format!("{:.3}× the stated σ", self.robust_sigma)
        } else {
            words::millimetres(self.robust_sigma)
        }
    }

    /// Number of parameter updates of the route taken.
    pub fn iterations(&self) -> usize {
        self.history.len() - 1
    }

    /// The unknowns the data must determine: the identified parameters and
    /// auxiliary unknowns, less the joined ones (held by their prior).
    pub fn unknowns(&self) -> usize {
        self.parameters.len() + self.auxiliary.len() - self.joined.len()
    }

    /// Observability indices O1–O5 of the data's W_b at the nominal robot
    /// (see [`crate::observability::Observability`]).
    pub fn observability(&self) -> Observability {
        self.excitation.observability()
    }

    /// RMS of the weighted residual before identification.
    pub fn rms_before(&self) -> f64 {
        self.history[0].rms
    }

    /// RMS of the weighted residual after identification.
    pub fn rms_after(&self) -> f64 {
        self.history
            .iter()
            .map(|h| h.rms)
            .fold(f64::INFINITY, f64::min)
    }

    /// Why the result is no solution, as a sentence, when the iteration did
    /// not converge or the data are degenerate (`None` otherwise; a fit that
    /// exceeds the stated noise is a solution, and says so in its verdict).
    pub fn failure(&self) -> Option<String> {
        if self.stop_reason != StopReason::Converged {
            let cause = self
                .verdict
                .shifted_join
                .as_ref()
                .map_or_else(String::new, |join| format!(": {}", join.words()));
            return Some(format!(
                "the identification did not converge ({}) after {} iteration{}; best residual \
                 RMS {:.3e}{cause}",
                self.stop_reason.as_str().replace('_', " "),
                self.iterations(),
                if self.iterations() == 1 { "" } else { "s" },
                self.rms_after(),
            ));
        }
        (self.verdict.outcome == Outcome::Degenerate).then(|| {
            format!(
                "the identification is not determined: {}",
                self.verdict.summary
            )
        })
    }
}
