//! A scale-aware check of calibrations by link (and other) methods, which
//! the held-out residuals of the method itself cannot give: link methods do
//! not observe the robot's scale, and a robot calibrated too small fits its
//! held-out sets as well as the real one. For each ready robot, method,
//! level of error and seed: 200 configurations to identify from, then 400
//! held-out configurations of the same real robot in pairs, and the RMS
//! difference between the distance of the two tool points that a robot
//! predicts and the real one (independent of the base frame, which link
//! methods do not observe): for the nominal robot, for the calibrated one,
//! the scale that best maps the calibrated distances onto the real ones, and
//! the RMS left once it is applied (the error of shape). Frame link does not
//! observe the tool (two configurations reaching one frame do so whatever
//! the tool), so its tool-point distances carry the tool's error.
//!
//! ```sh
//! cargo run --release --example link_scale                       # docs/methods.md
//! cargo run --release --example link_scale -- puma560 point-link 0.3,2 7
//! ```
//!
//! Arguments (all optional, in order): robots, methods, levels, seeds.

mod common;

use common::{Case, Cases, Failure};
use gecaro_calib::prelude::*;
use gecaro_core::{Robot, terminal_pose};

fn main() -> Result<(), Failure> {
    let cases = Cases::from_arguments([
        "panda,puma560,industrial6",
        "point-link,position",
        "0.3,1,2",
        "7",
    ])?;
    println!(
        "robot        method       level  seed  distance RMS (mm): nominal  calibrated   \
         scale    shape"
    );
    for robot in &cases.robots {
        for name in &cases.methods {
            for level in &cases.levels {
                for seed in &cases.seeds {
                    let check = distances(robot, name, *level, *seed)?;
                    println!(
                        "{robot:<12} {name:<11} {level:>6} {seed:>5}  {:>26.3}  {:>10.3}  \
                         {:>7.4}  {:>7.3}",
                        check.nominal * 1e3,
                        check.calibrated * 1e3,
                        check.scale,
                        check.shape * 1e3,
                    );
                }
            }
        }
    }
    Ok(())
}

/// Distance errors of one case (metres; the scale is a ratio).
struct Distances {
    nominal: f64,
    calibrated: f64,
    scale: f64,
    shape: f64,
}

fn distances(robot: &str, name: &str, level: f64, seed: u64) -> Result<Distances, Failure> {
    let mut case = Case::new(robot, name, level, seed)?;
    let study = case.measure(200)?;
    let result = case.identify(&study)?;
    let position = method("position", &MethodOptions::default())?;
    let held_out =
        simulate_measurements(&case.real, position.as_ref(), 400, 0.0, &mut case.sampler)?;
    let pairs = |robot: &Robot| -> Result<Vec<f64>, Failure> {
        held_out
            .chunks_exact(2)
            .map(|pair| {
                let a = terminal_pose(robot, &pair[0].motor_positions)?
                    .translation
                    .vector;
                let b = terminal_pose(robot, &pair[1].motor_positions)?
                    .translation
                    .vector;
                Ok((a - b).norm())
            })
            .collect()
    };
    let truth = pairs(&case.real)?;
    let rms = |predicted: &[f64], scale: f64| {
        let sum: f64 = predicted
            .iter()
            .zip(&truth)
            .map(|(p, t)| (scale * p - t).powi(2))
            .sum();
        (sum / truth.len() as f64).sqrt()
    };
    let calibrated = pairs(&result.calibrated)?;
    let scale = calibrated
        .iter()
        .zip(&truth)
        .map(|(c, t)| c * t)
        .sum::<f64>()
        / calibrated.iter().map(|c| c * c).sum::<f64>();
    Ok(Distances {
        nominal: rms(&pairs(&case.nominal)?, 1.0),
        calibrated: rms(&calibrated, 1.0),
        scale,
        shape: rms(&calibrated, scale),
    })
}
