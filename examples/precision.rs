//! Whether the σ an identification reports is the spread it has: for each
//! ready robot, method and level of error, one real robot and one set of
//! configurations measured again and again with fresh noise (σ 0.01 mm,
//! 0.01 mrad), identified each time; per parameter, the spread of the
//! identified values over the mean reported σ (1.00 is right). Printed: the
//! median and the range of these ratios, and the worst parameter.
//!
//! ```sh
//! cargo run --release --example precision                        # docs/methods.md
//! cargo run --release --example precision -- puma560 position 1 7
//! ```
//!
//! Arguments (all optional, in order): robots, methods, levels, seeds.

mod common;

use common::{Case, Cases, Failure, NOISE};
use gecaro_calib::prelude::*;

/// Repetitions of each case.
const RUNS: usize = 40;

fn main() -> Result<(), Failure> {
    let cases = Cases::from_arguments(["puma560,industrial6", "position,frame", "1,2", "7"])?;
    println!(
        "robot        method    level  seed  spread/σ_noise: median   range   worst           held by a prior  tied to moved"
    );
    for robot in &cases.robots {
        for name in &cases.methods {
            for level in &cases.levels {
                for seed in &cases.seeds {
                    let mut case = Case::new(robot, name, *level, *seed)?;
                    let exact = simulate_measurements(
                        &case.real,
                        case.method.as_ref(),
                        if name == "frame" { 40 } else { 60 },
                        0.0,
                        &mut case.sampler,
                        &mut Quiet,
                    )?;
                    let mut noise = Sampler::new(seed + 1000);
                    let mut values: Vec<Vec<f64>> = Vec::new();
                    let mut reported: Vec<f64> = Vec::new();
                    let mut whole: Vec<f64> = Vec::new();
                    let mut tied: Vec<bool> = Vec::new();
                    let mut names: Vec<String> = Vec::new();
                    for _ in 0..RUNS {
                        let noisy: Vec<Sample> = exact
                            .iter()
                            .map(|sample| Sample {
                                position: sample.position.map(|p| p + noise.gaussian_vector(NOISE)),
                                orientation: sample.orientation.map(|q| {
                                    q * nalgebra::UnitQuaternion::from_rotation_matrix(
                                        &noise.gaussian_rotation(NOISE),
                                    )
                                }),
                                ..sample.clone()
                            })
                            .collect();
                        let mut study = Study::single(case.method.clone_method(), noisy, "run");
                        study.sets[0].sigma = Some(NOISE);
                        let result = case.identify(&study)?;
                        let current: Vec<String> =
                            result.parameters.iter().map(|p| p.name.clone()).collect();
                        if names.is_empty() {
                            names = current.clone();
                            reported = vec![0.0; names.len()];
                            whole = vec![0.0; names.len()];
                            tied = vec![false; names.len()];
                            values = vec![Vec::new(); names.len()];
                        }
                        if current != names {
                            continue;
                        }
                        // A regrouped parameter's σ is that of its combination
                        // `Δη_b + Σ β_j Δη_j` (Appendix III): the parameters it
                        // absorbs may have moved too (a Hayati β set outside
                        // the base), so the combination is what is compared.
                        let deviation = |name: &str| {
                            case.nominal
                                .parameters()
                                .ids()
                                .iter()
                                .find(|id| id.to_string() == name)
                                .map_or(0.0, |id| {
                                    result.calibrated.parameter(*id) - case.nominal.parameter(*id)
                                })
                        };
                        for (column, parameter) in result.parameters.iter().enumerate() {
                            tied[column] |= parameter
                                .absorbs
                                .iter()
                                .any(|(name, _)| result.moved.iter().any(|m| &m.name == name));
                            let combination = parameter.identified
                                + parameter
                                    .absorbs
                                    .iter()
                                    .map(|(name, beta)| beta * deviation(name))
                                    .sum::<f64>();
                            values[column].push(combination);
                            reported[column] += parameter.noise_std;
                            whole[column] += parameter.std;
                        }
                    }
                    // A combination that holds a parameter left moved by the
                    // route (its spread not in the base set's σ) is counted
                    // apart; since moved parameters a base parameter absorbs
                    // are joined to the base set, there are none.
                    let tied_count = tied.iter().filter(|t| **t).count();
                    let mut ratios: Vec<(f64, &str)> = values
                        .iter()
                        .zip(&reported)
                        .zip(&names)
                        .zip(&tied)
                        .filter(|(_, tied)| !**tied)
                        .map(|(pair, _)| pair)
                        .filter(|((spread, _), _)| spread.len() > 2)
                        .map(|((spread, total), name)| {
                            let n = spread.len() as f64;
                            let mean = spread.iter().sum::<f64>() / n;
                            let sample = (spread.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
                                / (n - 1.0))
                                .sqrt();
                            (sample / (total / n), name.as_str())
                        })
                        .collect();
                    ratios.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let median = ratios[ratios.len() / 2].0;
                    let (low, high) = (ratios[0], ratios[ratios.len() - 1]);
                    let worst = if (1.0 / low.0) > high.0 { low } else { high };
                    if std::env::var_os("PRECISION_VALUES").is_some() {
                        let column = names.iter().position(|n| n == worst.1).unwrap_or(0);
                        eprintln!(
                            "{} values {:?} mean σ {}",
                            worst.1,
                            values[column],
                            reported[column] / values[column].len() as f64
                        );
                    }
                    let held = reported
                        .iter()
                        .zip(&whole)
                        .filter(|(noise, std)| *noise < &(0.5 * *std))
                        .count();
                    println!(
                        "{robot:<12} {name:<9} {level:>5} {seed:>5}  {median:>15.2}   {:.2}–{:.2}      {:<9} {:.2}  {held:>4}  {tied_count:>4}",
                        low.0, high.0, worst.1, worst.0
                    );
                }
            }
        }
    }
    Ok(())
}
