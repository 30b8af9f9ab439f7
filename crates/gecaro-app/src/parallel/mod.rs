//! Parallel robots as jobs (issue 79): a Gough–Stewart platform's points
//! generation, identifiable parameters, identification and evaluation, for
//! every front end. The mathematics is `gecaro_calib::parallel_robots`';
//! the robot files are `gecaro_io`'s (`kind = "parallel"`).
//!
//! A robot named on any front end is one kind or the other:
//! [`RobotKind::of`] says which, so that a front end runs the job of that
//! kind and a serial-only job (forward kinematics, compensation of a joint
//! program) refuses a parallel robot by name.

mod compensate;
mod documents;
mod evaluate;
mod generate;
mod identifiable;
mod identify;
mod leg;
mod plan;
mod predict;
mod region;
mod residuals;

use gecaro_calib::parallel_robots::PlatformMeasure;
use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_core::parallel_robot::ParallelRobot;
use gecaro_io::ParallelRobotFile;

use crate::error::{AppError, ErrorKind};
use crate::files::Files;

pub use compensate::{ParallelCompensateRequest, ParallelCompensated};
pub use documents::{
    PlatformErrorsDocument, PlatformIdentificationDocument, PlatformLegDocument,
    PlatformOutlierDocument, PlatformParameterDocument, PlatformRankDocument,
    PlatformRegionDocument, PlatformRelationDocument, PlatformStationDocument,
};
pub use evaluate::{ParallelEvaluateRequest, ParallelEvaluated};
pub use generate::{ParallelGenerateRequest, ParallelGenerated};
pub use identifiable::{DEFAULT_POSES, ParallelIdentifiableRequest};
pub use identify::{ParallelIdentified, ParallelIdentifyRequest};
pub use plan::{POOL_PER_POSE, ParallelPlanRequest, ParallelPlanned};
pub use predict::{
    MAX_SIMULATED_CALIBRATIONS, ParallelPredictRequest, ParallelPredicted,
    PredictedParameterDocument, SimulatedCalibrationsDocument,
};

/// The kind of a robot file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotKind {
    /// Frames 0..n+1 in Khalil–Kleinfinger parameters.
    Serial,
    /// A Gough–Stewart platform (`kind = "parallel"`).
    Parallel,
}

impl RobotKind {
    /// The kind of the robot `name` (a file of `files`, else a ready
    /// robot's name): parallel when its file says `kind = "parallel"` or it
    /// is a ready parallel robot; serial otherwise (its loading says what
    /// is wrong with it).
    pub fn of(name: &str, files: &dyn Files) -> RobotKind {
        if files.is_file(name) {
            return match files.read_text(name, &["toml"]) {
                Ok((_, text)) if gecaro_io::is_parallel_robot_text(&text) => RobotKind::Parallel,
                _ => RobotKind::Serial,
            };
        }
        if gecaro_io::ready_parallel_robots()
            .iter()
            .any(|ready| ready.name.eq_ignore_ascii_case(name))
        {
            RobotKind::Parallel
        } else {
            RobotKind::Serial
        }
    }
}

/// The parallel robot `name`: a file of `files`, else a ready parallel
/// robot.
///
/// # Errors
/// A file that cannot be read or parsed (its line and key), a serial
/// robot's file, an unknown name (listing the ready parallel robots).
pub fn load_parallel_robot(name: &str, files: &dyn Files) -> Result<ParallelRobotFile, AppError> {
    if files.is_file(name) {
        let (path, text) = files.read_text(name, &["toml"])?;
        if !gecaro_io::is_parallel_robot_text(&text) {
            return Err(AppError::plain(
                ErrorKind::Input,
                format!(
                    "{}: a serial robot's file, where this job needs a parallel robot's \
                     (`kind = \"parallel\"`)",
                    path.display()
                ),
            ));
        }
        return Ok(gecaro_io::parse_parallel_robot_file(&text, &path)?);
    }
    // Only the ready robots beyond `files`: the web page's folder is the
    // whole of what it reads.
    match gecaro_io::ready_parallel_robot(name) {
        Some(ready) => Ok(ready?),
        None => {
            if name.ends_with(".toml") || name.contains(['/', std::path::MAIN_SEPARATOR]) {
                // Looks like a path: say the file is missing.
                files.read_text(name, &["toml"])?;
            }
            Err(gecaro_io::Error::UnknownRobot {
                name: name.to_owned(),
                available: gecaro_io::ready_parallel_robots()
                    .iter()
                    .map(|ready| ready.name.to_owned())
                    .collect(),
            }
            .into())
        }
    }
}

/// The measure of a job on `robot`: `frame` (the platform's pose, for a
/// platform that turns) or `position` (its tool point), checked before any
/// file is read.
fn measure_for(name: &str, robot: &ParallelRobot) -> Result<PlatformMeasure, AppError> {
    let measure = measure_of(name)?;
    measure.check_for(robot)?;
    Ok(measure)
}

/// [`measure_for`] for a job that does not take a measuring leg yet
/// (`job`: identifiable, evaluate, plan, predict): the `leg` method refused
/// by name, with what takes it.
fn measure_without_leg(
    name: &str,
    robot: &ParallelRobot,
    job: &str,
) -> Result<PlatformMeasure, AppError> {
    let measure = measure_for(name, robot)?;
    if measure == PlatformMeasure::Leg {
        return Err(AppError::setting(
            "method",
            format!(
                "`leg` is generated, identified and reported (generate, identify, report); \
                 {job} of a measuring leg is not there yet: judge the calibrated platform with \
                 an instrument's held-out data (frame, position, distance)"
            ),
        ));
    }
    Ok(measure)
}

/// The measure called `name`: `frame` (the platform's pose), `position`
/// (its tool point), `distance` (between the tool points of a pair) or
/// `leg` (a measuring leg's readings).
fn measure_of(name: &str) -> Result<PlatformMeasure, AppError> {
    PlatformMeasure::named(name).map_err(|_| {
        AppError::setting(
            "method",
            format!(
                "a parallel robot is measured by `frame` (the platform's pose), `position` \
                 (its tool point), `distance` (between two tool points) or `leg` (a measuring \
                 leg's readings), not `{name}`"
            ),
        )
    })
}

/// The actuator values' joint types of a data file: a Gough–Stewart
/// platform's six prismatic actuators (read in the file's length unit), a
/// Delta robot's three motors (in its angle unit).
fn actuator_types(robot: &ParallelRobot) -> Vec<gecaro_core::FrameType> {
    let kind = match robot.actuator_unit() {
        ParameterUnit::Angle => gecaro_core::FrameType::Revolute,
        _ => gecaro_core::FrameType::Prismatic,
    };
    vec![kind; robot.actuator_count()]
}
