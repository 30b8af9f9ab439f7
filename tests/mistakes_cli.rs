//! Mistakes named where they sit, from the command line: a study set
//! labelled with the wrong reflector, a log joined one row off, joint angles
//! in degrees read as radians, a joint mastered 90° off.

use std::path::Path;

use crate::util::command;
use predicates::prelude::*;
use serde_json::Value;

/// `file`'s data rows rewritten by `edit` (comments and the header kept).
fn rewrite(from: &Path, to: &Path, edit: impl Fn(&[Vec<String>]) -> Vec<Vec<String>>) {
    let text = std::fs::read_to_string(from).expect("read");
    let (head, rows): (Vec<&str>, Vec<&str>) = text
        .lines()
        .partition(|line| line.starts_with('#') || line.starts_with("qm1"));
    let rows: Vec<Vec<String>> = rows
        .iter()
        .map(|row| row.split(',').map(str::to_owned).collect())
        .collect();
    let mut out: Vec<String> = head.iter().map(|line| (*line).to_owned()).collect();
    out.extend(edit(&rows).iter().map(|row| row.join(",")));
    std::fs::write(to, out.join("\n") + "\n").expect("written");
}

#[test]
fn a_set_labelled_with_the_wrong_reflector_is_named_alone() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tracker-cell");
    for file in ["smr_a_1.csv", "smr_b_1.csv", "smr_c_1.csv", "smr_a_2.csv"] {
        std::fs::copy(cell.join(file), folder.path().join(file)).expect("copied");
    }
    // Four sets; the second measures reflector b but is labelled a.
    let set = |data: &str, tool: &str, station: Option<&str>| {
        format!(
            "[[measurements]]\nmethod = \"position\"\ndata = \"{data}\"\ntool = \"{tool}\"\n{}\
             sigma = 0.02\n",
            station.map_or_else(String::new, |s| format!("station = \"{s}\"\n"))
        )
    };
    let study = format!(
        "robot = \"industrial6\"\nlength_unit = \"mm\"\nangle_unit = \"deg\"\n\
         [tools.smr_a]\nposition = [42, 24, 91.5]\n\
         [tools.smr_c]\nposition = [11, -58.5, 112]\n\
         [stations.tracker_2]\nposition = [-1150, 1700, -250]\nrpy = [0, 0, -130]\n{}{}{}{}",
        set("smr_a_1.csv", "smr_a", None),
        set("smr_b_1.csv", "smr_a", None),
        set("smr_c_1.csv", "smr_c", None),
        set("smr_a_2.csv", "smr_a", Some("tracker_2")),
    );
    std::fs::write(folder.path().join("study.toml"), study).expect("written");
    let output = command("identify --json --study")
        .arg(folder.path().join("study.toml"))
        .output()
        .expect("runs");
    assert_eq!(
        output.status.code(),
        Some(5),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let verdict = &document["verdict"];
    assert_eq!(verdict["outcome"], "exceeds_noise");
    assert_eq!(verdict["disagreement"]["set"], 1);
    assert!(
        verdict["disagreement"]["rest_ratio"]
            .as_f64()
            .expect("a ratio")
            < 1.2
    );
    let summary = verdict["summary"].as_str().expect("words");
    assert!(
        summary.contains("smr_b_1.csv disagrees with the other sets"),
        "{summary}"
    );
    for other in ["smr_a_1.csv", "smr_c_1.csv", "smr_a_2.csv"] {
        assert!(!summary.contains(other), "{summary}");
    }
    // Every set's σ̂/σ: the fit spreads the error over every set (which is
    // why one is left out at a time); the mislabelled one is the worst.
    let fits = verdict["sets"].as_array().expect("sets");
    // Sets are labelled by their file's path.
    let labels: Vec<&str> = fits
        .iter()
        .map(|f| f["label"].as_str().expect("a label"))
        .map(|label| label.rsplit('/').next().unwrap_or(label))
        .collect();
    assert_eq!(
        labels,
        [
            "smr_a_1.csv",
            "smr_b_1.csv",
            "smr_c_1.csv",
            "smr_a_2.csv",
            "tool smr_a",
            "tool smr_c",
            "station tracker_2"
        ]
    );
    let ratios: Vec<f64> = fits[..4]
        .iter()
        .map(|set| set["sigma_ratio"].as_f64().expect("a ratio"))
        .collect();
    assert!(ratios.iter().all(|ratio| *ratio <= ratios[1]), "{ratios:?}");
}

#[test]
fn a_log_joined_one_row_off_is_named() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    command("generate industrial6 --method position --count 120 --noise 2e-5 --seed 9 -o")
        .arg(at("joined.csv"))
        .assert()
        .success();
    // Each row's point is the next row's.
    rewrite(&at("joined.csv"), &at("shifted.csv"), |rows| {
        rows.windows(2)
            .map(|pair| [&pair[0][..6], &pair[1][6..]].concat())
            .collect()
    });
    command("identify industrial6 --method position --sigma 20um")
        .arg("--data")
        .arg(at("shifted.csv"))
        .assert()
        .code(4)
        .stderr(
            predicate::str::contains(
                "the measurements seem to belong to the configurations 1 row below them",
            )
            .and(predicate::str::contains("--solver lm").not()),
        );
}

#[test]
fn degrees_read_as_radians_are_named_with_the_option_that_reads_them() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    command("generate industrial6 --method position --count 60 --noise 2e-5 --seed 9 -o")
        .arg(at("radians.csv"))
        .assert()
        .success();
    rewrite(&at("radians.csv"), &at("degrees.csv"), |rows| {
        rows.iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .map(|(column, value)| match column {
                        0..6 => {
                            format!("{:?}", value.parse::<f64>().expect("a number").to_degrees())
                        }
                        _ => value.clone(),
                    })
                    .collect()
            })
            .collect()
    });
    command("identify industrial6 --method position --data")
        .arg(at("degrees.csv"))
        .assert()
        .code(3)
        .stderr(
            predicate::str::contains("the joint angles look like degrees read as radians")
                .and(predicate::str::contains("--angle-unit deg")),
        );
    command("identify industrial6 --method position --angle-unit deg")
        .arg("--data")
        .arg(at("degrees.csv"))
        .assert()
        .success();
}

#[test]
fn a_joint_mastered_a_quarter_turn_off_is_named_as_its_zero() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    let mut real = gecaro_io::load_robot("industrial6").expect("ready");
    let theta2: gecaro_core::ParameterId = "theta2".parse().expect("name");
    let turned = real.robot.parameter(theta2) + std::f64::consts::FRAC_PI_2 + 0.01;
    real.robot.set_parameter(theta2, turned).expect("turned");
    std::fs::write(at("real.toml"), gecaro_io::format_robot_file(&real)).expect("written");
    command("generate industrial6 --method position --count 100 --noise 2e-5 --seed 4 --real")
        .arg(at("real.toml"))
        .arg("-o")
        .arg(at("mastered.csv"))
        .assert()
        .success();
    let output = command("identify industrial6 --method position --sigma 20um --json --data")
        .arg(at("mastered.csv"))
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(5));
    let document: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let summary = document["verdict"]["summary"].as_str().expect("words");
    assert!(summary.contains("joint 2's zero is +90.6°"), "{summary}");
    assert!(summary.contains("a mastering question"), "{summary}");
    assert!(!summary.contains("excitation"), "{summary}");
    // The step took the short way: θ2 within 180° of its nominal value.
    let theta = document["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .find(|p| p["name"] == "theta2")
        .expect("theta2");
    let deviation =
        theta["identified"].as_f64().expect("value") - theta["nominal"].as_f64().expect("value");
    assert!((deviation - turned).abs() < 0.02, "θ2 moved by {deviation}");
}

#[test]
fn a_yielding_robot_fitted_rigidly_is_told_the_elastic_model_with_its_figures() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    command("generate industrial6 --method position --count 100 --noise 1e-5 --seed 3 --compliance-level 1 --payload 10kg")
        .arg("-o")
        .arg(at("sagging.csv"))
        .assert()
        .success();
    let output = command("identify industrial6 --method position --sigma 10um --json --data")
        .arg(at("sagging.csv"))
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(5));
    assert!(
        String::from_utf8_lossy(&output.stderr)
            .contains("the elastic model predicts better than the rigid one"),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(document["verdict"]["outcome"], "exceeds_noise");
    let advice = &document["model_advice"][0];
    assert_eq!(advice["model"], "elastic");
    assert!(advice["sigma_ratio"].as_f64().expect("ratio") < 1.2);
    let (held_out, rigid) = (
        advice["held_out"].as_f64().expect("m"),
        advice["instead_held_out"].as_f64().expect("m"),
    );
    assert!(
        held_out < 0.2 * rigid,
        "elastic {held_out} m, rigid {rigid} m"
    );
    // The elastic model, as advised, fits.
    command("identify industrial6 --method position --sigma 10um --model elastic --data")
        .arg(at("sagging.csv"))
        .assert()
        .success();
    // A smaller model compared on request: the gains of this rigid robot
    // are real (off by up to 1 %), so no advice.
    command("generate industrial6 --method position --count 80 --noise 1e-5 --seed 5 -o")
        .arg(at("rigid.csv"))
        .assert()
        .success();
    let output =
        command("identify industrial6 --method position --sigma 10um --check-model --json --data")
            .arg(at("rigid.csv"))
            .output()
            .expect("runs");
    assert!(output.status.success());
    let document: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(document["model_advice"], serde_json::json!([]));
}

#[test]
fn a_model_error_ten_times_the_noise_is_a_solution_written_and_not_trusted() {
    // UR10e positions, σ 18 µm, and an error no geometric model holds
    // (smooth in the joints, 0.25 mm): the fit converges to it, writes the
    // robot, and says how far above the noise it is (exit 5).
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    command("generate ur10e --method position --count 300 --noise 1.8e-5 --seed 2 -o")
        .arg(at("clean.csv"))
        .assert()
        .success();
    rewrite(&at("clean.csv"), &at("model_error.csv"), |rows| {
        rows.iter()
            .map(|row| {
                let value = |k: usize| row[k].parse::<f64>().expect("a number");
                let q: Vec<f64> = (0..6).map(value).collect();
                let error = [
                    2.5e-4 * (q[0] + 2.0 * q[1]).sin(),
                    2.5e-4 * (2.0 * q[2] - q[1]).cos(),
                    2.5e-4 * (q[3] + q[4]).sin(),
                ];
                let mut row = row.clone();
                for axis in 0..3 {
                    row[6 + axis] = format!("{:?}", value(6 + axis) + error[axis]);
                }
                row
            })
            .collect()
    });
    let output = command("identify ur10e --method position --sigma 18um --json")
        .arg("--data")
        .arg(at("model_error.csv"))
        .arg("-o")
        .arg(at("calibrated.toml"))
        .output()
        .expect("runs");
    assert_eq!(
        output.status.code(),
        Some(5),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(document["verdict"]["outcome"], "exceeds_noise");
    assert!(document["iterations"].as_u64().expect("iterations") <= 30);
    let ratio = document["verdict"]["noise_test"]["sigma_ratio"]
        .as_f64()
        .expect("ratio");
    assert!((8.0..12.0).contains(&ratio), "σ̂/σ {ratio}");
    assert!(at("calibrated.toml").exists());
}

/// The payload traps of the trial (issue 74): a centre in mixed units, a
/// centre 80 m away and a payload heavier than the arm are refused with
/// their value, by `generate`, `compensate` and a data file alike; the
/// honest `12kg,0,0,80mm` is read.
#[test]
fn a_payload_no_arm_carries_is_refused_with_its_value() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    let generate = |payload: &str| {
        command("generate industrial6 --method position --count 20 --compliance-level 1 --seed 4")
            .args(["--payload", payload, "-o"])
            .arg(at("loaded.csv"))
            .arg("--force")
            .output()
            .expect("runs")
    };
    for (payload, expected) in [
        (
            "12kg,-32.2959,17.2685,-17.3173mm",
            "mixes units: '-32.2959' has none",
        ),
        ("12kg,0,0,80", "80 m from the tool frame"),
        ("1200kg", "whose moving links weigh 36.3 kg"),
    ] {
        let output = generate(payload);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{payload}: {stderr}");
        assert!(stderr.contains(expected), "{payload}: {stderr}");
        assert!(!at("loaded.csv").exists(), "{payload}");
    }
    let output = generate("12kg,0,0,80mm");
    assert!(output.status.success(), "{output:?}");
    let rows = std::fs::read_to_string(at("loaded.csv")).expect("data");
    assert!(
        rows.lines()
            .nth(2)
            .is_some_and(|row| row.ends_with(",12.0,0.0,0.0,0.08")),
        "{rows}"
    );
    // A data file whose payload is heavier than the arm, fitted elastic.
    let heavy = rows.replacen(",12.0,0.0,0.0,0.08", ",1200.0,0.0,0.0,0.08", 1);
    std::fs::write(at("heavy.csv"), heavy).expect("write");
    let output = command("identify industrial6 --method position --model elastic --data")
        .arg(at("heavy.csv"))
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("a payload of 1200 kg"), "{stderr}");
}
