//! The "Identifiable parameters" and "Points generation" functions of a
//! method menu.

use axum::extract::State;
use gecaro_calib::{
    identifiability::identifiability,
    simulation::{Sampler, perturbed_robot, simulate_measurements, terminal_displacement},
    study::Study,
};
use gecaro_io::{RobotDocument, RobotFile, format_samples};
use gecaro_report::json::IdentifiableJson;
use serde::{Deserialize, Serialize};

use super::{DataRequest, Json, MethodRequest, data_file_name, robot_file, save_csv};
use crate::error::ApiError;
use crate::limits::{MAX_GENERATE, MAX_RANDOM};
use crate::state::AppState;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct IdentifiableRequest {
    robot: RobotDocument,
    method: MethodRequest,
    /// Measured data to check (structural analysis on data like them, and
    /// the excitation check); random configurations when absent.
    #[serde(default)]
    data: Option<DataRequest>,
    /// Random configurations (default: about 2.5 equations per unknown).
    #[serde(default)]
    count: Option<usize>,
    #[serde(default = "default_seed")]
    seed: u64,
}

fn default_seed() -> u64 {
    1
}

/// Identifiable parameters of a method (Appendix III).
pub(crate) async fn identifiable(
    State(state): State<AppState>,
    Json(request): Json<IdentifiableRequest>,
) -> Result<Json<IdentifiableJson>, ApiError> {
    let file = robot_file(&request.robot)?;
    let method = request.method.build()?;
    if let Some(count) = request.count
        && !(1..=MAX_RANDOM).contains(&count)
    {
        return Err(ApiError::BadRequest(format!(
            "count {count}: between 1 and {MAX_RANDOM} random configurations"
        )));
    }
    state
        .compute(move |state| {
            let study = match &request.data {
                Some(data) => {
                    let (samples, label) = data.samples(state, &file, method.as_ref())?;
                    Study::single(method, samples, label)
                }
                None => Study::single(method, Vec::new(), "random configurations"),
            };
            let robot = &file.robot;
            let analysis = identifiability(
                robot,
                &study,
                &robot.priority(),
                request.count,
                request.seed,
            )?;
            Ok(Json(IdentifiableJson::new(robot, &analysis)))
        })
        .await
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GenerateRequest {
    robot: RobotDocument,
    method: MethodRequest,
    /// Configurations to generate.
    count: usize,
    /// Errors of the simulated real robot (±L cm, ±L°, ±L %); default 1.
    #[serde(default)]
    error_level: Option<f64>,
    /// The real robot, instead of one with random errors.
    #[serde(default)]
    real: Option<RobotDocument>,
    /// Sensor noise, standard deviation (metres; radians for orientations).
    #[serde(default)]
    noise: f64,
    #[serde(default = "default_seed")]
    seed: u64,
    /// Also save the CSV to this file of the folder.
    #[serde(default)]
    save_as: Option<String>,
    #[serde(default)]
    overwrite: bool,
}

#[derive(Serialize)]
pub(crate) struct Generated {
    /// The data file's text.
    csv: String,
    configurations: usize,
    /// A file name to download it as.
    file_name: String,
    /// The file of the folder it was saved to.
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    /// The simulated real robot (to compare with what identification finds).
    real: RobotDocument,
    /// RMS and largest distance between the nominal and real terminal points (m).
    displacement_rms: f64,
    displacement_max: f64,
}

/// Points generation: measurements of a simulated real robot.
pub(crate) async fn generate(
    State(state): State<AppState>,
    Json(request): Json<GenerateRequest>,
) -> Result<Json<Generated>, ApiError> {
    let nominal = robot_file(&request.robot)?;
    let method = request.method.build()?;
    if !(1..=MAX_GENERATE).contains(&request.count) {
        return Err(ApiError::BadRequest(format!(
            "count {}: between 1 and {MAX_GENERATE} configurations per request",
            request.count
        )));
    }
    let given_real = request.real.as_ref().map(robot_file).transpose()?;
    if let Some(real) = &given_real
        && real.robot.joint_letters() != nominal.robot.joint_letters()
    {
        return Err(ApiError::Unprocessable(format!(
            "the real robot has joints {}, the nominal one {}",
            real.robot.joint_letters(),
            nominal.robot.joint_letters()
        )));
    }
    state
        .compute(move |state| {
            let robot = &nominal.robot;
            let mut sampler = Sampler::new(request.seed);
            let level = request.error_level.unwrap_or(1.0);
            let (real, description) = match given_real {
                Some(real) => (real.robot, "the given real robot".to_owned()),
                None => (
                    perturbed_robot(robot, level, &mut sampler)?,
                    format!(
                        "simulated real robot: {} at error level {level}, seed {}",
                        robot.name(),
                        request.seed
                    ),
                ),
            };
            let samples = simulate_measurements(
                &real,
                method.as_ref(),
                request.count,
                request.noise,
                &mut sampler,
            )?;
            let (displacement_rms, displacement_max) =
                terminal_displacement(robot, &real, &samples)?;
            let csv = format_samples(robot.joint_count(), method.data_columns(), &samples);
            let saved = save_csv(state, request.save_as.as_deref(), &csv, request.overwrite)?;
            let real_file = RobotFile {
                robot: real,
                description: Some(description),
                angle_unit: nominal.angle_unit,
                urdf: nominal.urdf.clone(),
            };
            Ok(Json(Generated {
                configurations: samples.len(),
                file_name: data_file_name(robot, &request.method.name, samples.len()),
                csv,
                saved,
                real: RobotDocument::from_robot_file(&real_file),
                displacement_rms,
                displacement_max,
            }))
        })
        .await
}
