//! Identification from the command line: identifiable parameters, generation, identification and evaluation, studies, reports, failures.

use super::*;

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
    command("generate industrial6 --method position --count 30")
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
fn table2_prints_the_paper_totals() {
    command("table2")
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
    command("identifiable stanford --method position --data")
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
    command("identifiable stanford --method position --data")
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
    command("identifiable stanford --method position --data")
        .arg(&nan)
        .assert()
        .code(3)
        .stderr(predicate::str::contains(
            "nan.csv:4: y: `NaN` is not a finite number",
        ));
}

#[test]
fn bad_method_options_are_usage_errors() {
    command("identifiable stanford --method plane3")
        .assert()
        .code(2)
        .stderr(predicate::str::contains("position").and(predicate::str::contains("distance")));
    command("identifiable stanford --method plane1 --plane-normal 0,0,0 --plane-point 0.3,0.2,0.6")
        .assert()
        .code(2)
        .stderr(predicate::str::contains("normal is zero"));
    command("identifiable stanford --method plane2")
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
    command("generate stanford --method position --count 40 --error-level 2 --seed 3 -o")
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
    command("generate stanford --method position --count 30 --seed 4 --real")
        .arg(&real)
        .arg("-o")
        .arg(&held_out)
        .assert()
        .success();
    let identification = command("identify stanford --method position --json --data")
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
    command("robot check").arg(&calibrated).assert().success();
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
    command("generate stanford --method frame --count 60 --error-level 1 --noise 0 --seed 11")
        .args(["-o", &data, "--real-out", &real])
        .assert()
        .success();
    // Other configurations of the same real robot, to judge the file where
    // its user will.
    command("generate stanford --method frame --count 200")
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
    command("generate stanford --method position --count 40 --error-level 10 --seed 2 -o")
        .arg(&data)
        .assert()
        .success();
    command("identify stanford --method position --max-iterations 1 --data")
        .arg(&data)
        .arg("-o")
        .arg(&output)
        .assert()
        .code(4)
        .stderr(predicate::str::contains("did not converge"))
        .stderr(predicate::str::contains("Nothing was written"));
    assert!(!output.exists());
    command("identify stanford --method position --max-iterations 1 --write-unconverged --data")
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
    command("generate stanford --method distance --count 10 -o")
        .arg(&data)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("--force"));
    assert_eq!(std::fs::read_to_string(&data).expect("read"), "keep me");
    command("generate stanford --method distance --count 10 -o")
        .arg(folder.path().join("missing/data.csv"))
        .assert()
        .code(3)
        .stderr(predicate::str::contains("does not exist"));
}

#[test]
fn demo_identifies_every_method() {
    command("demo")
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
    let output = command("identify --study")
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
    command("identify stanford --study")
        .arg(study)
        .assert()
        .code(2);
}

#[test]
fn study_files_report_their_own_mistakes() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let study = folder.path().join("study.toml");
    std::fs::write(&study, "robot = \"stanford\"\n[[measurements]]\nmethod = \"point-lnk\"\ndata = \"x.csv\"\nsigma = 0.001\n").expect("write");
    command("identify --study")
        .arg(&study)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("study.toml:3: method"))
        .stderr(predicate::str::contains("point-link"));
    std::fs::write(&study, "robot = \"stanford\"\n[[measurements]]\nmethod = \"distance\"\ndata = \"x.csv\"\nsigma = -1\n").expect("write");
    command("identify --study")
        .arg(&study)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("sigma: must be a positive"));
}

#[test]
fn report_and_plots_show_the_identification() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let data = folder.path().join("frame.csv");
    let report = folder.path().join("report.html");
    let plots = folder.path().join("plots");
    command("generate scara --method frame --count 25 --noise 1e-5 -o")
        .arg(&data)
        .assert()
        .success();
    command("report scara --method frame --data")
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
    command("report scara --method frame --data")
        .arg(&data)
        .arg("-o")
        .arg(&report)
        .assert()
        .code(3);
    assert_eq!(std::fs::read_to_string(&report).expect("report"), html);

    command("identify scara --method frame --data")
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

/// A cell that is not levelled, simulated (`generate --gravity-tilt`) and
/// found (`identify --model elastic-gravity`): the tilts within 3σ of
/// the truth, and the calibrated file states the gravity found; a tilt
/// for a rigid real robot is refused by name.
#[test]
fn a_tilted_cell_is_simulated_and_its_gravity_found() {
    let folder = tempfile::tempdir().expect("folder");
    let path = |name: &str| folder.path().join(name).to_str().expect("UTF-8").to_owned();
    let generate = |extra: &[&str], payload: &str, seed: &str, out: &str| {
        command("generate industrial6 --method position")
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
    command("generate industrial6 --method position --count 5")
        .args(["--gravity-tilt", "2deg,-1deg", "-o", &path("rigid.csv")])
        .assert()
        .failure()
        .stderr(predicates::str::contains(
            "--gravity-tilt: gravity's tilt loads elastic joints only",
        ));
}
