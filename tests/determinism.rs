//! The same inputs and seed give bit-identical outputs, run after run: each
//! run is a fresh process in its own folder, and every file it writes is
//! compared byte for byte.

use std::path::Path;

use assert_cmd::Command;

/// Runs a calibration from scratch in `folder`: generation (large enough for
/// the parallel kinematics), identification with plots, a report, and the
/// identifiable parameters as JSON.
fn calibrate(folder: &Path) -> Vec<(String, Vec<u8>)> {
    let run = |arguments: &[&str]| {
        let output = Command::cargo_bin("gecaro")
            .expect("binary")
            .args(arguments)
            .current_dir(folder)
            .output()
            .expect("runs");
        assert!(
            output.status.success(),
            "{arguments:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        output.stdout
    };
    run(&[
        "generate",
        "scara",
        "--method",
        "position",
        "--count",
        "1500",
        "--error-level",
        "3",
        "--noise",
        "2e-5",
        "--seed",
        "11",
        "-o",
        "train.csv",
        "--real-out",
        "real.toml",
    ]);
    run(&[
        "generate",
        "stanford",
        "--method",
        "plane1",
        "--count",
        "60",
        "--plane-normal",
        "0.3,0.5,0.81",
        "--plane-point",
        "0.02,0.02,0.53",
        "--seed",
        "5",
        "-o",
        "plane.csv",
    ]);
    let identified = run(&[
        "identify",
        "scara",
        "--method",
        "position",
        "--data",
        "train.csv",
        "-o",
        "calibrated.toml",
        "--plot",
        "plots",
        "--json",
    ]);
    run(&[
        "report",
        "scara",
        "--method",
        "position",
        "--data",
        "train.csv",
        "-o",
        "report.html",
    ]);
    let identifiable = run(&[
        "identifiable",
        "stanford",
        "--method",
        "plane1",
        "--plane",
        "unknown",
        "--data",
        "plane.csv",
        "--json",
    ]);
    let mut files: Vec<(String, Vec<u8>)> = [
        "train.csv",
        "real.toml",
        "plane.csv",
        "calibrated.toml",
        "report.html",
        "plots/convergence.svg",
        "plots/errors_histogram.svg",
        "plots/errors_per_configuration.svg",
    ]
    .iter()
    .map(|name| {
        (
            (*name).to_owned(),
            std::fs::read(folder.join(name)).expect(name),
        )
    })
    .collect();
    files.push(("identify --json".into(), identified));
    files.push(("identifiable --json".into(), identifiable));
    files
}

#[test]
fn the_same_inputs_and_seed_give_the_same_bytes() {
    let first = tempfile::tempdir().expect("folder");
    let second = tempfile::tempdir().expect("folder");
    let a = calibrate(first.path());
    let b = calibrate(second.path());
    for ((name, one), (_, two)) in a.iter().zip(&b) {
        assert!(one == two, "{name} differs between two identical runs");
        assert!(!one.is_empty(), "{name} is empty");
    }
}
