//! A calibration from end to end with the libraries: the Stanford arm of the
//! paper's Table 1, a simulated "real" robot with errors of a few millimetres
//! and tenths of a degree, 60 position measurements with 0.02 mm of noise,
//! the identification (eq. 10–11), and the calibrated robot judged on 40
//! measurements it was not identified from.
//!
//! ```sh
//! cargo run --release --example calibrate
//! ```

use gecaro_calib::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let nominal = gecaro_io::load_robot("stanford")?.robot;
    let position = method("position", &MethodOptions::default())?;

    // The robot as it really is, and what a laser tracker measures of it.
    let mut sampler = Sampler::new(7);
    let real = perturbed_robot(&nominal, 0.3, &mut sampler)?;
    let training =
        simulate_measurements(&real, position.as_ref(), 60, 2e-5, &mut sampler, &mut Quiet)?;
    let held_out =
        simulate_measurements(&real, position.as_ref(), 40, 2e-5, &mut sampler, &mut Quiet)?;

    let study = Study::single(position.clone_method(), training, "training");
    let mut iterations = 0;
    let result = identify(
        &nominal,
        &study,
        &IdentificationOptions::default(),
        &mut each_iteration(|_| iterations += 1),
    )?;
    println!(
        "{} parameters identified in {} iterations ({:?}): training RMS {:.3} → {:.4} mm",
        result.parameters.len(),
        result.iterations(),
        result.stop_reason,
        result.before.rms * 1e3,
        result.after.rms * 1e3
    );
    assert_eq!(iterations, result.history.len());

    let check = Study::single(position, held_out, "held out");
    let before = evaluate(&nominal, &check)?;
    let after = evaluate(&result.calibrated, &check)?;
    println!(
        "held out: {:.3} mm with the nominal robot, {:.4} mm calibrated",
        before.rms * 1e3,
        after.rms * 1e3
    );
    for parameter in result.parameters.iter().take(5) {
        println!(
            "  {:<8} {:+.6} ± {:.1e}",
            parameter.name,
            parameter.identified - parameter.nominal,
            parameter.std
        );
    }
    Ok(())
}
