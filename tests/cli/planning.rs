//! Plans and predictions from the command line: chosen configurations, units, criteria, the accuracy curve.

use super::*;

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
    command("plan stanford --method point-link --count 40")
        .args(["--pool", "400", "--seed", "2", "-o", output_text])
        .assert()
        .code(3)
        .stderr(predicate::str::contains("already exists"));
    let again = folder.path().join("again.csv");
    command("plan stanford --method point-link --count 40 --pool 400 --seed 2 -o")
        .arg(&again)
        .assert()
        .success();
    assert_eq!(std::fs::read_to_string(&again).expect("again"), text);
    // More than the pool holds is a usage error.
    command("plan stanford --method position --count 40 --pool 20")
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
    command("plan panda --method frame --count 30 -o")
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
    command("predict panda --method frame --noise 1e-4 --data")
        .arg(&few)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("equations").or(predicate::str::contains("do not determine")),
        );
    command("predict panda --method frame --noise -1 --data")
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
    command("plan stanford --method position --curve 10,20 --pool 300")
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--noise"));
}

#[test]
fn a_plan_in_degrees_is_measured_in_degrees() {
    // A plan for a teach pendant (degrees) measured at with the same units:
    // before, `generate --configurations` read every plan in radians.
    // (docs/data-files.md: a file in other units than gecaro's says so.)
    let folder = tempfile::tempdir().expect("folder");
    let plan = folder.path().join("plan.csv");
    let data = folder.path().join("data.csv");
    command("plan stanford --method position --count 15 --angle-unit deg -o")
        .arg(&plan)
        .assert()
        .success();
    command("generate stanford --method position --error-level 0")
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
    command("generate stanford --method position --error-level 0 --configurations")
        .arg(&plan)
        .arg("-o")
        .arg(&unstated)
        .assert()
        .success();
    assert_eq!(rows(&unstated), rows(&data));
    command("generate stanford --method position --configurations")
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
