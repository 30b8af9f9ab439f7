//! The road in and out, through the real binary: `robot import`, `robot
//! export` (and `compensate`), on the test files of `tests/data/`.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

fn gecaro() -> Command {
    Command::cargo_bin("gecaro").expect("the gecaro binary is built")
}

fn data(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
        .display()
        .to_string()
}

fn run(args: &[&str]) -> (String, String) {
    let output = gecaro().args(args).output().expect("runs");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    );
    assert!(
        output.status.success(),
        "gecaro {}: {stderr}",
        args.join(" ")
    );
    (stdout, stderr)
}

/// The 4×4 pose of `gecaro fk ROBOT --qm … --json` as 16 numbers.
fn fk(robot: &str, qm: &str) -> Vec<f64> {
    let (stdout, _) = run(&["fk", robot, "--qm", qm, "--json"]);
    let value: Value = serde_json::from_str(&stdout).expect("JSON");
    let mut numbers: Vec<f64> = value["position"]
        .as_array()
        .expect("position")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect();
    for row in value["rotation"].as_array().expect("rotation") {
        numbers.extend(
            row.as_array()
                .expect("row")
                .iter()
                .map(|v| v.as_f64().expect("number")),
        );
    }
    numbers
}

fn assert_close(a: &[f64], b: &[f64], tolerance: f64) {
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < tolerance, "{a:?}\n{b:?}");
}

fn path(folder: &tempfile::TempDir, name: &str) -> PathBuf {
    folder.path().join(name)
}

#[test]
fn a_symoro_file_and_a_table_import_to_the_ready_robots() {
    let folder = tempfile::tempdir().expect("folder");
    let stanford = path(&folder, "stanford.toml");
    let (stdout, stderr) = run(&[
        "robot",
        "import",
        &data("robots/stanford.par"),
        "-o",
        stanford.to_str().expect("utf8"),
    ]);
    assert!(stdout.contains("Stanford — 6 joints (RRPRRR)"), "{stdout}");
    assert!(
        stderr.contains("note: a .par file has no joint limits"),
        "{stderr}"
    );
    for qm in ["0,0,0.5,0,0,0", "0.3,-1.2,0.4,2.0,-0.7,1.1"] {
        assert_close(
            &fk(stanford.to_str().expect("utf8"), qm),
            &fk("stanford", qm),
            1e-12,
        );
    }
    let puma = path(&folder, "puma.toml");
    run(&[
        "robot",
        "import",
        &data("robots/puma560_mdh.toml"),
        "-o",
        puma.to_str().expect("utf8"),
    ]);
    assert_close(
        &fk(puma.to_str().expect("utf8"), "0.1,0.2,0.3,0.4,0.5,0.6"),
        &fk("puma560", "0.1,0.2,0.3,0.4,0.5,0.6"),
        1e-12,
    );
}

#[test]
fn a_urdf_goes_in_and_out_with_its_names() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = path(&folder, "kr16.toml");
    let robot = robot.to_str().expect("utf8");
    let (_, stderr) = run(&[
        "robot",
        "import",
        &data("urdf/kuka_kr16_2.urdf"),
        "-o",
        robot,
    ]);
    assert!(stderr.contains("fixed joint(s) folded"), "{stderr}");
    let (shown, _) = run(&["robot", "show", robot]);
    assert!(shown.contains("kuka_kr16_2 — 6 joints (RRRRRR)"), "{shown}");
    let urdf = path(&folder, "kr16.urdf");
    let (stdout, _) = run(&[
        "robot",
        "export",
        robot,
        "--to",
        "urdf",
        "-o",
        urdf.to_str().expect("utf8"),
    ]);
    assert!(
        stdout.contains("names of the URDF `kuka_kr16_2`"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&urdf).expect("written");
    for name in [
        "joint_a1",
        "joint_a6",
        "link_6",
        "tool0",
        "joint_a6-tool0",
        "base_link",
    ] {
        assert!(text.contains(&format!("name=\"{name}\"")), "{name}");
    }
    let again = path(&folder, "again.toml");
    run(&[
        "robot",
        "import",
        urdf.to_str().expect("utf8"),
        "-o",
        again.to_str().expect("utf8"),
    ]);
    let qm = "0.4,-1.0,0.7,2.5,-0.9,-2.2";
    assert_close(
        &fk(again.to_str().expect("utf8"), qm),
        &fk(robot, qm),
        1e-12,
    );
    assert!(
        !path(&folder, "kr16.joint_calibration.yaml").exists(),
        "K = 1: no joint calibration"
    );
}

#[test]
fn gains_go_beside_the_export_and_an_existing_output_stops_everything() {
    let folder = tempfile::tempdir().expect("folder");
    // A robot with a gain, as an identification leaves it.
    let robot = path(&folder, "geared.toml");
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/puma560.toml"))
            .expect("ready robot")
            .replacen("qmin = -160", "qmin = -160\nK = 1.001", 1);
    std::fs::write(&robot, text).expect("write");
    let urdf = path(&folder, "geared.urdf");
    let calibration = path(&folder, "geared.joint_calibration.yaml");
    let robot = robot.to_str().expect("utf8");
    let (_, stderr) = run(&[
        "robot",
        "export",
        robot,
        "--to",
        "urdf",
        "-o",
        urdf.to_str().expect("utf8"),
    ]);
    assert!(stderr.contains("not expressible in a URDF"), "{stderr}");
    assert!(stderr.contains("geared.joint_calibration.yaml"), "{stderr}");
    let yaml = std::fs::read_to_string(&calibration).expect("written beside");
    assert!(yaml.contains("1.001") && yaml.contains("joint_1"), "{yaml}");
    // Again without --force: refused, nothing touched.
    std::fs::remove_file(&urdf).expect("remove");
    let output = gecaro()
        .args([
            "robot",
            "export",
            robot,
            "--to",
            "urdf",
            "-o",
            urdf.to_str().expect("utf8"),
        ])
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&output.stderr).contains("already exists"));
    assert!(!urdf.exists(), "no URDF without its calibration");
    // A table carries no gain either.
    let mdh = path(&folder, "geared-mdh.toml");
    let (_, stderr) = run(&[
        "robot",
        "export",
        robot,
        "--to",
        "mdh",
        "-o",
        mdh.to_str().expect("utf8"),
    ]);
    assert!(stderr.contains("not expressible in a DH table"), "{stderr}");
    assert!(path(&folder, "geared-mdh.joint_calibration.yaml").exists());
}

#[test]
fn a_csv_dh_table_in_millimetres_and_degrees() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = path(&folder, "puma-dh.toml");
    let robot = robot.to_str().expect("utf8");
    run(&[
        "robot",
        "import",
        &data("robots/puma560_dh.csv"),
        "--from",
        "dh",
        "-o",
        robot,
    ]);
    // Corke's PUMA at q = 0: the flange 0.4318 + 0.0203 m out, 0.15005 m aside,
    // 0.6604 + 0.4318 + 0.05625 m up.
    let pose = fk(robot, "0,0,0,0,0,0");
    assert_close(
        &pose[..3],
        &[0.4521, -0.15005, 0.6604 + 0.4318 + 0.05625],
        1e-12,
    );
}
