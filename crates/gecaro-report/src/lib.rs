//! # gecaro-report
//!
//! The pictures of a calibration and a self-contained HTML report: plots as
//! SVG made with plotters ([`convergence_svg`], [`error_histograms_svg`],
//! [`errors_per_configuration_svg`], [`robot_projections_svg`]),
//! [`html_report`], one HTML file with the plots inline, readable without a
//! network, and the JSON documents of the results ([`json`]) that the command
//! line prints and the web API answers.

#![warn(missing_docs)]

mod html;
pub mod json;
mod plots;

pub use html::{ReportInput, html_report};
pub use plots::{
    accuracy_curve_svg, convergence_svg, error_histograms_svg, errors_per_configuration_svg,
    robot_projections_svg,
};

/// Errors of report making.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Drawing a plot failed.
    #[error("cannot draw a plot: {0}")]
    Plot(String),
    /// The robot or configuration does not fit.
    #[error("{0}")]
    Model(String),
}

/// The calibrated robot as a robot file: the identified robot, named
/// "<name> (calibrated)", with a description of how it was obtained from the
/// data labelled `data`, in the nominal file's angle unit.
pub fn calibrated_robot_file(
    nominal: &gecaro_io::RobotFile,
    study: &gecaro_calib::study::Study,
    result: &gecaro_calib::identification::Identification,
    data: &str,
) -> gecaro_io::RobotFile {
    let mut robot = result.calibrated.clone();
    robot.set_name(format!("{} (calibrated)", nominal.robot.name()));
    gecaro_io::RobotFile {
        robot,
        description: Some(format!(
            "{} calibrated by gecaro: {} method on {data}, {} parameters identified, residual RMS {:.3e} → {:.3e}",
            nominal.robot.name(),
            study.method_names(),
            result.parameters.len(),
            result.rms_before(),
            result.rms_after()
        )),
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
    }
}

/// The simulated real robot of a points generation as a robot file: `real`,
/// described as drawn from `nominal` at `error_level` with `seed`, in the
/// nominal file's angle unit.
pub fn simulated_robot_file(
    nominal: &gecaro_io::RobotFile,
    real: gecaro_core::Robot,
    error_level: f64,
    seed: u64,
) -> gecaro_io::RobotFile {
    gecaro_io::RobotFile {
        description: Some(format!(
            "simulated real robot: {} at error level {error_level}, seed {seed}",
            nominal.robot.name()
        )),
        robot: real,
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
    }
}
