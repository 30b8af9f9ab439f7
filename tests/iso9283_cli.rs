//! `gecaro iso9283 plan` and `evaluate` as an engineer runs them: a program
//! for the controller in millimetres and degrees with `;` and decimal
//! commas, read back; a tracker's export of the visits in millimetres,
//! evaluated against an independent computation.

use crate::util::{gecaro, json_output};

/// The plan is written in the units asked and read back by `evaluate`: a
/// measured file of the commanded positions shifted by known offsets gives
/// AP = the offset, RP from the offsets' spread, by hand.
#[test]
fn a_test_planned_in_millimetres_is_evaluated_end_to_end() {
    let folder = tempfile::tempdir().expect("folder");
    let program = folder.path().join("test.csv");
    let program = program.to_str().expect("path");
    let plan = json_output(&[
        "iso9283",
        "plan",
        "industrial6",
        "--cycles",
        "4",
        "--length-unit",
        "mm",
        "--angle-unit",
        "deg",
        "--delimiter",
        ";",
        "--decimal-comma",
        "-o",
        program,
        "--json",
    ]);
    assert_eq!(plan["rows"], 20);
    let text = std::fs::read_to_string(program).expect("program");
    assert!(text.starts_with("# units: angle_unit = deg, length_unit = mm\npose;cycle;"));
    assert!(text.lines().nth(2).expect("row").contains(','), "{text}");
    // The tracker saw every visit 0.1 mm off along x, and cycle 2 of each
    // pose 0.02 mm further along y: AP_x 0.1 mm, AP_y 0.005 mm.
    let mut measured = String::from("pose,cycle,x,y,z\n");
    for pose in plan["poses"].as_array().expect("poses") {
        let [x, y, z] = [0, 1, 2].map(|i| pose["position"][i].as_f64().expect("x") * 1e3);
        for cycle in 1..=4 {
            let dy = if cycle == 2 { 0.02 } else { 0.0 };
            measured.push_str(&format!(
                "{},{cycle},{},{},{z}\n",
                pose["pose"],
                x + 0.1,
                y + dy
            ));
        }
    }
    let data = folder.path().join("measured.csv");
    std::fs::write(&data, measured).expect("write");
    let report = json_output(&[
        "iso9283",
        "evaluate",
        "--program",
        program,
        "--data",
        data.to_str().expect("path"),
        "--length-unit",
        "mm",
        "--robot",
        "industrial6",
        "--load",
        "rated, 12 kg",
        "--json",
    ]);
    assert_eq!(report["warnings"], serde_json::json!([]));
    let before = &report["before"];
    assert_eq!(before["registration"], "base");
    assert_eq!(before["poses"].as_array().expect("poses").len(), 5);
    for pose in before["poses"].as_array().expect("poses") {
        let ap = &pose["ap"];
        assert!((ap["x"].as_f64().expect("x") - 1e-4).abs() < 1e-9);
        assert!((ap["y"].as_f64().expect("y") - 5e-6).abs() < 1e-9);
        // l = 15, 5, 5, 5 µm: l̄ = 7.5 µm, S_l = 5 µm → RP 22.5 µm.
        assert!((pose["rp"]["l"].as_f64().expect("l") - 22.5e-6).abs() < 1e-9);
        assert!(ap.get("a").is_none(), "no orientation measured");
    }
    assert_eq!(report["conditions"]["load"], "rated, 12 kg");
    // In text, for people.
    let output = gecaro()
        .args(["iso9283", "evaluate", "--program", program, "--data"])
        .arg(&data)
        .args(["--length-unit", "mm", "--frame", "best-fit"])
        .output()
        .expect("runs");
    assert!(output.status.success());
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("best fit") && stdout.contains("P5"),
        "{stdout}"
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("rigid motion"), "{stderr}");
    // The report: one HTML file with the tables and the plots inline.
    let report = folder.path().join("report.html");
    gecaro()
        .args(["iso9283", "evaluate", "--program", program, "--data"])
        .arg(&data)
        .args(["--length-unit", "mm", "-o"])
        .arg(&report)
        .assert()
        .success();
    let html = std::fs::read_to_string(&report).expect("report");
    assert!(html.contains("Acceptance test (ISO 9283)") && html.contains("RP_l"));
    assert_eq!(
        html.matches("<svg").count(),
        6,
        "the cube and five bullseyes"
    );
    assert!(
        html.contains("The cube (side"),
        "the planned poses are the cube's"
    );
    // The program is never replaced by an output.
    let again = gecaro()
        .args(["iso9283", "plan", "industrial6", "-o", program])
        .output()
        .expect("runs");
    assert!(!again.status.success());
}

/// A study set's σ measured by a repeatability file (poses revisited):
/// the verdict tests the residuals against it and says so; a file that
/// claims ten times less scatter than the data have is named as exceeded;
/// a σ both stated and measured is refused.
#[test]
fn a_repeatability_file_gives_a_study_its_noise() {
    let folder = tempfile::tempdir().expect("folder");
    let at = |name: &str| folder.path().join(name);
    let run = |args: &[&str]| {
        let output = gecaro()
            .current_dir(folder.path())
            .args(args)
            .output()
            .expect("runs");
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    };
    run(&[
        "generate",
        "stanford",
        "--method",
        "position",
        "--count",
        "80",
        "--noise",
        "2e-5",
        "--seed",
        "5",
        "-o",
        "data.csv",
        "--real-out",
        "real.toml",
    ]);
    // Five of the data's configurations, revisited twenty times each.
    let data = std::fs::read_to_string(at("data.csv")).expect("data");
    let rows: Vec<&str> = data.lines().filter(|line| !line.starts_with('#')).collect();
    let joints = |row: &str| row.split(',').take(6).collect::<Vec<_>>().join(",");
    let mut configurations = format!("{}\n", joints(rows[0]));
    for _ in 0..20 {
        for row in &rows[1..6] {
            configurations.push_str(&format!("{}\n", joints(row)));
        }
    }
    std::fs::write(at("configs.csv"), configurations).expect("configurations");
    run(&[
        "generate",
        "stanford",
        "--method",
        "position",
        "--configurations",
        "configs.csv",
        "--real",
        "real.toml",
        "--noise",
        "2e-5",
        "--seed",
        "6",
        "-o",
        "revisits.csv",
    ]);
    let revisits = std::fs::read_to_string(at("revisits.csv")).expect("revisits");
    let revisits: Vec<&str> = revisits
        .lines()
        .filter(|line| !line.starts_with('#'))
        .collect();
    let mut repeatability = format!("pose,{}\n", revisits[0]);
    for (index, row) in revisits[1..].iter().enumerate() {
        repeatability.push_str(&format!("{},{row}\n", index % 5 + 1));
    }
    std::fs::write(at("rep.csv"), repeatability).expect("repeatability");
    let study = "robot = \"stanford\"\n[[measurements]]\nmethod = \"position\"\ndata = \"data.csv\"\nrepeatability = \"rep.csv\"\n";
    std::fs::write(at("study.toml"), study).expect("study");
    let output = gecaro()
        .current_dir(folder.path())
        .args(["identify", "--study", "study.toml"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("σ 0.02"), "{stderr}");
    assert!(
        stdout.contains("fit the noise measured from the revisited poses of rep.csv"),
        "{stdout}"
    );
    // Revisits scattered ten times less than the data's noise.
    let mut small = String::from("pose,qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n");
    let parsed: Vec<Vec<f64>> = revisits[1..]
        .iter()
        .map(|row| row.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    for (index, row) in parsed.iter().enumerate() {
        let pose = index % 5;
        let members: Vec<&Vec<f64>> = parsed.iter().skip(pose).step_by(5).collect();
        let mean = |c: usize| members.iter().map(|m| m[c]).sum::<f64>() / members.len() as f64;
        let fields: Vec<String> = (0..9)
            .map(|c| {
                if c >= 6 {
                    (mean(c) + (row[c] - mean(c)) / 10.0).to_string()
                } else {
                    row[c].to_string()
                }
            })
            .collect();
        small.push_str(&format!("{},{}\n", pose + 1, fields.join(",")));
    }
    std::fs::write(at("small.csv"), small).expect("small");
    std::fs::write(at("small.toml"), study.replace("rep.csv", "small.csv")).expect("study");
    let output = gecaro()
        .current_dir(folder.path())
        .args(["identify", "--study", "small.toml"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("× the measured noise"), "{stdout}");
    let both = study.replace("repeatability", "sigma = \"20um\"\nrepeatability");
    std::fs::write(at("both.toml"), both).expect("study");
    let output = gecaro()
        .current_dir(folder.path())
        .args(["identify", "--study", "both.toml"])
        .output()
        .expect("runs");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("not both"), "{stderr}");
}
