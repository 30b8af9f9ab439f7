//! Where a calibration holds, from the command line: data measured within
//! ±15° of a home pose give a calibrated robot that is not trusted for the
//! whole workspace (exit 5), whose file keeps the joint ranges measured,
//! and which `compensate` and `evaluate` hold their poses against.

use std::path::Path;

use crate::util::{command, gecaro};
use gecaro_calib::simulation::Sampler;
use predicates::prelude::*;
use serde_json::Value;

/// `count` configurations of industrial6 (a header, then qm1..qm6 in
/// radians), drawn within `half_degrees` of the middle of every joint's
/// limits, written to `path`.
fn configurations(path: &Path, half_degrees: f64, count: usize, seed: u64) {
    let robot = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let mut sampler = Sampler::new(seed);
    let mut text = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for _ in 0..count {
        let row: Vec<String> = robot
            .joints()
            .iter()
            .map(|joint| {
                let middle = 0.5 * (joint.qmin + joint.qmax);
                let half = half_degrees
                    .to_radians()
                    .min(0.5 * (joint.qmax - joint.qmin));
                format!("{:?}", sampler.uniform(middle - half, middle + half))
            })
            .collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).expect("written");
}

#[test]
fn a_calibration_measured_in_a_small_region_holds_there_and_says_so() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let at = |name: &str| folder.path().join(name);
    configurations(&at("narrow.csv"), 15.0, 120, 5);
    configurations(&at("wide.csv"), 180.0, 100, 6);
    command("generate industrial6 --method position --noise 2e-5 --seed 5 --configurations")
        .arg(at("narrow.csv"))
        .arg("-o")
        .arg(at("data.csv"))
        .arg("--real-out")
        .arg(at("real.toml"))
        .assert()
        .success();
    let output = command("identify industrial6 --method position --sigma 20um --json --data")
        .arg(at("data.csv"))
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
    let verdict = &document["verdict"];
    assert_eq!(verdict["outcome"], "regional");
    assert_eq!(verdict["trusted"], false);
    let region = &verdict["region"];
    assert_eq!(region["holds_everywhere"], false);
    assert_eq!(region["work_is_limits"], true);
    assert!(
        region["predicted_work"].as_f64().expect("a number")
            > 10.0 * region["noise_floor"].as_f64().expect("a number")
    );
    assert_eq!(region["measured"].as_array().expect("an array").len(), 6);
    // The calibrated robot keeps the ranges, and loads with them.
    let file = std::fs::read_to_string(at("calibrated.toml")).expect("written");
    assert_eq!(file.matches("measured = [").count(), 6, "{file}");
    assert!(file.contains("holds within the measured joint ranges"));
    let calibrated = gecaro_io::read_robot_file(&at("calibrated.toml")).expect("reads back");
    let measured = calibrated.measured_region.expect("the region");
    for (j, range) in region["measured"]
        .as_array()
        .expect("an array")
        .iter()
        .enumerate()
    {
        let range = range.as_array().expect("an array");
        let (min, max) = measured.range(j);
        assert!((range[0].as_f64().expect("a number") - min).abs() < 1e-9);
        assert!((range[1].as_f64().expect("a number") - max).abs() < 1e-9);
    }
    // A stated work region as small as the data: trusted (exit 0).
    command("identify industrial6 --method position --sigma 20um --work-region q1=-10..10deg,q5=-10..10deg --data")
        .arg(at("data.csv"))
        .assert()
        .code(5);
    let home = "q1=-10..10deg,q2=-80..-65deg,q3=8..28deg,q4=-10..10deg,q5=-10..10deg,q6=-10..10deg";
    command("identify industrial6 --method position --sigma 20um")
        .args(["--work-region", home, "--data"])
        .arg(at("data.csv"))
        .assert()
        .success();
    // A bare range is refused by name.
    command("identify industrial6 --method position --work-region q1=-10..10")
        .arg("--data")
        .arg(at("data.csv"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("--work-region").and(predicates::str::contains("unit")));
    // A program with targets inside and outside: those outside are flagged.
    let narrow = std::fs::read_to_string(at("narrow.csv")).expect("read");
    let wide = std::fs::read_to_string(at("wide.csv")).expect("read");
    let program: Vec<&str> = narrow
        .lines()
        .take(11)
        .chain(wide.lines().skip(1).take(5))
        .collect();
    std::fs::write(at("job.csv"), program.join("\n") + "\n").expect("written");
    let compensation = command("compensate industrial6")
        .arg(at("calibrated.toml"))
        .args(["--match", "position", "--json", "--program"])
        .arg(at("job.csv"))
        .arg("-o")
        .arg(at("corrected.csv"))
        .output()
        .expect("runs");
    assert_eq!(compensation.status.code(), Some(4));
    let document: Value = serde_json::from_slice(&compensation.stdout).expect("JSON");
    let flagged: Vec<u64> = document["outside_region"]
        .as_array()
        .expect("lines")
        .iter()
        .map(|line| line.as_u64().expect("a line"))
        .collect();
    assert_eq!(flagged, vec![12, 13, 14, 15, 16], "{document}");
    let corrected = std::fs::read_to_string(at("corrected.csv")).expect("written");
    assert_eq!(corrected.matches(",outside-region").count(), 5);
    // Evaluated on poses over the whole workspace: the warning counts them.
    command("generate industrial6 --method position --noise 2e-5 --seed 6 --real")
        .arg(at("real.toml"))
        .arg("--configurations")
        .arg(at("wide.csv"))
        .arg("-o")
        .arg(at("held_out.csv"))
        .assert()
        .success();
    gecaro()
        .arg("evaluate")
        .arg(at("calibrated.toml"))
        .args(["--method", "position", "--data"])
        .arg(at("held_out.csv"))
        .assert()
        .success()
        .stderr(predicates::str::contains(
            "100 of 100 configurations lie outside the joint ranges",
        ));
}
