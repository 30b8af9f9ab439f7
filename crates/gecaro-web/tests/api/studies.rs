//! Studies: from a file or JSON, in a subfolder, from the editor, planned and predicted.

use crate::util::*;

/// The tracker cell of docs/tracker.md as a study file in the served folder
/// and as the same study stated in the request's JSON: one construction
/// path, one result; a field at fault is named by its path, and a study's
/// files stay inside the folder.
#[tokio::test]
async fn a_study_runs_from_its_file_or_its_json_alike() {
    let api = Api::new();
    let cell = api.with_tracker_cell();
    let text = std::fs::read_to_string(cell.join("study.toml")).expect("study");
    let stated: Value = toml::from_str::<toml::Value>(&text)
        .map(|value| serde_json::to_value(value).expect("json"))
        .expect("toml");
    let mut results = Vec::new();
    for study in [json!("study.toml"), stated.clone()] {
        let (status, submitted) = api.post("/api/identify", &json!({ "study": study })).await;
        assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
        let view = api.finished(submitted["job"].as_u64().expect("job")).await;
        assert_eq!(view["state"], "done", "{view}");
        let identification = view["result"]["identification"].clone();
        assert_eq!(identification["converged"], true, "{identification}");
        results.push(identification);
    }
    assert_eq!(results[0]["frames"], results[1]["frames"]);
    assert_eq!(results[0]["rms_after"], results[1]["rms_after"]);
    // Every measured point's deviation from the calibrated robot (issue
    // 76): one per configuration of the six sets, at the tracker's 20 µm,
    // drawn on the robot (the tracker itself 2.5 m away).
    let (_, submitted) = api
        .post("/api/identify", &json!({ "study": "study.toml" }))
        .await;
    let job = submitted["job"].as_u64().expect("job");
    let view = api.finished(job).await;
    let deviations = &view["result"]["deviations"];
    let configurations: usize = std::fs::read_dir(&cell)
        .expect("cell")
        .map(|entry| entry.expect("entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "csv"))
        .map(|path| {
            std::fs::read_to_string(path)
                .expect("data")
                .lines()
                .filter(|line| line.starts_with(|c: char| c.is_ascii_digit() || c == '-'))
                .count()
        })
        .sum();
    assert_eq!(deviations["total"], configurations, "{deviations:.300}");
    let points = deviations["points"].as_array().expect("points");
    assert_eq!(points.len(), configurations);
    let norm = |value: &Value| -> f64 {
        value
            .as_array()
            .expect("three")
            .iter()
            .map(|v| v.as_f64().expect("m").powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let rms = (points
        .iter()
        .map(|p| norm(&p["deviation"]).powi(2))
        .sum::<f64>()
        / points.len() as f64)
        .sqrt();
    assert!(rms < 5e-5, "deviation RMS {rms} m");
    assert!(
        points
            .iter()
            .all(|p| norm(&p["point"]) < 2.0 && p["line"].as_u64().is_some())
    );
    assert!(
        norm(&deviations["measurement_origin"]) > 1.0,
        "{deviations:.200}"
    );
    // The correlation matrix (the heatmap): symmetric, 1 on its diagonal,
    // one row per unknown; tracker 2's origin covariance, whose diagonal
    // gives the σ the frames table states.
    let correlation = &view["result"]["correlation"];
    let names = correlation["names"].as_array().expect("names");
    let values = correlation["values"].as_array().expect("rows");
    assert_eq!(values.len(), names.len());
    let at = |i: usize, j: usize| values[i][j].as_f64().expect("ρ");
    for i in 0..names.len() {
        assert!((at(i, i) - 1.0).abs() < 1e-12);
        for j in 0..names.len() {
            assert!((at(i, j) - at(j, i)).abs() < 1e-12 && at(i, j).abs() <= 1.0);
        }
    }
    // The errors set by set and station by station, against the residuals
    // file's rows summed here.
    let residuals = api
        .download(&format!("/api/jobs/{job}/residuals.csv"), "text/csv")
        .await;
    let mut reader = csv::Reader::from_reader(residuals.as_bytes());
    let headers = reader.headers().expect("header").clone();
    let column = |name: &str| headers.iter().position(|h| h == name).expect(name);
    let (set_column, after_column) = (column("set"), column("error_after_mm"));
    let mut sums = [(0usize, 0.0f64); 6];
    for record in reader.records() {
        let record = record.expect("row");
        let set: usize = record[set_column].parse().expect("set");
        let after: f64 = record[after_column].parse().expect("mm");
        sums[set - 1].0 += 1;
        sums[set - 1].1 += after * after;
    }
    let sets = view["result"]["identification"]["sets"]
        .as_array()
        .expect("sets");
    assert_eq!(sets.len(), 6);
    for (set, (count, squares)) in sets.iter().zip(sums) {
        assert_eq!(set["observations"], count);
        let rms = (squares / count as f64).sqrt() * 1e-3;
        assert!(
            (set["rms_after"].as_f64().expect("m") - rms).abs() < 1e-12,
            "{set}"
        );
    }
    assert_eq!(sets[3]["station"], "tracker_2");
    assert_eq!(sets[0]["tool"], "smr_a");
    let stations = view["result"]["identification"]["stations"]
        .as_array()
        .expect("stations");
    assert_eq!(stations.len(), 2);
    assert_eq!(stations[0]["name"], "the measurement frame");
    assert_eq!(
        stations[0]["observations"].as_u64().expect("n")
            + stations[1]["observations"].as_u64().expect("n"),
        configurations as u64
    );
    let block = &view["result"]["frame_covariances"]["tracker_2"];
    let auxiliary = view["result"]["identification"]["auxiliary"]
        .as_array()
        .expect("auxiliary");
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let stated = auxiliary
            .iter()
            .find(|p| p["name"] == format!("tracker_2.{axis}"))
            .expect("tracker_2's unknown")["std"]
            .as_f64()
            .expect("σ");
        let variance = block[k][k].as_f64().expect("m²");
        assert!(
            (variance.sqrt() - stated).abs() < 1e-9 * stated,
            "{axis}: {variance} against σ {stated}"
        );
    }
    let station = &results[0]["frames"]
        .as_array()
        .expect("frames")
        .iter()
        .find(|frame| frame["name"] == "tracker_2")
        .expect("tracker_2")["position"];
    // The simulated tracker 2 stands at (−1200, 1750, −200) mm; the study
    // states (−1150, 1700, −250).
    let truth = [-1.2, 1.75, -0.2];
    for (found, truth) in station.as_array().expect("position").iter().zip(truth) {
        assert!(
            (found.as_f64().expect("m") - truth).abs() < 1e-3,
            "{station}"
        );
    }
    let mut bad = stated.clone();
    bad["measurements"][2]["sigma"] = json!(-1);
    let (status, body) = api.post("/api/identify", &json!({ "study": bad })).await;
    assert!(status.is_client_error(), "{body}");
    assert!(
        error_text(&body)
            .contains("study.measurements[2].sigma: must be a positive standard deviation"),
        "{body}"
    );
    let mut outside = stated;
    outside["measurements"][0]["data"] = json!("../smr_a_1.csv");
    let (status, body) = api
        .post("/api/identify", &json!({ "study": outside }))
        .await;
    assert!(status.is_client_error(), "{body}");
    std::fs::write(
        api.folder.path().join("bad.toml"),
        text.replace("sigma = 0.02\n[[", "sigma = -0.02\n[["),
    )
    .expect("bad study");
    let (status, body) = api
        .post("/api/identify", &json!({ "study": "bad.toml" }))
        .await;
    assert!(status.is_client_error(), "{body}");
    let line = text
        .lines()
        .position(|line| line == "sigma = 0.02")
        .expect("a sigma")
        + 1;
    assert!(
        error_text(&body).contains(&format!("bad.toml:{line}: sigma: must be a positive")),
        "{body}"
    );
}

/// A study opened from a subfolder names its files from the folder's root,
/// as the page runs it (issue 75: it read the root's files of the same
/// names); saved into a subfolder it names them from there, and a file
/// outside that folder is refused, not written as a name that breaks.
#[tokio::test]
async fn a_study_in_a_subfolder_names_its_own_files() {
    let api = Api::new();
    let cell = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/tracker-cell");
    let sub = api.folder.path().join("cell");
    std::fs::create_dir(&sub).expect("subfolder");
    for entry in std::fs::read_dir(&cell).expect("cell") {
        let path = entry.expect("entry").path();
        std::fs::copy(&path, sub.join(path.file_name().expect("name"))).expect("copy");
    }
    let (status, opened) = api.get("/api/studies/file?name=cell/study.toml").await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    let study = opened["study"].clone();
    let first = study["measurements"][0]["data"]
        .as_str()
        .expect("data")
        .to_owned();
    assert!(first.starts_with("cell/"), "{study}");
    assert_eq!(
        study["robot"], "industrial6",
        "a ready robot's name is kept"
    );
    // Saved beside its files: named from there, and it opens the same.
    let (status, saved) = api
        .post(
            "/api/studies/save",
            &json!({ "name": "cell/copy.toml", "study": study }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    let written = std::fs::read_to_string(sub.join("copy.toml")).expect("written");
    assert!(!written.contains("cell/"), "{written}");
    let (_, again) = api.get("/api/studies/file?name=cell/copy.toml").await;
    assert_eq!(again["study"], study);
    // Saved into another folder: its files are outside it.
    std::fs::create_dir(api.folder.path().join("saved")).expect("folder");
    let (status, body) = api
        .post(
            "/api/studies/save",
            &json!({ "name": "saved/copy.toml", "study": study }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(
        error_text(&body).contains("outside the study's folder saved"),
        "{body}"
    );
}

#[tokio::test]
async fn the_study_editor_opens_saves_and_identifies_with_the_tables_robot() {
    let api = Api::new();
    api.with_tracker_cell();
    let (status, opened) = api.get("/api/studies/file?name=study.toml").await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    let mut study = opened["study"].clone();
    assert_eq!(study["robot"], "industrial6");
    assert_eq!(study["measurements"].as_array().expect("sets").len(), 6);
    assert_eq!(
        study["stations"]["tracker_2"]["rpy"],
        json!([0.0, 0.0, -130.0])
    );
    // Saved under another name, it opens to the same statement; an existing
    // file is not replaced.
    let (status, saved) = api
        .post(
            "/api/studies/save",
            &json!({ "name": "copy.toml", "study": study }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    let (_, again) = api.get("/api/studies/file?name=copy.toml").await;
    assert_eq!(again["study"], study);
    let (status, body) = api
        .post(
            "/api/studies/save",
            &json!({ "name": "copy.toml", "study": study }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    // The page's table as the study's robot: the statement names none.
    let document = api.document("industrial6").await;
    study.as_object_mut().expect("object").remove("robot");
    let (status, submitted) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "study": study }),
        )
        .await;
    assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
    let view = api.finished(submitted["job"].as_u64().expect("job")).await;
    assert_eq!(view["state"], "done", "{view}");
    let frames = view["result"]["identification"]["frames"]
        .as_array()
        .expect("frames")
        .clone();
    assert_eq!(frames.len(), 4, "3 reflectors, 1 station: {frames:?}");
    // Both a named robot and the table's: refused, by the field.
    study["robot"] = json!("industrial6");
    let (status, body) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "study": study }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("study.robot"), "{body}");
    // Not a study file: its line and key.
    let (status, body) = api.get("/api/studies/file?name=copy.csv").await;
    assert!(status.is_client_error(), "{body}");
}

/// Issue 37 §1: a cell planned and predicted from the study editor — the
/// table's robot for a stated study, a planned study saved only when it can
/// name its robot, its sets' files beside it, and its precision predicted
/// before anything is measured.
#[tokio::test]
async fn a_study_is_planned_as_a_job_and_predicted_from_the_editor() {
    let api = Api::new();
    api.with_tracker_cell();
    let (_, opened) = api.get("/api/studies/file?name=study.toml").await;
    let mut study = opened["study"].clone();
    study.as_object_mut().expect("object").remove("robot");
    let document = api.document("industrial6").await;
    // Planned with the table's robot, not saved: the sets' files to download.
    let request = json!({ "robot": document, "study": study, "count": 36, "pool": 150 });
    // In a teach pendant's degrees: a units line, and the cell need not be
    // measured yet (issue 74): its sets' files are what the plan writes.
    let mut unmeasured = study.clone();
    for (k, set) in unmeasured["measurements"]
        .as_array_mut()
        .expect("sets")
        .iter_mut()
        .enumerate()
    {
        set["data"] = json!(format!("not_yet_{k}.csv"));
    }
    let job = api
        .job(
            "/api/studies/plan",
            &json!({ "robot": document, "study": unmeasured, "count": 36, "pool": 150,
                     "format": { "angle_unit": "deg" } }),
        )
        .await
        .expect("started");
    assert_eq!(job["state"], "done", "{job}");
    let first = job["result"]["files"][0]["csv"].as_str().expect("csv");
    assert!(first.starts_with("# units: angle_unit = deg"), "{first}");
    let job = api
        .job("/api/studies/plan", &request)
        .await
        .expect("started");
    assert_eq!(job["state"], "done", "{job}");
    assert_eq!(job["phase"], "choosing the configurations", "{job}");
    let planned = &job["result"];
    let sets = planned["sets"].as_array().expect("sets");
    assert_eq!(sets.len(), 6);
    let counts: Vec<u64> = sets
        .iter()
        .map(|set| set["configurations"].as_u64().expect("count"))
        .collect();
    assert_eq!(counts.iter().sum::<u64>(), 36, "{counts:?}");
    assert_eq!(planned["configurations"], 36);
    assert!(
        planned["log_det"].as_f64().expect("plan")
            > planned["random_log_det"].as_f64().expect("random"),
        "{planned}"
    );
    let files = planned["files"].as_array().expect("files");
    assert_eq!(files[0]["file_name"], "planned_1.csv");
    let first = files[0]["csv"].as_str().expect("csv");
    assert!(first.starts_with("qm1,"), "{first}");
    assert_eq!(first.lines().count() as u64, counts[0] + 1);
    assert!(planned["output"].as_array().expect("output").is_empty());
    // Saving needs a robot the planned study can name: a table is refused at
    // once, by the field; the ready robot's name is written.
    let mut saving = request.clone();
    saving["save_as"] = json!("planned.toml");
    let Err((status, body)) = api.job("/api/studies/plan", &saving).await else {
        panic!("a table's robot cannot be named in a planned study");
    };
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("save_as"), "{body}");
    saving["robot"] = json!("industrial6");
    let job = api
        .job("/api/studies/plan", &saving)
        .await
        .expect("started");
    assert_eq!(job["state"], "done", "{job}");
    let written = std::fs::read_to_string(api.folder.path().join("planned.toml")).expect("study");
    assert!(written.contains("robot = \"industrial6\""), "{written}");
    assert!(written.contains("data = \"planned_6.csv\""), "{written}");
    for set in 1..=6 {
        assert!(
            api.folder
                .path()
                .join(format!("planned_{set}.csv"))
                .is_file()
        );
    }
    // Again: the files exist, refused before any work.
    let Err((status, _)) = api.job("/api/studies/plan", &saving).await else {
        panic!("the planned study exists");
    };
    assert_eq!(status, StatusCode::CONFLICT);
    // Predicted before it is measured: every unknown's σ, and the error.
    let (status, predicted) = api
        .post("/api/studies/predict", &json!({ "study": "planned.toml" }))
        .await;
    assert_eq!(status, StatusCode::OK, "{predicted}");
    assert_eq!(predicted["sets"].as_array().expect("sets").len(), 6);
    let parameters = predicted["parameters"].as_array().expect("parameters");
    assert!(
        parameters.iter().any(|p| p["name"] == "tracker_2.x"),
        "{predicted}"
    );
    let rms = predicted["predicted"]["position_rms"]
        .as_f64()
        .expect("rms");
    // σ 0.02 mm per reflector: the calibrated robot within a few σ.
    assert!(rms > 1e-6 && rms < 1e-4, "{rms}");
    // The same prediction from the stated study with the table's robot.
    let (status, again) = api
        .post(
            "/api/studies/predict",
            &json!({ "robot": document, "study": study }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{again}");
    assert!(again["predicted"]["position_rms"].as_f64().expect("rms") > 0.0);
}
