//! The precision of a parallel robot's calibration before it is measured
//! (as [`crate::prediction`] predicts a serial robot's, eq. 11): the
//! configurations to be measured, the sensor's σ and the nominal robot
//! give the covariance of the identifiable parameters, `C = (W_bᵀW_b)⁻¹`
//! with every row divided by its σ, and from it the calibrated robot's
//! predicted error at the planned poses and over the whole workspace
//! ([`super::region`]).
//!
//! W is formed where the nominal robot puts the platform at each
//! configuration (its direct model), with what the sensor would read
//! there; a measured robot near the nominal one has nearly the same W.

use gecaro_core::JointRegion;
use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;
use nalgebra::Isometry3;

use super::auxiliary::Auxiliary;
use super::descent::base_system;
use super::identifiability::PlatformRankReport;
use super::identification::{PlatformIdentificationOptions, identify_platform, structural_rank};
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{actuator_values, normal_system};
use super::region::{PlatformRegion, region_poses, where_it_holds};
use super::simulation::{
    PlatformWorkspace, perturbed_platform, random_platform_poses, simulate_platform,
};
use crate::Error;
use crate::identification::WORK_POSES;
use crate::simulation::Sampler;

/// What measuring a set of configurations is predicted to give.
#[derive(Clone, Debug)]
pub struct PlatformPrediction {
    /// The identifiable parameters of these configurations.
    pub rank: PlatformRankReport,
    /// Every identifiable parameter's name and predicted σ (m, rad, or a
    /// gain's), in vocabulary order.
    pub parameters: Vec<(String, f64)>,
    /// The calibrated robot's predicted error at the configurations and
    /// over the workspace, and whether it holds there.
    pub region: PlatformRegion,
}

/// Predicts measuring `model` by `measure` at the actuator values of
/// `configurations` (consecutive pairs for a distance) with a sensor of
/// noise `noise`; the calibrated robot's error predicted over `work`, the
/// actuator ranges it will be used in (`None`: its whole workspace).
///
/// # Errors
/// A measure the structure cannot take, configurations with another number
/// of actuator values or no pose (naming their line), too few equations,
/// configurations that do not determine the identifiable parameters, a
/// stated region whose actuator values the direct model solves too few of.
pub fn predict_platform<M: ParallelModel>(
    model: &M,
    configurations: &[Sample],
    measure: PlatformMeasure,
    noise: PlatformNoise,
    work: Option<&JointRegion>,
) -> Result<PlatformPrediction, Error> {
    measure.check_for(model)?;
    if !(noise.length > 0.0 && noise.angle > 0.0) {
        return Err(Error::InvalidOption {
            setting: crate::Setting::Noise,
            message: "a prediction needs the sensor's σ, above zero".into(),
        });
    }
    let home = model.home();
    let poses: Vec<Isometry3<f64>> = configurations
        .iter()
        .map(|sample| {
            let actuators = actuator_values(model, sample)?;
            model
                .direct(actuators, &home)
                .map_err(|cause| Error::InvalidData {
                    line: sample.line,
                    message: cause.to_string(),
                })
        })
        .collect::<Result<_, _>>()?;
    let samples = readings(model, configurations, &poses, measure)?;
    let rank = structural_rank(model, &samples, &Auxiliary::none(), measure, Some(noise))?;
    let mut solved = poses.clone();
    let system = normal_system(
        model,
        &samples,
        measure,
        Some(noise),
        None,
        &Auxiliary::none(),
        &mut solved,
    )?;
    if system.rows < rank.base.len() {
        return Err(Error::TooFewEquations {
            equations: system.rows,
            unknowns: rank.base.len(),
        });
    }
    let (covariance, _) = base_system(&system, &rank.base)?;
    let names = model.parameter_names();
    let parameters = rank
        .base
        .iter()
        .enumerate()
        .map(|(k, column)| (names[*column].clone(), covariance[(k, k)].sqrt()))
        .collect();
    let coordinates: f64 = if measure == PlatformMeasure::Distance {
        1.0
    } else {
        3.0
    };
    let region = where_it_holds(
        model,
        measure,
        &samples,
        |index| poses.get(index).copied(),
        (&rank.base, &covariance),
        coordinates.sqrt() * noise.length,
        work,
    )
    .ok_or_else(|| Error::Numerical {
        message: if work.is_some() {
            "the predicted error could not be formed: a configuration is singular, or the \
             direct model solves too few actuator values of the stated work region (state \
             ranges the platform reaches together)"
                .into()
        } else {
            "the predicted error could not be formed: a configuration is singular".into()
        },
    })?;
    Ok(PlatformPrediction {
        rank,
        parameters,
        region,
    })
}

/// What the sensor would read of `model` at `poses` (noise-free), with the
/// configurations' actuator values and lines; a distance's pairs numbered.
fn readings<M: ParallelModel>(
    model: &M,
    configurations: &[Sample],
    poses: &[Isometry3<f64>],
    measure: PlatformMeasure,
) -> Result<Vec<Sample>, Error> {
    let read = |sample: &Sample, pose: &Isometry3<f64>| {
        let mut reading = measure.reading(model, pose, &sample.motor_positions);
        reading.line = sample.line;
        reading
    };
    if measure != PlatformMeasure::Distance {
        return Ok(configurations
            .iter()
            .zip(poses)
            .map(|(sample, pose)| read(sample, pose))
            .collect());
    }
    if !configurations.len().is_multiple_of(2) {
        return Err(Error::InvalidData {
            line: configurations.last().and_then(|sample| sample.line),
            message: format!(
                "a distance is measured between two configurations: the last of {} has no pair",
                configurations.len()
            ),
        });
    }
    let mut samples = Vec::with_capacity(configurations.len());
    for (index, (pair, at)) in configurations
        .chunks_exact(2)
        .zip(poses.chunks_exact(2))
        .enumerate()
    {
        let distance = (model.tool_point(&at[1]) - model.tool_point(&at[0])).norm();
        for (sample, pose) in pair.iter().zip(at) {
            let mut reading = read(sample, pose);
            reading.group = Some(index as u64 + 1);
            reading.distance = Some(distance);
            samples.push(reading);
        }
    }
    Ok(samples)
}

/// What simulated calibrations from the configurations measured: the
/// prediction's check by simulated truth ([`simulate_calibrations`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatedCalibrations {
    /// Calibrations simulated.
    pub runs: usize,
    /// RMS over the runs of each calibrated robot's tool-point error
    /// against its real one over the workspace, or the stated work region (m).
    pub work_rms: f64,
    /// The largest of those errors at one pose (m).
    pub work_max: f64,
}

/// `runs` calibrations of real robots drawn about `model` at `level`
/// ([`perturbed_platform`]) from measurements at the actuator values of
/// `configurations` with noise `noise` (seed `seed`), each calibrated robot
/// judged against its real one at [`WORK_POSES`] poses over the workspace,
/// or over `work` when it is stated (actuator values drawn uniformly in it) —
/// the tool point the calibrated robot predicts for the real robot's
/// actuator values there (for measured poses, which do not observe the tool
/// point, the calibrated tool's place on the real platform). What [`predict_platform`]'s `region.work_rms`
/// predicts, measured.
///
/// # Errors
/// Distances (their calibration has no base frame to judge in), and as
/// [`predict_platform`] and [`identify_platform`].
pub fn simulate_calibrations<M: ParallelModel>(
    model: &M,
    configurations: &[Sample],
    measure: PlatformMeasure,
    noise: PlatformNoise,
    (runs, level, seed): (usize, f64, u64),
    work: Option<&JointRegion>,
) -> Result<SimulatedCalibrations, Error> {
    if measure == PlatformMeasure::Distance {
        return Err(Error::InvalidOption {
            setting: crate::Setting::Method,
            message: "simulated calibrations from distances have no base frame to be judged \
                      in: predict them without simulations"
                .into(),
        });
    }
    let mut sampler = Sampler::new(seed);
    let (mut squares, mut count, mut largest) = (0.0, 0usize, 0.0f64);
    for _ in 0..runs {
        let real = perturbed_platform(model, level, &mut sampler)?;
        let home = real.home();
        let poses: Vec<Isometry3<f64>> = configurations
            .iter()
            .map(|sample| {
                let actuators = actuator_values(&real, sample)?;
                real.direct(actuators, &home)
                    .map_err(|cause| Error::InvalidData {
                        line: sample.line,
                        message: cause.to_string(),
                    })
            })
            .collect::<Result<_, _>>()?;
        let samples = simulate_platform(&real, measure, &poses, noise, &mut sampler)?;
        let result = identify_platform(
            model,
            &samples,
            measure,
            Some(noise),
            &PlatformIdentificationOptions::default(),
        )?;
        let poses = match work {
            None => random_platform_poses(
                &real,
                WORK_POSES,
                PlatformWorkspace::whole(&real),
                &mut sampler,
            )?,
            Some(region) => {
                region_poses(&real, region, &mut sampler).ok_or_else(|| Error::Numerical {
                    message: "the direct model of a simulated real robot solves too few actuator \
                              values of the stated work region (state ranges the platform \
                              reaches together)"
                        .into(),
                })?
            }
        };
        for pose in &poses {
            let actuators = real.actuator_values(pose)?;
            let calibrated = result
                .calibrated
                .direct(&actuators, &result.calibrated.home())?;
            // Poses measured observe the platform, not the tool point: both
            // judged at the calibrated tool's place on it.
            let truth = match measure {
                PlatformMeasure::Pose => result.calibrated.tool_point(pose),
                _ => real.tool_point(pose),
            };
            let error = (result.calibrated.tool_point(&calibrated) - truth).norm();
            squares += error * error;
            largest = largest.max(error);
            count += 1;
        }
    }
    Ok(SimulatedCalibrations {
        runs,
        work_rms: (squares / count.max(1) as f64).sqrt(),
        work_max: largest,
    })
}
