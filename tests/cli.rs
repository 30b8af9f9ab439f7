//! End-to-end tests of the `gecaro` binary: each runs the real executable.

use gecaro_calib::study::Samples;
use std::path::Path;

use crate::util::{gecaro, json_output};
use predicates::prelude::*;
use serde_json::Value;

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
fn robot_show_prints_the_table_and_priorities() {
    gecaro()
        .args(["robot", "show", "stanford"])
        .assert()
        .success()
        .stdout(predicate::str::contains("RRPRRR"))
        .stdout(predicate::str::contains("Priority matrix"))
        .stdout(predicate::str::contains("1.570796"));
}

/// The loads of elastic joints: a robot with masses lists them; one that
/// states a compliance lists every joint's; a rigid robot without masses
/// prints neither (its table unchanged).
#[test]
fn robot_show_prints_masses_and_compliances() {
    gecaro()
        .args(["robot", "show", "industrial6"])
        .assert()
        .success()
        .stdout(predicate::str::contains("Masses (51.3 kg;"))
        .stdout(predicate::str::contains("Compliances").not());
    let folder = tempfile::tempdir().expect("folder");
    let rigid = folder.path().join("arm.toml");
    gecaro()
        .args([
            "robot",
            "new",
            "--joints",
            "RR",
            "-o",
            rigid.to_str().expect("UTF-8"),
        ])
        .assert()
        .success();
    let text = std::fs::read_to_string(&rigid).expect("written");
    // After joint 1's gain line.
    let at = text.find("\nK = ").expect("a gain line") + 1;
    let end = at + text[at..].find('\n').expect("its end") + 1;
    let stated = format!("{}compliance = 5e-6\n{}", &text[..end], &text[end..]);
    assert_ne!(stated, text, "{text}");
    let elastic = folder.path().join("elastic.toml");
    std::fs::write(&elastic, stated).expect("written");
    gecaro()
        .args(["robot", "show", elastic.to_str().expect("UTF-8")])
        .assert()
        .success()
        .stdout(predicate::str::contains("c1 = 5.0e-6, c2 = 0"));
    gecaro()
        .args(["robot", "show", "stanford"])
        .assert()
        .success()
        .stdout(predicate::str::contains("Masses").not());
}

/// A study stating `model = "elastic"` identifies the compliances without
/// `--model`; `--model full` on the command line overrides it.
#[test]
fn a_study_s_model_is_the_default_of_the_command_line() {
    let folder = tempfile::tempdir().expect("folder");
    let path = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    for (index, payload) in ["0kg", "20kg,0,0,100mm"].iter().enumerate() {
        let mut args = vec![
            "generate".to_owned(),
            "industrial6".into(),
            "--method".into(),
            "position".into(),
            "--count".into(),
            "40".into(),
            "--noise".into(),
            "2e-5".into(),
            "--payload".into(),
            (*payload).into(),
            "--seed".into(),
            (index + 1).to_string(),
            "-o".into(),
            path(&format!("p{index}.csv")),
        ];
        let real: Vec<String> = if index == 0 {
            vec![
                "--compliance-level".into(),
                "1".into(),
                "--real-out".into(),
                path("real.toml"),
            ]
        } else {
            vec!["--real".into(), path("real.toml")]
        };
        args.extend(real);
        gecaro().args(&args).assert().success();
    }
    let study = path("payloads.toml");
    std::fs::write(
        &study,
        "robot = \"industrial6\"\nmodel = \"elastic\"\n\
         [[measurements]]\nmethod = \"position\"\ndata = \"p0.csv\"\nsigma = \"20um\"\n\
         [[measurements]]\nmethod = \"position\"\ndata = \"p1.csv\"\nsigma = \"20um\"\n",
    )
    .expect("written");
    let identify = |extra: &[&str]| {
        let output = gecaro()
            .args(["identify", "--study", &study, "--json"])
            .args(extra)
            .output()
            .expect("ran");
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        json["parameters"]
            .as_array()
            .expect("parameters")
            .iter()
            .filter(|p| p["name"].as_str().is_some_and(|name| name.starts_with('c')))
            .count()
    };
    assert!(identify(&[]) >= 2, "the study's elastic model");
    assert_eq!(
        identify(&["--model", "full"]),
        0,
        "the command line's model"
    );
    // The report's identifiable grid has the compliances' column.
    let report = path("report.html");
    gecaro()
        .args(["report", "--study", &study, "-o", &report])
        .assert()
        .success();
    let html = std::fs::read_to_string(&report).expect("report");
    assert!(html.contains("<th>K</th><th>c</th>"), "a column c");
}

/// The identifiable parameters of the elastic model list the compliances
/// in a column of their own (a vertical first axis: no effect), and their
/// priorities; a rigid model's table keeps its six columns.
#[test]
fn identifiable_compliances_have_their_column() {
    let folder = tempfile::tempdir().expect("folder");
    let data = folder.path().join("p.csv");
    let data = data.to_str().expect("UTF-8");
    gecaro()
        .args([
            "generate",
            "industrial6",
            "--method",
            "position",
            "--count",
            "30",
        ])
        .args(["--payload", "10kg", "--seed", "3", "-o", data])
        .assert()
        .success();
    let identifiable = |model: &str| {
        let output = gecaro()
            .args([
                "identifiable",
                "industrial6",
                "--method",
                "position",
                "--data",
                data,
            ])
            .args(["--model", model])
            .output()
            .expect("ran");
        assert!(output.status.success(), "{model}");
        String::from_utf8(output.stdout).expect("UTF-8")
    };
    let elastic = identifiable("elastic");
    assert!(elastic.contains("K ┆  c │"), "{elastic}");
    assert!(elastic.contains("id ┆  0 │"), "c1 has no effect: {elastic}");
    assert!(
        elastic.contains("K ┆ c │"),
        "the priorities' column: {elastic}"
    );
    assert!(!elastic.contains("tilt"), "{elastic}");
    // Gravity's tilts, analysed on typical compliances (the file states
    // none), and the note that says so.
    let leaning = identifiable("elastic-gravity");
    assert!(
        leaning.contains("gravity's tilts: tilt1 identifiable, tilt2 identifiable"),
        "{leaning}"
    );
    let rigid = identifiable("full");
    assert!(rigid.contains("K │") && !rigid.contains("┆  c"), "{rigid}");
}

#[test]
fn robot_show_of_the_stanford_arm_is_table_1() {
    // The whole text, column widths and all: a change of layout shows up here
    // as a diff to review (`cargo insta review`), not as a silent change.
    let output = gecaro()
        .args(["robot", "show", "stanford"])
        .output()
        .expect("runs");
    assert!(output.status.success());
    insta::assert_snapshot!(String::from_utf8(output.stdout).expect("utf-8"));
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
fn robot_reframe_keeps_every_link_s_mass_on_its_body() {
    // Masses on links 2 and 6 and on the tool, and a tilted gravity: after a
    // new world and a new tool, gravity loads every joint as before.
    let folder = tempfile::tempdir().expect("temporary folder");
    let stanford = gecaro_io::load_robot("stanford").expect("stanford");
    let mut file = gecaro_io::RobotFile::of(stanford.robot.clone());
    for (frame, mass, com) in [
        (2, 5.0, [0.1, 0.0, 0.02]),
        (6, 1.5, [0.0, 0.01, 0.04]),
        (7, 8.0, [0.0, 0.0, 0.1]),
    ] {
        file.masses
            .set_link(
                frame,
                gecaro_core::LinkMass {
                    mass,
                    com: com.into(),
                },
            )
            .expect("mass");
    }
    file.masses
        .set_gravity(nalgebra::Vector3::new(0.2, 0.0, -9.8))
        .expect("gravity");
    let original = folder.path().join("loaded.toml");
    std::fs::write(&original, gecaro_io::format_robot_file(&file)).expect("written");
    let moved = folder.path().join("moved.toml");
    gecaro()
        .args(["robot", "reframe"])
        .arg(&original)
        .args([
            "--world",
            "0.1,0.2,-0.5,0.9238795325112867,0,0.3826834323650898,0",
            "--tool",
            "0,0.05,0.1,0.7071067811865476,0.7071067811865476,0,0",
            "-o",
        ])
        .arg(&moved)
        .assert()
        .success();
    let before = gecaro_io::load_robot(original.to_str().expect("path")).expect("before");
    let after = gecaro_io::load_robot(moved.to_str().expect("path")).expect("after");
    assert!(!after.masses.is_empty());
    for q in [
        [0.3, -0.4, 0.6, 0.2, 0.9, -1.1],
        [-2.0, 1.0, 0.2, 3.0, -1.0, 0.5],
    ] {
        let torques = |file: &gecaro_io::RobotFile| {
            gecaro_core::gravity_torques(&file.robot, &file.masses, None, &q).expect("torques")
        };
        let (a, b) = (torques(&before), torques(&after));
        assert!((&a - &b).norm() < 1e-9 * a.norm(), "{a} vs {b}");
    }
}

#[test]
fn robot_reframe_moves_the_world_and_tool_frames_and_nothing_else() {
    use nalgebra::{IsometryMatrix3, Matrix3, Quaternion, Translation3, UnitQuaternion};
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("moved.toml");
    // The old world 0.5 m below and turned 45° about y; a tool 0.1 m out along
    // z and 5 cm along y, turned 90° about x.
    let (world, tool) = (
        "0.1,0.2,-0.5,0.9238795325112867,0,0.3826834323650898,0",
        "0,0.05,0.1,0.7071067811865476,0.7071067811865476,0,0",
    );
    gecaro()
        .args([
            "robot", "reframe", "stanford", "--world", world, "--tool", tool, "-o",
        ])
        .arg(&path)
        .assert()
        .success()
        .stdout(predicate::str::contains("frames 0, 1 and 6, 7 rewritten"));
    let pose = |text: &str| -> IsometryMatrix3<f64> {
        let v: Vec<f64> = text
            .split(',')
            .map(|x| x.parse().expect("number"))
            .collect();
        let rotation = UnitQuaternion::from_quaternion(Quaternion::new(v[3], v[4], v[5], v[6]));
        IsometryMatrix3::from_parts(
            Translation3::new(v[0], v[1], v[2]),
            rotation.to_rotation_matrix(),
        )
    };
    let fk = |robot: &str, qm: &str| -> IsometryMatrix3<f64> {
        let json = json_output(&["fk", robot, "--qm", qm, "--json"]);
        let p = as_f64s(&json["position"]);
        let rows: Vec<Vec<f64>> = json["rotation"]
            .as_array()
            .expect("rows")
            .iter()
            .map(as_f64s)
            .collect();
        let rotation = Matrix3::from_fn(|i, j| rows[i][j]);
        IsometryMatrix3::from_parts(
            Translation3::new(p[0], p[1], p[2]),
            nalgebra::Rotation3::from_matrix_unchecked(rotation),
        )
    };
    let moved = path.to_str().expect("utf-8 path");
    for qm in [
        "0,0,0.5,0,0,0",
        "0.3,-0.4,0.6,0.2,0.9,-1.1",
        "-2,1,0.2,3,-1,0.5",
    ] {
        let expected = pose(world) * fk("stanford", qm) * pose(tool);
        let got = fk(moved, qm);
        let difference = expected.inverse() * got;
        assert!(
            difference.translation.vector.norm() < 1e-9
                && (difference.rotation.matrix() - Matrix3::identity()).norm() < 1e-9,
            "{qm}: {difference:?}"
        );
    }
    // Only one of the two: frames 0, 1 only; nothing asked: a usage error, no file.
    let world_only = folder.path().join("world.toml");
    gecaro()
        .args(["robot", "reframe", "stanford", "--world", world, "-o"])
        .arg(&world_only)
        .assert()
        .success()
        .stdout(predicate::str::contains("frames 0, 1 rewritten"));
    let nothing = folder.path().join("nothing.toml");
    gecaro()
        .args(["robot", "reframe", "stanford", "-o"])
        .arg(&nothing)
        .assert()
        .failure()
        .stderr(predicate::str::contains("give --world, --tool or both"));
    gecaro()
        .args([
            "robot",
            "reframe",
            "stanford",
            "--tool",
            "0,0,0,2,0,0,0",
            "-o",
        ])
        .arg(&nothing)
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "--tool: (qw, qx, qy, qz) has norm 2.000000",
        ));
    assert!(!nothing.exists());
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
    // Observability: O3 = σ_min grows as √m with more configurations of the
    // same kind, O1 is normalised by √m and stays; O2 = O3/σ_max ≤ 1.
    let observability = |count: &str| {
        let report = json_output(&[
            "identifiable",
            "stanford",
            "--method",
            "position",
            "--count",
            count,
            "--json",
        ]);
        ["o1", "o2", "o3", "o4", "o5"]
            .map(|key| report["observability"][key].as_f64().expect("an index"))
    };
    let (few, many) = (observability("100"), observability("400"));
    assert!(
        (0.8..1.25).contains(&(many[0] / few[0])),
        "O1 {few:?} {many:?}"
    );
    assert!(
        (1.5..2.6).contains(&(many[2] / few[2])),
        "O3 {few:?} {many:?}"
    );
    assert!(few.iter().all(|v| *v > 0.0) && few[1] <= 1.0);
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
        gecaro_calib::methods::method("position", &gecaro_calib::methods::MethodOptions::default())
            .expect("method");
    let samples = gecaro_calib::identifiability::random_samples(
        &robot,
        method.as_ref(),
        Some(40),
        9,
        &mut gecaro_calib::Quiet,
    )
    .expect("samples");
    let good = folder.path().join("good.csv");
    std::fs::write(
        &good,
        gecaro_io::format_samples(
            6,
            method.data_columns(),
            Samples::from(samples.as_slice()).as_slice(),
        ),
    )
    .expect("write");
    gecaro()
        .args(["identifiable", "stanford", "--method", "position", "--data"])
        .arg(&good)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "the data excite every identifiable parameter",
        ));
    // Five configurations: 15 equations for 43 unknowns.
    let few = folder.path().join("few.csv");
    std::fs::write(
        &few,
        gecaro_io::format_samples(
            6,
            method.data_columns(),
            Samples::from(&samples[..5]).as_slice(),
        ),
    )
    .expect("write");
    gecaro()
        .args(["identifiable", "stanford", "--method", "position", "--data"])
        .arg(&few)
        .assert()
        .code(4)
        .stderr(predicate::str::contains("too few equations"));
    // A NaN in the data: the line and the column.
    let nan = folder.path().join("nan.csv");
    let text = gecaro_io::format_samples(
        6,
        method.data_columns(),
        Samples::from(samples.as_slice()).as_slice(),
    );
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

#[test]
fn generate_identify_evaluate_round_trip() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let data = folder.path().join("train.csv");
    let held_out = folder.path().join("test.csv");
    let real = folder.path().join("real.toml");
    let calibrated = folder.path().join("calibrated.toml");
    gecaro()
        .args([
            "generate",
            "stanford",
            "--method",
            "position",
            "--count",
            "40",
            "--error-level",
            "2",
            "--seed",
            "3",
            "-o",
        ])
        .arg(&data)
        .arg("--real-out")
        .arg(&real)
        .assert()
        .success()
        .stdout(predicate::str::contains("wrote 40 configurations"));
    let header = std::fs::read_to_string(&data).expect("data");
    // A comment says where the data came from; the reader skips it.
    assert!(
        header.starts_with(
            "# gecaro generate: 40 position measurements of a real robot drawn from Stanford \
             at error level 2 (seed 3), configurations drawn with seed 3; sensor noise sigma 0 m"
        ),
        "{header}"
    );
    assert!(
        header.contains("\nqm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n"),
        "{header}"
    );
    // Held-out data from the same real robot, other configurations.
    gecaro()
        .args([
            "generate", "stanford", "--method", "position", "--count", "30", "--seed", "4",
            "--real",
        ])
        .arg(&real)
        .arg("-o")
        .arg(&held_out)
        .assert()
        .success();
    let identification = gecaro()
        .args([
            "identify", "stanford", "--method", "position", "--json", "--data",
        ])
        .arg(&data)
        .arg("-o")
        .arg(&calibrated)
        .output()
        .expect("runs");
    assert!(
        identification.status.success(),
        "{}",
        String::from_utf8_lossy(&identification.stderr)
    );
    let report: Value = serde_json::from_slice(&identification.stdout).expect("JSON");
    assert_eq!(report["converged"], true);
    assert_eq!(report["stop_reason"], "converged");
    assert_eq!(report["method"], "position");
    assert!(report["iterations"].as_u64().expect("count") <= 6);
    assert_eq!(
        report["parameters"].as_array().expect("parameters").len(),
        31
    );
    assert!(report["rms_after"].as_f64().expect("rms") < 1e-10);
    assert_eq!(
        report["rms_history"].as_array().expect("history").len() as u64,
        report["iterations"].as_u64().expect("count") + 1
    );
    for parameter in report["parameters"].as_array().expect("parameters") {
        for key in ["name", "nominal", "identified", "std"] {
            assert!(parameter.get(key).is_some(), "{key}");
        }
    }
    // The calibrated robot file loads everywhere and predicts held-out data of the real robot.
    gecaro()
        .args(["robot", "check"])
        .arg(&calibrated)
        .assert()
        .success();
    let before = json_output(&[
        "evaluate",
        "stanford",
        "--method",
        "position",
        "--json",
        "--data",
        held_out.to_str().expect("utf-8"),
    ]);
    let after = json_output(&[
        "evaluate",
        calibrated.to_str().expect("utf-8"),
        "--method",
        "position",
        "--json",
        "--data",
        held_out.to_str().expect("utf-8"),
    ]);
    assert_eq!(after["count"], 30);
    assert!(before["rms"].as_f64().expect("rms") > 1e-3);
    assert!(after["rms"].as_f64().expect("rms") < 1e-9, "{after}");
    // The same file as a spreadsheet exports it: `;` and decimal commas,
    // with the separator named by its character.
    let text = std::fs::read_to_string(&held_out).expect("held out");
    let semicolons = folder.path().join("held_out_semicolons.csv");
    std::fs::write(&semicolons, text.replace(',', ";").replace('.', ",")).expect("written");
    for delimiter in [";", "semicolon"] {
        let again = json_output(&[
            "evaluate",
            calibrated.to_str().expect("utf-8"),
            "--method",
            "position",
            "--json",
            "--delimiter",
            delimiter,
            "--data",
            semicolons.to_str().expect("utf-8"),
        ]);
        assert_eq!(again, after, "--delimiter {delimiter}");
    }
}

/// A noise-free frame fit whose W all but loses a direction (the Stanford
/// arm at seed 11, 60 configurations: θ3, θ4 and the tilt of z4). The last
/// step computed there was long (0.12 rad) and lowered nothing; applied
/// through the linear model `r ← r − W Δ`, it gave a calibrated robot file
/// 0.011 mm RMS from its own data while the report said 0. The file written
/// must reproduce what the report says of it.
#[test]
fn the_calibrated_robot_file_reproduces_the_residuals_its_report_states() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = |name: &str| folder.path().join(name).to_str().expect("utf-8").to_owned();
    let (data, calibrated) = (path("frames.csv"), path("calibrated.toml"));
    let (real, held_out) = (path("real.toml"), path("held_out.csv"));
    gecaro()
        .args(["generate", "stanford", "--method", "frame", "--count", "60"])
        .args(["--error-level", "1", "--noise", "0", "--seed", "11"])
        .args(["-o", &data, "--real-out", &real])
        .assert()
        .success();
    // Other configurations of the same real robot, to judge the file where
    // its user will.
    gecaro()
        .args([
            "generate", "stanford", "--method", "frame", "--count", "200",
        ])
        .args([
            "--noise", "0", "--seed", "5", "--real", &real, "-o", &held_out,
        ])
        .assert()
        .success();
    let report = json_output(&[
        "identify",
        "stanford",
        "--method",
        "frame",
        "--json",
        "--data",
        &data,
        "-o",
        &calibrated,
    ]);
    assert_eq!(report["stop_reason"], "converged");
    let stated = report["rms_after"].as_f64().expect("rms");
    assert!(stated < 1e-10, "{stated:e}");
    // Residuals at rounding leave nothing for parameters outside the base
    // set to explain: no second pass, no damped descent reading rounding
    // for structure ("took the RMS error from 0.0000 to 0.0000 mm").
    assert_eq!(report["second_pass"], serde_json::json!([]), "{report}");
    assert_eq!(report["moved"], serde_json::json!([]), "{report}");
    for warning in report["warnings"].as_array().expect("warnings") {
        let warning = warning.as_str().expect("text");
        assert!(!warning.contains("outside the base set"), "{warning}");
    }
    // The written file's RMS error on a data file, as `evaluate` reads it.
    let rms_on = |file: &str| {
        let args = [
            "evaluate",
            &calibrated,
            "--method",
            "frame",
            "--json",
            "--data",
            file,
        ];
        json_output(&args)["rms"].as_f64().expect("rms")
    };
    let again = rms_on(&data);
    assert!(
        again < 1e-10,
        "the calibrated robot misses its own data by {again:e} m RMS; the report said {stated:e}"
    );
    let held = rms_on(&held_out);
    assert!(held < 1e-10, "held-out {held:e} m RMS");
}

#[test]
fn identification_failures_exit_4_and_write_nothing() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let data = folder.path().join("far.csv");
    let output = folder.path().join("calibrated.toml");
    gecaro()
        .args([
            "generate",
            "stanford",
            "--method",
            "position",
            "--count",
            "40",
            "--error-level",
            "10",
            "--seed",
            "2",
            "-o",
        ])
        .arg(&data)
        .assert()
        .success();
    gecaro()
        .args([
            "identify",
            "stanford",
            "--method",
            "position",
            "--max-iterations",
            "1",
            "--data",
        ])
        .arg(&data)
        .arg("-o")
        .arg(&output)
        .assert()
        .code(4)
        .stderr(predicate::str::contains("did not converge"))
        .stderr(predicate::str::contains("Nothing was written"));
    assert!(!output.exists());
    gecaro()
        .args([
            "identify",
            "stanford",
            "--method",
            "position",
            "--max-iterations",
            "1",
            "--write-unconverged",
            "--data",
        ])
        .arg(&data)
        .arg("-o")
        .arg(&output)
        .assert()
        .code(4);
    assert!(output.exists(), "the best iterate is written when asked");
}

#[test]
fn generate_refuses_existing_outputs_before_doing_anything() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let data = folder.path().join("data.csv");
    std::fs::write(&data, "keep me").expect("write");
    gecaro()
        .args([
            "generate", "stanford", "--method", "distance", "--count", "10", "-o",
        ])
        .arg(&data)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("--force"));
    assert_eq!(std::fs::read_to_string(&data).expect("read"), "keep me");
    gecaro()
        .args([
            "generate", "stanford", "--method", "distance", "--count", "10", "-o",
        ])
        .arg(folder.path().join("missing/data.csv"))
        .assert()
        .code(3)
        .stderr(predicate::str::contains("does not exist"));
}

#[test]
fn demo_identifies_every_method() {
    gecaro()
        .args(["demo"])
        .assert()
        .success()
        .stdout(predicate::str::contains("Position measure"))
        .stdout(predicate::str::contains("Distance measure"))
        .stdout(predicate::str::contains("Plane link 2"));
}

#[test]
fn studies_stack_several_methods_from_a_file() {
    let study = Path::new("examples/real/mukca_panda_3/study.toml");
    let report = json_output(&[
        "identifiable",
        "--study",
        study.to_str().expect("utf-8"),
        "--json",
    ]);
    assert_eq!(report["method"], "point-link+distance");
    assert_eq!(report["excitation"]["same_base_set"], true, "{report}");
    let folder = tempfile::tempdir().expect("temporary folder");
    let calibrated = folder.path().join("calibrated.toml");
    let output = gecaro()
        .args(["identify", "--study"])
        .arg(study)
        .arg("--json")
        .arg("-o")
        .arg(&calibrated)
        .output()
        .expect("runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let result: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(result["converged"], true);
    assert!(result["after"]["rms"].as_f64().expect("rms") < 0.5e-3);
    // The held-out scatter of the ball, as `evaluate --json` reports it.
    let before = json_output(&[
        "evaluate",
        "examples/real/mukca_panda_3/robot.toml",
        "--method",
        "point-link",
        "--json",
        "--data",
        "examples/real/mukca_panda_3/test_sets.csv",
    ]);
    let after = json_output(&[
        "evaluate",
        calibrated.to_str().expect("utf-8"),
        "--method",
        "point-link",
        "--json",
        "--data",
        "examples/real/mukca_panda_3/test_sets.csv",
    ]);
    assert!(before["rms"].as_f64().expect("rms") > 3e-3);
    assert!(after["rms"].as_f64().expect("rms") < 0.35e-3, "{after}");
    // --study excludes ROBOT and --method.
    gecaro()
        .args(["identify", "stanford", "--study"])
        .arg(study)
        .assert()
        .code(2);
}

#[test]
fn study_files_report_their_own_mistakes() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let study = folder.path().join("study.toml");
    std::fs::write(&study, "robot = \"stanford\"\n[[measurements]]\nmethod = \"point-lnk\"\ndata = \"x.csv\"\nsigma = 0.001\n").expect("write");
    gecaro()
        .args(["identify", "--study"])
        .arg(&study)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("study.toml:3: method"))
        .stderr(predicate::str::contains("point-link"));
    std::fs::write(&study, "robot = \"stanford\"\n[[measurements]]\nmethod = \"distance\"\ndata = \"x.csv\"\nsigma = -1\n").expect("write");
    gecaro()
        .args(["identify", "--study"])
        .arg(&study)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("sigma: must be a positive"));
}

/// Text of every `<text>` element of an SVG, for checking what a plot says.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|rest| {
            let start = rest.find('>')? + 1;
            let end = rest.find("</text>")?;
            Some(rest[start..end].trim().to_owned())
        })
        .collect()
}

#[test]
fn report_and_plots_show_the_identification() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let data = folder.path().join("frame.csv");
    let report = folder.path().join("report.html");
    let plots = folder.path().join("plots");
    gecaro()
        .args([
            "generate", "scara", "--method", "frame", "--count", "25", "--noise", "1e-5", "-o",
        ])
        .arg(&data)
        .assert()
        .success();
    gecaro()
        .args(["report", "scara", "--method", "frame", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&report)
        .assert()
        .success()
        .stdout(predicate::str::contains("wrote the report"));
    let html = std::fs::read_to_string(&report).expect("report");
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    // Self-contained: no scripts, stylesheets or images fetched from anywhere.
    for fetch in ["src=\"http", "href=\"http", "<script", "<link", "url("] {
        assert!(!html.contains(fetch), "the report fetches {fetch}");
    }
    for section in [
        "Convergence",
        "Errors before and after",
        "Identified parameters",
        "Identifiable parameters",
        "Robot (nominal)",
    ] {
        assert!(html.contains(&format!("<h2>{section}</h2>")), "{section}");
    }
    assert_eq!(
        html.matches("<svg").count(),
        4,
        "convergence, histograms, per configuration, robot"
    );
    assert!(
        html.contains("gecaro report scara --method frame --data"),
        "the command line is recorded"
    );
    assert!(html.contains("converged after"));
    // Text from the user's files and command line is escaped, quotes included.
    let hostile = folder.path().join("hostile.toml");
    let scara = std::fs::read_to_string("robots/scara.toml").expect("scara");
    let renamed: String = scara
        .lines()
        .map(|line| {
            if line.starts_with("name =") {
                r#"name = "<b>x</b> & 'y' \"z\"""#.to_owned()
            } else {
                line.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(&hostile, renamed).expect("write");
    let escaped = folder.path().join("escaped.html");
    gecaro()
        .arg("report")
        .arg(&hostile)
        .args(["--method", "frame", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&escaped)
        .assert()
        .success();
    let page = std::fs::read_to_string(&escaped).expect("report");
    assert!(!page.contains("<b>x</b>"), "markup from a robot name");
    assert!(page.contains("&lt;b&gt;x&lt;/b&gt; &amp; 'y' &quot;z&quot;"));
    // Every identified parameter has a row with its σ.
    let identified = json_output(&[
        "identify",
        "scara",
        "--method",
        "frame",
        "--json",
        "--data",
        data.to_str().expect("utf-8"),
    ]);
    for parameter in identified["parameters"].as_array().expect("parameters") {
        let name = parameter["name"].as_str().expect("name");
        assert!(html.contains(&format!("<td>{name}</td>")), "{name}");
    }
    // The same report again needs --force, and leaves the first intact without it.
    gecaro()
        .args(["report", "scara", "--method", "frame", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&report)
        .assert()
        .code(3);
    assert_eq!(std::fs::read_to_string(&report).expect("report"), html);

    gecaro()
        .args(["identify", "scara", "--method", "frame", "--data"])
        .arg(&data)
        .arg("--plot")
        .arg(&plots)
        .assert()
        .success()
        .stdout(predicate::str::contains("wrote the plots"));
    let convergence = std::fs::read_to_string(plots.join("convergence.svg")).expect("svg");
    let texts = svg_texts(&convergence);
    assert!(texts.iter().any(|t| t == "iteration"), "{texts:?}");
    // One marker per iterate of the history (plus none elsewhere).
    let iterations = identified["iterations"].as_u64().expect("count") as usize;
    assert_eq!(convergence.matches("<circle").count(), iterations + 1);
    let per_configuration =
        std::fs::read_to_string(plots.join("errors_per_configuration.svg")).expect("svg");
    // 25 configurations before and after, plus two legend markers.
    assert_eq!(per_configuration.matches("<circle").count(), 2 * 25 + 2);
    assert!(plots.join("errors_histogram.svg").is_file());
}

#[test]
fn a_reader_that_goes_away_ends_the_output_quietly() {
    // `gecaro robot show stanford | head -1`: no panic about a failed print.
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("gecaro"))
        .args(["robot", "show", "stanford"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    drop(child.stdout.take());
    let output = child.wait_with_output().expect("ends");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn plan_writes_the_chosen_configurations_and_beats_a_random_choice() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let output = folder.path().join("planned.csv");
    let output_text = output.to_str().expect("utf-8");
    let report = json_output(&[
        "plan",
        "stanford",
        "--method",
        "point-link",
        "--count",
        "40",
        "--pool",
        "400",
        "--seed",
        "2",
        "-o",
        output_text,
        "--json",
    ]);
    assert_eq!(report["configurations"], 40);
    assert_eq!(report["units"], 10);
    assert!(report["log_det"].as_f64().expect("D") > report["random_log_det"].as_f64().expect("D"));
    let text = std::fs::read_to_string(&output).expect("planned file");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("qm1,qm2,qm3,qm4,qm5,qm6,set"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 40);
    // Whole sets of four, each set id four times.
    let mut sets = std::collections::BTreeMap::new();
    for row in &rows {
        *sets
            .entry(row.rsplit(',').next().expect("set").to_owned())
            .or_insert(0) += 1;
    }
    assert!(sets.values().all(|count| *count == 4), "{sets:?}");
    // The same inputs give the same plan; an existing output is kept.
    gecaro()
        .args([
            "plan",
            "stanford",
            "--method",
            "point-link",
            "--count",
            "40",
        ])
        .args(["--pool", "400", "--seed", "2", "-o", output_text])
        .assert()
        .code(3)
        .stderr(predicate::str::contains("already exists"));
    let again = folder.path().join("again.csv");
    gecaro()
        .args([
            "plan",
            "stanford",
            "--method",
            "point-link",
            "--count",
            "40",
        ])
        .args(["--pool", "400", "--seed", "2", "-o"])
        .arg(&again)
        .assert()
        .success();
    assert_eq!(std::fs::read_to_string(&again).expect("again"), text);
    // More than the pool holds is a usage error.
    gecaro()
        .args([
            "plan", "stanford", "--method", "position", "--count", "40", "--pool", "20",
        ])
        .arg("-o")
        .arg(folder.path().join("too-many.csv"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--count"));
}

/// A plan written for a teach pendant (degrees, its own joint names, `;`
/// and decimal commas) holds the same configurations as in radians, and
/// `predict` reads it back in those units to the same prediction.
#[test]
fn a_plan_is_written_in_the_robot_s_own_units_and_read_back() {
    let folder = tempfile::tempdir().expect("folder");
    let file = |name: &str| folder.path().join(name).display().to_string();
    let plan = |output: &str, extra: &[&str]| {
        let mut args = vec![
            "plan",
            "industrial6",
            "--method",
            "position",
            "--count",
            "12",
            "--pool",
            "300",
            "-o",
            output,
        ];
        args.extend(extra);
        gecaro().args(&args).assert().success();
    };
    let pendant = [
        "--angle-unit",
        "deg",
        "--delimiter",
        ";",
        "--decimal-comma",
        "--columns",
        "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6",
    ];
    plan(&file("si.csv"), &[]);
    plan(&file("pendant.csv"), &pendant);
    let si = std::fs::read_to_string(file("si.csv")).expect("si");
    let pendant_text = std::fs::read_to_string(file("pendant.csv")).expect("pendant");
    // In degrees, the file says so before its header; in radians, nothing.
    assert!(
        pendant_text.starts_with("# units: angle_unit = deg, length_unit = m\nA1;A2;A3;A4;A5;A6\n"),
        "{pendant_text}"
    );
    assert!(si.starts_with("qm1,"), "{si}");
    for (a, b) in si.lines().skip(1).zip(pendant_text.lines().skip(2)) {
        for (radians, degrees) in a.split(',').zip(b.split(';')) {
            let radians: f64 = radians.parse().expect("number");
            let degrees: f64 = degrees.replace(',', ".").parse().expect("number");
            assert!((radians.to_degrees() - degrees).abs() < 1e-9, "{a} / {b}");
        }
    }
    let predict = |data: &str, extra: &[&str]| {
        let mut args = vec![
            "predict",
            "industrial6",
            "--method",
            "position",
            "--noise",
            "2e-5",
            "--json",
            "--data",
            data,
        ];
        args.extend(extra);
        json_output(&args)
    };
    let mut read_back = pendant.to_vec();
    read_back.retain(|arg| *arg != "--decimal-comma");
    let (a, b) = (
        predict(&file("si.csv"), &[]),
        predict(&file("pendant.csv"), &read_back),
    );
    assert_eq!(a["configurations"], b["configurations"]);
    let (a, b) = (
        a["predicted"]["position_rms"].as_f64().expect("rms"),
        b["predicted"]["position_rms"].as_f64().expect("rms"),
    );
    assert!((a - b).abs() < 1e-9 * a, "{a} vs {b}");
}

#[test]
fn plan_by_other_criteria_with_a_minimum_distance_and_test_poses() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = |name: &str| folder.path().join(name).to_str().expect("utf-8").to_owned();
    let common = [
        "plan", "stanford", "--method", "position", "--count", "24", "--pool", "240", "--json",
    ];
    for criterion in ["a", "e", "o4", "o5"] {
        let output = path(&format!("{criterion}.csv"));
        let mut args = common.to_vec();
        args.extend([
            "--criterion",
            criterion,
            "--min-distance",
            "1",
            "-o",
            &output,
        ]);
        let report = json_output(&args);
        assert_eq!(report["criterion"], criterion);
        let (mine, random) = (
            report["value"].as_f64().expect("value"),
            report["random_value"].as_f64().expect("random"),
        );
        // A is minimised, the others maximised.
        assert!(
            if criterion == "a" {
                mine < random
            } else {
                mine > random
            },
            "{criterion}: {mine} vs {random}"
        );
        assert_eq!(
            std::fs::read_to_string(&output)
                .expect("plan")
                .lines()
                .count(),
            25
        );
    }
    // Test poses from a file (the A plan's configurations, as a stand-in for
    // where the robot works): the value is the predicted error per unit σ,
    // which `gecaro predict` gives on another route.
    let output = path("test.csv");
    let mut args = common.to_vec();
    let poses = path("a.csv");
    args.extend(["--criterion", "test", "--test-poses", &poses, "-o", &output]);
    let report = json_output(&args);
    let per_sigma = report["value"].as_f64().expect("value");
    let predicted = json_output(&[
        "predict",
        "stanford",
        "--method",
        "position",
        "--data",
        &output,
        "--noise",
        "1e-4",
        "--test-poses",
        &poses,
        "--json",
    ]);
    assert_eq!(predicted["test_poses"], 24);
    let rms = predicted["predicted"]["position_rms"]
        .as_f64()
        .expect("rms");
    assert!(
        (rms / (per_sigma * 1e-4) - 1.0).abs() < 1e-6,
        "{rms} vs {per_sigma}"
    );
    // An impossible distance names the option.
    gecaro()
        .args(&common[..common.len() - 1])
        .args(["--min-distance", "40", "-o"])
        .arg(path("far.csv"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--min-distance"));
    assert!(!folder.path().join("far.csv").exists());
}

#[test]
fn predict_agrees_with_its_monte_carlo_and_refuses_bad_input() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let planned = folder.path().join("planned.csv");
    gecaro()
        .args(["plan", "panda", "--method", "frame", "--count", "30", "-o"])
        .arg(&planned)
        .assert()
        .success();
    let planned_text = planned.to_str().expect("utf-8");
    let report = json_output(&[
        "predict",
        "panda",
        "--method",
        "frame",
        "--data",
        planned_text,
        "--noise",
        "5e-5",
        "--monte-carlo",
        "300",
        "--json",
    ]);
    let parameters = report["parameters"].as_array().expect("parameters");
    assert!(parameters.len() > 30);
    assert!(
        parameters
            .iter()
            .all(|p| p["sigma"].as_f64().is_some_and(|s| s > 0.0 && s < 1e-2))
    );
    let ratio = report["monte_carlo"]["position_ratio"]
        .as_f64()
        .expect("ratio");
    assert!((ratio - 1.0).abs() < 0.15, "measured / predicted {ratio}");
    assert!(report["predicted"]["rotation_rms"].as_f64().is_some());
    // Text output names both rows.
    gecaro()
        .args([
            "predict",
            "panda",
            "--method",
            "frame",
            "--data",
            planned_text,
        ])
        .args(["--noise", "5e-5", "--monte-carlo", "20"])
        .assert()
        .success()
        .stdout(
            predicate::str::contains("predicted")
                .and(predicate::str::contains("Monte Carlo (20 runs)")),
        );
    // Too few configurations; a bad σ.
    let few = folder.path().join("few.csv");
    std::fs::write(
        &few,
        std::fs::read_to_string(&planned)
            .expect("planned")
            .lines()
            .take(4)
            .collect::<Vec<_>>()
            .join("\n"),
    )
    .expect("written");
    gecaro()
        .args([
            "predict", "panda", "--method", "frame", "--noise", "1e-4", "--data",
        ])
        .arg(&few)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("equations").or(predicate::str::contains("do not determine")),
        );
    gecaro()
        .args([
            "predict", "panda", "--method", "frame", "--noise", "-1", "--data",
        ])
        .arg(&planned)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--noise"));
}

#[test]
fn the_curve_shows_planned_below_random_as_a_table_json_and_svg() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let plot = folder.path().join("curve.svg");
    let report = json_output(&[
        "plan",
        "stanford",
        "--method",
        "position",
        "--curve",
        "8,12,24,48",
        "--noise",
        "1e-4",
        "--pool",
        "600",
        "--json",
        "--plot",
        plot.to_str().expect("utf-8"),
    ]);
    let points = report["points"].as_array().expect("points");
    assert_eq!(points.len(), 4);
    // 8 configurations (24 equations) cannot determine 31 parameters.
    assert!(points[0]["planned"].is_null());
    let planned: Vec<f64> = points[1..]
        .iter()
        .map(|p| p["planned"].as_f64().expect("planned"))
        .collect();
    let random: Vec<f64> = points[1..]
        .iter()
        .map(|p| p["random"].as_f64().expect("random"))
        .collect();
    assert!(planned.windows(2).all(|w| w[1] < w[0]), "{planned:?}");
    assert!(
        planned.iter().zip(&random).all(|(p, r)| p < r),
        "{planned:?} {random:?}"
    );
    let svg = std::fs::read_to_string(&plot).expect("svg");
    assert!(svg.starts_with("<svg") && svg.contains("planned") && svg.contains("random"));
    gecaro()
        .args([
            "plan", "stanford", "--method", "position", "--curve", "10,20", "--pool", "300",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--noise"));
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
    gecaro()
        .args(["robot", "check"])
        .arg(&robot)
        .assert()
        .success();
    gecaro()
        .args(["robot", "show"])
        .arg(&robot)
        .assert()
        .success()
        .stdout(predicate::str::contains("6.981317"));
    std::fs::write(&robot, text.replace("d = 0.3", "d = 0.3\nalpha = 90")).expect("write");
    gecaro()
        .args(["robot", "check"])
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
    gecaro()
        .args(["identifiable", "stanford", "--method", "position"])
        .assert()
        .success()
        .stdout(predicate::str::contains("warning:").not());
}

#[test]
fn a_plan_in_degrees_is_measured_in_degrees() {
    // A plan for a teach pendant (degrees) measured at with the same units:
    // before, `generate --configurations` read every plan in radians.
    // (docs/data-files.md: a file in other units than gecaro's says so.)
    let folder = tempfile::tempdir().expect("folder");
    let plan = folder.path().join("plan.csv");
    let data = folder.path().join("data.csv");
    gecaro()
        .args(["plan", "stanford", "--method", "position", "--count", "15"])
        .args(["--angle-unit", "deg", "-o"])
        .arg(&plan)
        .assert()
        .success();
    gecaro()
        .args([
            "generate",
            "stanford",
            "--method",
            "position",
            "--error-level",
            "0",
        ])
        .arg("--configurations")
        .arg(&plan)
        .args(["--angle-unit", "deg", "-o"])
        .arg(&data)
        .assert()
        .success();
    let rows = |path: &Path| -> Vec<Vec<f64>> {
        std::fs::read_to_string(path)
            .expect("file")
            .lines()
            .filter(|line| !line.starts_with('#'))
            .skip(1)
            .map(|line| {
                line.split(',')
                    .take(6)
                    .map(|value| value.parse().expect("number"))
                    .collect()
            })
            .collect()
    };
    // The plan states its units: read without --angle-unit, the same
    // configurations (before, 28° were read as 28 rad, silently); a request
    // for other units than the file states is refused, naming its line.
    let unstated = folder.path().join("unstated.csv");
    gecaro()
        .args(["generate", "stanford", "--method", "position"])
        .args(["--error-level", "0", "--configurations"])
        .arg(&plan)
        .arg("-o")
        .arg(&unstated)
        .assert()
        .success();
    assert_eq!(rows(&unstated), rows(&data));
    gecaro()
        .args([
            "generate",
            "stanford",
            "--method",
            "position",
            "--configurations",
        ])
        .arg(&plan)
        .args(["--length-unit", "mm", "-o"])
        .arg(folder.path().join("refused.csv"))
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "plan.csv:1: the file states its lengths in m, and it is read in mm",
        ));
    let (planned, measured) = (rows(&plan), rows(&data));
    assert_eq!(planned.len(), measured.len());
    for (degrees, radians) in planned.iter().zip(&measured) {
        for (joint, (a, b)) in degrees.iter().zip(radians).enumerate() {
            // Joint 3 of the Stanford arm is prismatic: metres either way.
            let expected = if joint == 2 { *a } else { a.to_radians() };
            assert!(
                (expected - b).abs() < 1e-12,
                "joint {}: {a} → {b}",
                joint + 1
            );
        }
    }
}

/// A cell that is not levelled, simulated (`generate --gravity-tilt`) and
/// found (`identify --model elastic-gravity`): the tilts within 3σ of
/// the truth, and the calibrated file states the gravity found; a tilt
/// for a rigid real robot is refused by name.
#[test]
fn a_tilted_cell_is_simulated_and_its_gravity_found() {
    let folder = tempfile::tempdir().expect("folder");
    let path = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    let generate = |extra: &[&str], payload: &str, seed: &str, out: &str| {
        gecaro()
            .args(["generate", "industrial6", "--method", "position"])
            .args(["--count", "150", "--noise", "2e-5", "--seed", seed])
            .args(["--payload", payload, "-o", out])
            .args(extra)
            .assert()
            .success();
    };
    let (real, first) = (path("real.toml"), path("p0.csv"));
    generate(
        &[
            "--compliance-level",
            "1",
            "--gravity-tilt",
            "0.05rad,-0.04rad",
            "--real-out",
            &real,
        ],
        "0kg",
        "41",
        &first,
    );
    let real_text = std::fs::read_to_string(&real).expect("real robot");
    assert!(real_text.contains("gravity = ["), "{real_text}");
    let mut rows = std::fs::read_to_string(&first).expect("data");
    assert!(
        rows.contains("gravity tilted by 0.05rad,-0.04rad"),
        "{rows}"
    );
    for (payload, seed) in [("10kg,0,0,100mm", "42"), ("20kg,0,0,100mm", "43")] {
        let out = path(&format!("p{seed}.csv"));
        generate(&["--real", &real], payload, seed, &out);
        let text = std::fs::read_to_string(&out).expect("data");
        rows.extend(
            text.lines()
                .filter(|line| !line.starts_with('#'))
                .skip(1)
                .map(|line| format!("{line}\n")),
        );
    }
    let data = path("all.csv");
    std::fs::write(&data, rows).expect("written");
    let output = gecaro()
        .args([
            "identify",
            "industrial6",
            "--method",
            "position",
            "--data",
            &data,
        ])
        .args(["--sigma", "20um", "--model", "elastic-gravity", "--json"])
        .args(["-o", &path("calibrated.toml")])
        .output()
        .expect("ran");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    for (name, truth) in [("tilt1", 0.05), ("tilt2", -0.04)] {
        let p = document["parameters"]
            .as_array()
            .expect("parameters")
            .iter()
            .find(|p| p["name"] == name)
            .unwrap_or_else(|| panic!("{name} identified: {document}"));
        let (value, std) = (
            p["identified"].as_f64().expect("value"),
            p["std"].as_f64().expect("σ"),
        );
        assert!(
            (value - truth).abs() < 3.0 * std,
            "{name}: {value} vs {truth} (σ {std})"
        );
    }
    let calibrated = std::fs::read_to_string(path("calibrated.toml")).expect("calibrated");
    assert!(calibrated.contains("gravity = ["), "{calibrated}");
    gecaro()
        .args([
            "generate",
            "industrial6",
            "--method",
            "position",
            "--count",
            "5",
        ])
        .args(["--gravity-tilt", "2deg,-1deg", "-o", &path("rigid.csv")])
        .assert()
        .failure()
        .stderr(predicates::str::contains(
            "--gravity-tilt: gravity's tilt loads elastic joints only",
        ));
}
