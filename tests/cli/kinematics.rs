//! The models from the command line: fk, jacobian (against finite differences), joint ranges of several turns, a point on a joint axis.

use super::*;

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
fn fk_and_jacobian_read_the_configuration_in_the_stated_units() {
    let si = json_output(&[
        "fk",
        "stanford",
        "--qm",
        "0.1,-0.4,0.5,0.2,0.9,-1.1",
        "--json",
    ]);
    let qm = [0.1_f64, -0.4, 0.5, 0.2, 0.9, -1.1];
    // Joint 3 of the Stanford arm is prismatic: millimetres; the others degrees.
    let stated: Vec<String> = qm
        .iter()
        .enumerate()
        .map(|(j, q)| {
            if j == 2 {
                (q * 1e3).to_string()
            } else {
                q.to_degrees().to_string()
            }
        })
        .collect();
    let stated = stated.join(",");
    let args = ["--angle-unit", "deg", "--length-unit", "mm", "--json"];
    for command in ["fk", "jacobian"] {
        let expected = if command == "fk" {
            si.clone()
        } else {
            json_output(&[
                "jacobian",
                "stanford",
                "--qm",
                "0.1,-0.4,0.5,0.2,0.9,-1.1",
                "--json",
            ])
        };
        let mut line = vec![command, "stanford", "--qm", &stated];
        line.extend(args);
        let got = json_output(&line);
        let (got, expected) = (got.to_string(), expected.to_string());
        let numbers = |text: &str| -> Vec<f64> {
            text.split(|c: char| !(c.is_ascii_digit() || "-.e".contains(c)))
                .filter_map(|word| word.parse().ok())
                .collect()
        };
        for (a, b) in numbers(&got).iter().zip(numbers(&expected)) {
            assert!((a - b).abs() < 1e-12, "{command}: {a} vs {b}");
        }
    }
    // The text gives the position in the stated length unit.
    gecaro()
        .args([
            "fk",
            "stanford",
            "--qm",
            &stated,
            "--length-unit",
            "mm",
            "--angle-unit",
            "deg",
        ])
        .assert()
        .success()
        .stdout(predicate::str::contains("position (mm)"));
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
fn joint_limits_may_span_several_turns() {
    // ABB IRB 120 axis 6 turns ±400°: limits beyond a turn are real; other
    // angles beyond a turn still say that the file looks like degrees.
    let folder = tempfile::tempdir().expect("temporary folder");
    let robot = folder.path().join("turns.toml");
    let text = "name = \"turns\"\n[[frame]]\nsigma = 2\n[[frame]]\nsigma = 0\nqmin = -6.981317\nqmax = 6.981317\n\
                [[frame]]\nsigma = 0\nd = 0.3\n[[frame]]\nsigma = 2\nd = 0.2\n";
    std::fs::write(&robot, text).expect("write");
    command("robot check").arg(&robot).assert().success();
    command("robot show")
        .arg(&robot)
        .assert()
        .success()
        .stdout(predicate::str::contains("6.981317"));
    std::fs::write(&robot, text.replace("d = 0.3", "d = 0.3\nalpha = 90")).expect("write");
    command("robot check")
        .arg(&robot)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("more than a full turn"));
}

#[test]
fn a_measured_point_on_a_joint_axis_is_named_before_any_data() {
    // The ready Panda's and UR10e's tool points lie on their last axis: a
    // position sensor cannot see the last joint turn.
    for (robot, joint) in [("panda", 7), ("ur10e", 6)] {
        let analysis = json_output(&["identifiable", robot, "--method", "position", "--json"]);
        let warnings = analysis["warnings"].as_array().expect("warnings");
        assert_eq!(warnings.len(), 1, "{robot}: {warnings:?}");
        let warning = warnings[0].as_str().expect("text");
        assert!(
            warning.starts_with(&format!("joint {joint} turns about the measured point")),
            "{warning}"
        );
        // A frame sensor sees it turn.
        let frames = json_output(&["identifiable", robot, "--method", "frame", "--json"]);
        assert_eq!(frames["warnings"].as_array().expect("warnings").len(), 0);
    }
    command("identifiable stanford --method position")
        .assert()
        .success()
        .stdout(predicate::str::contains("warning:").not());
}
