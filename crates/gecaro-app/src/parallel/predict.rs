//! The precision of a parallel robot's calibration before measuring: the
//! configurations to be measured (a plan's actuator values) and the
//! sensor's σ give every identifiable parameter's σ and the calibrated
//! robot's predicted error at them and over the workspace
//! (`gecaro_calib::parallel_robots::predict_platform`).

use gecaro_calib::parallel_robots::{PlatformNoise, predict_platform, simulate_calibrations};
use gecaro_calib::simulation::{DEFAULT_ERROR_LEVEL, DEFAULT_SEED};
use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_io::StandardDeviation;
use serde::{Deserialize, Serialize};

use super::documents::PlatformRegionDocument;
use super::region::stated_work_region;
use super::{actuator_types, load_parallel_robot, measure_without_leg};
use crate::error::AppError;
use crate::files::Files;
use crate::sources::{DataFormatSpec, DataSource};

/// Simulated calibrations a prediction runs at most.
pub const MAX_SIMULATED_CALIBRATIONS: usize = 100;

/// A prediction for a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelPredictRequest {
    /// The nominal platform (a file, or a ready parallel robot's name).
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: String,
    /// The configurations to be measured (their actuator values; a plan's
    /// file), consecutive rows a pair for distances.
    pub data: DataSource,
    /// Units and columns of the configurations file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The sensor's σ of a position coordinate (of a distance): a number in
    /// the data's length unit, or a text with its unit (`"20um"`); also the
    /// orientations' unless `sigma_rotation` is given.
    pub sigma: StandardDeviation,
    /// The σ of a rotation angle: a number in the data's angle unit, or a
    /// text with its unit (`"0.001deg"`).
    pub sigma_rotation: Option<StandardDeviation>,
    /// Also simulate this many calibrations (real robots drawn at
    /// `error_level`), each judged against its real robot over the
    /// workspace: the prediction checked by simulated truth.
    #[serde(default)]
    pub monte_carlo: Option<usize>,
    /// The simulated real robots' errors: ±L mm on every joint centre and
    /// length, ±L mrad on angles, ±L·10⁻³ on gains (default 1).
    #[serde(default)]
    pub error_level: Option<f64>,
    /// Seed of the simulations (default [`DEFAULT_SEED`]).
    #[serde(default)]
    pub seed: Option<u64>,
    /// The region the calibrated robot will be used in, over which its
    /// error is predicted (and the simulated calibrations judged): actuator
    /// ranges with their units, `"qm1=-12..12mm,qm4=0..20mm"` (actuators not
    /// named: their ranges). `None`: the whole workspace.
    #[serde(default)]
    pub work_region: Option<String>,
}

/// Simulated calibrations' measured error.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SimulatedCalibrationsDocument {
    /// Calibrations simulated.
    pub runs: usize,
    /// RMS of the calibrated robots' tool-point errors over the workspace
    /// against their real ones (m).
    pub work_rms: f64,
    /// The largest at one pose (m).
    pub work_max: f64,
}

/// One identifiable parameter's predicted precision.
#[derive(Clone, Debug, Serialize)]
pub struct PredictedParameterDocument {
    /// `a1x`, `l3`, `K6`, `tz`.
    pub name: String,
    /// `m`, `rad`, or `""` for a gain.
    pub unit: &'static str,
    /// Its predicted σ.
    pub sigma: f64,
}

/// A prediction, as `gecaro predict … --json` prints it (m, rad).
#[derive(Clone, Debug, Serialize)]
pub struct ParallelPredicted {
    /// The robot's name.
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: &'static str,
    /// The configurations' label.
    pub data: String,
    /// Configurations to be measured.
    pub configurations: usize,
    /// Identifiable parameters.
    pub rank: usize,
    /// Every identifiable parameter with its predicted σ.
    pub parameters: Vec<PredictedParameterDocument>,
    /// The calibrated robot's predicted error at the configurations and
    /// over the workspace, and whether it will hold there.
    pub region: PlatformRegionDocument,
    /// The simulated calibrations, when asked for.
    pub monte_carlo: Option<SimulatedCalibrationsDocument>,
}

impl ParallelPredictRequest {
    /// Runs the prediction.
    ///
    /// # Errors
    /// A robot or configurations file that cannot be read, a σ that is no
    /// sensor's, configurations with no pose (naming their line), too few
    /// equations for the identifiable parameters.
    pub fn run(&self, files: &dyn Files) -> Result<ParallelPredicted, AppError> {
        let file = load_parallel_robot(&self.robot, files)?;
        let measure = measure_without_leg(&self.method, &file.robot, "predict")?;
        let format = self.format.format()?;
        let read = self
            .data
            .read(files, &actuator_types(&file.robot), &[], &format)?;
        let length = self
            .sigma
            .value(false, format.units)
            .map_err(|message| AppError::setting("sigma", message))?;
        let angle = self
            .sigma_rotation
            .as_ref()
            .map(|sigma| sigma.value(true, format.units))
            .transpose()
            .map_err(|message| AppError::setting("sigma_rotation", message))?;
        let noise = PlatformNoise {
            length,
            angle: angle.unwrap_or(length),
        };
        let configurations = read.samples.to_rows();
        let work = self
            .work_region
            .as_deref()
            .map(|text| stated_work_region(&file.robot, text))
            .transpose()?;
        let prediction =
            predict_platform(&file.robot, &configurations, measure, noise, work.as_ref())?;
        let monte_carlo = match self.monte_carlo {
            Some(runs) => {
                if !(1..=MAX_SIMULATED_CALIBRATIONS).contains(&runs) {
                    return Err(AppError::setting_value(
                        "monte_carlo",
                        runs,
                        format!("takes 1 to {MAX_SIMULATED_CALIBRATIONS} calibrations"),
                    ));
                }
                let simulated = simulate_calibrations(
                    &file.robot,
                    &configurations,
                    measure,
                    noise,
                    (
                        runs,
                        self.error_level.unwrap_or(DEFAULT_ERROR_LEVEL),
                        self.seed.unwrap_or(DEFAULT_SEED),
                    ),
                    work.as_ref(),
                )?;
                Some(SimulatedCalibrationsDocument {
                    runs: simulated.runs,
                    work_rms: simulated.work_rms,
                    work_max: simulated.work_max,
                })
            }
            None => None,
        };
        let names = file.robot.parameter_names();
        Ok(ParallelPredicted {
            robot: file.robot.name().to_owned(),
            method: measure.name(),
            data: read.label,
            configurations: configurations.len(),
            rank: prediction.rank.rank(),
            parameters: prediction
                .parameters
                .iter()
                .map(|(name, sigma)| PredictedParameterDocument {
                    unit: names
                        .iter()
                        .position(|own| own == name)
                        .map_or("", |index| match file.robot.parameter_unit(index) {
                            ParameterUnit::Length => "m",
                            ParameterUnit::Angle => "rad",
                            ParameterUnit::Gain => "",
                        }),
                    name: name.clone(),
                    sigma: *sigma,
                })
                .collect(),
            region: (&prediction.region).into(),
            monte_carlo,
        })
    }
}
