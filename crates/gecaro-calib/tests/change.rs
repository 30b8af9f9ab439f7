//! A change of the cell during the measurement, against simulated truth:
//! the reflector re-seated or the tracker bumped for the last 10 % of the
//! rows is named with its first observation, whatever the loss or a
//! rejection makes of those rows; honest data and scattered gross errors
//! are no change.

use gecaro_calib::{
    Quiet,
    identification::{IdentificationOptions, Loss, LossKind, Outcome, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_at},
    study::{Sample, Samples, Study},
};
use gecaro_core::{ParameterId, Robot};

const SIGMA: f64 = 2e-5;

fn industrial6() -> Robot {
    let mut robot = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let tool: ParameterId = "d7".parse().expect("name");
    robot.set_parameter(tool, 0.06).expect("d7");
    robot
}

/// `real` with parameter `name` moved by `by`.
fn moved(real: &Robot, name: &str, by: f64) -> Robot {
    let mut moved = real.clone();
    let id: ParameterId = name.parse().expect("name");
    moved
        .set_parameter(id, real.parameter(id) + by)
        .expect("set");
    moved
}

/// 120 positions over the workspace, the last `changed` of them measured
/// on `after` instead of `before`, σ stated.
fn study(before: &Robot, after: &Robot, changed: usize, sampler: &mut Sampler) -> Study {
    let position = method("position", &MethodOptions::default()).expect("method");
    let configurations: Vec<Sample> = (0..120)
        .map(|_| Sample::new(sampler.configuration(before)))
        .collect();
    let measure = |real: &Robot, rows: &[Sample], sampler: &mut Sampler| {
        let planned: Samples = rows.to_vec().into();
        simulate_at(
            real,
            position.as_ref(),
            planned.as_slice(),
            SIGMA,
            sampler,
            &mut Quiet,
        )
        .expect("measured")
    };
    let split = configurations.len() - changed;
    let mut samples = measure(before, &configurations[..split], sampler);
    if changed > 0 {
        samples.extend(measure(after, &configurations[split..], sampler));
    }
    let mut study = Study::single(position, samples, "tracker.csv");
    study.sets[0].sigma = Some(SIGMA);
    study
}

#[test]
fn a_change_in_the_last_rows_is_named_whatever_the_loss() {
    let nominal = industrial6();
    let mut sampler = Sampler::new(21);
    let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
    // The reflector re-seated 0.5 mm (along the flange's x), the tracker
    // bumped 0.3 mm (the world frame moved along z).
    for (what, after) in [
        ("re-seated", moved(&real, "d7", 5e-4)),
        ("bumped", moved(&real, "r0", 3e-4)),
    ] {
        let data = study(&real, &after, 12, &mut sampler);
        let options = [
            ("least squares", IdentificationOptions::default()),
            (
                "tukey",
                IdentificationOptions {
                    loss: Loss::new(LossKind::Tukey),
                    ..IdentificationOptions::default()
                },
            ),
            (
                "reject",
                IdentificationOptions {
                    reject: true,
                    ..IdentificationOptions::default()
                },
            ),
        ];
        for (fit, options) in options {
            let result = identify(&nominal, &data, &options, &mut Quiet).expect("identified");
            let verdict = &result.verdict;
            assert_eq!(
                verdict.outcome,
                Outcome::Changed,
                "{what}, {fit}: {}",
                verdict.summary
            );
            assert!(!verdict.outcome.trusted());
            let change = &verdict.changes[0];
            assert_eq!(verdict.changes.len(), 1);
            assert!(change.to_end(), "{what}, {fit}: {change:?}");
            assert!(
                (107..=109).contains(&change.first),
                "{what}, {fit}: from observation {}",
                change.first + 1
            );
            assert!(
                verdict
                    .summary
                    .contains("the cell seems to have changed from observation 1"),
                "{}",
                verdict.summary
            );
        }
    }
}

#[test]
fn honest_data_and_scattered_gross_errors_are_no_change() {
    let nominal = industrial6();
    let mut sampler = Sampler::new(5);
    let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
    let tukey = IdentificationOptions {
        loss: Loss::new(LossKind::Tukey),
        ..IdentificationOptions::default()
    };
    for _ in 0..10 {
        let mut data = study(&real, &real, 0, &mut sampler);
        let result = identify(&nominal, &data, &tukey, &mut Quiet).expect("identified");
        assert!(
            result.verdict.changes.is_empty(),
            "{}",
            result.verdict.summary
        );
        // Five gross errors of 5–20 mm scattered over the rows.
        let mut rows = data.sets[0].samples.to_rows();
        for (k, row) in rows.iter_mut().enumerate().filter(|(k, _)| k % 23 == 4) {
            let position = row.position.as_mut().expect("a position");
            position.x += 5e-3 * (1.0 + (k % 4) as f64);
        }
        data.sets[0].samples = rows.into();
        let result = identify(&nominal, &data, &tukey, &mut Quiet).expect("identified");
        assert_eq!(result.outliers.len(), 6);
        assert!(
            result.verdict.changes.is_empty(),
            "{}",
            result.verdict.summary
        );
    }
}
