//! The settings of an identification ([`IdentificationOptions`]).

use gecaro_core::{JointRegion, MassModel, PriorityMatrix, Robot};

use super::outliers::DEFAULT_OUTLIER_THRESHOLD;
use crate::error::{Error, Setting};
pub use crate::fold::DEFAULT_STREAMED_ROWS;
use crate::prior::Prior;
use crate::robust::Loss;

/// Studies of more configurations than this begin on a subsample
/// ([`IdentificationOptions::coarse_from`]): at 10⁵ configurations, the
/// subsample's descent costs a sixth of the two evaluations of all the data
/// it saves.
pub const DEFAULT_COARSE_FROM: usize = 100_000;

/// How steps are taken.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// The paper's plain Gauss–Newton steps, with the minimum-norm route when they fail.
    #[default]
    GaussNewton,
    /// Levenberg–Marquardt damping from the first step.
    LevenbergMarquardt,
}

impl Solver {
    /// The names users give: `gauss-newton`, `lm`.
    pub const NAMES: [&'static str; 2] = ["gauss-newton", "lm"];

    /// The solver of a name of [`NAMES`](Self::NAMES).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "gauss-newton" => Some(Solver::GaussNewton),
            "lm" | "levenberg-marquardt" => Some(Solver::LevenbergMarquardt),
            _ => None,
        }
    }
}

/// Settings of [`identify`](super::identify).
#[derive(Clone, Debug, PartialEq)]
pub struct IdentificationOptions {
    /// Step rule.
    pub solver: Solver,
    /// Iteration limit (parameter updates) of each route.
    pub max_iterations: usize,
    /// Priority matrix; the robot's when `None`.
    pub priority: Option<PriorityMatrix>,
    /// A step is negligible when `‖Δη_b‖ ≤ step_tolerance · (1 + ‖η_b‖)`.
    pub step_tolerance: f64,
    /// The loss (plain least squares by default).
    pub loss: Loss,
    /// A Gaussian prior on the parameters (none by default).
    pub prior: Option<Prior>,
    /// Observations beyond this many robust σ̂ are reported as outliers.
    pub outlier_threshold: f64,
    /// Drop the outliers and identify again (once).
    pub reject: bool,
    /// The masses that load an elastic robot's joints (its links' own;
    /// each sample states its payload): the samples' torques, evaluated at
    /// the nominal robot, then follow each pass, evaluated again at its
    /// solution and its descent continued there while they move the model
    /// by more than a tenth of the noise ([`crate::elastic::reweighed`]).
    /// None (the default) keeps the samples' torques as they are.
    pub masses: Option<MassModel>,
    /// Systems of at least this many measured rows, whose sets'
    /// configurations are independent, are streamed
    /// ([`Study::is_streamed`](crate::study::Study::is_streamed)): every
    /// block of rows is folded into the normal equations (or a triangular
    /// factor, where they would not be accurate) as it is written, and W is
    /// never held ([`crate::observation::ObservationSystem::is_folded`]). The
    /// results differ from those of the held W in floating-point order only.
    /// [`DEFAULT_STREAMED_ROWS`] by default; 0 streams every system,
    /// `usize::MAX` none.
    pub streamed_rows: usize,
    /// Studies of more than this many configurations begin the first pass
    /// on a spread subsample of a fifth as many units, and the descent on
    /// all the data starts at its solution (see the `coarse` module): the
    /// results are the whole data's, to the stopping tolerance.
    /// [`DEFAULT_COARSE_FROM`] by default; `usize::MAX` never.
    pub coarse_from: usize,
    /// The region of the joint space the calibrated robot will be used in,
    /// over which the verdict predicts its error (`None`: the joint
    /// limits; see [`RegionPrediction`](super::RegionPrediction)).
    pub work_region: Option<JointRegion>,
}

/// The iteration limit of an identification when none is asked for: the
/// command line's `--max-iterations`, Python's `max_iterations`, the page's
/// field (sent by `/api/info`). Gauss–Newton on the paper's problems takes
/// 3–8; the limit is for a slow LM route.
pub const DEFAULT_MAX_ITERATIONS: usize = 30;

impl Default for IdentificationOptions {
    fn default() -> Self {
        IdentificationOptions {
            solver: Solver::GaussNewton,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            priority: None,
            step_tolerance: 1e-8,
            loss: Loss::default(),
            prior: None,
            outlier_threshold: DEFAULT_OUTLIER_THRESHOLD,
            reject: false,
            masses: None,
            streamed_rows: DEFAULT_STREAMED_ROWS,
            coarse_from: DEFAULT_COARSE_FROM,
            work_region: None,
        }
    }
}

/// Checks the options a user gives beyond the robot and data.
pub(super) fn check_options(robot: &Robot, options: &IdentificationOptions) -> Result<(), Error> {
    let threshold = options.outlier_threshold;
    if !(threshold.is_finite() && threshold > 0.0) {
        return Err(Error::InvalidOption {
            setting: Setting::OutlierThreshold,
            message: format!("must be a positive number of robust σ, not {threshold}"),
        });
    }
    if !options.loss.is_l2() {
        Loss::with_scale(options.loss.kind, options.loss.scale)?;
    }
    if let Some(prior) = &options.prior {
        prior.check(robot)?;
    }
    if let Some(region) = &options.work_region
        && region.joints() != robot.joint_count()
    {
        return Err(Error::InvalidOption {
            setting: Setting::WorkRegion,
            message: format!(
                "gives {} joint ranges for a robot of {} joints",
                region.joints(),
                robot.joint_count()
            ),
        });
    }
    Ok(())
}
