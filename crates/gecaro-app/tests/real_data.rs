//! Calibrations of the real datasets in examples/real, judged on held-out data
//! (docs/real-data.md). The thresholds are what these data support, with margin.

use gecaro_app::read_study_file;
use gecaro_calib::{
    Quiet,
    identification::{IdentificationOptions, StopReason, evaluate, identify},
    methods::{MethodOptions, method},
    study::Study,
};
use gecaro_core::Robot;
use gecaro_io::{read_priority_file, read_samples};
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/real")
        .join(name)
}

/// The held-out RMS error (and orientation RMS) of `robot` on a data file.
fn held_out(robot: &Robot, name: &str, file: &str) -> (f64, Option<f64>) {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    let samples = read_samples(
        &example(file),
        &gecaro_io::joint_types(robot),
        chosen.data_columns(),
        &gecaro_io::DataFormat::default(),
    )
    .expect("data")
    .samples;
    let summary = evaluate(robot, &Study::single(chosen, samples, file)).expect("evaluation");
    (summary.rms, summary.rms_rotation)
}

fn calibrate(study: &Path, priority: Option<&Path>) -> (Robot, Robot) {
    let file = read_study_file(study).expect("study");
    let options = IdentificationOptions {
        priority: priority
            .map(|path| read_priority_file(path, &file.robot.robot).expect("priority"))
            .or(file.priority),
        ..IdentificationOptions::default()
    };
    let result =
        identify(&file.robot.robot, &file.study, &options, &mut Quiet).expect("identification");
    assert_eq!(result.stop_reason, StopReason::Converged);
    (file.robot.robot, result.calibrated)
}

#[test]
fn panda_point_link_and_distance_bring_the_held_out_scatter_to_a_quarter_millimetre() {
    let (nominal, calibrated) = calibrate(&example("mukca_panda_3/study.toml"), None);
    let (before, _) = held_out(&nominal, "point-link", "mukca_panda_3/test_sets.csv");
    let (after, _) = held_out(&calibrated, "point-link", "mukca_panda_3/test_sets.csv");
    assert!(
        before > 3e-3 && after < 0.35e-3,
        "scatter {before:e} → {after:e}"
    );
    let (before, _) = held_out(&nominal, "distance", "mukca_panda_3/test_pairs.csv");
    let (after, _) = held_out(&calibrated, "distance", "mukca_panda_3/test_pairs.csv");
    assert!(
        before > 3e-3 && after < 0.3e-3,
        "distance {before:e} → {after:e}"
    );
}

#[test]
fn gen3_lite_improves_only_with_a_light_model() {
    let study = example("mukca_dinova_2/study.toml");
    let (nominal, light) = calibrate(
        &study,
        Some(&example("mukca_dinova_2/priority_offsets.toml")),
    );
    let (before, _) = held_out(&nominal, "point-link", "mukca_dinova_2/test_sets.csv");
    let (after, _) = held_out(&light, "point-link", "mukca_dinova_2/test_sets.csv");
    assert!(after < 0.75 * before, "scatter {before:e} → {after:e}");
}

#[test]
fn ur10e_camera_finds_its_unknown_measurement_and_camera_frames() {
    let (nominal, calibrated) = calibrate(&example("ur10e_camera/study_frames.toml"), None);
    let (before, before_rotation) = held_out(&nominal, "frame", "ur10e_camera/test.csv");
    let (after, after_rotation) = held_out(&calibrated, "frame", "ur10e_camera/test.csv");
    assert!(
        before > 0.05 && after < 5e-3,
        "position {before:e} → {after:e}"
    );
    assert!(
        before_rotation.expect("frames") > 0.05
            && after_rotation.expect("frames") < 1f64.to_radians()
    );
}

#[test]
fn fr3_full_model_beats_the_frames_alone_on_held_out_poses() {
    let (nominal, frames) = calibrate(&example("fr3_camera/study_frames.toml"), None);
    let (_, full) = calibrate(&example("fr3_camera/study.toml"), None);
    let (before, _) = held_out(&nominal, "frame", "fr3_camera/test.csv");
    let (with_frames, _) = held_out(&frames, "frame", "fr3_camera/test.csv");
    let (with_model, rotation) = held_out(&full, "frame", "fr3_camera/test.csv");
    assert!(
        before > 0.01 && with_frames < 5e-3 && with_model < 2e-3,
        "{before:e} → {with_frames:e} → {with_model:e}"
    );
    assert!(rotation.expect("frames") < 0.3f64.to_radians());
}
