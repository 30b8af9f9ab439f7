//! How close identification comes to the noise floor, by size of error: the
//! table of docs/methods.md ("The second pass"). For each ready robot and
//! measure method, a simulated real robot with errors at each level (±1 cm,
//! ±1°, ±1 % at level 1), 200 configurations to identify from and 200 held out
//! (σ 0.01 mm, 0.01 mrad), and the held-out RMS of the identified robot over
//! that of the real robot itself (the floor: 1.00 is the best possible).
//!
//! ```sh
//! cargo run --release --example noise_floor                # the docs' table
//! cargo run --release --example noise_floor -- puma560 position 2 7
//! ```
//!
//! Arguments (all optional, in order): robots (comma-separated), methods,
//! levels, seeds.

mod common;

use common::{Case, Cases, Failure};
use gecaro_calib::identification::Warning;
use gecaro_calib::prelude::*;

fn main() -> Result<(), Failure> {
    let cases = Cases::from_arguments([
        "panda,puma560,industrial6",
        "position,frame",
        "0.1,0.3,1,2",
        "7",
    ])?;
    println!("robot        method    level  seed  held-out/floor  phases  verdict");
    for robot in &cases.robots {
        for name in &cases.methods {
            for level in &cases.levels {
                for seed in &cases.seeds {
                    let (ratio, result) = held_out_over_floor(robot, name, *level, *seed)?;
                    println!(
                        "{robot:<12} {name:<9} {level:>5} {seed:>5}  {ratio:>14.3}  {:>6}  {}",
                        phases(&result),
                        result.verdict.summary,
                    );
                }
            }
        }
    }
    Ok(())
}

/// Which phases the identification went through: the paper's pass (P), the
/// second pass (2), the damped descent over every parameter (D).
fn phases(result: &Identification) -> String {
    let mut phases = String::from("P");
    if !result.second_pass.is_empty() {
        phases.push('2');
    }
    if result
        .warnings
        .iter()
        .any(|w| matches!(w, Warning::FullModelDescent { .. }))
    {
        phases.push('D');
    }
    phases
}

/// The held-out RMS of the identified robot over the real robot's own, and
/// the identification.
fn held_out_over_floor(
    robot: &str,
    name: &str,
    level: f64,
    seed: u64,
) -> Result<(f64, Identification), Failure> {
    let mut case = Case::new(robot, name, level, seed)?;
    let (train, check) = (case.measure_with_sigma(200)?, case.measure(200)?);
    let result = case.identify(&train)?;
    let floor = evaluate(&case.real, &check)?.rms;
    let held_out = evaluate(&result.calibrated, &check)?.rms;
    Ok((held_out / floor, result))
}
