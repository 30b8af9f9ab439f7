//! End-to-end tests of the `gecaro` binary: each runs the real executable.

use std::path::Path;

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn gecaro() -> Command {
    Command::cargo_bin("gecaro").expect("the gecaro binary is built")
}

fn json_output(args: &[&str]) -> Value {
    let output = gecaro().args(args).output().expect("runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("valid JSON")
}

fn as_f64s(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("array")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect()
}

#[test]
fn fk_of_the_stanford_reference_configuration() {
    let pose = json_output(&["fk", "stanford", "--qm", "0,0,0.5,0,0,0", "--json"]);
    let position = as_f64s(&pose["position"]);
    let expected = [-0.0505392, 0.2, 1.0344655];
    for (got, want) in position.iter().zip(expected) {
        assert!((got - want).abs() < 1e-7, "{position:?}");
    }
    let rotation: Vec<Vec<f64>> = pose["rotation"]
        .as_array()
        .expect("rows")
        .iter()
        .map(as_f64s)
        .collect();
    // A rotation matrix: orthonormal rows.
    for i in 0..3 {
        for j in 0..3 {
            let dot: f64 = (0..3).map(|k| rotation[i][k] * rotation[j][k]).sum();
            assert!((dot - f64::from(u8::from(i == j))).abs() < 1e-12);
        }
    }
}

#[test]
fn jacobian_matches_finite_differences_of_fk() {
    let qm = [0.3, -0.4, 0.6, 0.2, 0.9, -1.1];
    let qm_text = qm.map(|v| v.to_string()).join(",");
    let jacobian = json_output(&["jacobian", "stanford", "--qm", &qm_text, "--json"]);
    let names: Vec<&str> = jacobian["parameters"]
        .as_array()
        .expect("names")
        .iter()
        .map(|v| v.as_str().expect("name"))
        .collect();
    assert_eq!(names.len(), 43);
    assert_eq!(names[..3], ["theta0", "r0", "alpha1"]);
    let rows: Vec<Vec<f64>> = jacobian["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .map(as_f64s)
        .collect();
    assert_eq!(rows.len(), 6);
    // The gain column K2 through the CLI: qm2 scales q2, so ∂P/∂K2 = qm2 · ∂P/∂q2.
    let position_at = |q2: f64| {
        let mut moved = qm;
        moved[1] = q2;
        let text = moved.map(|v| v.to_string()).join(",");
        as_f64s(&json_output(&["fk", "stanford", "--qm", &text, "--json"])["position"])
    };
    let step = 1e-6;
    let (plus, minus) = (position_at(qm[1] + step), position_at(qm[1] - step));
    let k2 = names.iter().position(|n| *n == "K2").expect("K2");
    for axis in 0..3 {
        let numeric = qm[1] * (plus[axis] - minus[axis]) / (2.0 * step);
        assert!((rows[axis][k2] - numeric).abs() < 1e-7, "axis {axis}");
    }
}

#[test]
fn robot_show_prints_the_table_and_priorities() {
    gecaro()
        .args(["robot", "show", "stanford"])
        .assert()
        .success()
        .stdout(predicate::str::contains("RRPRRR"))
        .stdout(predicate::str::contains("Priority matrix"))
        .stdout(predicate::str::contains("1.570796"));
}

#[test]
fn every_ready_robot_checks_out() {
    for name in [
        "stanford",
        "puma560",
        "industrial6",
        "scara",
        "panda",
        "ur10e",
    ] {
        gecaro()
            .args(["robot", "check", name])
            .assert()
            .success()
            .stdout(predicate::str::starts_with("ok:"));
    }
    // And the files in robots/ are the same robots.
    for entry in std::fs::read_dir("robots").expect("robots/") {
        let path = entry.expect("entry").path();
        gecaro()
            .args(["robot", "check"])
            .arg(&path)
            .assert()
            .success();
    }
}

#[test]
fn robot_check_names_file_line_and_key() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("broken.toml");
    let text = std::fs::read_to_string("robots/stanford.toml").expect("stanford");
    std::fs::write(&path, text.replace("sigma = 1", "sigma = 7")).expect("write");
    gecaro()
        .args(["robot", "check"])
        .arg(&path)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("broken.toml:25: frame 3, sigma"))
        .stderr(predicate::str::contains("panicked").not());
}

#[test]
fn robot_new_writes_a_loadable_template_and_refuses_to_overwrite() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("arm.toml");
    gecaro()
        .args(["robot", "new", "--joints", "RRPRRR", "-o"])
        .arg(&path)
        .assert()
        .success();
    gecaro()
        .args(["robot", "check"])
        .arg(&path)
        .assert()
        .success()
        .stdout(predicate::str::contains("RRPRRR"));
    let before = std::fs::read(&path).expect("read");
    gecaro()
        .args(["robot", "new", "--joints", "RR", "-o"])
        .arg(&path)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("--force"));
    assert_eq!(std::fs::read(&path).expect("read"), before);
    gecaro()
        .args(["robot", "new", "--joints", "RR", "--force", "-o"])
        .arg(&path)
        .assert()
        .success();
    assert!(Path::new(&path).exists());
}

#[test]
fn bad_command_lines_are_clear_errors() {
    gecaro()
        .args(["fk", "stanfrod", "--qm", "0,0,0,0,0,0"])
        .assert()
        .code(3)
        .stderr(predicate::str::contains("ready robots: stanford, puma560"));
    gecaro()
        .args(["fk", "stanford", "--qm", "0,0"])
        .assert()
        .code(3)
        .stderr(predicate::str::contains("needs 6 motor values"));
    gecaro()
        .args(["fk", "stanford", "--qm", "0,x"])
        .assert()
        .code(2);
    gecaro()
        .args(["fk", "no/such/robot.toml", "--qm", "0"])
        .assert()
        .code(3)
        .stderr(predicate::str::contains("no/such/robot.toml"));
}

#[test]
fn table2_prints_the_paper_totals() {
    gecaro()
        .args(["table2"])
        .assert()
        .success()
        .stdout(predicate::str::is_match(r"Total\s*┆\s*31\s*┆\s*34\s*┆\s*24\s*┆\s*21\s*┆\s*27\s*┆\s*24\s*┆\s*26\s*┆\s*24\s*┆\s*25").expect("regex"));
    let table = json_output(&["table2", "stanford", "--json"]);
    let totals: Vec<u64> = table["totals"]
        .as_array()
        .expect("totals")
        .iter()
        .map(|v| v.as_u64().expect("count"))
        .collect();
    assert_eq!(totals, [31, 34, 24, 21, 27, 24, 26, 24, 25]);
}

#[test]
fn identifiable_json_lists_every_parameter_in_vocabulary_order() {
    let report = json_output(&["identifiable", "stanford", "--method", "position", "--json"]);
    assert_eq!(report["count"], 31);
    assert_eq!(report["method"], "position");
    let parameters = report["parameters"].as_array().expect("parameters");
    assert_eq!(parameters.len(), 43);
    assert_eq!(parameters[0]["name"], "theta0");
    assert_eq!(parameters[42]["name"], "K6");
    let identifiable = parameters
        .iter()
        .filter(|p| p["status"] == "identifiable")
        .count();
    assert_eq!(identifiable, 31);
    assert!(report["condition_number"].as_f64().expect("number") > 1.0);
    assert_eq!(report["priority_matrix"].as_array().expect("rows").len(), 8);
    // A plane method with an unknown plane: a, b, c are auxiliary unknowns.
    let plane = json_output(&[
        "identifiable",
        "stanford",
        "--method",
        "plane1",
        "--plane",
        "unknown",
        "--plane-normal",
        "0.3,0.5,0.81",
        "--plane-point",
        "0.3,0.2,0.6",
        "--json",
    ]);
    assert_eq!(plane["count"], 24);
    assert_eq!(plane["auxiliary"].as_array().expect("auxiliary").len(), 3);
}

#[test]
fn identifiable_on_measured_data_checks_the_excitation() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let robot = gecaro_io::load_robot("stanford").expect("stanford").robot;
    let method =
        gecaro_calib::method("position", &gecaro_calib::MethodOptions::default()).expect("method");
    let samples =
        gecaro_calib::random_samples(&robot, method.as_ref(), Some(40), 9).expect("samples");
    let good = folder.path().join("good.csv");
    std::fs::write(
        &good,
        gecaro_io::format_samples(6, method.data_columns(), &samples),
    )
    .expect("write");
    gecaro()
        .args(["identifiable", "stanford", "--method", "position", "--data"])
        .arg(&good)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "same base set as random configurations",
        ));
    // Five configurations: 15 equations for 43 unknowns.
    let few = folder.path().join("few.csv");
    std::fs::write(
        &few,
        gecaro_io::format_samples(6, method.data_columns(), &samples[..5]),
    )
    .expect("write");
    gecaro()
        .args(["identifiable", "stanford", "--method", "position", "--data"])
        .arg(&few)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("too few equations"));
    // A NaN in the data: the line and the column.
    let nan = folder.path().join("nan.csv");
    let text = gecaro_io::format_samples(6, method.data_columns(), &samples);
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let mut fields: Vec<String> = lines[3].split(',').map(str::to_owned).collect();
    fields[7] = "NaN".into();
    lines[3] = fields.join(",");
    std::fs::write(&nan, lines.join("\n")).expect("write");
    gecaro()
        .args(["identifiable", "stanford", "--method", "position", "--data"])
        .arg(&nan)
        .assert()
        .code(3)
        .stderr(predicate::str::contains(
            "nan.csv:4: y: `NaN` is not a finite number",
        ));
}

#[test]
fn bad_method_options_are_usage_errors() {
    gecaro()
        .args(["identifiable", "stanford", "--method", "plane3"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("position").and(predicate::str::contains("distance")));
    gecaro()
        .args([
            "identifiable",
            "stanford",
            "--method",
            "plane1",
            "--plane-normal",
            "0,0,0",
            "--plane-point",
            "0.3,0.2,0.6",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("normal is zero"));
    gecaro()
        .args(["identifiable", "stanford", "--method", "plane2"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("needs a plane"));
}
