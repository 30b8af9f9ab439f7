//! The customer's frames, end to end (issue 74): compensation for the tool
//! that works after a reflector study, against simulated truth — the real
//! robot of `named_frames::write_cell` and its true reflector.

use std::path::Path;

use gecaro_calib::simulation::{Sampler, perturbed_robot};
use gecaro_core::{Robot, terminal_pose};
use nalgebra::{IsometryMatrix3, Point3, Vector3};

use super::named_frames::{tracker_1, write_cell};
use crate::util::{command, gecaro, json_output};

/// The real robot of `write_cell`, seen from tracker 1 (its first draw).
fn real_robot() -> Robot {
    let nominal = gecaro_io::load_robot("industrial6").expect("robot").robot;
    perturbed_robot(&nominal, 0.5, &mut Sampler::new(5))
        .expect("real")
        .reframed(&tracker_1().inverse(), &IsometryMatrix3::identity())
        .expect("seen from tracker 1")
}

/// The point `tool` (in frame n+1) at `qm` on `robot`.
fn point(robot: &Robot, qm: &[f64], tool: &Vector3<f64>) -> Vector3<f64> {
    (terminal_pose(robot, qm).expect("pose") * Point3::from(*tool)).coords
}

fn rms(errors: &[f64]) -> f64 {
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt()
}

/// Joint rows of a CSV (its first six columns after the header).
fn joint_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .expect("read")
        .lines()
        .filter(|line| !line.starts_with('#'))
        .skip(1)
        .map(|line| {
            line.split(',')
                .take(6)
                .map(|v| v.parse().expect("number"))
                .collect()
        })
        .collect()
}

/// A three-reflector study, every set naming its reflector: the calibrated
/// file holds the reflectors as identified and says frame n+1 was not
/// observed; compensating tool0 (or a tool posed in it) is refused, and a
/// job compensated for `smr_a` lands at the calibration's own held-out
/// accuracy at that reflector on the real robot (≤ 1.2×).
#[test]
fn a_reflector_study_compensates_its_reflector_and_refuses_tool0() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    write_cell(folder.path());
    let calibrated = at("calibrated.toml");
    command("identify --study")
        .arg(at("study.toml"))
        .arg("-o")
        .arg(&calibrated)
        .assert()
        .success();
    let file = gecaro_io::load_robot(calibrated.to_str().expect("UTF-8")).expect("reads back");
    assert!(!file.tool_frame_observed);
    // The base's mass rides with the base, not with the tracker's frame:
    // as far from joint 1's axis frame as in the nominal robot.
    let base_offset = |file: &gecaro_io::RobotFile| {
        let com = file.masses.link(0).expect("a base mass").com;
        let frame_1 = gecaro_core::frame_transform(&file.robot.frames()[1], 0.0);
        (frame_1.inverse() * Point3::from(com)).coords
    };
    let nominal_file = gecaro_io::load_robot("industrial6").expect("robot");
    assert!((base_offset(&file) - base_offset(&nominal_file)).norm() < 1e-12);
    let names: Vec<&str> = file.tools.iter().map(|tool| tool.name.as_str()).collect();
    assert_eq!(names, ["smr_a", "smr_b", "smr_c"]);
    let identified = file.tools[0].pose.translation.vector;
    // The nominal robot where the calibrated one stands: tracker 1's frame.
    let nominal = gecaro_io::load_robot("industrial6").expect("robot");
    let nominal_seen = gecaro_io::RobotFile::of(
        nominal
            .robot
            .reframed(&tracker_1().inverse(), &IsometryMatrix3::identity())
            .expect("reframed"),
    );
    let nominal_path = at("nominal.toml");
    std::fs::write(
        &nominal_path,
        gecaro_io::robot_file_text(&nominal_seen, &nominal_path).expect("text"),
    )
    .expect("written");
    // A job of 40 joint targets drawn apart from the study's data.
    let mut sampler = Sampler::new(2024);
    let job: Vec<Vec<f64>> = (0..40)
        .map(|_| sampler.configuration(&nominal_seen.robot))
        .collect();
    let mut text = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for qm in &job {
        let row: Vec<String> = qm.iter().map(|v| format!("{v:?}")).collect();
        text += &(row.join(",") + "\n");
    }
    std::fs::write(at("job.csv"), text).expect("job");
    let compensate = |extra: &[&str]| {
        gecaro()
            .arg("compensate")
            .arg(&nominal_path)
            .arg(&calibrated)
            .arg("--program")
            .arg(at("job.csv"))
            .args(["--match", "position", "--force", "-o"])
            .arg(at("corrected.csv"))
            .args(extra)
            .output()
            .expect("runs")
    };
    for extra in [&[][..], &["--tool", "0,0,100mm"][..]] {
        let output = compensate(extra);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains("is not calibrated") && stderr.contains("tool smr_a, smr_b, smr_c"),
            "{stderr}"
        );
        assert!(!at("corrected.csv").exists());
    }
    // The position match turns the tool (a 0.5-level robot: several
    // degrees): flagged beyond 1°, accepted when asked.
    let output = compensate(&["--tool", "smr_a"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.contains("turns the tool by more than 1.00°"),
        "{stderr}"
    );
    let output = compensate(&["--tool", "smr_a", "--max-tool-turn", "30deg"]);
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("largest tool turn left by the position match"),
        "{stdout}"
    );
    // On the real robot, with its true reflector.
    let real = real_robot();
    let truth = Vector3::new(0.04, 0.025, 0.09);
    let corrected = joint_rows(&at("corrected.csv"));
    assert_eq!(corrected.len(), job.len());
    let landed: Vec<f64> = job
        .iter()
        .zip(&corrected)
        .map(|(qm, q)| {
            let target = point(&nominal_seen.robot, qm, &identified);
            (point(&real, q, &truth) - target).norm()
        })
        .collect();
    let floor: Vec<f64> = job
        .iter()
        .map(|qm| (point(&real, qm, &truth) - point(&file.robot, qm, &identified)).norm())
        .collect();
    let (landed, floor) = (rms(&landed), rms(&floor));
    assert!(
        landed <= 1.2 * floor,
        "compensated {:.4} mm, floor {:.4} mm",
        landed * 1e3,
        floor * 1e3
    );
    eprintln!(
        "smr_a compensated {:.4} mm, floor {:.4} mm",
        landed * 1e3,
        floor * 1e3
    );
}

/// The tool0 point of `a` and `b` at each of `configurations`: RMS (m).
fn apart(a: &Robot, b: &Robot, configurations: &[Vec<f64>]) -> f64 {
    let zero = Vector3::zeros();
    rms(&configurations
        .iter()
        .map(|qm| (point(a, qm, &zero) - point(b, qm, &zero)).norm())
        .collect::<Vec<_>>())
}

/// The owner's base registered by five plate points (issue 74): a robot
/// calibrated from a tracker 3 m away and tilted 0.5° (150 poses, σ 20 µm),
/// its plate's holes measured by the same tracker and written as a tracker
/// exports them (`;`, decimal commas, mm). Held out in the owner's base
/// frame: with the holes measured as a static point is (σ 5 µm, averaged),
/// within 1.5× the calibration's own accuracy; with the holes at the poses'
/// σ of 20 µm, the base's own error adds what the registration states
/// (five points cannot do better); the base by joint 1's axis misses by
/// millimetres.
#[test]
fn the_owner_s_base_is_registered_by_plate_points() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let text = |name: &str| at(name).to_str().expect("UTF-8").to_owned();
    let nominal = gecaro_io::load_robot("industrial6").expect("robot");
    let mut sampler = Sampler::new(31);
    let real = perturbed_robot(&nominal.robot, 1.0, &mut sampler).expect("real");
    let tracker = IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(3.0, -0.5, 0.4),
        nalgebra::Rotation3::from_euler_angles(0.5f64.to_radians(), -0.3f64.to_radians(), 2.6),
    );
    let seen = real
        .reframed(&tracker.inverse(), &IsometryMatrix3::identity())
        .expect("seen from the tracker");
    let seen_path = at("real_seen.toml");
    std::fs::write(
        &seen_path,
        gecaro_io::robot_file_text(&gecaro_io::RobotFile::of(seen.clone()), &seen_path)
            .expect("text"),
    )
    .expect("written");
    gecaro()
        .args(["generate", "industrial6", "--real", &text("real_seen.toml")])
        .args(["--method", "position", "--count", "150", "--noise", "2e-5"])
        .args(["--seed", "8", "-o", &text("train.csv")])
        .assert()
        .success();
    command("identify industrial6 --method position --sigma 20um")
        .args(["--data", &text("train.csv"), "-o", &text("calibrated.toml")])
        .assert()
        .success();
    let load = |name: &str| gecaro_io::load_robot(&text(name)).expect("robot").robot;
    let mut held = Sampler::new(99);
    let configurations: Vec<Vec<f64>> = (0..60).map(|_| held.configuration(&real)).collect();
    let floor = apart(&load("calibrated.toml"), &seen, &configurations);
    // The held-out points' RMS distance from the base's origin.
    let reach = rms(&configurations
        .iter()
        .map(|qm| point(&real, qm, &Vector3::zeros()).norm())
        .collect::<Vec<_>>());
    // The plate's holes as the drawing gives them.
    let holes = [
        ("H1", 250.0, 250.0, 0.0),
        ("H2", -250.0, 250.0, 0.0),
        ("H3", -250.0, -250.0, 0.0),
        ("H4", 250.0, -250.0, 0.0),
        ("P5", 0.0, 320.0, 40.0),
    ];
    for (sigma, output) in [(5e-6, "in_base_5um.toml"), (2e-5, "in_base_20um.toml")] {
        let mut plate = String::from("# plate holes, tracker 1\nname;x;y;z;base_x;base_y;base_z\n");
        for (name, x, y, z) in holes {
            let base = Vector3::new(x, y, z) * 1e-3;
            let measured =
                (tracker.inverse() * Point3::from(base)).coords + sampler.gaussian_vector(sigma);
            let mm = |v: f64| format!("{:.4}", v * 1e3).replace('.', ",");
            plate += &format!(
                "{name};{};{};{};{x};{y};{z}\n",
                mm(measured.x),
                mm(measured.y),
                mm(measured.z)
            );
        }
        std::fs::write(at("plate.csv"), plate).expect("plate");
        let run = gecaro()
            .args([
                "robot",
                "rebase",
                &text("calibrated.toml"),
                "--nominal",
                "industrial6",
            ])
            .args([
                "--base-points",
                &text("plate.csv"),
                "--length-unit",
                "mm",
                "--json",
            ])
            .args(["--force", "-o", &text(output)])
            .output()
            .expect("runs");
        assert!(run.status.success(), "{run:?}");
        let json: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON");
        let registration = &json["registration"];
        assert_eq!(registration["points"].as_array().expect("points").len(), 5);
        assert_eq!(registration["points"][0]["name"], "H1");
        let found = registration["sigma"].as_f64().expect("σ");
        assert!(found > 0.3 * sigma && found < 2.0 * sigma, "{registration}");
        // What the registration says it adds at the held-out points' reach.
        let (origin, rotation) = (
            registration["origin_sigma"].as_f64().expect("σ"),
            registration["rotation_sigma"].as_f64().expect("σ"),
        );
        let stated = (3.0 * origin * origin + 2.0 * (rotation * reach).powi(2)).sqrt();
        let at_one_metre = registration["at_one_metre"].as_f64().expect("m");
        assert!(
            (at_one_metre - (3.0 * origin * origin + 2.0 * rotation * rotation).sqrt()).abs()
                < 1e-12
        );
        let in_base = apart(&load(output), &real, &configurations);
        let added = (in_base * in_base - floor * floor).max(0.0).sqrt();
        eprintln!(
            "plate σ {:.0} µm: held out in the owner's base {:.4} mm (floor {:.4} mm), the base \
             adds {:.4} mm, stated {:.4} mm",
            sigma * 1e6,
            in_base * 1e3,
            floor * 1e3,
            added * 1e3,
            stated * 1e3
        );
        assert!(added < 2.0 * stated, "{added} vs stated {stated}");
        if sigma < 1e-5 {
            assert!(in_base <= 1.5 * floor, "{in_base} vs floor {floor}");
        }
    }
    gecaro()
        .args([
            "robot",
            "rebase",
            &text("calibrated.toml"),
            "--nominal",
            "industrial6",
        ])
        .args(["-o", &text("by_convention.toml")])
        .assert()
        .success();
    let by_convention = apart(&load("by_convention.toml"), &real, &configurations);
    eprintln!("by joint 1's axis {:.4} mm", by_convention * 1e3);
    assert!(
        by_convention > 10.0 * floor,
        "{by_convention} vs floor {floor}"
    );
}

/// Joint values of `count` orientations of `robot` with the tip `tool` (in
/// frame n+1) on `fixed` (plus `noise`: the tip's placement, m per axis),
/// tilted by up to 35° about random axes from a pose looking down.
fn pivot_configurations(
    robot: &Robot,
    tool: &Vector3<f64>,
    fixed: &Vector3<f64>,
    (count, noise): (usize, f64),
    sampler: &mut Sampler,
) -> Vec<Vec<f64>> {
    let tooled = robot
        .reframed(
            &IsometryMatrix3::identity(),
            &IsometryMatrix3::translation(tool.x, tool.y, tool.z),
        )
        .expect("tooled");
    let down = nalgebra::Rotation3::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    let start = [0.0, -0.3, 0.9, 0.0, 0.9, 0.0];
    let mut configurations = Vec::new();
    while configurations.len() < count {
        let axis = nalgebra::Unit::new_normalize(sampler.gaussian_vector(1.0));
        let turn = nalgebra::Rotation3::from_axis_angle(&axis, sampler.uniform(-0.6, 0.6));
        let target = IsometryMatrix3::from_parts(
            nalgebra::Translation3::from(fixed + sampler.gaussian_vector(noise)),
            turn * down,
        );
        if let Ok(solution) = gecaro_core::inverse_kinematics(
            &tooled,
            &gecaro_core::Target::Frame(target),
            &start,
            &gecaro_core::InverseOptions::default(),
        ) && robot.within_limits(&solution.joint_positions)
        {
            configurations.push(solution.motor_positions);
        }
    }
    configurations
}

/// `gecaro tcp`: 8 orientations of an exact robot give the tip to 1e-6 m;
/// with the tip placed to 20 µm, within 3σ of the σ it states (issue 74).
#[test]
fn a_tool_point_is_taught_by_pivoting() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = gecaro_io::load_robot("industrial6").expect("robot").robot;
    let (tool, fixed) = (
        Vector3::new(0.015, -0.02, 0.18),
        Vector3::new(0.75, 0.1, 0.3),
    );
    let mut sampler = Sampler::new(17);
    for (noise, name) in [(0.0, "exact.csv"), (2e-5, "noisy.csv")] {
        let configurations = pivot_configurations(&robot, &tool, &fixed, (8, noise), &mut sampler);
        let mut text = String::from("qm1;qm2;qm3;qm4;qm5;qm6\n");
        for qm in &configurations {
            let row: Vec<String> = qm
                .iter()
                .map(|v| format!("{:.10}", v.to_degrees()).replace('.', ","))
                .collect();
            text += &(row.join(";") + "\n");
        }
        let path = folder.path().join(name);
        std::fs::write(&path, text).expect("pivot");
        let output = command("tcp industrial6 --angle-unit deg --json --data")
            .arg(&path)
            .output()
            .expect("runs");
        assert!(output.status.success(), "{output:?}");
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        let found: Vec<f64> = (0..3)
            .map(|axis| json["tool"][axis].as_f64().expect("m"))
            .collect();
        let error = (Vector3::from_column_slice(&found) - tool).abs().max();
        let sigma = json["tool_sigma"].as_f64().expect("σ");
        eprintln!("pivot with noise {noise}: tip off by {error:.2e} m, σ {sigma:.2e} m");
        if noise == 0.0 {
            assert!(error < 1e-6, "{json}");
        } else {
            assert!(error < 3.0 * sigma && sigma < 1e-4, "{json}");
        }
    }
    // Turned about the tool's axis alone: refused, the spread named.
    let about_axis: String = (0..5)
        .map(|i| format!("0,-0.3,0.9,0,0.9,{}\n", f64::from(i) * 0.5))
        .collect();
    let path = folder.path().join("about_axis.csv");
    std::fs::write(&path, format!("qm1,qm2,qm3,qm4,qm5,qm6\n{about_axis}")).expect("pivot");
    let output = command("tcp industrial6 --data")
        .arg(&path)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("not determined"), "{stderr}");
}

/// `gecaro frame`: a fixture's frame from its origin, +x and xy points
/// (exact), and from four points with their place in it (least squares,
/// with σ), as a tracker exports them (mm).
#[test]
fn a_user_frame_is_made_from_measured_points() {
    let folder = tempfile::tempdir().expect("folder");
    let truth = IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(1.2, -0.35, 0.74),
        nalgebra::Rotation3::from_euler_angles(0.01, -0.02, 0.6),
    );
    let measured = |x: f64, y: f64, z: f64| (truth * Point3::new(x, y, z)).coords * 1e3;
    let three = [("origin", 0.0, 0.0), ("x", 0.4, 0.0), ("xy", 0.1, 0.3)];
    let mut text = String::from("name,x,y,z\n");
    for (name, x, y) in three {
        let p = measured(x, y, 0.0);
        text += &format!("{name},{},{},{}\n", p.x, p.y, p.z);
    }
    let mut placed = String::from("name,x,y,z,frame_x,frame_y,frame_z\n");
    for (i, (x, y)) in [(0.0, 0.0), (400.0, 0.0), (400.0, 300.0), (0.0, 300.0)]
        .iter()
        .enumerate()
    {
        let p = measured(x * 1e-3, y * 1e-3, 0.0);
        placed += &format!("P{i},{},{},{},{x},{y},0\n", p.x + 0.01, p.y, p.z);
    }
    for (name, content, least_squares) in [("three.csv", text, false), ("four.csv", placed, true)] {
        let path = folder.path().join(name);
        std::fs::write(&path, content).expect("points");
        let output = command("frame --length-unit mm --json --points")
            .arg(&path)
            .output()
            .expect("runs");
        assert!(output.status.success(), "{output:?}");
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        let position = Vector3::new(
            json["position"][0].as_f64().expect("m"),
            json["position"][1].as_f64().expect("m"),
            json["position"][2].as_f64().expect("m"),
        );
        let tolerance = if least_squares { 2e-5 } else { 1e-9 };
        assert!(
            (position - truth.translation.vector).norm() < tolerance,
            "{json}"
        );
        let q = &json["quaternion"];
        let found = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[0].as_f64().expect("w"),
            q[1].as_f64().expect("x"),
            q[2].as_f64().expect("y"),
            q[3].as_f64().expect("z"),
        ));
        let expected = nalgebra::UnitQuaternion::from_rotation_matrix(&truth.rotation);
        assert!(found.angle_to(&expected) < tolerance * 10.0, "{json}");
        assert_eq!(json["sigma"].is_number(), least_squares, "{json}");
    }
}

/// A cell planned before it is measured (issue 74): the study's set files
/// do not exist yet, the plan writes them in the teach pendant's degrees
/// with a units line, and the planned study reads back.
#[test]
fn a_cell_is_planned_before_it_is_measured() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    std::fs::copy("examples/tracker-cell/study.toml", at("study.toml")).expect("study");
    let output = command("plan --study")
        .arg(at("study.toml"))
        .args(["--count", "24", "--angle-unit", "deg", "-o"])
        .arg(at("planned.toml"))
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let first = std::fs::read_to_string(at("planned_1.csv")).expect("written");
    assert!(first.starts_with("# units: angle_unit = deg"), "{first}");
    let planned = std::fs::read_to_string(at("planned.toml")).expect("written");
    assert!(planned.contains("angle_unit = \"deg\""), "{planned}");
    assert!(planned.contains("(qm in deg and m)"), "{planned}");
    let predicted = command("predict --study")
        .arg(at("planned.toml"))
        .output()
        .expect("runs");
    assert!(predicted.status.success(), "{predicted:?}");
}

/// Files written alike are described once: `columns`, `delimiter` and the
/// units at a study's top level hold for every set.
#[test]
fn a_study_states_its_files_format_once() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let study = std::fs::read_to_string("examples/tracker-cell/study.toml").expect("study");
    for entry in std::fs::read_dir("examples/tracker-cell")
        .expect("cell")
        .flatten()
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.ends_with(".csv") {
            // As the tracker's software writes them: its own names, `;`.
            let text = std::fs::read_to_string(entry.path()).expect("data");
            let renamed: String = text
                .lines()
                .map(|line| {
                    if line.starts_with("qm1") {
                        "A1;A2;A3;A4;A5;A6;X;Y;Z".to_owned()
                    } else if line.starts_with('#') {
                        line.to_owned()
                    } else {
                        line.replace(',', ";")
                    }
                })
                .collect::<Vec<_>>()
                .join("\n");
            std::fs::write(at(&name), renamed + "\n").expect("written");
        }
    }
    let top = "columns = { qm1 = \"A1\", qm2 = \"A2\", qm3 = \"A3\", qm4 = \"A4\", qm5 = \"A5\", \
               qm6 = \"A6\", x = \"X\", y = \"Y\", z = \"Z\" }\ndelimiter = \";\"\n";
    let study = study.replacen(
        "angle_unit = \"deg\"\n",
        &format!("angle_unit = \"deg\"\n{top}"),
        1,
    );
    std::fs::write(at("study.toml"), study).expect("study");
    let output = command("identify --study")
        .arg(at("study.toml"))
        .arg("--json")
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(
        json["verdict"]["outcome"], "fits_noise",
        "{}",
        json["verdict"]
    );
}

/// Data measured from another tracker position (issue 74): `evaluate`
/// names the error as a frame mismatch instead of printing metres of
/// "error"; `--register 30%` registers the frame on 30 % of the rows and
/// judges the robot on the rest, at the noise.
#[test]
fn data_from_another_tracker_position_are_registered() {
    let folder = tempfile::tempdir().expect("folder");
    let text = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    let nominal = gecaro_io::load_robot("industrial6").expect("robot");
    let tracker = IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(2.2, 1.4, -0.3),
        nalgebra::Rotation3::from_euler_angles(0.01, 0.0, -2.0),
    );
    let seen = gecaro_io::RobotFile::of(
        nominal
            .robot
            .reframed(&tracker.inverse(), &IsometryMatrix3::identity())
            .expect("seen"),
    );
    let seen_path = folder.path().join("seen.toml");
    std::fs::write(
        &seen_path,
        gecaro_io::robot_file_text(&seen, &seen_path).expect("text"),
    )
    .expect("written");
    gecaro()
        .args(["generate", "industrial6", "--real", &text("seen.toml")])
        .args(["--method", "position", "--count", "60", "--noise", "2e-5"])
        .args(["--seed", "5", "-o", &text("other.csv")])
        .assert()
        .success();
    let evaluate = |extra: &[&str]| {
        command("evaluate industrial6 --method position --json")
            .args(["--data", &text("other.csv")])
            .args(extra)
            .output()
            .expect("runs")
    };
    let plain = evaluate(&[]);
    let stderr = String::from_utf8_lossy(&plain.stderr);
    assert!(
        stderr.contains("look measured in another frame"),
        "{stderr}"
    );
    let registered = evaluate(&["--register", "30%"]);
    assert!(registered.status.success(), "{registered:?}");
    let stderr = String::from_utf8_lossy(&registered.stderr);
    assert!(
        stderr.contains("registered the measurement frame in closed form on 18 of the 60 rows"),
        "{stderr}"
    );
    let json: serde_json::Value = serde_json::from_slice(&registered.stdout).expect("JSON");
    let rms = json["rms"].as_f64().expect("m");
    assert!(rms < 6e-5, "{json}");
    assert_eq!(json["count"], 42, "{json}");
    let refused = evaluate(&["--register", "150%"]);
    assert_eq!(refused.status.code(), Some(2));
}

/// A 6-D probe's export as it is (issue 74): orientations as Euler angles
/// x, y′, z″ in degrees, positions in mm, each point's σ, `;` and decimal
/// commas — read with `--rotation euler-xyz` and identified as the
/// quaternions the probe stood for are, the verdict testing each row
/// against its own σ.
#[test]
fn a_probe_s_euler_angles_are_read_as_they_are() {
    let folder = tempfile::tempdir().expect("folder");
    let text = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    command("generate industrial6 --method frame --count 40")
        .args(["--noise", "1e-5", "--seed", "6", "-o", &text("frames.csv")])
        .assert()
        .success();
    let original = std::fs::read_to_string(text("frames.csv")).expect("data");
    // The probe states each point's σ too: 0,01 mm and 1e-5 rad in degrees.
    let mut probe = String::from("A1;A2;A3;A4;A5;A6;X;Y;Z;RX;RY;RZ;SP;SR\n");
    for line in original
        .lines()
        .filter(|line| !line.starts_with('#'))
        .skip(1)
    {
        let v: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("number"))
            .collect();
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            v[9], v[10], v[11], v[12],
        ));
        // R = Rx(a)·Ry(b)·Rz(c), written out independently.
        let m = q.to_rotation_matrix().into_inner();
        let b = m[(0, 2)].asin();
        let a = (-m[(1, 2)]).atan2(m[(2, 2)]);
        let c = (-m[(0, 1)]).atan2(m[(0, 0)]);
        let mut fields: Vec<f64> = v[..6].iter().map(|q| q.to_degrees()).collect();
        fields.extend(v[6..9].iter().map(|p| p * 1e3));
        fields.extend([a, b, c].map(f64::to_degrees));
        fields.extend([1e-2, 1e-5f64.to_degrees()]);
        let row: Vec<String> = fields
            .iter()
            .map(|x| format!("{x:.12}").replace('.', ","))
            .collect();
        probe += &(row.join(";") + "\n");
    }
    std::fs::write(text("probe.csv"), probe).expect("probe");
    let identify = |extra: &[&str]| -> serde_json::Value {
        let output = command("identify industrial6 --method frame --json --no-check-model")
            .args(extra)
            .output()
            .expect("runs");
        assert!(output.status.success(), "{output:?}");
        serde_json::from_slice(&output.stdout).expect("JSON")
    };
    let by_quaternions = identify(&["--data", &text("frames.csv"), "--sigma", "1e-5"]);
    let columns = "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6,x=X,y=Y,z=Z,rx=RX,ry=RY,rz=RZ,\
                   sigma=SP,sigma_angle=SR";
    let by_euler = identify(&[
        "--data",
        &text("probe.csv"),
        "--rotation",
        "euler-xyz",
        "--angle-unit",
        "deg",
        "--length-unit",
        "mm",
        "--columns",
        columns,
    ]);
    let values = |json: &serde_json::Value| -> Vec<f64> {
        json["parameters"]
            .as_array()
            .expect("parameters")
            .iter()
            .map(|p| p["identified"].as_f64().expect("value"))
            .collect()
    };
    let (a, b) = (values(&by_quaternions), values(&by_euler));
    assert!(
        a.len() > 20 && a.len() == b.len(),
        "{} vs {}",
        a.len(),
        b.len()
    );
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-8, "{x} vs {y}");
    }
    // The rows' own σ test them as the stated one does.
    for json in [&by_quaternions, &by_euler] {
        assert_eq!(
            json["verdict"]["outcome"], "fits_noise",
            "{}",
            json["verdict"]
        );
    }
    let ratio = |json: &serde_json::Value| json["verdict"]["noise_test"]["sigma_ratio"].as_f64();
    let (stated, own) = (
        ratio(&by_quaternions).expect("σ̂/σ"),
        ratio(&by_euler).expect("σ̂/σ"),
    );
    assert!((stated - own).abs() < 1e-6, "{stated} vs {own}");
}

/// The owner's base registered by the circles of joints 1 and 2 (issue
/// 74): the base as a robot's maker defines it (z along axis 1, the origin
/// where the common normal of axes 1 and 2 meets it, x along that normal
/// at joint 1's zero), measured by a tracker 3 m away (σ 20 µm) while
/// joint 1 turned alone and joint 2 turned alone, the joints written in
/// the pendant's degrees and the points in mm. Held out against the real
/// robot in that base: within 2× the calibration's own accuracy.
#[test]
fn the_maker_s_base_is_registered_by_circles() {
    use gecaro_calib::axis_circles::{Axis, axes_frame};
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let text = |name: &str| at(name).to_str().expect("UTF-8").to_owned();
    let nominal = gecaro_io::load_robot("industrial6").expect("robot").robot;
    let mut sampler = Sampler::new(41);
    let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
    let tracker = IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(-2.6, 1.4, 0.3),
        nalgebra::Rotation3::from_euler_angles(-0.4f64.to_radians(), 0.2f64.to_radians(), -0.9),
    );
    let seen = real
        .reframed(&tracker.inverse(), &IsometryMatrix3::identity())
        .expect("seen from the tracker");
    std::fs::write(
        at("real_seen.toml"),
        gecaro_io::robot_file_text(
            &gecaro_io::RobotFile::of(seen.clone()),
            &at("real_seen.toml"),
        )
        .expect("text"),
    )
    .expect("written");
    gecaro()
        .args(["generate", "industrial6", "--real", &text("real_seen.toml")])
        .args(["--method", "position", "--count", "150", "--noise", "2e-5"])
        .args(["--seed", "12", "-o", &text("train.csv")])
        .assert()
        .success();
    command("identify industrial6 --method position")
        .args(["--sigma", "20um", "--data", &text("train.csv")])
        .args(["-o", &text("calibrated.toml")])
        .assert()
        .success();
    // The circles as a tracker measures them: a static point (averaged, σ
    // 5 µm) every 10° of joint 1 from −150° to 150°, then every 5° of joint
    // 2 from −80° to 30° with joint 1 held at 25°.
    let start = [0.0, -20.0, 30.0, 10.0, 40.0, 0.0];
    let held = 25.0;
    let mut rows: Vec<[f64; 6]> = (-15..=15)
        .map(|step| {
            let mut row = start;
            row[0] = f64::from(step) * 10.0;
            row
        })
        .collect();
    for step in -16..=6 {
        let mut row = start;
        row[0] = held;
        row[1] = f64::from(step) * 5.0;
        rows.push(row);
    }
    let mut file = String::from(
        "# circles of joints 1 and 2, tracker at station A\nqm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n",
    );
    for row in &rows {
        let qm: Vec<f64> = row.iter().map(|q| q.to_radians()).collect();
        let p = point(&seen, &qm, &Vector3::zeros()) + sampler.gaussian_vector(5e-6);
        let joints: Vec<String> = row.iter().map(|q| q.to_string()).collect();
        file += &format!(
            "{},{:.4},{:.4},{:.4}\n",
            joints.join(","),
            p.x * 1e3,
            p.y * 1e3,
            p.z * 1e3
        );
    }
    std::fs::write(at("circles.csv"), file).expect("circles");
    let run = gecaro()
        .args([
            "robot",
            "rebase",
            &text("calibrated.toml"),
            "--nominal",
            "industrial6",
        ])
        .args(["--base-circles", &text("circles.csv")])
        .args(["--length-unit", "mm", "--angle-unit", "deg", "--json"])
        .args(["-o", &text("in_base.toml")])
        .output()
        .expect("runs");
    assert!(run.status.success(), "{run:?}");
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON");
    let registration = &json["registration"];
    assert_eq!(registration["by"], "circles", "{registration}");
    // The row of joint 2's circle at the start's −20° is on joint 1's
    // circle too (joint 1 at 25°, every other joint at the start).
    assert_eq!(registration["points"].as_array().expect("points").len(), 55);
    let sigma = registration["sigma"].as_f64().expect("σ");
    assert!(sigma > 2.5e-6 && sigma < 1e-5, "{registration}");
    // The truth: the real robot's own axes, in its own frame.
    let axes = |robot: &Robot, qm: &[f64]| {
        let chain = gecaro_core::forward_kinematics(robot, qm).expect("chain");
        let axis = |frame: usize| {
            let pose = chain.world_from_frame(frame);
            Axis {
                point: pose.translation.vector,
                direction: nalgebra::Unit::new_normalize(pose.rotation * Vector3::z()),
            }
        };
        (axis(1), axis(2))
    };
    let zero = [0.0; 6];
    let (nominal_1, nominal_2) = axes(&nominal, &zero);
    let (nominal_frame, kind) =
        axes_frame(&nominal_1, &nominal_2, 0.0, None).expect("nominal axes");
    let mut at_held = start.map(f64::to_radians);
    at_held[0] = held.to_radians();
    let (real_1, real_2) = axes(&real, &at_held);
    let (real_frame, _) =
        axes_frame(&real_1, &real_2, held.to_radians(), Some(kind)).expect("real axes");
    let base = real_frame * nominal_frame.inverse();
    let truth = real
        .reframed(&base.inverse(), &IsometryMatrix3::identity())
        .expect("the real robot in the maker's base");
    let load = |name: &str| gecaro_io::load_robot(&text(name)).expect("robot").robot;
    let mut held_out = Sampler::new(77);
    let configurations: Vec<Vec<f64>> = (0..60).map(|_| held_out.configuration(&real)).collect();
    let floor = apart(&load("calibrated.toml"), &seen, &configurations);
    let in_base = apart(&load("in_base.toml"), &truth, &configurations);
    eprintln!(
        "circles: held out in the maker's base {:.4} mm (floor {:.4} mm); stated at 1 m {:.4} mm",
        in_base * 1e3,
        floor * 1e3,
        registration["at_one_metre"].as_f64().expect("m") * 1e3
    );
    assert!(in_base <= 2.0 * floor, "{in_base} vs floor {floor}");
    // A row that turns two joints is named.
    let mut bad = std::fs::read_to_string(at("circles.csv")).expect("read");
    bad += "10,10,30,10,40,0,1000,1000,1000\n";
    // The comment and header are lines 1 and 2; the 54 rows 3 to 56.
    std::fs::write(at("bad.csv"), bad).expect("bad");
    let run = gecaro()
        .args([
            "robot",
            "rebase",
            &text("calibrated.toml"),
            "--nominal",
            "industrial6",
        ])
        .args(["--base-circles", &text("bad.csv")])
        .args(["--length-unit", "mm", "--angle-unit", "deg"])
        .args(["-o", &text("bad.toml")])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && stderr.contains("line 57"),
        "{stderr}"
    );
    assert!(!at("bad.toml").exists());
}

/// `gecaro join` (issue 74): a tracker's export (`;`, decimal commas, mm,
/// its own column names, the points in another order) joined with a
/// controller's log (degrees, its own names, rows nothing measured) by
/// the point's name gives the simulated truth back; joined by row order
/// with a row more at the log's top, the shift is refused with its
/// direction; the files as they come, row for row, join.
#[test]
fn an_instrument_export_joins_a_controller_log() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let text = |name: &str| at(name).to_str().expect("UTF-8").to_owned();
    let real = real_robot();
    let reflector = Vector3::new(0.01, -0.02, 0.12);
    let mut sampler = Sampler::new(23);
    let configurations: Vec<Vec<f64>> = (0..40).map(|_| sampler.configuration(&real)).collect();
    let points: Vec<Vector3<f64>> = configurations
        .iter()
        .map(|qm| point(&real, qm, &reflector) + sampler.gaussian_vector(2e-5))
        .collect();
    let mm = |v: f64| format!("{:.4}", v * 1e3).replace('.', ",");
    let degrees = |qm: &[f64]| {
        qm.iter()
            .map(|q| format!("{:.9}", q.to_degrees()))
            .collect::<Vec<_>>()
            .join(",")
    };
    // The export, last point first; the log with two rows nothing measured.
    let mut export = String::from("Point;X;Y;Z;RMS\n");
    for (i, p) in points.iter().enumerate().rev() {
        export += &format!("P{};{};{};{};0,01\n", i + 1, mm(p.x), mm(p.y), mm(p.z));
    }
    let mut log = String::from("Name,A1,A2,A3,A4,A5,A6,Speed\n");
    log += &format!("HOME,{},100\n", degrees(&[0.0; 6]));
    for (i, qm) in configurations.iter().enumerate() {
        log += &format!("P{},{},100\n", i + 1, degrees(qm));
    }
    log += &format!("PARK,{},100\n", degrees(&[0.0, -1.0, 1.0, 0.0, 0.5, 0.0]));
    std::fs::write(at("export.csv"), &export).expect("export");
    std::fs::write(at("log.csv"), &log).expect("log");
    let join = |tracker: &str, log: &str, key: bool, output: &str| {
        let mut command = gecaro();
        command
            .args(["join", &text(tracker), &text(log), "--robot", "industrial6"])
            .args(["--tracker-columns", "x=X,y=Y,z=Z", "--length-unit", "mm"])
            .args(["--log-columns", "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6"])
            .args(["--angle-unit", "deg", "-o", &text(output)]);
        if key {
            command.args(["--key", "Point", "--log-key", "Name"]);
        }
        command.output().expect("runs")
    };
    let run = join("export.csv", "log.csv", true, "joined.csv");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("2 log row(s) have no measured point") && stderr.contains("HOME (line 2)"),
        "{stderr}"
    );
    // Read back as data: the truth, in the export's order.
    let joined = std::fs::read_to_string(at("joined.csv")).expect("joined");
    let rows: Vec<Vec<f64>> = joined
        .lines()
        .filter(|line| !line.starts_with('#'))
        .skip(1)
        .map(|line| {
            line.split(',')
                .map(|v| v.parse().expect("number"))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 40);
    for (row, i) in rows.iter().zip((0..40).rev()) {
        for j in 0..6 {
            assert!((row[j] - configurations[i][j]).abs() < 1e-10, "row {i}");
        }
        for axis in 0..3 {
            assert!((row[6 + axis] - points[i][axis]).abs() < 1e-7, "row {i}");
        }
    }
    command("identify industrial6 --method position --sigma 20um")
        .args([
            "--data",
            &text("joined.csv"),
            "-o",
            &text("calibrated.toml"),
        ])
        .assert()
        .success();
    // By row order: the log's HOME row at its top shifts every point by one.
    let mut in_order = String::from("Point;X;Y;Z;RMS\n");
    for (i, p) in points.iter().enumerate() {
        in_order += &format!("P{};{};{};{};0,01\n", i + 1, mm(p.x), mm(p.y), mm(p.z));
    }
    std::fs::write(at("in_order.csv"), &in_order).expect("export");
    let shifted_log: String = log
        .lines()
        .take(41)
        .map(|line| format!("{line}\n"))
        .collect();
    std::fs::write(at("shifted_log.csv"), shifted_log).expect("log");
    let run = join("in_order.csv", "shifted_log.csv", false, "shifted.csv");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success()
            && stderr.contains("looks shifted")
            && stderr.contains("1 after its own"),
        "{stderr}"
    );
    assert!(!at("shifted.csv").exists());
    // The log without HOME and PARK: row for row.
    let plain_log: String = log
        .lines()
        .filter(|line| !line.starts_with("HOME") && !line.starts_with("PARK"))
        .map(|line| format!("{line}\n"))
        .collect();
    std::fs::write(at("plain_log.csv"), plain_log).expect("log");
    let run = join(
        "in_order.csv",
        "plain_log.csv",
        false,
        "in_order_joined.csv",
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // And counts that differ are named.
    let run = join("in_order.csv", "log.csv", false, "counts.csv");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("40 measured points and 42 log rows"),
        "{stderr}"
    );
}

/// `gecaro join` of a 6-D probe's export (issue 74): its orientations as
/// Euler angles x, y′, z″ in degrees are joined as the quaternions they
/// stand for (the frame's truth to 1e-9), and the same export joined
/// without saying their form is refused rather than joined position-only.
#[test]
fn a_probe_export_joins_its_orientations() {
    use nalgebra::UnitQuaternion;
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    let real = real_robot();
    let mut sampler = Sampler::new(29);
    let configurations: Vec<Vec<f64>> = (0..30).map(|_| sampler.configuration(&real)).collect();
    let poses: Vec<_> = configurations
        .iter()
        .map(|qm| gecaro_core::terminal_pose(&real, qm).expect("pose"))
        .collect();
    let mut export = String::from("Point,X,Y,Z,A,B,C\n");
    let mut log = String::from("Point,A1,A2,A3,A4,A5,A6\n");
    for (i, (qm, pose)) in configurations.iter().zip(&poses).enumerate() {
        // Intrinsic x, y′, z″ angles of the pose's rotation.
        let r = pose.rotation.matrix();
        let b = r[(0, 2)].clamp(-1.0, 1.0).asin();
        let a = (-r[(1, 2)]).atan2(r[(2, 2)]);
        let c = (-r[(0, 1)]).atan2(r[(0, 0)]);
        let t = pose.translation.vector * 1e3;
        export += &format!(
            "P{i},{},{},{},{},{},{}\n",
            t.x,
            t.y,
            t.z,
            a.to_degrees(),
            b.to_degrees(),
            c.to_degrees()
        );
        let angles: Vec<String> = qm.iter().map(|q| q.to_degrees().to_string()).collect();
        log += &format!("P{i},{}\n", angles.join(","));
    }
    std::fs::write(at("probe.csv"), &export).expect("export");
    std::fs::write(at("log.csv"), &log).expect("log");
    let join = |rotation: bool, output: &str| {
        let mut command = gecaro();
        command
            .args([
                "join",
                &at("probe.csv"),
                &at("log.csv"),
                "--robot",
                "industrial6",
            ])
            .args([
                "--key",
                "Point",
                "--length-unit",
                "mm",
                "--angle-unit",
                "deg",
            ])
            .args(["--tracker-columns", "x=X,y=Y,z=Z,rx=A,ry=B,rz=C"])
            .args(["--log-columns", "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6"])
            .args(["-o", &at(output)]);
        if rotation {
            command.args(["--rotation", "euler-xyz", "--rotation-unit", "deg"]);
        }
        command.output().expect("runs")
    };
    let refused = join(false, "position-only.csv");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success()
            && stderr.contains("has rx, ry, rz columns but no rotation format"),
        "{stderr}"
    );
    assert!(!std::path::Path::new(&at("position-only.csv")).exists());
    let run = join(true, "poses.csv");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let joined = std::fs::read_to_string(at("poses.csv")).expect("joined");
    let mut lines = joined.lines().filter(|line| !line.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z,qw,qx,qy,qz")
    );
    for (line, pose) in lines.zip(&poses) {
        let v: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("number"))
            .collect();
        let q =
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(v[9], v[10], v[11], v[12]));
        let truth = UnitQuaternion::from_rotation_matrix(&pose.rotation);
        assert!(q.angle_to(&truth) < 1e-9, "{line}");
    }
}

/// A log whose prismatic joint is in millimetres (`--log-length-unit mm`)
/// joins in metres: the Stanford arm's joint 3 as the controller logged it.
#[test]
fn a_log_s_prismatic_joint_is_read_in_its_unit() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    let robot = gecaro_io::load_robot("stanford").expect("robot").robot;
    let mut sampler = Sampler::new(31);
    let configurations: Vec<Vec<f64>> = (0..20).map(|_| sampler.configuration(&robot)).collect();
    let mut export = String::from("Point,x,y,z\n");
    let mut log = String::from("Point,qm1,qm2,qm3,qm4,qm5,qm6\n");
    for (i, qm) in configurations.iter().enumerate() {
        let p = point(&robot, qm, &Vector3::zeros());
        export += &format!("P{i},{},{},{}\n", p.x, p.y, p.z);
        let logged: Vec<String> = qm
            .iter()
            .enumerate()
            .map(|(j, q)| {
                if j == 2 {
                    (q * 1e3).to_string()
                } else {
                    q.to_string()
                }
            })
            .collect();
        log += &format!("P{i},{}\n", logged.join(","));
    }
    std::fs::write(at("export.csv"), export).expect("export");
    std::fs::write(at("log.csv"), log).expect("log");
    gecaro()
        .args([
            "join",
            &at("export.csv"),
            &at("log.csv"),
            "--robot",
            "stanford",
        ])
        .args([
            "--key",
            "Point",
            "--log-length-unit",
            "mm",
            "-o",
            &at("joined.csv"),
        ])
        .assert()
        .success();
    let joined = joint_rows(Path::new(&at("joined.csv")));
    for (row, qm) in joined.iter().zip(&configurations) {
        assert!((row[2] - qm[2]).abs() < 1e-12, "{row:?} against {qm:?}");
    }
}

/// A tracker export that states each point's uncertainty (issue 74), in its
/// own column name and millimetres: mapped with `--columns
/// sigma=Uncertainty_mm`, every row counts by its own σ and the verdict
/// tests it so (no `--sigma` needed), and the calibration stands several
/// times closer to the real robot at held-out configurations than with
/// one σ for all rows.
#[test]
fn a_tracker_export_s_own_sigma_weights_its_rows() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let path = |name: &str| at(name).to_str().expect("UTF-8").to_owned();
    let mut real = gecaro_io::load_robot("industrial6").expect("robot");
    real.robot = perturbed_robot(&real.robot, 1.0, &mut Sampler::new(8)).expect("real");
    std::fs::write(at("real.toml"), gecaro_io::format_robot_file(&real)).expect("written");
    for (name, count, seed) in [("exact.csv", "120", "3"), ("held.csv", "200", "9")] {
        command("generate industrial6 --method position --noise 0")
            .args([
                "--count",
                count,
                "--seed",
                seed,
                "--real",
                &path("real.toml"),
            ])
            .args(["-o", &path(name)])
            .assert()
            .success();
    }
    // The export: positions and σ in millimetres, σ log-uniform between
    // 5 µm and 0.5 mm, the noise drawn with it.
    let mut noise = Sampler::new(74);
    let mut export = String::from("A1,A2,A3,A4,A5,A6,X_mm,Y_mm,Z_mm,Uncertainty_mm\n");
    let mut squares = 0.0;
    let text = std::fs::read_to_string(at("exact.csv")).expect("read");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|line| !line.starts_with('#'))
        .skip(1)
        .map(|line| {
            line.split(',')
                .map(|v| v.parse().expect("number"))
                .collect()
        })
        .collect();
    for row in &rows {
        let sigma = 5e-6 * 100f64.powf(noise.uniform(0.0, 1.0));
        squares += sigma * sigma;
        let measured = Vector3::new(row[6], row[7], row[8]) + noise.gaussian_vector(sigma);
        let mut fields: Vec<String> = row[..6].iter().map(|q| format!("{q:?}")).collect();
        fields.extend(measured.iter().map(|x| format!("{:?}", x * 1e3)));
        fields.push(format!("{:?}", sigma * 1e3));
        export.push_str(&(fields.join(",") + "\n"));
    }
    std::fs::write(at("export.csv"), export).expect("written");
    let rms_sigma_mm = (squares / rows.len() as f64).sqrt() * 1e3;
    let columns = "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6,x=X_mm,y=Y_mm,z=Z_mm";
    let identify = |extra: &[&str], output: &str| -> serde_json::Value {
        let (data, output) = (path("export.csv"), path(output));
        let mut args = vec!["identify", "industrial6", "--method", "position", "--json"];
        args.extend(["--data", &data, "--length-unit", "mm", "-o", &output]);
        args.extend(extra);
        json_output(&args)
    };
    let weighted = identify(
        &["--columns", &format!("{columns},sigma=Uncertainty_mm")],
        "weighted.toml",
    );
    assert_eq!(
        weighted["verdict"]["outcome"], "fits_noise",
        "{}",
        weighted["verdict"]
    );
    let single = identify(
        &[
            "--columns",
            columns,
            "--sigma",
            &format!("{rms_sigma_mm}mm"),
        ],
        "single.toml",
    );
    let held_out = |robot: &str| -> f64 {
        let (robot, data) = (path(robot), path("held.csv"));
        json_output(&[
            "evaluate", &robot, "--method", "position", "--json", "--data", &data,
        ])["rms"]
            .as_f64()
            .expect("rms")
    };
    let (by_rows, by_one) = (held_out("weighted.toml"), held_out("single.toml"));
    println!(
        "held out: {:.1} µm by the rows' σ, {:.1} µm by one σ of {rms_sigma_mm:.4} mm",
        by_rows * 1e6,
        by_one * 1e6
    );
    assert!(
        by_rows * 2.0 < by_one,
        "held out {by_rows} m by the rows' σ, {by_one} m by one σ ({})",
        single["verdict"]["outcome"]
    );
}
