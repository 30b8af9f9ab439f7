//! A parallel robot's jobs end to end through the files a user has: the
//! ready hexapod generated, identified from the written data file, the
//! calibrated platform written, read back and evaluated on held-out data.

use gecaro_app::LocalFiles;
use gecaro_app::parallel::{
    ParallelCompensateRequest, ParallelEvaluateRequest, ParallelGenerateRequest,
    ParallelIdentifiableRequest, ParallelIdentifyRequest, RobotKind,
};
use gecaro_app::{DataSource, Output};
use gecaro_core::parallel_model::ParallelModel;

fn generate(folder: &std::path::Path, name: &str, count: usize, seed: u64) -> String {
    let path = folder.join(name).display().to_string();
    ParallelGenerateRequest {
        robot: "hexapod".into(),
        method: "frame".into(),
        count,
        configurations: None,
        format: Default::default(),
        error_level: None,
        real: Some(folder.join("real.toml").display().to_string()),
        noise: 2e-5,
        seed: Some(seed),
        output: Output::to(path.clone()),
        real_save_as: None,
        leg_base: None,
        leg_platform: None,
        leg_gain: None,
    }
    .run(&LocalFiles)
    .expect("generated");
    path
}

#[test]
fn a_hexapod_is_calibrated_from_its_files_to_the_noise_floor() {
    let folder = tempfile::tempdir().expect("folder");
    assert_eq!(RobotKind::of("hexapod", &LocalFiles), RobotKind::Parallel);
    assert_eq!(RobotKind::of("stanford", &LocalFiles), RobotKind::Serial);
    // The real platform, drawn once and written.
    ParallelGenerateRequest {
        robot: "hexapod".into(),
        method: "frame".into(),
        count: 1,
        configurations: None,
        format: Default::default(),
        error_level: Some(1.0),
        real: None,
        noise: 0.0,
        seed: Some(7),
        output: Output::default(),
        real_save_as: Some(folder.path().join("real.toml").display().to_string()),
        leg_base: None,
        leg_platform: None,
        leg_gain: None,
    }
    .run(&LocalFiles)
    .expect("real platform");
    let data = generate(folder.path(), "poses.csv", 60, 8);
    let held_out = generate(folder.path(), "held-out.csv", 200, 9);
    let calibrated = folder.path().join("calibrated.toml").display().to_string();
    let identified = ParallelIdentifyRequest {
        robot: "hexapod".into(),
        method: "frame".into(),
        data: DataSource::File(data),
        stations: Vec::new(),
        leg_base: None,
        leg_platform: None,
        leg_gain: None,
        format: Default::default(),
        sigma: Some("20um".parse().expect("σ")),
        sigma_rotation: Some("20e-6rad".parse().expect("σ")),
        max_iterations: None,
        work_region: None,
        loss: None,
        loss_scale: None,
        reject: None,
        prior: None,
        output: Output::to(calibrated.clone()),
    }
    .run(&LocalFiles)
    .expect("identified");
    assert_eq!(
        identified.document.outcome, "fits_noise",
        "{}",
        identified.document.summary
    );
    assert_eq!(identified.document.rank, 48);
    let evaluate = |robot: &str| {
        ParallelEvaluateRequest {
            robot: robot.into(),
            method: "frame".into(),
            data: DataSource::File(held_out.clone()),
            format: Default::default(),
        }
        .run(&LocalFiles)
        .expect("evaluated")
        .errors
        .position_rms
    };
    let floor = evaluate(&folder.path().join("real.toml").display().to_string());
    let after = evaluate(&calibrated);
    let before = evaluate("hexapod");
    assert!(
        after <= 1.2 * floor,
        "{after} m against the floor's {floor} m"
    );
    assert!(before > 20.0 * floor, "{before} m before, floor {floor} m");
    // A job written for the nominal platform (targets and their nominal
    // actuator values), compensated: the real platform lands on its
    // targets at the calibration's precision, not 1 mm off.
    let job = folder.path().join("job.csv").display().to_string();
    ParallelGenerateRequest {
        robot: "hexapod".into(),
        method: "frame".into(),
        count: 40,
        configurations: None,
        format: Default::default(),
        error_level: Some(0.0),
        real: None,
        noise: 0.0,
        seed: Some(11),
        output: Output::to(job.clone()),
        real_save_as: None,
        leg_base: None,
        leg_platform: None,
        leg_gain: None,
    }
    .run(&LocalFiles)
    .expect("job");
    let corrected = folder.path().join("corrected.csv").display().to_string();
    let compensated = ParallelCompensateRequest {
        nominal: "hexapod".into(),
        calibrated: calibrated.clone(),
        program: DataSource::File(job.clone()),
        format: Default::default(),
        matching: None,
        output: Output::to(corrected.clone()),
    }
    .run(&LocalFiles)
    .expect("compensated");
    assert_eq!(compensated.targets, 40);
    assert!(compensated.failure().is_none());
    let real = gecaro_io::read_parallel_robot_file(&folder.path().join("real.toml"))
        .expect("real")
        .robot;
    let off_target = |program: &str| {
        let read = gecaro_io::read_samples(
            std::path::Path::new(program),
            &[gecaro_core::FrameType::Prismatic; 6],
            &[
                gecaro_calib::study::DataColumn::Position,
                gecaro_calib::study::DataColumn::Orientation,
            ],
            &Default::default(),
        )
        .expect("program");
        let squares: Vec<f64> = read
            .samples
            .to_rows()
            .iter()
            .map(|row| {
                let actuators: [f64; 6] = row.motor_positions.as_slice().try_into().expect("six");
                let reached = real.direct(&actuators, &real.home()).expect("pose");
                (reached.translation.vector - row.position.expect("target")).norm_squared()
            })
            .collect();
        (squares.iter().sum::<f64>() / squares.len() as f64).sqrt()
    };
    let (before, after) = (off_target(&job), off_target(&corrected));
    assert!(before > 0.5e-3 && after < 0.05e-3, "{before} m → {after} m");
    // What was written reads back as the platform identified.
    let read =
        gecaro_io::read_parallel_robot_file(std::path::Path::new(&calibrated)).expect("read");
    assert_eq!(
        read.robot.parameters(),
        identified.calibrated.robot.parameters()
    );
}

#[test]
fn identifiable_parameters_of_one_platform_point() {
    let report = ParallelIdentifiableRequest {
        robot: "hexapod".into(),
        method: "position".into(),
        data: None,
        format: Default::default(),
        count: None,
        seed: None,
    }
    .run(&LocalFiles)
    .expect("rank");
    assert_eq!(report.rank, 45);
    assert_eq!(report.regrouped.len(), 6);
    let report = ParallelIdentifiableRequest {
        robot: "hexapod".into(),
        method: "distance".into(),
        data: None,
        format: Default::default(),
        count: None,
        seed: None,
    }
    .run(&LocalFiles)
    .expect("rank");
    assert_eq!(report.rank, 39);
    let error = ParallelIdentifiableRequest {
        robot: "hexapod".into(),
        method: "plane1".into(),
        data: None,
        format: Default::default(),
        count: None,
        seed: None,
    }
    .run(&LocalFiles)
    .expect_err("refused")
    .to_string();
    assert!(
        error.contains("`position` (its tool point), `distance`"),
        "{error}"
    );
}

#[test]
fn a_serial_job_refuses_a_parallel_robot_by_name() {
    let error = gecaro_app::RobotSource::Named("hexapod".into())
        .load(&LocalFiles)
        .expect_err("refused")
        .to_string();
    assert!(error.contains("a parallel robot"), "{error}");
}
