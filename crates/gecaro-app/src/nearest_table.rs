//! The nearest robot a table can carry (issue 74): DH, modified-DH and
//! SYMORO tables have no Hayati β between two joints, which a calibration
//! gives nearly parallel axes (an industrial arm's joints 2 and 3); a
//! table's base and tool transforms carry the β of frames 1 and n+1. Such a robot is
//! written as the robot without β that moves its tool most like it, with
//! the largest error that costs stated — or refused beyond
//! [`MAX_TABLE_ERROR`], where the table would mislead its user.
//!
//! The nearest robot is identified as a calibration would (the frame
//! method, Gauss–Newton on the analytic Jacobian, `gecaro_calib`), from
//! the robot's own exact tool poses at [`FIT_POSES`] configurations drawn
//! within its joint limits, starting from the robot with every β set to 0,
//! where it stays: β is not identified (priority 0). Its error is measured
//! on [`CHECK_POSES`] other configurations: the largest distance between
//! the two tools' origins, and the largest angle between their frames.

use gecaro_calib::prelude::{
    IdentificationOptions, MethodOptions, Quiet, Sampler, Study, identify, method,
    simulate_measurements,
};
use gecaro_core::{ParameterId, ParameterKind, Robot, terminal_pose};

use crate::error::{AppError, ErrorKind};

/// Configurations the nearest robot is fitted to.
pub const FIT_POSES: usize = 400;

/// Configurations its error is measured on (others than the fit's).
pub const CHECK_POSES: usize = 2_000;

/// The largest tool error (m) a table may carry: 0.1 mm, the order of a
/// calibrated industrial arm's accuracy — a larger one undoes the
/// calibration it was meant to export.
pub const MAX_TABLE_ERROR: f64 = 1e-4;

/// The seed of the configurations: an export is a pure function of its robot.
const SEED: u64 = 0x7AB1E;

/// A robot without β, and what it costs against the robot with β.
#[derive(Clone, Debug)]
pub struct NearestTable {
    /// The robot without β.
    pub robot: Robot,
    /// The largest distance between the two tools' origins (m).
    pub position_error: f64,
    /// The largest angle between the two tools' frames (rad).
    pub orientation_error: f64,
}

impl NearestTable {
    /// The note an export carries.
    pub fn note(&self) -> String {
        format!(
            "Hayati's β has no place in a table: written is the nearest robot without it (fitted \
             to the robot's own tool poses), off by up to {:.4} mm and {:.4} mrad at the tool over \
             {CHECK_POSES} configurations within the joint limits",
            self.position_error * 1e3,
            self.orientation_error * 1e3
        )
    }
}

/// The nearest robot to `robot` without β (see the module docs).
///
/// # Errors
/// A fit that fails, or an error beyond [`MAX_TABLE_ERROR`] (named, with
/// the formats that carry β).
pub(crate) fn nearest_without_beta(robot: &Robot, format: &str) -> Result<NearestTable, AppError> {
    // β before joint 1 and after joint n is a table's base and tool.
    let between = 2..=robot.joint_count();
    let mut spec = robot.to_spec();
    for (j, frame) in spec.frames.iter_mut().enumerate() {
        if between.contains(&j) {
            frame.beta = 0.0;
        }
    }
    let start = Robot::new(spec)?;
    let frame = method("frame", &MethodOptions::default())?;
    let mut sampler = Sampler::new(SEED);
    let samples = simulate_measurements(
        robot,
        frame.as_ref(),
        FIT_POSES,
        0.0,
        &mut sampler,
        &mut Quiet,
    )?;
    // β between the joints is not identified (priority 0): held at 0
    // exactly, whatever the fit's residuals.
    let mut priority = start.priority();
    for j in between.clone() {
        priority.set(ParameterId::new(ParameterKind::Beta, j), 0);
    }
    let options = IdentificationOptions {
        priority: Some(priority),
        ..IdentificationOptions::default()
    };
    let study = Study::single(frame, samples, "the robot's own poses");
    let spec = identify(&start, &study, &options, &mut Quiet)?
        .calibrated
        .to_spec();
    let fitted = Robot::new(spec)?;
    let (mut position_error, mut orientation_error) = (0.0f64, 0.0f64);
    for _ in 0..CHECK_POSES {
        let qm = sampler.configuration(robot);
        let (a, b) = (terminal_pose(robot, &qm)?, terminal_pose(&fitted, &qm)?);
        position_error = position_error.max((a.translation.vector - b.translation.vector).norm());
        orientation_error = orientation_error.max((a.rotation.inverse() * b.rotation).angle());
    }
    let nearest = NearestTable {
        robot: fitted,
        position_error,
        orientation_error,
    };
    if position_error > MAX_TABLE_ERROR {
        return Err(AppError::plain(
            ErrorKind::Usage,
            format!(
                "{} has Hayati's β (nearly parallel axes), which {format} cannot carry: the \
                 nearest robot without it is off by up to {:.4} mm at the tool (beyond {} mm); \
                 export to urdf, or keep gecaro's TOML",
                robot.name(),
                position_error * 1e3,
                MAX_TABLE_ERROR * 1e3
            ),
        ));
    }
    Ok(nearest)
}
