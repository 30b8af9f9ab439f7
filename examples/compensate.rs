//! What a calibration is for: a program taught on the nominal model, its
//! targets reached by the calibrated robot. The PUMA 560 is given errors of
//! about a millimetre; a program of ten joint targets is corrected so that
//! the calibrated robot puts its tool where the nominal program meant.
//!
//! ```sh
//! cargo run --release --example compensate
//! ```

use gecaro_calib::compensation::{Match, ProgramPoint, ProgramTarget, compensate};
use gecaro_calib::prelude::*;
use gecaro_core::terminal_pose;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let nominal = gecaro_io::load_robot("puma560")?.robot;
    let mut sampler = Sampler::new(3);
    // Stands in for the robot an identification returns.
    let calibrated = perturbed_robot(&nominal, 0.1, &mut sampler)?;
    let program: Vec<ProgramPoint> = (0..10)
        .map(|_| ProgramPoint {
            target: ProgramTarget::Joints(sampler.configuration(&nominal)),
            joints: None,
        })
        .collect();

    let corrected = compensate(&nominal, &calibrated, &program, Match::Pose, &mut Quiet)?;
    for (point, result) in program.iter().zip(&corrected) {
        let ProgramTarget::Joints(taught) = &point.target else {
            continue;
        };
        let meant = terminal_pose(&nominal, taught)?.translation.vector;
        let as_taught = terminal_pose(&calibrated, taught)?.translation.vector;
        let reached = terminal_pose(&calibrated, &result.motor_positions)?
            .translation
            .vector;
        println!(
            "{:<10} taught: {:.3} mm off, corrected: {:.1e} mm off",
            result.status.word(),
            (as_taught - meant).norm() * 1e3,
            (reached - meant).norm() * 1e3
        );
    }
    Ok(())
}
