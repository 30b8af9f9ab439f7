//! What many of these tests share: the ready Stanford arm and simulated data.

use gecaro_calib::{
    Quiet,
    methods::CalibrationMethod,
    simulation::{Sampler, simulate_measurements},
    study::Sample,
};
use gecaro_core::Robot;

/// The ready Stanford arm (Table 1 of the paper), read as a user reads it.
pub(crate) fn stanford() -> Robot {
    gecaro_io::load_robot("stanford")
        .expect("ready robot")
        .robot
}

/// `count` measurements of `measure` on `real` with Gaussian noise of σ
/// `noise` (metres, radians), drawn from `sampler`.
pub(crate) fn simulated(
    real: &Robot,
    measure: &dyn CalibrationMethod,
    count: usize,
    noise: f64,
    sampler: &mut Sampler,
) -> Vec<Sample> {
    simulate_measurements(real, measure, count, noise, sampler, &mut Quiet).expect("simulated data")
}
