//! The errors of a robot on a study, without identifying anything: what
//! [`evaluate`] reports on held-out data and what an identification reports
//! before it starts.

use gecaro_core::Robot;

use super::result::ErrorSummary;
use crate::Error;
use crate::observation::{ObservationErrors, ObservationSystem};
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

/// Error statistics of a (calibrated) robot on a study: per configuration (or
/// pair), the norm of its position-like residuals — distance to the measured
/// point, to the mean point of its set, to the plane, or the distance error —
/// and of its orientation residuals.
///
/// # Errors
/// Invalid data, or auxiliary unknowns that cannot be initialised.
pub fn evaluate(robot: &Robot, study: &Study) -> Result<ErrorSummary, Error> {
    study.check(robot)?;
    Ok(errors_at(robot, study)?.0)
}

/// [`evaluate`], with the errors of every observation (configuration or
/// pair, in data order): the position-like error (m) and the orientation
/// error (rad), for plots.
///
/// # Errors
/// As [`evaluate`].
pub fn evaluate_errors(
    robot: &Robot,
    study: &Study,
) -> Result<(ErrorSummary, ObservationErrors), Error> {
    study.check(robot)?;
    let (summary, errors, _) = errors_at(robot, study)?;
    Ok((summary, errors))
}

/// The errors of `robot` on `study`: their summary, per observation, and
/// the RMS of the weighted residual rows (an iteration record's).
pub(super) fn errors_at(
    robot: &Robot,
    study: &Study,
) -> Result<(ErrorSummary, ObservationErrors, f64), Error> {
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    let layout = ColumnLayout::new(robot.parameters().len(), &[], auxiliary.len());
    let mut system = ObservationSystem::default();
    study.linearise(robot, &auxiliary, &layout, &mut states, &mut system)?;
    let cost = system.weighted_cost();
    let rms = (cost / system.rows().max(1) as f64).sqrt();
    let errors = system.observation_errors();
    Ok((ErrorSummary::of_errors(&errors), errors, rms))
}
