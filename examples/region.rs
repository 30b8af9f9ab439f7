//! Where a calibration holds, judged against the simulated real robot: 120
//! position measurements (σ 20 µm, stated) within ±H° of the middle of every
//! joint's limits, the reflector 60 mm off the last axis; the calibrated
//! robot held out within the measured region and over the joint limits
//! (300 configurations each, the RMS of 6 fresh draws of the noise) beside
//! what the verdict predicted there, and the verdict.
//!
//! ```sh
//! cargo run --release --example region                 # docs/methods.md, "Where the result holds"
//! cargo run --release --example region -- ur10e 5,15,30 1
//! ```
//!
//! Arguments (all optional, in order): robots, half-widths (degrees), seeds.

mod common;

use common::Failure;
use gecaro_calib::prelude::*;
use gecaro_core::{ParameterId, Robot, terminal_pose};

/// The trial's tracker: σ = 20 µm a coordinate.
const SIGMA: f64 = 2e-5;

/// Draws of the noise per case.
const DRAWS: usize = 6;

fn main() -> Result<(), Failure> {
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    let list = |index: usize, default: &str| -> Vec<String> {
        arguments
            .get(index)
            .map_or(default, String::as_str)
            .split(',')
            .map(str::to_owned)
            .collect()
    };
    let robots = list(0, "industrial6,ur10e");
    let halves: Vec<f64> = list(1, "5,15,30,60,180")
        .iter()
        .map(|h| h.parse())
        .collect::<Result<_, _>>()?;
    let seeds: Vec<u64> = list(2, "1,2")
        .iter()
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    println!(
        "robot        ±H°  seed  held out (mm): region  limits   predicted (mm): region  limits   \
         floor (mm)  verdict"
    );
    for name in &robots {
        let mut nominal = gecaro_io::load_robot(name)?.robot;
        let tool: ParameterId = format!("d{}", nominal.joint_count() + 1).parse()?;
        nominal.set_parameter(tool, 0.06)?;
        for half in &halves {
            for seed in &seeds {
                let mut sampler = Sampler::new(*seed);
                let real = perturbed_robot(&nominal, 1.0, &mut sampler)?;
                let region = configurations(&nominal, Some(half.to_radians()), 120, &mut sampler)?;
                let inside = configurations(&nominal, Some(half.to_radians()), 300, &mut sampler)?;
                let whole = configurations(&nominal, None, 300, &mut sampler)?;
                let mut sums = [0.0; 4];
                let mut floor = 0.0;
                let mut outcomes = Vec::new();
                for _ in 0..DRAWS {
                    let result = calibrate(&nominal, &real, &region, &mut sampler)?;
                    let prediction = result
                        .verdict
                        .region
                        .clone()
                        .ok_or("no prediction of where the result holds")?;
                    sums[0] += held_out(&result.calibrated, &real, &inside)?.powi(2);
                    sums[1] += held_out(&result.calibrated, &real, &whole)?.powi(2);
                    sums[2] += prediction.inside.powi(2);
                    sums[3] += prediction.work_rms.powi(2);
                    floor += prediction.floor / DRAWS as f64;
                    outcomes.push(result.verdict.outcome.as_str());
                }
                outcomes.dedup();
                let [region_mm, limits_mm, predicted_region, predicted_limits] =
                    sums.map(|sum| 1e3 * (sum / DRAWS as f64).sqrt());
                println!(
                    "{name:<12} {half:>4}  {seed:>4}  {region_mm:>20.4}  {limits_mm:>6.4}  \
                     {predicted_region:>22.4}  {predicted_limits:>6.4}   {:>9.4}  {}",
                    1e3 * floor,
                    outcomes.join("/")
                );
            }
        }
    }
    Ok(())
}

/// Motor values of `count` configurations within `half` (rad) of the middle
/// of every joint's limits (over the whole limits for `None`).
fn configurations(
    robot: &Robot,
    half: Option<f64>,
    count: usize,
    sampler: &mut Sampler,
) -> Result<Vec<Vec<f64>>, Failure> {
    (0..count)
        .map(|_| {
            let joints: Vec<f64> = robot
                .joints()
                .iter()
                .map(|joint| {
                    let middle = 0.5 * (joint.qmin + joint.qmax);
                    match half {
                        Some(half) => sampler.uniform(
                            (middle - half).max(joint.qmin),
                            (middle + half).min(joint.qmax),
                        ),
                        None => sampler.uniform(joint.qmin, joint.qmax),
                    }
                })
                .collect();
            Ok(robot.motor_positions(&joints)?.as_slice().to_vec())
        })
        .collect()
}

/// The nominal robot identified from position measurements of `real` at
/// `configurations`, σ stated.
fn calibrate(
    nominal: &Robot,
    real: &Robot,
    configurations: &[Vec<f64>],
    sampler: &mut Sampler,
) -> Result<Identification, Failure> {
    let position = method("position", &MethodOptions::default())?;
    let planned: Samples = configurations
        .iter()
        .map(|q| Sample::new(q.clone()))
        .collect();
    let samples = simulate_at(
        real,
        position.as_ref(),
        planned.as_slice(),
        SIGMA,
        sampler,
        &mut Quiet,
    )?;
    let mut study = Study::single(position, samples, "region");
    study.sets[0].sigma = Some(SIGMA);
    Ok(identify(
        nominal,
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )?)
}

/// The RMS distance between the terminal points of `robot` and `real` at
/// `poses` (metres).
fn held_out(robot: &Robot, real: &Robot, poses: &[Vec<f64>]) -> Result<f64, Failure> {
    let mut squares = 0.0;
    for q in poses {
        let a = terminal_pose(robot, q)?.translation.vector;
        let b = terminal_pose(real, q)?.translation.vector;
        squares += (a - b).norm_squared();
    }
    Ok((squares / poses.len() as f64).sqrt())
}
