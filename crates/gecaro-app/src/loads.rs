//! The loads of an elastic robot's joints (issue 38, docs/elastic.md), for
//! every job: payloads as a request states them, the robot made elastic,
//! the rules an elastic job obeys (something must load the joints; the
//! method's sensor must see the sag), candidate configurations crossed with
//! the payloads a plan may choose, and every configuration's gravity
//! torques from the robot file's masses, and what compliances industrial
//! joints have.

use gecaro_calib::elastic::load_samples;
use gecaro_calib::methods::CalibrationMethod;
use gecaro_calib::study::{SampleSlice, Samples};
use gecaro_core::{LinkMass, Robot};
use gecaro_io::RobotFile;

use crate::error::AppError;

/// The compliance range of industrial arms' joints at level 1 (rad/(N·m)).
pub(crate) const COMPLIANCE_RANGE: (f64, f64) = (2e-6, 1e-5);

/// A typical industrial joint's compliance (rad/(N·m)): the middle of
/// [`COMPLIANCE_RANGE`].
pub(crate) const TYPICAL_COMPLIANCE: f64 = (COMPLIANCE_RANGE.0 + COMPLIANCE_RANGE.1) / 2.0;

/// The payload of `text` (`"20kg"`, `"20kg,0,0,100mm"`) carried by
/// `file`'s robot, naming `setting`.
///
/// # Errors
/// A text that is not a payload ([`gecaro_io::parse_payload`]), or one
/// the robot cannot carry ([`require_carried`]).
pub(crate) fn payload(file: &RobotFile, text: &str, setting: &str) -> Result<LinkMass, AppError> {
    let payload =
        gecaro_io::parse_payload(text).map_err(|message| AppError::setting(setting, message))?;
    require_carried(file, &payload, setting)?;
    Ok(payload)
}

/// The payloads of `texts` carried by `file`'s robot, naming `setting`.
///
/// # Errors
/// As [`payload`].
pub(crate) fn payloads(
    file: &RobotFile,
    texts: &[String],
    setting: &str,
) -> Result<Vec<LinkMass>, AppError> {
    texts
        .iter()
        .map(|text| payload(file, text, setting))
        .collect()
}

/// Refuses a payload heavier than the robot that would carry it: when
/// `file` states its links' masses, no serial arm carries more than its
/// moving links weigh (a cobot about a third, an industrial arm a tenth
/// to a quarter), so a payload beyond them is a unit or a digit wrong
/// (`1200kg` for `12kg`).
///
/// # Errors
/// That case, with both masses, naming `setting`.
pub(crate) fn require_carried(
    file: &RobotFile,
    payload: &LinkMass,
    setting: &str,
) -> Result<(), AppError> {
    let robot_mass = file.masses.moving_mass();
    if robot_mass > 0.0 && payload.mass > robot_mass {
        return Err(AppError::setting(
            setting,
            format!(
                "a payload of {} kg on {}, whose moving links weigh {robot_mass:.1} kg: no \
                 serial arm carries more than itself; check the mass and its unit",
                payload.mass,
                file.robot.name()
            ),
        ));
    }
    Ok(())
}

/// Makes `robot` elastic, every compliance 0, unless it is already.
///
/// # Errors
/// Never for a valid robot (the compliances are n finite values).
pub(crate) fn make_elastic(robot: &mut Robot, setting: &str) -> Result<(), AppError> {
    if !robot.is_elastic() {
        let zeros = vec![0.0; robot.joint_count()];
        robot
            .set_compliances(Some(zeros))
            .map_err(|error| AppError::setting(setting, error.to_string()))?;
    }
    Ok(())
}

/// Refuses an elastic job whose joints nothing loads: `file` states no
/// masses, and there is no payload.
///
/// # Errors
/// That case, naming `setting`.
pub(crate) fn require_loads(
    file: &RobotFile,
    payloads: bool,
    setting: &str,
) -> Result<(), AppError> {
    if file.masses.is_empty() && !payloads {
        return Err(AppError::setting(
            setting,
            format!(
                "an elastic model needs loads on the joints: {} states no masses (mass, com per \
                 frame of the robot file; robot import reads them from URDF) and there is no \
                 payload",
                file.robot.name()
            ),
        ));
    }
    Ok(())
}

/// Refuses to simulate or plan loads for a method whose sensor measures
/// the robot rigid ([`gecaro_calib::methods::Sensor::yields_to_loads`]).
///
/// # Errors
/// That case, naming `setting`.
pub(crate) fn require_loading_sensor(
    method: &dyn CalibrationMethod,
    setting: &str,
) -> Result<(), AppError> {
    if method.sensor().yields_to_loads() {
        return Ok(());
    }
    Err(AppError::setting(
        setting,
        format!(
            "the {} method's simulated sensor measures the robot rigid: loads are simulated \
             and planned for the measure methods (position, frame)",
            method.name()
        ),
    ))
}

/// `file` with its robot made elastic (every compliance 0 unless it states
/// them), for a job whose loads are `payloads` and the file's masses.
///
/// # Errors
/// A robot whose joints nothing would load: no masses, and no payload.
pub(crate) fn elastic_file(
    file: &RobotFile,
    payloads: bool,
    setting: &str,
) -> Result<RobotFile, AppError> {
    require_loads(file, payloads, setting)?;
    let mut file = file.clone();
    make_elastic(&mut file.robot, setting)?;
    Ok(file)
}

/// Every configuration of `samples` once with each payload (configuration
/// by configuration), each with its gravity torques on `file`'s robot.
///
/// # Errors
/// A configuration that does not fit the robot.
pub(crate) fn loaded(
    file: &RobotFile,
    samples: SampleSlice<'_>,
    payloads: &[LinkMass],
) -> Result<Samples, AppError> {
    let mut crossed: Samples = if payloads.is_empty() {
        samples.to_samples()
    } else {
        samples
            .iter()
            .flat_map(|sample| {
                payloads.iter().map(move |payload| {
                    let mut loaded = sample.to_sample();
                    loaded.set_payload(Some(*payload));
                    loaded
                })
            })
            .collect()
    };
    load_samples(&file.robot, &file.masses, &mut crossed)?;
    Ok(crossed)
}
