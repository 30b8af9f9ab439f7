//! A prediction's document: errors at test poses, each parameter's
//! predicted σ, simulated calibrations.

use gecaro_calib::prediction::{MonteCarlo, PoseErrors, Prediction};
use serde::Serialize;

/// Errors at test poses (m, rad).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PoseErrorsJson {
    /// RMS position error.
    pub position_rms: f64,
    /// Largest position error.
    pub position_max: f64,
    /// RMS orientation error, for methods that measure orientation.
    pub rotation_rms: Option<f64>,
    /// Largest orientation error.
    pub rotation_max: Option<f64>,
}

impl From<PoseErrors> for PoseErrorsJson {
    fn from(errors: PoseErrors) -> Self {
        PoseErrorsJson {
            position_rms: errors.position_rms,
            position_max: errors.position_max,
            rotation_rms: errors.rotation_rms,
            rotation_max: errors.rotation_max,
        }
    }
}

/// A parameter's predicted σ.
#[derive(Clone, Debug, Serialize)]
pub struct SigmaJson {
    /// Its name.
    pub name: String,
    /// Its predicted standard deviation.
    pub sigma: f64,
}

impl SigmaJson {
    /// Every (name, σ) of a prediction.
    pub fn list(parameters: &[(String, f64)]) -> Vec<SigmaJson> {
        parameters
            .iter()
            .map(|(name, sigma)| SigmaJson {
                name: name.clone(),
                sigma: *sigma,
            })
            .collect()
    }
}

/// Simulated calibrations.
#[derive(Clone, Debug, Serialize)]
pub struct MonteCarloJson {
    /// Calibrations run.
    pub runs: usize,
    /// Those that did not converge.
    pub not_converged: usize,
    /// The real robots' error level.
    pub error_level: f64,
    /// The errors measured at the test poses.
    pub measured: PoseErrorsJson,
    /// Measured / predicted RMS position error.
    pub position_ratio: f64,
}

/// A prediction (`gecaro predict --json`).
#[derive(Clone, Debug, Serialize)]
pub struct PredictJson {
    /// The method's name.
    pub method: &'static str,
    /// Configurations of the plan.
    pub configurations: usize,
    /// The sensor's σ.
    pub noise: f64,
    /// Test poses.
    pub test_poses: usize,
    /// Every base parameter's predicted σ.
    pub parameters: Vec<SigmaJson>,
    /// The predicted errors at the test poses.
    pub predicted: PoseErrorsJson,
    /// The simulated calibrations, if run.
    pub monte_carlo: Option<MonteCarloJson>,
}

impl PredictJson {
    /// The document of a prediction for `method` from `configurations`
    /// with σ `noise` at `test_poses` poses, and of the simulated
    /// calibrations at their error level, if run.
    pub fn new(
        method: &'static str,
        configurations: usize,
        noise: f64,
        test_poses: usize,
        prediction: &Prediction,
        measured: Option<(&MonteCarlo, f64)>,
    ) -> Self {
        let predicted = prediction.errors;
        PredictJson {
            method,
            configurations,
            noise,
            test_poses,
            parameters: SigmaJson::list(&prediction.parameters),
            predicted: predicted.into(),
            monte_carlo: measured.map(|(measured, error_level)| MonteCarloJson {
                runs: measured.runs,
                not_converged: measured.not_converged,
                error_level,
                measured: measured.errors.into(),
                position_ratio: measured.errors.position_rms / predicted.position_rms,
            }),
        }
    }
}
