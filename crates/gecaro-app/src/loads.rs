//! The loads of an elastic robot's joints for the jobs that plan and
//! predict (issue 38, docs/elastic.md): the robot made elastic, candidate
//! configurations crossed with the payloads a plan may choose, and every
//! configuration's gravity torques from the robot file's masses.

use gecaro_calib::elastic::load_samples;
use gecaro_calib::study::Sample;
use gecaro_core::{LinkMass, PriorityMatrix};
use gecaro_io::RobotFile;

use crate::error::AppError;

/// The payloads of `texts` (`"0kg"`, `"20kg,0,0,100mm"`), naming `setting`.
///
/// # Errors
/// A text that is not a payload.
pub(crate) fn payloads(texts: &[String], setting: &str) -> Result<Vec<LinkMass>, AppError> {
    texts
        .iter()
        .map(|text| {
            gecaro_io::parse_payload(text).map_err(|message| AppError::setting(setting, message))
        })
        .collect()
}

/// `file`'s robot made elastic (every compliance 0 unless it states them)
/// and the priority matrix that identifies the compliances after the
/// geometry, as `--model elastic` does.
///
/// # Errors
/// A robot whose joints nothing would load: no masses, and no payload.
pub(crate) fn elastic(
    file: &RobotFile,
    payloads: bool,
    setting: &str,
) -> Result<(RobotFile, PriorityMatrix), AppError> {
    if file.masses.is_empty() && !payloads {
        return Err(AppError::setting(
            setting,
            format!(
                "an elastic model needs loads on the joints: {} states no masses (mass, com per \
                 frame of the robot file) and no payload is given",
                file.robot.name()
            ),
        ));
    }
    let mut file = file.clone();
    if !file.robot.is_elastic() {
        let zeros = vec![0.0; file.robot.joint_count()];
        file.robot
            .set_compliances(Some(zeros))
            .map_err(|error| AppError::setting(setting, error.to_string()))?;
    }
    let priority = file.robot.priority().with_compliances(1);
    Ok((file, priority))
}

/// Every configuration of `samples` once with each payload (configuration
/// by configuration), each with its gravity torques on `file`'s robot.
///
/// # Errors
/// A configuration that does not fit the robot.
pub(crate) fn loaded(
    file: &RobotFile,
    samples: &[Sample],
    payloads: &[LinkMass],
) -> Result<Vec<Sample>, AppError> {
    let mut crossed: Vec<Sample> = if payloads.is_empty() {
        samples.to_vec()
    } else {
        samples
            .iter()
            .flat_map(|sample| {
                payloads.iter().map(move |payload| Sample {
                    payload: Some(*payload),
                    ..sample.clone()
                })
            })
            .collect()
    };
    load_samples(&file.robot, &file.masses, &mut crossed)?;
    Ok(crossed)
}
