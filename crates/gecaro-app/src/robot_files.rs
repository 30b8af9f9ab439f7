//! The robot files a job writes: the calibrated robot of an identification
//! and the simulated real robot of a points generation, each described by how
//! it was obtained, in the nominal file's angle unit and with its URDF names.

use gecaro_calib::identification::Identification;
use gecaro_calib::study::Study;
use gecaro_core::Robot;
use gecaro_io::RobotFile;

/// The calibrated robot as a robot file: the identified robot, named
/// "<name> (calibrated)", with a description of how it was obtained from the
/// data labelled `data`.
pub fn calibrated_robot_file(
    nominal: &RobotFile,
    study: &Study,
    result: &Identification,
    data: &str,
) -> RobotFile {
    let mut robot = result.calibrated.clone();
    robot.set_name(format!("{} (calibrated)", nominal.robot.name()));
    // A file states its angles within a turn (and is read back).
    robot.wrap_angles();
    RobotFile {
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
        // The masses are the nominal's: a geometric calibration does not
        // weigh the links.
        masses: nominal.masses.clone(),
    }
}

/// The simulated real robot of a points generation as a robot file: `real`,
/// described as drawn from `nominal` at `error_level` with `seed`.
pub fn simulated_robot_file(
    nominal: &RobotFile,
    real: Robot,
    error_level: f64,
    seed: u64,
) -> RobotFile {
    RobotFile {
        description: Some(format!(
            "simulated real robot: {} at error level {error_level}, seed {seed}",
            nominal.robot.name()
        )),
        robot: real,
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
        masses: nominal.masses.clone(),
    }
}
