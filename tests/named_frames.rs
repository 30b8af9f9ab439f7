//! End-to-end: a study of three reflectors seen from two tracker stations
//! (issue 24 §1), written as a tracker writes it (mm, degrees), identified
//! by the command line; simulated truth, so the right answer is known.

use gecaro_calib::study::Samples;
use std::path::Path;

use crate::util::{command, gecaro};
use gecaro_calib::{
    frames::{FrameRole, NamedFrame, measuring_robot},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_measurements},
    study::DataColumn,
};
use gecaro_io::OutputPolicy;
use nalgebra::{IsometryMatrix3, Rotation3, Translation3};
use serde_json::Value;

/// `gecaro SUBCOMMAND --study STUDY [extra…]`, run to its end.
fn on_study(subcommand: &str, study: &Path, extra: &[&str]) -> std::process::Output {
    gecaro()
        .args([subcommand, "--study"])
        .arg(study)
        .args(extra)
        .output()
        .expect("runs")
}

fn frame(name: &str, role: FrameRole, position: [f64; 3], rpy_deg: [f64; 3]) -> NamedFrame {
    let [r, p, y] = rpy_deg.map(f64::to_radians);
    NamedFrame {
        name: name.into(),
        role,
        pose: IsometryMatrix3::from_parts(
            Translation3::new(position[0], position[1], position[2]),
            Rotation3::from_euler_angles(r, p, y),
        ),
    }
}

/// The study's text: reflectors and the second station stated roughly (mm,
/// degrees); tracker 1 is the world frame (its sets name no station).
const STUDY: &str = r#"
robot = "industrial6"
length_unit = "mm"
angle_unit = "deg"

[tools.smr_a]
position = [42, 24, 91.5]
[tools.smr_b]
position = [-51.5, 32, 69]
[tools.smr_c]
position = [11, -58.5, 112]

[stations.tracker_2]
position = [-1150, 1700, -250]
rpy = [0, 0, -130]

[[measurements]]
method = "position"
data = "smr_a_1.csv"
tool = "smr_a"
sigma = 0.02
[[measurements]]
method = "position"
data = "smr_b_1.csv"
tool = "smr_b"
sigma = 0.02
[[measurements]]
method = "position"
data = "smr_c_1.csv"
tool = "smr_c"
sigma = 0.02
[[measurements]]
method = "position"
data = "smr_a_2.csv"
tool = "smr_a"
station = "tracker_2"
sigma = 0.02
[[measurements]]
method = "position"
data = "smr_b_2.csv"
tool = "smr_b"
station = "tracker_2"
sigma = 0.02
[[measurements]]
method = "position"
data = "smr_c_2.csv"
tool = "smr_c"
station = "tracker_2"
sigma = 0.02
"#;

/// Writes the cell's data and study into `folder` (the bundled
/// `examples/tracker-cell`) and returns tracker 2's true pose in tracker
/// 1's frame: x −1200, y 1750, z −200 mm, rpy 0.4°, −0.3°, −128°.
pub(super) fn write_cell(folder: &Path) -> NamedFrame {
    write_cell_seen_from(folder, &tracker_1())
}

/// Where tracker 1 stands in the robot's base frame, as in a real cell:
/// 2.5 m away, turned 126°.
pub(super) fn tracker_1() -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::new(2.5, 0.4, -0.3),
        Rotation3::from_euler_angles(0.0, 0.0, 2.2),
    )
}

/// [`write_cell`], tracker 1 standing at `tracker_1` in the robot's base
/// frame (its frame is the world frame of the data).
fn write_cell_seen_from(folder: &Path, tracker_1: &IsometryMatrix3<f64>) -> NamedFrame {
    let nominal = gecaro_io::load_robot("industrial6").expect("robot").robot;
    let mut sampler = Sampler::new(5);
    let real = perturbed_robot(&nominal, 0.5, &mut sampler)
        .expect("real")
        .reframed(&tracker_1.inverse(), &IsometryMatrix3::identity())
        .expect("seen from tracker 1");
    let tools = [
        frame("smr_a", FrameRole::Tool, [0.04, 0.025, 0.09], [0.0; 3]),
        frame("smr_b", FrameRole::Tool, [-0.05, 0.03, 0.07], [0.0; 3]),
        frame("smr_c", FrameRole::Tool, [0.01, -0.06, 0.11], [0.0; 3]),
    ];
    let tracker_2 = frame(
        "tracker_2",
        FrameRole::Station,
        [-1.2, 1.75, -0.2],
        [0.4, -0.3, -128.0],
    );
    let position = method("position", &MethodOptions::default()).expect("method");
    for tool in &tools {
        for (station, suffix) in [(None, "1"), (Some(&tracker_2), "2")] {
            let robot = measuring_robot(&real, Some(tool), station).expect("robot");
            let mut samples = simulate_measurements(
                &robot,
                position.as_ref(),
                25,
                2e-5,
                &mut sampler,
                &mut gecaro_calib::Quiet,
            )
            .expect("data");
            // As the tracker writes them: millimetres, joint angles in degrees.
            for sample in &mut samples {
                sample.position = sample.position.map(|p| p * 1e3);
                for q in &mut sample.motor_positions {
                    *q = q.to_degrees();
                }
            }
            gecaro_io::write_samples(
                &folder.join(format!("{}_{suffix}.csv", tool.name)),
                6,
                &[DataColumn::Position],
                Samples::from(samples.as_slice()).as_slice(),
                OutputPolicy::KeepExisting,
            )
            .expect("written");
        }
    }
    std::fs::write(folder.join("study.toml"), STUDY).expect("study");
    tracker_2
}

/// The bundled example (`examples/tracker-cell`) is what [`write_cell`]
/// writes, byte for byte; `GECARO_REGENERATE=1` rewrites it.
#[test]
fn the_bundled_cell_example_is_what_its_generator_writes() {
    let bundled = Path::new("examples/tracker-cell");
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let mut names: Vec<String> = std::fs::read_dir(folder.path())
        .expect("listing")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    for name in names {
        let written = std::fs::read(folder.path().join(&name)).expect("written");
        if std::env::var_os("GECARO_REGENERATE").is_some() {
            std::fs::write(bundled.join(&name), &written).expect("regenerated");
        }
        let kept = std::fs::read(bundled.join(&name)).unwrap_or_default();
        assert!(
            kept == written,
            "examples/tracker-cell/{name} differs from what its generator writes; \
             GECARO_REGENERATE=1 cargo test --test named_frames rewrites it"
        );
    }
}

/// `gecaro identify --study STUDY --json` of a cell written by
/// [`write_cell`]: it fits the noise, and finds the second station `truth`
/// to within 0.1 mm (its σ here is about 10 µm).
fn identified_cell(study: &Path, truth: &NamedFrame) -> Value {
    let output = on_study("identify", study, &["--json"]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let json: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(
        json["verdict"]["outcome"], "fits_noise",
        "{}",
        json["verdict"]
    );
    let station = json["frames"]
        .as_array()
        .expect("frames")
        .iter()
        .find(|f| f["name"] == "tracker_2")
        .expect("tracker_2");
    assert_eq!(station["role"], "station");
    for axis in 0..3 {
        let found = station["position"][axis].as_f64().expect("number");
        let expected = truth.pose.translation.vector[axis];
        assert!(
            (found - expected).abs() < 1e-4,
            "tracker_2 axis {axis}: {found} vs {expected}"
        );
    }
    json
}

#[test]
fn a_cell_of_three_reflectors_and_two_stations_is_identified_from_its_study_file() {
    let folder = tempfile::tempdir().expect("folder");
    let truth = write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let json = identified_cell(&study, &truth);
    assert_eq!(json["frames"].as_array().expect("frames").len(), 4);
    // The text output states the identified frames as a study states them.
    let text = on_study("identify", &study, &[]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("[stations.tracker_2]"), "{text}");
    assert!(text.contains("tracker_2.rz"), "{text}");
    // Appendix III covers the frames: a reflector's orientation has no effect.
    let report = on_study("identifiable", &study, &[]);
    let report = String::from_utf8_lossy(&report.stdout);
    assert!(report.contains("tracker_2.x: identifiable"), "{report}");
    assert!(report.contains("smr_a.rx: no"), "{report}");
}

#[test]
fn a_station_stated_at_the_tracker_origin_is_registered_in_closed_form() {
    // The second tracker stated at the world's origin, turned as the world
    // is, though it stands 2 m away and turned 130°: before, no closed-form
    // start for named frames and no convergence (exit 4).
    let folder = tempfile::tempdir().expect("folder");
    let truth = write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let text = std::fs::read_to_string(&study).expect("study");
    let stated = text
        .lines()
        .map(|line| {
            if line.starts_with("position = [-") || line.starts_with("rpy") {
                if line.starts_with("rpy") {
                    "rpy = [0, 0, 0]".to_owned()
                } else {
                    "position = [0, 0, 0]".to_owned()
                }
            } else {
                line.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_ne!(stated, text, "the station's stated pose was replaced");
    std::fs::write(&study, stated).expect("study");
    let json = identified_cell(&study, &truth);
    let warnings = json["warnings"].to_string();
    assert!(
        warnings.contains("first fitted in closed form"),
        "{warnings}"
    );
}

#[test]
fn a_study_naming_an_unknown_station_is_refused_at_its_line() {
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let text = STUDY.replace("station = \"tracker_2\"\nsigma = 0.02\n[[measurements]]\nmethod = \"position\"\ndata = \"smr_b_2.csv\"", "station = \"tracker_3\"\nsigma = 0.02\n[[measurements]]\nmethod = \"position\"\ndata = \"smr_b_2.csv\"");
    std::fs::write(&study, &text).expect("study");
    let output = on_study("identify", &study, &[]);
    assert!(!output.status.success());
    let message = String::from_utf8_lossy(&output.stderr);
    let line = text
        .lines()
        .position(|l| l.contains("tracker_3"))
        .expect("line")
        + 1;
    assert!(
        message.contains("no station named `tracker_3` in this study"),
        "{message}"
    );
    assert!(message.contains(&format!(":{line}")), "{message}");
    // A station on a method that measures no pose in a frame.
    let text = STUDY.replace(
        "method = \"position\"\ndata = \"smr_a_2.csv\"",
        "method = \"distance\"\ndata = \"smr_a_2.csv\"",
    );
    std::fs::write(&study, &text).expect("study");
    let output = on_study("identify", &study, &[]);
    assert!(!output.status.success());
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("tools and stations go with"), "{message}");
}

/// `gecaro evaluate ROBOT --study STUDY`: the robot on every set of the
/// study, frames as stated. The nominal robot gives the identification's
/// errors before; the calibrated robot, with the identified frames stated in
/// the study, its errors after.
#[test]
fn a_robot_is_evaluated_on_a_study() {
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let calibrated = folder.path().join("calibrated.toml");
    let output = command("identify --study")
        .arg(&study)
        .arg("--json")
        .arg("-o")
        .arg(&calibrated)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let identified: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert!(
        identified["frames"][3]["name"] == "tracker_2",
        "{identified}"
    );
    let evaluate = |robot: &Path, study: &Path| -> Value {
        let output = gecaro()
            .arg("evaluate")
            .arg(robot)
            .arg("--study")
            .arg(study)
            .arg("--json")
            .output()
            .expect("runs");
        assert!(output.status.success(), "{output:?}");
        serde_json::from_slice(&output.stdout).expect("JSON")
    };
    let close = |a: &Value, b: &Value| {
        let (a, b) = (a.as_f64().expect("a"), b.as_f64().expect("b"));
        assert!((a - b).abs() <= 1e-9 + 1e-6 * b.abs(), "{a} vs {b}");
    };
    let before = evaluate(Path::new("industrial6"), &study);
    assert_eq!(before["count"], 150);
    close(&before["rms"], &identified["before"]["rms"]);
    // The identified frames stated in the study (metres and radians).
    let mut text =
        String::from("robot = \"industrial6\"\nlength_unit = \"mm\"\nangle_unit = \"deg\"\n");
    for frame in identified["frames"].as_array().expect("frames") {
        text += &format!(
            "[{}s.{}]\nlength_unit = \"m\"\nangle_unit = \"rad\"\nposition = {}\nrpy = {}\n",
            frame["role"].as_str().expect("role"),
            frame["name"].as_str().expect("name"),
            frame["position"],
            frame["rpy"]
        );
    }
    let original = std::fs::read_to_string(&study).expect("study");
    let sets = &original[original.find("[[measurements]]").expect("sets")..];
    let restated = folder.path().join("identified.toml");
    std::fs::write(&restated, text + sets).expect("written");
    let after = evaluate(&calibrated, &restated);
    close(&after["rms"], &identified["after"]["rms"]);
    assert!(after["rms"].as_f64().expect("rms") < 5e-5, "{after}");
}

/// `gecaro predict --study`: the whole cell's predicted precision from its
/// sets' configurations alone — a plan per reflector and station before it
/// is measured gives what the measured files give — every set weighted by
/// its σ; the second station's predicted σ is the identification's. The
/// prediction is for the robot where the study's robot file puts it: here
/// the nominal robot stated where it stands in tracker 1's frame
/// (`robot reframe --world`), as the stations are stated.
#[test]
fn a_cell_is_predicted_before_it_is_measured() {
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let robot_seen = tracker_1().inverse();
    let (t, q) = (
        robot_seen.translation.vector,
        nalgebra::UnitQuaternion::from_rotation_matrix(&robot_seen.rotation),
    );
    let world = format!("{},{},{},{},{},{},{}", t.x, t.y, t.z, q.w, q.i, q.j, q.k);
    let placed = folder.path().join("industrial6_in_tracker_1.toml");
    let output = gecaro()
        .args(["robot", "reframe", "industrial6", "--world", &world, "-o"])
        .arg(&placed)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let text = std::fs::read_to_string(&study).expect("study");
    std::fs::write(
        &study,
        text.replace(
            "robot = \"industrial6\"",
            "robot = \"industrial6_in_tracker_1.toml\"",
        ),
    )
    .expect("study");
    let predict = |study: &Path| -> Value {
        let output = on_study("predict", study, &["--json"]);
        assert!(output.status.success(), "{output:?}");
        serde_json::from_slice(&output.stdout).expect("JSON")
    };
    let measured = predict(&study);
    assert_eq!(measured["sets"].as_array().expect("sets").len(), 6);
    assert_eq!(measured["sets"][3]["station"], "tracker_2");
    // The same cell planned, not measured: joint values only.
    let planned_folder = folder.path().join("planned");
    std::fs::create_dir(&planned_folder).expect("folder");
    for entry in std::fs::read_dir(folder.path()).expect("listing") {
        let path = entry.expect("entry").path();
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        if name.ends_with(".csv") {
            let text = std::fs::read_to_string(&path).expect("data");
            let planned: Vec<String> = text
                .lines()
                .map(|line| line.split(',').take(6).collect::<Vec<_>>().join(","))
                .collect();
            std::fs::write(planned_folder.join(&name), planned.join("\n") + "\n").expect("plan");
        } else if name.ends_with(".toml") {
            std::fs::copy(&path, planned_folder.join(&name)).expect("study");
        }
    }
    let planned = predict(&planned_folder.join("study.toml"));
    assert_eq!(planned["parameters"], measured["parameters"]);
    assert_eq!(planned["predicted"], measured["predicted"]);
    // The identification's σ of the second station agrees (eq. 11 at the
    // identified robot rather than the nominal).
    let identified = on_study("identify", &study, &["--json"]);
    let identified: Value = serde_json::from_slice(&identified.stdout).expect("JSON");
    for unknown in ["x", "y", "z", "rx", "ry", "rz"] {
        let name = format!("tracker_2.{unknown}");
        let find = |list: &Value, key: &str| -> f64 {
            list.as_array()
                .expect("list")
                .iter()
                .find(|p| p["name"] == name.as_str())
                .and_then(|p| p[key].as_f64())
                .unwrap_or_else(|| panic!("{name} in {list}"))
        };
        let (before, after) = (
            find(&measured["parameters"], "sigma"),
            find(&identified["auxiliary"], "std"),
        );
        assert!(
            (0.7..1.4).contains(&(before / after)),
            "{name}: predicted {before:e}, identified {after:e}"
        );
    }
}

/// Tracker 1 (the world frame of the data) stands 2.5 m from the robot's
/// base, turned 126°, as in a real cell: the robot's base in it is
/// registered in closed form with the stations and reflectors (before: the
/// iteration limit at 30 mm RMS), the calibration fits the noise, and
/// `robot rebase` finds where tracker 1 stood.
#[test]
fn a_cell_whose_reference_tracker_stands_far_from_the_base_is_registered() {
    let folder = tempfile::tempdir().expect("folder");
    let truth = write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let calibrated = folder.path().join("calibrated.toml");
    let json = identified_cell(&study, &truth);
    assert!(
        json["iterations"].as_u64().expect("iterations") <= 10,
        "{}",
        json["iterations"]
    );
    let warnings = json["warnings"].to_string();
    assert!(
        warnings.contains("first fitted in closed form"),
        "{warnings}"
    );
    let output = on_study(
        "identify",
        &study,
        &["-o", calibrated.to_str().expect("utf-8")],
    );
    assert!(output.status.success(), "{output:?}");
    let output = command("robot rebase")
        .arg(&calibrated)
        .args(["--nominal", "industrial6", "--json", "-o"])
        .arg(folder.path().join("own.toml"))
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let rebased: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    // The measurement frame (tracker 1) in the robot's base frame, against
    // the truth: the real robot's own base errors (level 0.5) are in it.
    let expected = tracker_1().translation.vector;
    for axis in 0..3 {
        let found = rebased["position"][axis].as_f64().expect("number");
        assert!(
            (found - expected[axis]).abs() < 0.02,
            "axis {axis}: {found} vs {}",
            expected[axis]
        );
    }
    let yaw = rebased["rpy"][2].as_f64().expect("yaw");
    assert!((yaw - 2.2).abs() < 0.02, "yaw {yaw}");
}

/// `gecaro plan --study`: the cell's configurations chosen as one D-optimal
/// design over every set (each through its reflector and station), written
/// as a planned study that `predict --study` reads before it is measured.
#[test]
fn a_cell_is_planned_as_one_design() {
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let planned = folder.path().join("planned.toml");
    let output = command("plan --study")
        .arg(&study)
        .args(["--count", "48", "--json", "-o"])
        .arg(&planned)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let plan: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let sets = plan["sets"].as_array().expect("sets");
    assert_eq!(sets.len(), 6);
    let total: u64 = sets
        .iter()
        .map(|set| set["configurations"].as_u64().expect("count"))
        .sum();
    assert_eq!(total, 48);
    // Better than as many configurations drawn at random from the same pools.
    let (planned_det, random_det) = (
        plan["log_det"].as_f64().expect("log det"),
        plan["random_log_det"].as_f64().expect("log det"),
    );
    assert!(
        planned_det > random_det + 1.0,
        "{planned_det} vs {random_det}"
    );
    // Seven files: the planned study and one per set, read back by predict.
    assert_eq!(plan["output"].as_array().expect("files").len(), 7);
    assert!(folder.path().join("planned_6.csv").is_file());
    let output = on_study("predict", &planned, &["--json"]);
    assert!(output.status.success(), "{output:?}");
    let predicted: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(
        predicted["sets"][5]["configurations"],
        sets[5]["configurations"]
    );
    assert_eq!(predicted["sets"][5]["station"], "tracker_2");
    let rms = predicted["predicted"]["position_rms"]
        .as_f64()
        .expect("rms");
    assert!(rms > 0.0 && rms < 1e-4, "{rms}");
    // The study file planned from is never replaced.
    let again = command("plan --study")
        .arg(&study)
        .args(["--count", "48", "-o"])
        .arg(&study)
        .output()
        .expect("runs");
    assert!(!again.status.success());
}

/// `plan --study` in a cell: every candidate, hence every planned
/// configuration, keeps the arm above the floor and shows its set's
/// reflector to its set's station (the named one, or `--station` for the
/// sets that name none) within the incidence, the sight line clear of the
/// arm.
#[test]
fn a_cell_is_planned_within_its_floor_and_lines_of_sight() {
    use gecaro_calib::cell::{Cell, Station};
    let folder = tempfile::tempdir().expect("folder");
    write_cell(folder.path());
    let study = folder.path().join("study.toml");
    let planned = folder.path().join("planned.toml");
    let output = command("plan --study")
        .arg(&study)
        .args([
            "--count",
            "48",
            "--floor",
            "-0.3",
            "--station",
            "2.5,0.4,-0.3",
        ])
        .args(["--max-incidence", "60deg", "--clearance", "0.05", "-o"])
        .arg(&planned)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let file = gecaro_app::read_study_file_for(&planned, gecaro_app::StudyData::Configurations)
        .expect("the planned study reads");
    let robot = &file.robot.robot;
    let mut checked = 0;
    for set in &file.study.sets {
        let frame = |index: Option<usize>| index.map(|i| &file.study.frames[i]);
        let with_tool = measuring_robot(robot, frame(set.tool), None).expect("tool");
        let position = frame(set.station).map_or_else(
            || nalgebra::Vector3::new(2.5, 0.4, -0.3),
            |station| station.pose.translation.vector,
        );
        let cell = Cell {
            floor: Some(-0.3),
            station: Some(Station {
                position,
                max_incidence: Some(60f64.to_radians()),
                clearance: 0.05,
            }),
        };
        for sample in set.samples.iter() {
            assert!(
                cell.admits(&with_tool, sample.motor_positions()),
                "{}: {:?} is not measurable",
                set.label,
                sample.motor_positions()
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 48);
    // A cell that admits nothing is named, nothing written.
    let blocked = folder.path().join("blocked.toml");
    let output = command("plan --study")
        .arg(&study)
        .args(["--count", "48", "--floor", "100", "-o"])
        .arg(&blocked)
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(4), "{output:?}");
    assert!(String::from_utf8_lossy(&output.stderr).contains("next to nothing to measure"));
    assert!(!blocked.exists());
}
