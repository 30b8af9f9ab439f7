//! Elastic joints (issue 38), judged against simulated truth: a real
//! industrial6 with compliances measured with three payloads, identified
//! with the geometry, and judged on a fourth payload it never carried.

use gecaro_app::{
    DataSource, EvaluateRequest, GenerateRequest, IdentifyRequest, LocalFiles, Measurements,
    MethodSpec, RobotSource,
};
use gecaro_calib::Quiet;
use gecaro_core::{ParameterId, ParameterKind};

const NOISE: f64 = 2e-5;

/// Position data of the real robot `real` (drawn at the first call and
/// saved there) carrying `payload`, `count` configurations drawn with `seed`.
fn measured(real: &str, first: bool, payload: &str, count: usize, seed: u64) -> String {
    let mut request = GenerateRequest::new(
        RobotSource::Named("industrial6".into()),
        MethodSpec::named("position"),
        count,
    );
    request.noise = NOISE;
    request.payload = Some(payload.into());
    request.seed = Some(seed);
    if first {
        request.compliance_level = Some(1.0);
        request.real_save_as = Some(real.into());
    } else {
        request.real = Some(RobotSource::Named(real.into()));
    }
    request.run(&LocalFiles, &mut Quiet).expect("generated").csv
}

/// The rows of several generated files under one header.
fn joined(files: &[String]) -> String {
    let mut text = String::new();
    for (index, file) in files.iter().enumerate() {
        let rows = file.lines().filter(|line| !line.starts_with('#'));
        for line in rows.skip(usize::from(index > 0)) {
            text.push_str(line);
            text.push('\n');
        }
    }
    text
}

fn measurements(robot: RobotSource, csv: &str) -> Measurements {
    Measurements {
        robot: Some(robot),
        method: Some(MethodSpec::named("position")),
        data: Some(DataSource::Csv {
            text: csv.to_owned(),
            name: Some("payloads.csv".into()),
        }),
        sigma: Some(gecaro_io::StandardDeviation::Number(NOISE)),
        ..Measurements::default()
    }
}

/// RMS error (m) of `robot` on the held-out data.
fn held_out(robot: RobotSource, csv: &str) -> f64 {
    EvaluateRequest::new(measurements(robot, csv))
        .run(&LocalFiles)
        .expect("evaluated")
        .summary
        .rms
}

#[test]
fn compliances_identified_with_three_payloads_hold_a_fourth_at_the_noise_floor() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let real_path = folder.path().join("real.toml");
    let real = real_path.to_str().expect("UTF-8 path");
    let training = joined(&[
        measured(real, true, "0kg", 60, 1),
        measured(real, false, "10kg,0,0,100mm", 60, 2),
        measured(real, false, "20kg,0,0,100mm", 60, 3),
    ]);
    let unseen = measured(real, false, "15kg,0,0,100mm", 60, 4);
    let truth = gecaro_io::load_robot(real).expect("the real robot");
    let true_compliances = truth.robot.compliances().expect("elastic").to_vec();

    let identify = |model: &str| {
        let mut request = IdentifyRequest::new(measurements(
            RobotSource::Named("industrial6".into()),
            &training,
        ));
        request.settings.model = Some(model.into());
        request.run(&LocalFiles, &mut Quiet).expect("identified")
    };
    let elastic = identify("elastic");
    let verdict = &elastic.result.verdict;
    assert!(verdict.outcome.trusted(), "{}", verdict.summary);
    // Each compliance gravity loads is identified, within 3σ of the truth;
    // joint 1 (vertical) carries no gravity torque and is not identified.
    let mut identified = 0;
    for p in &elastic.result.parameters {
        let Some(ParameterId {
            kind: ParameterKind::Compliance,
            frame,
        }) = p.parameter
        else {
            continue;
        };
        identified += 1;
        let truth = true_compliances[frame - 1];
        assert!(
            (p.identified - truth).abs() < 3.0 * p.std,
            "{}: {:.3e} vs truth {truth:.3e}, σ {:.1e}",
            p.name,
            p.identified,
            p.std
        );
    }
    assert!(identified >= 3, "{identified} compliances identified");
    assert!(
        !elastic.result.parameters.iter().any(|p| p.name == "c1"),
        "a vertical first axis carries no gravity torque"
    );

    let floor = held_out(RobotSource::Named(real.into()), &unseen);
    let calibrated = held_out(RobotSource::Loaded(Box::new(elastic.calibrated())), &unseen);
    assert!(
        calibrated <= 1.2 * floor,
        "held out with 15 kg: {:.4} mm, the floor {:.4} mm",
        calibrated * 1e3,
        floor * 1e3
    );
    // The geometry alone cannot follow the payload: several times the floor.
    let geometric = identify("full");
    let rigid = held_out(
        RobotSource::Loaded(Box::new(geometric.calibrated())),
        &unseen,
    );
    assert!(
        rigid > 4.0 * floor,
        "geometric only: {:.4} mm, the floor {:.4} mm",
        rigid * 1e3,
        floor * 1e3
    );
}
