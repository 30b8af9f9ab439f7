//! A parallel robot on the command line: the ready hexapod generated,
//! identified and judged on held-out poses through files, as a user runs
//! it; serial-only options and jobs refused by name.

use serde_json::Value;

use crate::util::{command, json_output};

/// `robot`'s 60 tool points measured on a real robot drawn at level 1 (σ
/// 20 µm) and identified with the verdict; the calibrated robot's RMS error
/// on 200 held-out points, and the real robot's own (the noise floor).
/// Files in `folder`: points.csv, held.csv, real.toml, calibrated.toml.
fn calibrated_from_points(folder: &std::path::Path, robot: &str) -> (Value, f64, f64) {
    let at = |name: &str| folder.join(name).display().to_string();
    command(&format!(
        "generate {robot} --method position --count 60 --noise 2e-5 --seed 3 -o"
    ))
    .arg(at("points.csv"))
    .arg("--real-out")
    .arg(at("real.toml"))
    .assert()
    .success();
    command(&format!(
        "generate {robot} --method position --count 200 --noise 2e-5 --seed 4 -o"
    ))
    .arg(at("held.csv"))
    .arg("--real")
    .arg(at("real.toml"))
    .assert()
    .success();
    let identified = json_output(&[
        "identify",
        robot,
        "--method",
        "position",
        "--sigma",
        "0.02mm",
        "--json",
        "--data",
        &at("points.csv"),
        "-o",
        &at("calibrated.toml"),
    ]);
    let rms = |robot: &str| {
        json_output(&[
            "evaluate",
            robot,
            "--method",
            "position",
            "--json",
            "--data",
            &at("held.csv"),
        ])["errors"]["position_rms"]
            .as_f64()
            .expect("rms")
    };
    let (after, floor) = (rms(&at("calibrated.toml")), rms(&at("real.toml")));
    (identified, after, floor)
}

#[test]
fn a_hexapod_calibrated_on_the_command_line_reaches_the_noise_floor() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let (identified, after, floor) = calibrated_from_points(folder.path(), "hexapod");
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    assert_eq!(identified["rank"], 45);
    assert!(after <= 1.3 * floor, "{after} m, floor {floor} m");
    // One point does not observe the platform frame: a program of
    // platform poses is not compensated with it, and said why.
    command("generate hexapod --method frame --count 10 --error-level 0 --seed 5 -o")
        .arg(at("job.csv"))
        .assert()
        .success();
    let output = command("compensate hexapod")
        .arg(at("calibrated.toml"))
        .arg("--program")
        .arg(at("job.csv"))
        .arg("-o")
        .arg(at("corrected.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        error.contains("its platform frame is not observed")
            && error.contains("compensate a program of tool points (match position)"),
        "{error}"
    );
    assert!(!std::path::Path::new(&at("corrected.csv")).exists());
    // Its tool point is what it observed: the 200 held-out points as a
    // program of tool points (the platform level) are reached by the real
    // platform at the calibration's error, against a millimetre as written
    // for the nominal one; the orientation's limit said.
    let reached = |calibrated: &str, corrected: &str| {
        let output = command("compensate hexapod --match position")
            .arg(calibrated)
            .arg("--program")
            .arg(at("held.csv"))
            .arg("-o")
            .arg(at(corrected))
            .output()
            .expect("runs");
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let rms = json_output(&[
            "evaluate",
            &at("real.toml"),
            "--method",
            "position",
            "--json",
            "--data",
            &at(corrected),
        ])["errors"]["position_rms"]
            .as_f64()
            .expect("rms");
        (rms, String::from_utf8_lossy(&output.stdout).into_owned())
    };
    let (compensated, said) = reached(&at("calibrated.toml"), "points-corrected.csv");
    let (as_written, _) = reached("hexapod", "points-nominal.csv");
    assert!(compensated < 0.03e-3, "{compensated} m off the targets");
    assert!(as_written > 0.5e-3, "{as_written} m off as written");
    assert!(said.contains("200 targets (tool points)"), "{said}");
    assert!(
        said.contains(
            "note: the tool points are met; the platform's orientation is the calibration's"
        ),
        "{said}"
    );
    let shown = command("robot show")
        .arg(at("calibrated.toml"))
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&shown.stdout);
    assert!(
        text.contains("hexapod (calibrated) — Gough–Stewart platform, 6 actuators"),
        "{text}"
    );
}

#[test]
fn the_identifiable_parameters_of_measured_poses_are_every_leg_parameter() {
    let report: Value = json_output(&["identifiable", "hexapod", "--method", "frame", "--json"]);
    assert_eq!(report["rank"], 48);
    assert_eq!(report["regrouped"].as_array().map(Vec::len), Some(0));
}

#[test]
fn serial_only_options_and_jobs_are_refused_by_name() {
    let output = command("identify hexapod --method frame --data x.csv --priority p.toml")
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(2));
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        error.contains("--priority has no meaning for a parallel robot"),
        "{error}"
    );
    // Every serial option a parallel command would otherwise pass over
    // without a word (no file is read before the refusal).
    for (job, option) in [
        (
            "identify hexapod --method frame --data x.csv",
            "--solver lm",
        ),
        (
            "identify hexapod --method frame --data x.csv",
            "--outlier-threshold 2",
        ),
        (
            "identify hexapod --method frame --data x.csv",
            "--check-model",
        ),
        (
            "identify hexapod --method frame --data x.csv",
            "--write-unconverged",
        ),
        (
            "identify hexapod --method frame --data x.csv",
            "--strict-limits",
        ),
        ("identify hexapod --method frame --data x.csv", "--cv 5"),
        (
            "evaluate hexapod --method frame --data x.csv",
            "--orientation cross-products",
        ),
        (
            "evaluate hexapod --method frame --data x.csv",
            "--strict-limits",
        ),
        (
            "generate hexapod --method frame --count 5 -o x.csv",
            "--set-size 5",
        ),
        ("identifiable hexapod --method frame", "--plane known"),
        (
            "predict hexapod --method frame --noise 2e-5 --data x.csv",
            "--orientation cross-products",
        ),
    ] {
        let output = command(&format!("{job} {option}")).output().expect("runs");
        let error = String::from_utf8_lossy(&output.stderr);
        let name = option.split(' ').next().expect("a name");
        assert_eq!(output.status.code(), Some(2), "{job} {option}: {error}");
        assert!(
            error.contains(&format!("{name} has no meaning for a parallel robot")),
            "{job} {option}: {error}"
        );
    }
    let output = command("fk hexapod --qm 0,0,0,0,0,0")
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(error.contains("a parallel robot"), "{error}");
    let output = command("identifiable hexapod --method plane1")
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        error.contains("`frame` (the platform's pose), `position` (its tool point), `distance`"),
        "{error}"
    );
}

#[test]
fn a_delta_is_calibrated_from_its_tool_point_and_a_program_compensated() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let (identified, after, floor) = calibrated_from_points(folder.path(), "delta");
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    assert_eq!(identified["rank"], 24);
    assert!(after <= 1.3 * floor, "{after} m, floor {floor} m");
    // The held-out tool points as a program: the compensated motor angles
    // put the real Delta's tool point on them (its own noise aside).
    command("compensate delta")
        .arg(at("calibrated.toml"))
        .arg("--program")
        .arg(at("held.csv"))
        .arg("-o")
        .arg(at("corrected.csv"))
        .assert()
        .success();
    let corrected = json_output(&[
        "evaluate",
        &at("real.toml"),
        "--method",
        "position",
        "--json",
        "--data",
        &at("corrected.csv"),
    ]);
    let off = corrected["errors"]["position_rms"].as_f64().expect("rms");
    assert!(off < 0.05e-3, "{off} m off the targets");
    // Its report: three arms turning, their ranges in degrees, the tool
    // point's errors at the measured points.
    command("report delta --method position --sigma 0.02mm --data")
        .arg(at("points.csv"))
        .arg("-o")
        .arg(at("report.html"))
        .assert()
        .success();
    let html = std::fs::read_to_string(at("report.html")).expect("the report");
    assert!(
        html.contains("a Delta robot, 3 arms"),
        "the structure named"
    );
    assert!(html.contains("tool point the direct model predicts"));
    assert!(
        html.contains("<th>arm</th>") && html.contains("°</td>"),
        "the arms' ranges in degrees"
    );
    assert!(html.contains(identified["summary"].as_str().expect("words")));
    let output = command("identify delta --method frame --data")
        .arg(at("points.csv"))
        .output()
        .expect("runs");
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("only translates"));
}

#[test]
fn planned_poses_are_measured_and_identified_as_a_cell_would() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let plan = json_output(&[
        "plan",
        "hexapod",
        "--method",
        "frame",
        "--count",
        "20",
        "--json",
        "-o",
        &at("plan.csv"),
    ]);
    assert_eq!(plan["count"], 20);
    assert!(
        plan["criterion"].as_f64() > plan["random_criterion"].as_f64(),
        "{plan}"
    );
    let header = std::fs::read_to_string(at("plan.csv")).expect("plan");
    assert!(header.starts_with("qm1,qm2,qm3,qm4,qm5,qm6\n"), "{header}");
    command("generate hexapod --method frame --noise 2e-5 --seed 5 --configurations")
        .arg(at("plan.csv"))
        .arg("-o")
        .arg(at("measured.csv"))
        .assert()
        .success();
    let identified = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--json",
        "--data",
        &at("measured.csv"),
    ]);
    assert_eq!(identified["configurations"], 20);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    // Planned for the calibrated platform's error over its workspace: said
    // in words, below random poses'; the test poses are the workspace's,
    // so a serial robot's --test-poses is refused by name.
    let output = command("plan hexapod --method frame --count 20 --criterion test -o")
        .arg(at("other.csv"))
        .output()
        .expect("runs");
    let said = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        said.contains("(the predicted error over the workspace): predicted RMS tool-point error"),
        "{said}"
    );
    let output = command("plan hexapod --method frame --count 20 --criterion test --test-poses")
        .arg(at("measured.csv"))
        .arg("-o")
        .arg(at("third.csv"))
        .output()
        .expect("runs");
    assert!(String::from_utf8_lossy(&output.stderr).contains("--test-poses has no meaning"));
}

/// A hexapod measured with every leg within ±12 mm of its zero (poses near
/// home only) fits its noise there, and the verdict says it holds only
/// there (`regional`, exit 5 as an untrusted fit), with the measured leg
/// ranges in words; the calibrated file keeps them, and a program over the
/// workspace compensated with it is flagged target by target (exit 4).
#[test]
fn a_hexapod_measured_near_home_holds_only_there() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    // Leg values from a fixed linear congruential stream, ±12 mm.
    let mut state: u64 = 12345;
    let mut draw = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 0.012
    };
    let mut configurations = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for _ in 0..60 {
        let row: Vec<String> = (0..6).map(|_| format!("{:.6}", draw())).collect();
        configurations.push_str(&(row.join(",") + "\n"));
    }
    std::fs::write(at("near.csv"), configurations).expect("written");
    command("generate hexapod --method frame --noise 2e-5 --seed 8 --configurations")
        .arg(at("near.csv"))
        .arg("-o")
        .arg(at("poses.csv"))
        .assert()
        .success();
    let output = command("identify hexapod --method frame --sigma 20um --data")
        .arg(at("poses.csv"))
        .arg("-o")
        .arg(at("calibrated.toml"))
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&output.stdout);
    let error = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(5), "{text}{error}");
    assert!(
        text.contains("fit the stated noise")
            && text.contains("holds only where the data were taken (qm1 "),
        "{text}"
    );
    assert!(text.contains("predicted tool-point error"), "{text}");
    let file = std::fs::read_to_string(at("calibrated.toml")).expect("calibrated");
    assert_eq!(file.matches("measured = [").count(), 6, "{file}");
    // Used where it was measured (the legs within ±12 mm), it is trusted:
    // the verdict judges the stated region, and says so.
    let stated = command("identify hexapod --method frame --sigma 20um --work-region")
        .arg("qm1=-12..12mm,qm2=-12..12mm,qm3=-12..12mm,qm4=-12..12mm,qm5=-12..12mm,qm6=-12..12mm")
        .arg("--data")
        .arg(at("poses.csv"))
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&stated.stdout);
    assert_eq!(stated.status.code(), Some(0), "{text}");
    assert!(
        text.contains("fit the stated noise") && text.contains("over the stated work region"),
        "{text}"
    );
    // A region the robot has no actuator for is refused by name.
    let refused = command("identify hexapod --method frame --sigma 20um --work-region qm7=0..1mm")
        .arg("--data")
        .arg(at("poses.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{error}");
    assert!(
        error.contains("--work-region: 'qm7' is not an actuator of this robot"),
        "{error}"
    );
    // Legs 1 and 2 stretched to 500 mm of stroke: a region with one at
    // +475 mm and the other at −475 mm has no pose at its centre (their
    // joints are 259 mm apart on the base and 424 mm on the platform).
    let hexapod = std::fs::read_to_string("robots/hexapod.toml").expect("the ready hexapod");
    let stretched = hexapod.replacen("min = -100\nmax = 100", "min = -500\nmax = 500", 2);
    assert_eq!(stretched.matches("max = 500").count(), 2);
    std::fs::write(at("stretched.toml"), stretched).expect("written");
    let refused = command("identify")
        .arg(at("stretched.toml"))
        .args(["--method", "frame", "--sigma", "20um", "--work-region"])
        .arg("qm1=450..500mm,qm2=-500..-450mm")
        .arg("--data")
        .arg(at("poses.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{error}");
    assert!(
        error.contains("--work-region: no platform pose puts every actuator at the middle"),
        "{error}"
    );
    command("generate hexapod --method frame --count 10 --error-level 0 --seed 5 -o")
        .arg(at("job.csv"))
        .assert()
        .success();
    let output = command("compensate hexapod")
        .arg(at("calibrated.toml"))
        .arg("--program")
        .arg(at("job.csv"))
        .arg("-o")
        .arg(at("corrected.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(4), "{error}");
    assert!(
        error.contains("outside the actuator values the calibration measured"),
        "{error}"
    );
    assert!(std::path::Path::new(&at("corrected.csv")).exists());
}

/// A hexapod calibrated from 200 measured distances (a ballbar's or a
/// tracker's, `pair` and `distance` columns) as a user runs it: 39
/// parameters identifiable, the fit at the noise, held-out distances at
/// the real robot's own; a program in the base frame, which distances
/// never observe, refused for compensation; an odd pose out refused.
#[test]
fn a_hexapod_is_calibrated_from_distances_on_the_command_line() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("generate hexapod --method distance --count 400 --noise 2e-5 --seed 3 -o")
        .arg(at("pairs.csv"))
        .arg("--real-out")
        .arg(at("real.toml"))
        .assert()
        .success();
    command("generate hexapod --method distance --count 200 --noise 2e-5 --seed 4 -o")
        .arg(at("held.csv"))
        .arg("--real")
        .arg(at("real.toml"))
        .assert()
        .success();
    let header = std::fs::read_to_string(at("pairs.csv")).expect("pairs");
    assert!(header.starts_with("qm1,qm2,qm3,qm4,qm5,qm6,pair,distance\n"));
    let identified = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "distance",
        "--sigma",
        "0.02mm",
        "--json",
        "--data",
        &at("pairs.csv"),
        "-o",
        &at("calibrated.toml"),
    ]);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    assert_eq!(identified["rank"], 39);
    assert_eq!(identified["region"]["distances"], true);
    let rms = |robot: &str| {
        json_output(&[
            "evaluate",
            robot,
            "--method",
            "distance",
            "--json",
            "--data",
            &at("held.csv"),
        ])["errors"]["position_rms"]
            .as_f64()
            .expect("rms")
    };
    let (after, floor) = (rms(&at("calibrated.toml")), rms(&at("real.toml")));
    assert!(after <= 1.3 * floor, "{after} m, floor {floor} m");
    let output = command("compensate hexapod")
        .arg(at("calibrated.toml"))
        .arg("--program")
        .arg(at("held.csv"))
        .arg("-o")
        .arg(at("corrected.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(error.contains("its base frame is not observed"), "{error}");
    let output = command("generate hexapod --method distance --count 5 -o")
        .arg(at("odd.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(error.contains("5 poses are not whole pairs"), "{error}");
    assert!(!std::path::Path::new(&at("odd.csv")).exists());
}

/// The precision before measuring: 30 planned poses predict every leg
/// parameter's σ and a tool-point error over the workspace below the
/// noise of a held-out measurement, which four simulated calibrations
/// measure; the legs within ±12 mm predict an error many times it, with the
/// warning, and over a stated region of ±12 mm what simulated calibrations
/// measure there; options of serial robots only refused by name.
#[test]
fn a_plan_is_predicted_before_it_is_measured() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("plan hexapod --method frame --count 30 -o")
        .arg(at("plan.csv"))
        .assert()
        .success();
    let predicted = json_output(&[
        "predict",
        "hexapod",
        "--method",
        "frame",
        "--noise",
        "2e-5",
        "--json",
        "--data",
        &at("plan.csv"),
    ]);
    assert_eq!(predicted["rank"], 48);
    assert_eq!(predicted["parameters"].as_array().map(Vec::len), Some(48));
    let region = &predicted["region"];
    assert_eq!(region["holds_everywhere"], true, "{region}");
    assert!(
        region["predicted_work"].as_f64() < region["noise_floor"].as_f64(),
        "{region}"
    );
    // Legs within ±12 mm of zero: a plan that calibrates near home only.
    let mut near = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for k in 0..40 {
        let row: Vec<String> = (0..6)
            .map(|j| {
                format!(
                    "{:.4}",
                    0.012 * (((k * 7 + j * 13) % 17) as f64 / 8.0 - 1.0)
                )
            })
            .collect();
        near.push_str(&(row.join(",") + "\n"));
    }
    std::fs::write(at("near.csv"), near).expect("written");
    let output = command("predict hexapod --method frame --noise 2e-5 --data")
        .arg(at("near.csv"))
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        text.contains("calibrate the platform where they are only"),
        "{text}"
    );
    // Simulated calibrations from the plan measure what was predicted.
    let simulated = json_output(&[
        "predict",
        "hexapod",
        "--method",
        "frame",
        "--noise",
        "2e-5",
        "--monte-carlo",
        "4",
        "--json",
        "--data",
        &at("plan.csv"),
    ]);
    let (measured, predicted) = (
        simulated["monte_carlo"]["work_rms"]
            .as_f64()
            .expect("simulated"),
        simulated["region"]["predicted_work"]
            .as_f64()
            .expect("predicted"),
    );
    assert_eq!(simulated["monte_carlo"]["runs"], 4);
    assert!(
        (0.6..1.6).contains(&(measured / predicted)),
        "{measured} against {predicted}"
    );
    // The legs' plan judged over the region it will be used in, ±12 mm:
    // predicted far below the workspace's error, and what simulated
    // calibrations measure against their real robots over that region.
    let region = (1..=6)
        .map(|k| format!("qm{k}=-12..12mm"))
        .collect::<Vec<_>>()
        .join(",");
    let near = json_output(&[
        "predict",
        "hexapod",
        "--method",
        "frame",
        "--noise",
        "2e-5",
        "--monte-carlo",
        "4",
        "--json",
        "--work-region",
        &region,
        "--data",
        &at("near.csv"),
    ]);
    let (measured, predicted) = (
        near["monte_carlo"]["work_rms"].as_f64().expect("simulated"),
        near["region"]["predicted_work"]
            .as_f64()
            .expect("predicted"),
    );
    assert_eq!(near["region"]["work_is_ranges"], false, "{near}");
    assert_eq!(near["region"]["work_name"], "the stated work region");
    assert!(
        (0.6..1.6).contains(&(measured / predicted)),
        "{measured} against {predicted}"
    );
    let whole = json_output(&[
        "predict",
        "hexapod",
        "--method",
        "frame",
        "--noise",
        "2e-5",
        "--json",
        "--data",
        &at("near.csv"),
    ]);
    let over_workspace = whole["region"]["predicted_work"]
        .as_f64()
        .expect("predicted");
    assert!(
        predicted < 0.1 * over_workspace,
        "{predicted} against {over_workspace}"
    );
    for (robot, region, refused) in [
        ("hexapod", "qm7=0..1mm", "qm7"),
        (
            "stanford",
            "q1=0..10deg",
            "--work-region of `predict` is a parallel robot's",
        ),
    ] {
        let output = command(&format!(
            "predict {robot} --method position --noise 2e-5 --work-region {region} --data"
        ))
        .arg(at("near.csv"))
        .output()
        .expect("runs");
        let error = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{error}");
        assert!(error.contains(refused), "{error}");
    }
    let output = command("predict hexapod --method frame --noise 2e-5 --model full --data")
        .arg(at("plan.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        error.contains("--model has no meaning for a parallel robot"),
        "{error}"
    );
}

/// `path`'s measured poses (`qm1…qm6,x,y,z,qw,qx,qy,qz`) as a tracker at
/// `tracker` (the base frame in its own) reads them, written to `to`.
fn in_tracker_frame(path: &str, to: &str, tracker: &nalgebra::Isometry3<f64>) {
    let text = std::fs::read_to_string(path).expect("data");
    let mut lines = text.lines();
    let mut written = format!("{}\n", lines.next().expect("header"));
    for line in lines {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("number"))
            .collect();
        let point = tracker * nalgebra::Point3::new(values[6], values[7], values[8]);
        let turn = tracker.rotation
            * nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                values[9], values[10], values[11], values[12],
            ));
        let mut row: Vec<String> = values[..6].iter().map(|v| format!("{v:?}")).collect();
        row.extend([point.x, point.y, point.z].map(|v| format!("{v:?}")));
        row.extend([turn.w, turn.i, turn.j, turn.k].map(|v| format!("{v:?}")));
        written.push_str(&(row.join(",") + "\n"));
    }
    std::fs::write(to, written).expect("written");
}

/// A hexapod's poses measured by a tracker 2.9 m away, turned 35° and
/// tilted 0.5°: the identification registers its frame before the fit and
/// says so, finds the tracker within 10 mm, fits the noise, and held-out
/// poses from the same tracker (registered too, said) are at the real
/// platform's own error.
#[test]
fn a_hexapod_measured_from_a_tracker_elsewhere_is_registered() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let tracker = nalgebra::Isometry3::from_parts(
        nalgebra::Translation3::new(2.2, -1.7, 0.4),
        nalgebra::UnitQuaternion::from_euler_angles(0.0087, 0.0, 0.61),
    );
    command("generate hexapod --method frame --count 60 --noise 2e-5 --seed 3 -o")
        .arg(at("poses.csv"))
        .arg("--real-out")
        .arg(at("real.toml"))
        .assert()
        .success();
    command("generate hexapod --method frame --count 200 --noise 2e-5 --seed 4 -o")
        .arg(at("held.csv"))
        .arg("--real")
        .arg(at("real.toml"))
        .assert()
        .success();
    in_tracker_frame(&at("poses.csv"), &at("tracker.csv"), &tracker);
    in_tracker_frame(&at("held.csv"), &at("tracker-held.csv"), &tracker);
    let identified = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--json",
        "--data",
        &at("tracker.csv"),
        "-o",
        &at("calibrated.toml"),
    ]);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    let summary = identified["summary"].as_str().expect("summary");
    assert!(
        summary.contains("the instrument's frame was registered"),
        "{summary}"
    );
    let position: Vec<f64> = identified["registered"]["position"]
        .as_array()
        .expect("registered")
        .iter()
        .filter_map(Value::as_f64)
        .collect();
    let off =
        ((position[0] - 2.2).powi(2) + (position[1] + 1.7).powi(2) + (position[2] - 0.4).powi(2))
            .sqrt();
    assert!(off < 0.01, "{position:?}");
    let evaluated = |robot: &str, data: &str| {
        json_output(&[
            "evaluate", robot, "--method", "frame", "--json", "--data", data,
        ])
    };
    let after = evaluated(&at("calibrated.toml"), &at("tracker-held.csv"));
    assert!(after["registered"].is_object(), "{after}");
    let floor = evaluated(&at("real.toml"), &at("held.csv"));
    assert!(floor["registered"].is_null(), "{floor}");
    let rms = |answer: &Value| answer["errors"]["position_rms"].as_f64().expect("rms");
    assert!(rms(&after) <= 1.3 * rms(&floor), "{after} against {floor}");
}

/// The data file `from` written to `to` with the poses of lines 7, 19 and
/// 35 (rows 6, 18, 34 of the file: a header, then data) half a millimetre
/// off in x.
fn three_off(from: &str, to: &str) {
    let text = std::fs::read_to_string(from).expect("read");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let x = lines[0]
        .split(',')
        .position(|column| column == "x")
        .expect("an x column");
    for row in [6, 18, 34] {
        let mut values: Vec<String> = lines[row].split(',').map(str::to_owned).collect();
        let moved = values[x].parse::<f64>().expect("a number") + 0.5e-3;
        values[x] = moved.to_string();
        lines[row] = values.join(",");
    }
    std::fs::write(to, lines.join("\n") + "\n").expect("written");
}

/// Three of 60 measured poses off by half a millimetre: least squares is
/// not trusted (the residuals twice the noise, the three named); `--reject`
/// drops them, `--loss cauchy` weighs them down — trusted, held out at the
/// noise floor, and the words say what was done.
#[test]
fn gross_errors_are_weighed_down_on_the_command_line() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("generate hexapod --method frame --count 60 --noise 2e-5 --seed 3 -o")
        .arg(at("poses.csv"))
        .arg("--real-out")
        .arg(at("real.toml"))
        .assert()
        .success();
    command("generate hexapod --method frame --count 200 --noise 2e-5 --seed 4 -o")
        .arg(at("held.csv"))
        .arg("--real")
        .arg(at("real.toml"))
        .assert()
        .success();
    three_off(&at("poses.csv"), &at("off.csv"));
    let plain = command("identify hexapod --method frame --sigma 20um --data")
        .arg(at("off.csv"))
        .output()
        .expect("runs");
    assert_eq!(plain.status.code(), Some(5), "not trusted");
    // Rejected instead: the three dropped, the rest fits the noise.
    let rejected = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--reject",
        "--json",
        "--data",
        &at("off.csv"),
    ]);
    assert_eq!(rejected["outcome"], "fits_noise", "{}", rejected["summary"]);
    let mut dropped: Vec<u64> = rejected["rejected"]
        .as_array()
        .expect("rejected")
        .iter()
        .filter_map(|outlier| outlier["line"].as_u64())
        .collect();
    dropped.sort_unstable();
    assert_eq!(dropped, [7, 19, 35], "{rejected}");
    assert!(
        rejected["summary"]
            .as_str()
            .is_some_and(|words| words.contains("without the 3 measurements that stood out")),
        "{}",
        rejected["summary"]
    );
    let robust = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--loss",
        "cauchy",
        "--json",
        "--data",
        &at("off.csv"),
        "-o",
        &at("calibrated.toml"),
    ]);
    assert_eq!(robust["outcome"], "fits_noise", "{}", robust["summary"]);
    assert_eq!(robust["weighed_down"], 3, "{robust}");
    let summary = robust["summary"].as_str().expect("words");
    assert!(
        summary.contains("the robust loss, cauchy (k = 2.385 σ̂), weighed 3 of 60"),
        "{summary}"
    );
    let lines: Vec<u64> = robust["outliers"]
        .as_array()
        .expect("outliers")
        .iter()
        .filter_map(|outlier| outlier["line"].as_u64())
        .collect();
    assert_eq!(lines.len(), 3, "{robust}");
    for line in [7, 19, 35] {
        assert!(lines.contains(&line), "{lines:?}");
    }
    let rms = |robot: &str| {
        json_output(&[
            "evaluate",
            robot,
            "--method",
            "frame",
            "--json",
            "--data",
            &at("held.csv"),
        ])["errors"]["position_rms"]
            .as_f64()
            .expect("rms")
    };
    let (after, floor) = (rms(&at("calibrated.toml")), rms(&at("real.toml")));
    assert!(after <= 1.3 * floor, "{after} m, floor {floor} m");
    // A prior about the nominal values, said; one that lacks a unit's σ refused.
    let held = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--prior",
        "1mm,0.05deg,0.1%",
        "--json",
        "--data",
        &at("poses.csv"),
    ]);
    assert_eq!(held["outcome"], "fits_noise", "{}", held["summary"]);
    assert_eq!(held["prior"], "1 mm, 0.05°, 0.1 %");
    assert!(
        held["summary"]
            .as_str()
            .is_some_and(|words| words.contains("held by a prior of σ 1 mm, 0.05°, 0.1 %")),
        "{}",
        held["summary"]
    );
    let output = command("identify hexapod --method frame --sigma 20um --prior 1mm --data")
        .arg(at("poses.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{error}");
    assert!(
        error.contains("--prior") && error.contains("lacks the angle and gain σ"),
        "{error}"
    );
}

/// `gecaro report` of a parallel robot: the HTML report of the
/// identification, with the words `identify` prints, every parameter, the
/// plots, and the measurements that stand out named by their line — written
/// whether the fit is trusted or not, the exit status that of `identify`
/// (5 for a fit its data do not trust).
#[test]
fn a_parallel_robot_is_reported_as_identified() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("generate hexapod --method frame --count 60 --noise 2e-5 --seed 3 -o")
        .arg(at("poses.csv"))
        .assert()
        .success();
    three_off(&at("poses.csv"), &at("off.csv"));
    let report = |data: &str, name: &str, extra: &[&str]| {
        let output = command("report hexapod --method frame --sigma 20um --data")
            .arg(at(data))
            .args(extra)
            .arg("-o")
            .arg(at(name))
            .output()
            .expect("runs");
        let html = std::fs::read_to_string(at(name)).expect("the report is written");
        // What `identify` prints of the same, trusted or not.
        let printed = command("identify hexapod --method frame --sigma 20um --json --data")
            .arg(at(data))
            .args(extra)
            .output()
            .expect("runs");
        let identified: Value = serde_json::from_slice(&printed.stdout).expect("JSON");
        (output, html, identified)
    };
    // Three poses half a millimetre off: not trusted, said, and named.
    let (output, html, identified) = report("off.csv", "off.html", &[]);
    assert_eq!(output.status.code(), Some(5), "not trusted");
    assert!(html.contains("class=\"verdict bad\""), "the verdict in red");
    let summary = identified["summary"].as_str().expect("words");
    assert!(
        html.contains(summary),
        "the report says what identify said: {summary}"
    );
    assert!(
        html.contains("Standing out of the fit"),
        "the outliers listed"
    );
    for line in [7, 19, 35] {
        assert!(
            html.contains(&format!("<td>{line}</td>")),
            "line {line} listed"
        );
        assert!(
            html.contains(&format!("(line {line})")),
            "line {line} on the plot"
        );
    }
    for parameter in identified["parameters"].as_array().expect("parameters") {
        let name = parameter["name"].as_str().expect("name");
        assert!(
            html.contains(&format!("<td>{name}</td>")),
            "{name} in the table"
        );
    }
    assert_eq!(
        html.matches("<svg").count(),
        2,
        "the histograms and the errors per pose"
    );
    // Dropped and identified again: trusted, the three named as dropped.
    let (output, html, identified) = report("off.csv", "rejected.html", &["--reject"]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(identified["outcome"], "fits_noise");
    assert!(html.contains("class=\"verdict ok\""));
    assert!(
        html.contains("Dropped before this fit</strong> (3)"),
        "the three dropped"
    );
    assert!(html.contains("The result holds over the workspace"));
    // A report is never written over a file without --force.
    let again = command("report hexapod --method frame --data")
        .arg(at("poses.csv"))
        .arg("-o")
        .arg(at("rejected.html"))
        .output()
        .expect("runs");
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("already exists"));
    // A serial robot's job still refuses a parallel robot, naming the jobs
    // that read one.
    let refused = command("fk hexapod --qm 0,0,0,0,0,0")
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&refused.stderr);
    assert!(
        error.contains("`report`") && error.contains("`compensate`"),
        "{error}"
    );
}

/// Tool-point targets of a platform that turns are met with the platform
/// turned as the program says — its `qw,qx,qy,qz`, under their own names
/// or under the file's mapped by `--columns` alike — and level without
/// them.
#[test]
fn tool_point_targets_keep_the_programs_orientation() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("generate hexapod --method frame --count 5 --error-level 0 --seed 9 -o")
        .arg(at("job.csv"))
        .assert()
        .success();
    let text = std::fs::read_to_string(at("job.csv")).expect("read");
    let (header, rows) = text.split_once('\n').expect("a header");
    assert_eq!(header, "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z,qw,qx,qy,qz");
    std::fs::write(
        at("renamed.csv"),
        format!("qm1,qm2,qm3,qm4,qm5,qm6,X,Y,Z,Q0,Q1,Q2,Q3\n{rows}"),
    )
    .expect("written");
    let corrected = |program: &str, columns: &str, name: &str| {
        let mut line = command("compensate hexapod hexapod --match position --program");
        line.arg(at(program));
        if !columns.is_empty() {
            line.arg("--columns").arg(columns);
        }
        // Exit 4 when a target needs a leg beyond its range: written anyway.
        line.arg("-o").arg(at(name)).output().expect("runs");
        std::fs::read_to_string(at(name)).expect("the corrected program")
    };
    let plain = corrected("job.csv", "", "plain.csv");
    let mapped = corrected(
        "renamed.csv",
        "x=X,y=Y,z=Z,qw=Q0,qx=Q1,qy=Q2,qz=Q3",
        "mapped.csv",
    );
    let level = corrected("renamed.csv", "x=X,y=Y,z=Z", "level.csv");
    assert_eq!(plain, mapped, "the orientation read under either name");
    assert_ne!(plain, level, "without orientations the platform is level");
}

/// Two files of a hexapod's poses, the second measured from a tracker
/// station 2.6 m away and turned 130°: `--data` twice identifies the
/// station with the platform (fits the noise, the station within a
/// millimetre, held-out poses at the real platform's own error), the
/// report names both files, a measurement off in the second file is named
/// by its file and line, and a serial robot's second `--data` is refused
/// with where several sets go.
#[test]
fn files_from_two_tracker_stations_are_identified_together() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let station = nalgebra::Isometry3::from_parts(
        nalgebra::Translation3::new(-1.2, 2.3, -0.25),
        nalgebra::UnitQuaternion::from_euler_angles(0.01, -0.02, 2.27),
    );
    command("generate hexapod --method frame --count 40 --noise 2e-5 --seed 21 -o")
        .arg(at("first.csv"))
        .arg("--real-out")
        .arg(at("real.toml"))
        .assert()
        .success();
    for (name, count, seed) in [("later.csv", "40", "22"), ("held.csv", "200", "23")] {
        command("generate hexapod --method frame --noise 2e-5")
            .args(["--count", count, "--seed", seed, "-o"])
            .arg(at(name))
            .arg("--real")
            .arg(at("real.toml"))
            .assert()
            .success();
    }
    in_tracker_frame(&at("later.csv"), &at("station2.csv"), &station);
    let identify = |second: &str, extra: &[&str]| {
        let mut args = vec![
            "identify", "hexapod", "--method", "frame", "--sigma", "20um", "--json", "--data",
        ];
        let (first, second) = (at("first.csv"), at(second));
        args.extend([first.as_str(), "--data", second.as_str()]);
        args.extend(extra);
        json_output(&args)
    };
    let identified = identify("station2.csv", &["-o", &at("calibrated.toml")]);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    let found = &identified["stations"][0];
    assert!(
        found["data"]
            .as_str()
            .expect("data")
            .ends_with("station2.csv"),
        "{found}"
    );
    let position: Vec<f64> = found["frame"]["position"]
        .as_array()
        .expect("a position")
        .iter()
        .filter_map(Value::as_f64)
        .collect();
    let off = (nalgebra::Vector3::from_column_slice(&position) - station.translation.vector).norm();
    assert!(off < 1e-3, "the station found {off} m off: {found}");
    let summary = identified["summary"].as_str().expect("summary");
    assert!(
        summary.contains("station2.csv was measured from another station"),
        "{summary}"
    );
    let evaluated = |robot: &str| {
        json_output(&[
            "evaluate",
            robot,
            "--method",
            "frame",
            "--json",
            "--data",
            &at("held.csv"),
        ])["errors"]["position_rms"]
            .as_f64()
            .expect("rms")
    };
    let (after, floor) = (
        evaluated(&at("calibrated.toml")),
        evaluated(&at("real.toml")),
    );
    assert!(after <= 1.2 * floor, "{after} against the floor {floor}");
    // The report names both files.
    command("report hexapod --method frame --sigma 20um --data")
        .arg(at("first.csv"))
        .arg("--data")
        .arg(at("station2.csv"))
        .arg("-o")
        .arg(at("report.html"))
        .assert()
        .success();
    let html = std::fs::read_to_string(at("report.html")).expect("the report");
    assert!(
        html.contains("first.csv") && html.contains("station2.csv"),
        "the report names both files"
    );
    // A measurement off in the second file: named by its file and line.
    three_off(&at("station2.csv"), &at("station2-off.csv"));
    let output = command("identify hexapod --method frame --sigma 20um --json --data")
        .arg(at("first.csv"))
        .arg("--data")
        .arg(at("station2-off.csv"))
        .assert()
        .failure();
    let off: Value = serde_json::from_slice(&output.get_output().stdout).expect("JSON");
    let outliers = off["outliers"].as_array().expect("outliers");
    assert!(
        outliers.iter().any(|outlier| {
            outlier["data"]
                .as_str()
                .is_some_and(|data| data.ends_with("station2-off.csv"))
                && outlier["line"] == 19
        }),
        "{off}"
    );
    // Actuator values no pose has in the second file: named by its file
    // and line.
    let text = std::fs::read_to_string(at("station2.csv")).expect("data");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[5] = "1,2,3,4,5,6,0.1,0.2,0.3,1,0,0,0".into();
    std::fs::write(at("station2-bad.csv"), lines.join("\n") + "\n").expect("written");
    let refused = command("identify hexapod --method frame --sigma 20um --data")
        .arg(at("first.csv"))
        .arg("--data")
        .arg(at("station2-bad.csv"))
        .assert()
        .failure();
    let error = String::from_utf8_lossy(&refused.get_output().stderr).to_string();
    assert!(
        error.contains("station2-bad.csv:6: no platform pose"),
        "{error}"
    );
    // A serial robot's sets go in a study file.
    let refused = command("identify stanford --method position --data a.csv --data b.csv")
        .assert()
        .failure();
    let error = String::from_utf8_lossy(&refused.get_output().stderr).to_string();
    assert!(error.contains("study file"), "{error}");
}

/// `--residuals` and `--plot` of a parallel fit: one row per measured
/// pose with its line, the three dropped by `--reject` at weight 0 and
/// named outliers, the errors after the fit those the document sums; the
/// two plots written.
#[test]
fn a_parallel_fits_residuals_and_plots_are_written() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    command("generate hexapod --method frame --count 60 --noise 2e-5 --seed 3 -o")
        .arg(at("poses.csv"))
        .assert()
        .success();
    three_off(&at("poses.csv"), &at("off.csv"));
    let identified = json_output(&[
        "identify",
        "hexapod",
        "--method",
        "frame",
        "--sigma",
        "20um",
        "--reject",
        "--json",
        "--data",
        &at("off.csv"),
        "--residuals",
        &at("residuals.csv"),
        "--plot",
        &at("plots"),
    ]);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    // No field is quoted: the file's label has no comma here.
    let text = std::fs::read_to_string(at("residuals.csv")).expect("the residuals");
    let mut records = text.lines().map(|line| line.split(',').collect::<Vec<_>>());
    let header = records.next().expect("a header");
    let column = |name: &str| {
        header
            .iter()
            .position(|field| *field == name)
            .unwrap_or_else(|| panic!("no {name} in {header:?}"))
    };
    let rows: Vec<Vec<&str>> = records.collect();
    assert_eq!(rows.len(), 60);
    assert!(header.contains(&"rotation_after_deg"));
    let (lines, weight, outlier, after) = (
        column("lines"),
        column("weight"),
        column("outlier"),
        column("error_after_mm"),
    );
    for row in &rows {
        let dropped = ["7", "19", "35"].contains(&row[lines]);
        assert_eq!(row[weight] == "0", dropped, "{row:?}");
        if dropped {
            assert_eq!(row[outlier], "true", "{row:?}");
        }
    }
    let squares: f64 = rows
        .iter()
        .map(|row| row[after].parse::<f64>().expect("a number").powi(2))
        .sum();
    let rms = (squares / rows.len() as f64).sqrt();
    let stated = identified["errors_after"]["position_rms"]
        .as_f64()
        .expect("rms")
        * 1e3;
    assert!(
        (rms - stated).abs() <= 1e-9 * stated,
        "{rms} against {stated}"
    );
    for plot in ["errors_histogram.svg", "errors_per_configuration.svg"] {
        let svg = std::fs::read_to_string(folder.path().join("plots").join(plot)).expect(plot);
        assert!(svg.contains("<svg"), "{plot}");
    }
}

/// The autonomous way on the command line: a hexapod's own actuators and a
/// measuring leg's readings (σ 1 µm) generated and identified — the fit at
/// the noise, the leg found and its frames said to be the joints', the
/// leg's lengths after the fit at the noise where the nominal's are a
/// tenth of a millimetre off; the leg's options refused where they mean
/// nothing (another method, a serial robot, a job that takes no leg yet).
#[test]
fn a_measuring_legs_readings_calibrate_a_hexapod_on_the_command_line() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).display().to_string();
    let mount = [
        "--leg-base",
        "250mm,-100mm,0",
        "--leg-platform=-120mm,80mm,0",
    ];
    command("generate hexapod --method leg --count 600 --noise 1e-6 --seed 5 -o")
        .arg(at("legs.csv"))
        .args(mount)
        .assert()
        .success();
    let mut args = vec![
        "identify", "hexapod", "--method", "leg", "--sigma", "1um", "--json",
    ];
    args.extend(mount);
    let legs = at("legs.csv");
    args.extend(["--data", legs.as_str()]);
    let identified = json_output(&args);
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    let summary = identified["summary"].as_str().expect("summary");
    assert!(
        summary.contains("the measuring leg found") && summary.contains("joints 1–3"),
        "{summary}"
    );
    assert_eq!(identified["leg"]["gain"], 1.0, "{}", identified["leg"]);
    let rms = |errors: &Value| errors["position_rms"].as_f64().expect("rms");
    let (before, after) = (
        rms(&identified["errors_before"]),
        rms(&identified["errors_after"]),
    );
    assert!(after < 2e-6 && before > 50.0 * after, "{before} → {after}");
    // Its platform, written and read back, compensated for a program: the
    // frames it holds said.
    command("identify hexapod --method leg --sigma 1um")
        .args(mount)
        .arg("--data")
        .arg(at("legs.csv"))
        .arg("-o")
        .arg(at("calibrated.toml"))
        .assert()
        .success();
    command("generate hexapod --method frame --count 10 --error-level 0 --seed 6 -o")
        .arg(at("program.csv"))
        .assert()
        .success();
    let compensated = command("compensate hexapod")
        .arg(at("calibrated.toml"))
        .arg("--program")
        .arg(at("program.csv"))
        .arg("-o")
        .arg(at("compensated.csv"))
        .assert()
        .success();
    let said = String::from_utf8_lossy(&compensated.get_output().stdout).to_string();
    assert!(said.contains("joints 1–3"), "{said}");
    // Readings in millimetres read as metres: named, with the unit to state.
    let text = std::fs::read_to_string(at("legs.csv")).expect("data");
    let mut lines = text.lines();
    let mut in_mm = format!("{}\n", lines.next().expect("header"));
    for line in lines {
        let mut values: Vec<String> = line.split(',').map(str::to_owned).collect();
        let reading: f64 = values[6].parse().expect("a reading");
        values[6] = format!("{:?}", reading * 1e3);
        in_mm.push_str(&(values.join(",") + "\n"));
    }
    std::fs::write(at("legs-mm.csv"), in_mm).expect("written");
    let output = command("identify hexapod --method leg --sigma 1um")
        .args(mount)
        .arg("--data")
        .arg(at("legs-mm.csv"))
        .output()
        .expect("runs");
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && error.contains("--length-unit mm"),
        "{error}"
    );
    // Two files of a leg's readings are one set (a leg has no frame).
    let mut twice = args.clone();
    twice.extend(["--data", legs.as_str()]);
    let both = json_output(&twice);
    assert_eq!(both["configurations"], 1200, "{}", both["summary"]);
    assert_eq!(both["stations"], serde_json::json!([]));
    // The frames' convention: twelve joint coordinates held, the tool not seen.
    let statuses: Vec<&str> = identified["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .filter_map(|parameter| parameter["status"].as_str())
        .collect();
    assert_eq!(
        statuses
            .iter()
            .filter(|status| **status == "excluded")
            .count(),
        15,
        "{statuses:?}"
    );
    for (line, wanted) in [
        (
            "identify hexapod --method frame --sigma 20um --leg-base 0,0,0 --data x.csv",
            "--leg-base: states a measuring leg",
        ),
        (
            "identify stanford --method position --leg-base 0,0,0 --data x.csv",
            "--leg-base is a parallel robot's measuring leg",
        ),
        (
            "generate stanford --method leg --count 5 -o x.csv",
            "--method leg is a parallel robot's measuring leg",
        ),
        (
            "identify hexapod --method leg --sigma 1um --data x.csv",
            "--leg-base: the `leg` method needs the measuring leg's base socket",
        ),
        (
            "evaluate hexapod --method leg --data x.csv",
            "is not there yet",
        ),
    ] {
        let output = command(line)
            .current_dir(folder.path())
            .output()
            .expect("runs");
        let error = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{line}");
        assert!(error.contains(wanted), "{line}: {error}");
    }
}
