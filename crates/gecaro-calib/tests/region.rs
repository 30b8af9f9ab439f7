//! Where a result holds, against simulated truth: a calibration measured in
//! a small region of the joint space is trusted there, not over the whole
//! workspace, and its predicted error over the workspace is the one the
//! real robot shows held out there.

use gecaro_calib::{
    Quiet,
    identification::{Identification, IdentificationOptions, Outcome, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_at},
    study::{Sample, Samples, Study},
};
use gecaro_core::{JointRegion, ParameterId, Robot, terminal_pose};

/// The trial's tracker: σ = 20 µm a coordinate.
const SIGMA: f64 = 2e-5;

/// A ready robot with its reflector 60 mm off the last axis (on it, a
/// position sensor cannot see the last joint turn).
fn robot(name: &str) -> Robot {
    let mut robot = gecaro_io::load_robot(name).expect("ready robot").robot;
    let tool_offset: ParameterId = format!("d{}", robot.joint_count() + 1)
        .parse()
        .expect("a parameter name");
    robot
        .set_parameter(tool_offset, 0.06)
        .expect("d of frame n+1");
    robot
}

/// Motor values of `count` configurations drawn within `half` (rad) of the
/// middle of every joint's limits (or over the whole limits for `None`).
fn configurations(
    robot: &Robot,
    half: Option<f64>,
    count: usize,
    sampler: &mut Sampler,
) -> Vec<Vec<f64>> {
    (0..count)
        .map(|_| {
            let joints: Vec<f64> = robot
                .joints()
                .iter()
                .map(|joint| {
                    let middle = 0.5 * (joint.qmin + joint.qmax);
                    match half {
                        Some(half) => sampler.uniform(middle - half, middle + half),
                        None => sampler.uniform(joint.qmin, joint.qmax),
                    }
                })
                .collect();
            robot
                .motor_positions(&joints)
                .expect("motor values")
                .as_slice()
                .to_vec()
        })
        .collect()
}

/// Position measurements of `real` at `configurations`, σ stated, and the
/// identification of `nominal` from them.
fn calibrated(
    nominal: &Robot,
    real: &Robot,
    configurations: &[Vec<f64>],
    sampler: &mut Sampler,
    options: &IdentificationOptions,
) -> Identification {
    let position = method("position", &MethodOptions::default()).expect("method");
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
    )
    .expect("measured");
    let mut study = Study::single(position, samples, "region");
    study.sets[0].sigma = Some(SIGMA);
    identify(nominal, &study, options, &mut Quiet).expect("identified")
}

/// The RMS distance between the terminal points of `robot` and `real` at
/// `poses` (both in the measurement frame, which position data observe).
fn held_out(robot: &Robot, real: &Robot, poses: &[Vec<f64>]) -> f64 {
    let squares: f64 = poses
        .iter()
        .map(|q| {
            let a = terminal_pose(robot, q).expect("pose").translation.vector;
            let b = terminal_pose(real, q).expect("pose").translation.vector;
            (a - b).norm_squared()
        })
        .sum();
    (squares / poses.len() as f64).sqrt()
}

/// ±15° about the middle of the limits, 120 poses (the trial's case): the
/// fit passes the global test, but the verdict says the result holds in the
/// measured region only, names its ranges, and predicts the error over the
/// joint limits within 1.5× of what the real robot shows there (averaged
/// over fresh noise: one draw's error is dominated by a few directions).
#[test]
fn a_small_measured_region_is_not_trusted_for_the_whole_workspace() {
    for name in ["industrial6", "ur10e"] {
        let nominal = robot(name);
        let mut sampler = Sampler::new(7);
        let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let region = configurations(&nominal, Some(15f64.to_radians()), 120, &mut sampler);
        let whole = configurations(&nominal, None, 300, &mut sampler);
        let (mut measured, mut predicted) = (0.0, 0.0);
        let draws = 6;
        for draw in 0..draws {
            let result = calibrated(
                &nominal,
                &real,
                &region,
                &mut sampler,
                &IdentificationOptions::default(),
            );
            let verdict = &result.verdict;
            let test = verdict.noise_test.expect("σ stated");
            assert!(test.passed, "{name}: {}", verdict.summary);
            assert_eq!(
                verdict.outcome,
                Outcome::Regional,
                "{name}: {}",
                verdict.summary
            );
            assert!(!verdict.outcome.trusted());
            let prediction = verdict.region.as_ref().expect("predicted");
            assert!(!prediction.holds_everywhere);
            assert!(
                prediction.work_rms > 10.0 * prediction.floor,
                "{name}: {} against the floor {}",
                prediction.work_rms,
                prediction.floor
            );
            assert!(prediction.inside < prediction.floor);
            // The measured region is the box of the calibrated robot's joint
            // variables (eq. 4 with its gains) at the measured configurations:
            // about ±15° about the middle of every joint's limits.
            let joints: Vec<Vec<f64>> = region
                .iter()
                .map(|qm| {
                    let q = result.calibrated.joint_positions(qm).expect("joints");
                    q.as_slice().to_vec()
                })
                .collect();
            let covering = JointRegion::covering(6, joints.iter().map(Vec::as_slice));
            for (j, joint) in nominal.joints().iter().enumerate() {
                let ((min, max), (low, high)) = (prediction.measured.range(j), covering.range(j));
                assert!((min - low).abs() < 1e-12 && (max - high).abs() < 1e-12);
                let middle = 0.5 * (joint.qmin + joint.qmax);
                let half = 0.5 * (max - min);
                assert!(
                    (half - 15f64.to_radians()).abs() < 1.5f64.to_radians(),
                    "q{}",
                    j + 1
                );
                assert!(
                    (0.5 * (min + max) - middle).abs() < 4f64.to_radians(),
                    "q{}",
                    j + 1
                );
            }
            assert_eq!(prediction.narrow_joints(), (1..=6).collect::<Vec<_>>());
            if draw == 0 {
                assert!(
                    verdict
                        .summary
                        .contains("the data cover only part of the joint space (q1 ")
                        && verdict.summary.contains("over the joint limits"),
                    "{}",
                    verdict.summary
                );
            }
            measured += held_out(&result.calibrated, &real, &whole).powi(2);
            predicted += prediction.work_rms.powi(2);
            // Within the region, the calibrated robot is at the noise.
            assert!(held_out(&result.calibrated, &real, &region) < prediction.floor);
        }
        let (measured, predicted) = (
            (measured / draws as f64).sqrt(),
            (predicted / draws as f64).sqrt(),
        );
        assert!(
            (predicted / measured - 1.0).abs() < 0.5,
            "{name}: predicted {predicted} m over the joint limits, measured {measured} m"
        );
    }
}

/// Honest data over the whole workspace: the prediction holds everywhere
/// and adds no alarm (the true σ passes as before).
#[test]
fn data_over_the_workspace_hold_everywhere() {
    for name in ["industrial6", "ur10e"] {
        let nominal = robot(name);
        let mut sampler = Sampler::new(3);
        let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let mut fits = 0;
        for _ in 0..5 {
            let poses = configurations(&nominal, None, 120, &mut sampler);
            let result = calibrated(
                &nominal,
                &real,
                &poses,
                &mut sampler,
                &IdentificationOptions::default(),
            );
            let prediction = result.verdict.region.as_ref().expect("predicted");
            assert!(
                prediction.holds_everywhere,
                "{name}: {}",
                result.verdict.summary
            );
            assert!(prediction.work_rms < prediction.floor);
            fits += usize::from(result.verdict.outcome == Outcome::FitsNoise);
        }
        assert!(fits >= 4, "{name}: {fits} of 5 fit the noise");
    }
}

/// A work region the user states is the one judged: the same small-region
/// data hold over a work region no larger than what they measured.
#[test]
fn a_stated_work_region_is_the_one_judged() {
    let nominal = robot("industrial6");
    let mut sampler = Sampler::new(11);
    let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
    let region = configurations(&nominal, Some(15f64.to_radians()), 120, &mut sampler);
    let work = JointRegion::new(
        nominal
            .joints()
            .iter()
            .map(|joint| {
                let middle = 0.5 * (joint.qmin + joint.qmax);
                (middle - 12f64.to_radians(), middle + 12f64.to_radians())
            })
            .collect(),
    )
    .expect("region");
    let options = IdentificationOptions {
        work_region: Some(work.clone()),
        ..IdentificationOptions::default()
    };
    let result = calibrated(&nominal, &real, &region, &mut sampler, &options);
    let prediction = result.verdict.region.as_ref().expect("predicted");
    assert_eq!(prediction.work, work);
    assert!(!prediction.work_is_limits);
    assert!(prediction.holds_everywhere, "{}", result.verdict.summary);
    assert_eq!(result.verdict.outcome, Outcome::FitsNoise);
    // A work region of another robot's joint count is refused by name.
    let wrong = IdentificationOptions {
        work_region: Some(JointRegion::new(vec![(0.0, 1.0)]).expect("region")),
        ..IdentificationOptions::default()
    };
    let position = method("position", &MethodOptions::default()).expect("method");
    let study = Study::single(position, Samples::empty(), "none");
    let error = identify(&nominal, &study, &wrong, &mut Quiet).expect_err("refused");
    assert!(error.to_string().contains("work region"), "{error}");
}
