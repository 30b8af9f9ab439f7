//! A Gough–Stewart platform calibrated against simulated truth (issue 79's
//! targets): identifiability against an independent rank computation, and
//! calibrations judged on held-out poses against the real platform.

use gecaro_calib::identifiability::ParameterStatus;
use gecaro_calib::identification::Outcome;
use gecaro_calib::parallel_robots::{
    PlatformIdentificationOptions, PlatformMeasure, PlatformNoise, PlatformWorkspace,
    identify_platform, perturbed_platform, platform_errors, platform_identifiability,
    random_platform_poses, simulate_platform,
};
use gecaro_calib::simulation::Sampler;
use gecaro_core::gough_stewart::{GoughStewart, LEGS, PARAMETER_COUNT, PARAMETERS_PER_LEG};
use gecaro_data::sample::Sample;
use nalgebra::DMatrix;

/// The ready hexapod (`robots/hexapod.toml`): base joints on a circle of
/// 0.5 m, platform joints on one of 0.3 m, 0.6 m legs with ±0.1 m of
/// stroke, a tool point 0.1 m above the platform.
fn hexapod() -> GoughStewart {
    gecaro_io::load_parallel_robot("hexapod")
        .expect("the ready hexapod")
        .platform
}

const NOISE: PlatformNoise = PlatformNoise {
    length: 20e-6,
    angle: 20e-6,
};

fn measured(
    real: &GoughStewart,
    measure: PlatformMeasure,
    count: usize,
    noise: PlatformNoise,
    seed: u64,
) -> Vec<Sample> {
    let mut sampler = Sampler::new(seed);
    let poses = random_platform_poses(real, count, PlatformWorkspace::of(real), &mut sampler)
        .expect("reachable poses");
    simulate_platform(real, measure, &poses, noise, &mut sampler)
}

/// The rank of W made by central differences of what the sensor reads
/// (the legs' equations for poses, the direct model's tool point for
/// points), by nalgebra's SVD.
fn independent_rank(
    platform: &GoughStewart,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> usize {
    let values = platform.parameters();
    let columns = match measure {
        PlatformMeasure::Pose => LEGS * PARAMETERS_PER_LEG,
        PlatformMeasure::Point => PARAMETER_COUNT,
    };
    let read = |delta: f64, column: usize| -> Vec<f64> {
        let mut changed = values.clone();
        changed[column] += delta;
        let changed = platform.with_parameters(&changed).expect("platform");
        samples
            .iter()
            .flat_map(|sample| {
                let actuators: [f64; LEGS] =
                    sample.motor_positions.as_slice().try_into().expect("6");
                let measured = nalgebra::Isometry3::from_parts(
                    sample.position.expect("position").into(),
                    sample.orientation.unwrap_or_default(),
                );
                match measure {
                    PlatformMeasure::Pose => changed
                        .leg_residuals(&measured, &actuators)
                        .iter()
                        .copied()
                        .collect::<Vec<_>>(),
                    PlatformMeasure::Point => {
                        let pose = changed.direct(&actuators, &platform.home()).expect("pose");
                        changed.tool_point(&pose).iter().copied().collect()
                    }
                }
            })
            .collect()
    };
    let h = 1e-6;
    let rows = samples.len() * measure.rows_per_sample();
    let mut matrix = DMatrix::zeros(rows, columns);
    for column in 0..columns {
        let (plus, minus) = (read(h, column), read(-h, column));
        for row in 0..rows {
            matrix[(row, column)] = (plus[row] - minus[row]) / (2.0 * h);
        }
    }
    let singular = matrix.singular_values();
    let largest = singular.max();
    singular.iter().filter(|s| **s > 1e-7 * largest).count()
}

#[test]
fn measured_poses_identify_every_leg_parameter() {
    let nominal = hexapod();
    let samples = measured(&nominal, PlatformMeasure::Pose, 30, NOISE, 1);
    let report = platform_identifiability(&nominal, &samples, PlatformMeasure::Pose).expect("rank");
    assert_eq!(report.rank(), 48);
    assert_eq!(
        report.rank(),
        independent_rank(&nominal, &samples, PlatformMeasure::Pose)
    );
    assert!(report.relations.is_empty());
    // The tool point is not in these equations.
    assert_eq!(
        report.statuses[PARAMETER_COUNT - 1],
        ParameterStatus::Excluded
    );
    assert!(report.condition_number.is_finite());
}

#[test]
fn one_measured_point_leaves_the_platform_frame_to_six_regroupings() {
    let nominal = hexapod();
    let samples = measured(&nominal, PlatformMeasure::Point, 40, NOISE, 2);
    let report =
        platform_identifiability(&nominal, &samples, PlatformMeasure::Point).expect("rank");
    assert_eq!(
        report.rank(),
        independent_rank(&nominal, &samples, PlatformMeasure::Point)
    );
    assert_eq!(report.rank(), PARAMETER_COUNT - 6, "{:?}", report.statuses);
    assert_eq!(report.relations.len(), 6);
    // Every regrouped parameter is a platform joint's: the tool point, the
    // base joints, lengths and gains are all identifiable.
    for relation in &report.relations {
        let name = &report.names[relation.parameter];
        assert!(name.starts_with('b'), "{name}");
        assert!(!relation.terms.is_empty());
    }
}

/// Identifies from `count` measurements and judges the calibrated platform
/// on 200 held-out poses of the real one: its RMS position error over the
/// real platform's own (the noise floor of held-out measurements).
fn held_out_ratio(measure: PlatformMeasure, count: usize, seed: u64) -> (f64, Outcome, f64) {
    let nominal = hexapod();
    let real = perturbed_platform(&nominal, 1.0, &mut Sampler::new(seed)).expect("real platform");
    let data = measured(&real, measure, count, NOISE, seed + 1);
    let result = identify_platform(
        &nominal,
        &data,
        measure,
        Some(NOISE),
        &PlatformIdentificationOptions::default(),
    )
    .expect("identified");
    let held_out = measured(&real, measure, 200, NOISE, seed + 2);
    let floor = platform_errors(&real, &held_out, measure).expect("floor");
    let calibrated = platform_errors(&result.calibrated, &held_out, measure).expect("calibrated");
    let before = platform_errors(&nominal, &held_out, measure).expect("nominal");
    println!(
        "{measure:?}: nominal {:.4} mm, calibrated {:.4} mm, floor {:.4} mm; {:?} σ̂/σ {:.3}",
        before.position_rms * 1e3,
        calibrated.position_rms * 1e3,
        floor.position_rms * 1e3,
        result.outcome,
        result.noise_test.map_or(f64::NAN, |t| t.sigma_ratio)
    );
    (
        calibrated.position_rms / floor.position_rms,
        result.outcome,
        before.position_rms / floor.position_rms,
    )
}

#[test]
fn sixty_measured_poses_calibrate_to_the_noise_floor() {
    let (ratio, outcome, before) = held_out_ratio(PlatformMeasure::Pose, 60, 10);
    assert!(
        before > 20.0,
        "the real platform is off: {before}× the floor"
    );
    assert!(ratio <= 1.2, "{ratio}× the noise floor");
    assert_eq!(outcome, Outcome::FitsNoise);
}

#[test]
fn one_platform_point_calibrates_to_the_noise_floor() {
    let (ratio, outcome, before) = held_out_ratio(PlatformMeasure::Point, 60, 20);
    assert!(
        before > 20.0,
        "the real platform is off: {before}× the floor"
    );
    assert!(ratio <= 1.3, "{ratio}× the noise floor");
    assert_eq!(outcome, Outcome::FitsNoise);
}

#[test]
fn a_stated_noise_ten_times_too_small_is_named() {
    let nominal = hexapod();
    let real = perturbed_platform(&nominal, 1.0, &mut Sampler::new(5)).expect("real");
    let data = measured(&real, PlatformMeasure::Pose, 60, NOISE, 6);
    let stated = PlatformNoise {
        length: NOISE.length / 10.0,
        angle: NOISE.angle / 10.0,
    };
    let result = identify_platform(
        &nominal,
        &data,
        PlatformMeasure::Pose,
        Some(stated),
        &PlatformIdentificationOptions::default(),
    )
    .expect("identified");
    assert_eq!(result.outcome, Outcome::ExceedsNoise);
    let ratio = result.noise_test.expect("tested").sigma_ratio;
    assert!((8.0..12.0).contains(&ratio), "{ratio}");
}
