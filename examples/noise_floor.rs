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

use gecaro_calib::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    let list = |index: usize, default: &str| -> Vec<String> {
        arguments
            .get(index)
            .map_or(default, String::as_str)
            .split(',')
            .map(str::to_owned)
            .collect()
    };
    let robots = list(0, "panda,puma560,industrial6");
    let methods = list(1, "position,frame");
    let levels: Vec<f64> = list(2, "0.1,0.3,1,2")
        .iter()
        .map(|level| level.parse())
        .collect::<Result<_, _>>()?;
    let seeds: Vec<u64> = list(3, "7")
        .iter()
        .map(|seed| seed.parse())
        .collect::<Result<_, _>>()?;

    println!("robot        method    level  seed  held-out/floor  phases  verdict");
    for robot in &robots {
        for name in &methods {
            for level in &levels {
                for seed in &seeds {
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
    if result.warnings.iter().any(|w| w.contains("damped descent")) {
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
) -> Result<(f64, Identification), Box<dyn std::error::Error>> {
    let nominal = gecaro_io::load_robot(robot)?.robot;
    let method = method(name, &MethodOptions::default())?;
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&nominal, level, &mut sampler)?;
    let mut measure = || -> Result<Study, Error> {
        let samples = simulate_measurements(&real, method.as_ref(), 200, 1e-5, &mut sampler)?;
        Ok(Study::single(method.clone_method(), samples, "simulated"))
    };
    let (train, check) = (measure()?, measure()?);
    let result = identify(
        &nominal,
        &train,
        &IdentificationOptions::default(),
        &mut Quiet,
    )?;
    let floor = evaluate(&real, &check)?.rms;
    let held_out = evaluate(&result.calibrated, &check)?.rms;
    Ok((held_out / floor, result))
}
