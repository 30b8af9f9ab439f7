//! A parallel robot through the API: the ready hexapod's measurements
//! simulated into the folder, identified, and judged on held-out poses; a
//! path outside the folder is never read.

use crate::util::*;

#[tokio::test]
async fn a_hexapod_is_calibrated_through_the_api() {
    let api = Api::new();
    let generate = |count: u64, seed: u64, save: &str, real: Value| {
        json!({
            "robot": "hexapod", "method": "frame", "count": count, "noise": 2e-5,
            "seed": seed, "save_as": save, "real_save_as": real["save"], "real": real["use"],
        })
    };
    let (status, body) = api
        .post(
            "/api/parallel/generate",
            &generate(60, 3, "poses.csv", json!({"save": "real.toml"})),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(body["configurations"], 60);
    let (status, body) = api
        .post(
            "/api/parallel/generate",
            &generate(200, 4, "held.csv", json!({"use": "real.toml"})),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    // The page's plan criterion: the workspace error, below random poses';
    // a criterion that is none refused by name.
    let (status, planned) = api
        .post(
            "/api/parallel/plan",
            &json!({"robot": "hexapod", "method": "frame", "count": 12, "pool": 200,
                    "criterion": "test", "save_as": "planned.csv"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{planned}");
    assert_eq!(planned["criterion_name"], "test");
    assert!(
        planned["criterion"].as_f64() < planned["random_criterion"].as_f64(),
        "{planned}"
    );
    let (status, refused) = api
        .post(
            "/api/parallel/plan",
            &json!({"robot": "hexapod", "method": "frame", "count": 12, "criterion": "z",
                    "save_as": "planned.csv", "overwrite": true}),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{refused}");
    assert!(refused.to_string().contains("criterion"), "{refused}");
    let (status, identified) = api
        .post(
            "/api/parallel/identify",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "poses.csv"},
                    "sigma": "20um", "save_as": "calibrated.toml"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{identified}");
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    assert_eq!(identified["trusted"], true);
    // Where it holds: over the whole workspace, predicted within twice the
    // noise floor.
    let region = &identified["region"];
    assert_eq!(region["holds_everywhere"], true, "{region}");
    assert!(
        region["predicted_work"].as_f64() < region["noise_floor"].as_f64().map(|f| 2.0 * f),
        "{region}"
    );
    assert!(api.folder.path().join("calibrated.toml").is_file());
    // The report to download: the verdict's words, every parameter.
    let report = identified["report"].as_str().expect("the report");
    assert!(report.starts_with("<!DOCTYPE html>"), "{report:.80}");
    let summary = identified["summary"].as_str().expect("words");
    assert!(report.contains(summary), "the report says {summary}");
    assert!(report.contains("<td>a6x</td>") && report.contains("<td>K6</td>"));
    // The residuals to download: a row per measured pose.
    let residuals = identified["residuals"].as_str().expect("the residuals");
    assert!(
        residuals.starts_with("set,file,kind,observation,lines,"),
        "{residuals:.80}"
    );
    assert_eq!(residuals.lines().count(), 61);
    // Over a stated work region (the page's field): judged there, said so.
    let (status, stated) = api
        .post(
            "/api/parallel/identify",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "poses.csv"},
                    "sigma": "20um", "work_region": "qm1=-5..5mm,qm2=-5..5mm"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{stated}");
    assert_eq!(stated["region"]["work_is_ranges"], false, "{stated}");
    assert_eq!(stated["region"]["work_name"], "the stated work region");
    assert_eq!(stated["region"]["work"][1], json!([-0.005, 0.005]));
    assert!(
        stated["region"]["predicted_work"].as_f64() < region["predicted_work"].as_f64(),
        "{stated}"
    );
    // The page's loss: reweighted, said so; a loss that is none refused by name.
    let (status, robust) = api
        .post(
            "/api/parallel/identify",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "poses.csv"},
                    "sigma": "20um", "loss": "cauchy", "reject": true,
                    "prior": "1mm,0.05deg,0.1%"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{robust}");
    assert_eq!(robust["outcome"], "fits_noise", "{}", robust["summary"]);
    assert!(
        robust["loss"]
            .as_str()
            .is_some_and(|loss| loss.starts_with("cauchy"))
    );
    assert!(robust["reweightings"].as_u64() > Some(0), "{robust}");
    // Clean data: nothing stands out, nothing rejected.
    assert_eq!(robust["rejected"], json!([]), "{robust}");
    assert_eq!(robust["prior"], "1 mm, 0.05°, 0.1 %");
    assert_eq!(identified["prior"], Value::Null);
    assert_eq!(identified["loss"], "l2");
    let (status, refused) = api
        .post(
            "/api/parallel/identify",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "poses.csv"},
                    "sigma": "20um", "loss": "banana"}),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{refused}");
    assert!(refused.to_string().contains("loss"), "{refused}");
    let rms = |answer: &Value| answer["errors"]["position_rms"].as_f64().expect("rms");
    let evaluate =
        |robot: &str| json!({"robot": robot, "method": "frame", "data": {"file": "held.csv"}});
    let (_, after) = api
        .post("/api/parallel/evaluate", &evaluate("calibrated.toml"))
        .await;
    let (_, floor) = api
        .post("/api/parallel/evaluate", &evaluate("real.toml"))
        .await;
    assert!(rms(&after) <= 1.2 * rms(&floor), "{after} against {floor}");
    let (status, planned) = api
        .post(
            "/api/parallel/plan",
            &json!({"robot": "hexapod", "method": "frame", "count": 20, "save_as": "plan.csv"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{planned}");
    assert_eq!(planned["configurations"].as_array().map(Vec::len), Some(20));
    assert!(api.folder.path().join("plan.csv").is_file());
    let (status, predicted) = api
        .post(
            "/api/parallel/predict",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "plan.csv"},
                    "sigma": "20um"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{predicted}");
    assert_eq!(predicted["rank"], 48);
    assert_eq!(predicted["region"]["holds_everywhere"], true);
    // The page's work region reaches the prediction.
    let (status, near) = api
        .post(
            "/api/parallel/predict",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "plan.csv"},
                    "sigma": "20um", "work_region": "qm1=-5..5mm,qm2=-5..5mm"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{near}");
    assert_eq!(near["region"]["work_name"], "the stated work region");
    assert!(
        near["region"]["predicted_work"].as_f64() < predicted["region"]["predicted_work"].as_f64(),
        "{near} against {predicted}"
    );
    let (status, compensated) = api
        .post(
            "/api/parallel/compensate",
            &json!({"nominal": "hexapod", "calibrated": "calibrated.toml",
                    "program": {"file": "held.csv"}, "save_as": "held-compensated.csv"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{compensated}");
    assert_eq!(compensated["targets"], 200);
    assert_eq!(compensated["outside_measured"], json!([]));
    assert!(
        compensated["program"]
            .as_str()
            .expect("csv")
            .starts_with("qm1,")
    );
    assert!(api.folder.path().join("held-compensated.csv").is_file());
    // The page's match: the poses' origins read as tool points, the file's
    // tool point taken as it is and said; a match that is none refused.
    let (status, points) = api
        .post(
            "/api/parallel/compensate",
            &json!({"nominal": "hexapod", "calibrated": "calibrated.toml",
                    "program": {"file": "held.csv"}, "match": "position",
                    "save_as": "held-points.csv"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{points}");
    assert_eq!(points["matched"], "position");
    assert!(
        points["note"]
            .as_str()
            .is_some_and(|note| note.contains("the tool point is the file's")),
        "{points}"
    );
    assert!(
        points["program"]
            .as_str()
            .expect("csv")
            .starts_with("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n")
    );
    let (status, refused) = api
        .post(
            "/api/parallel/compensate",
            &json!({"nominal": "hexapod", "calibrated": "calibrated.toml",
                    "program": {"file": "held.csv"}, "match": "orientation",
                    "save_as": "held-points.csv"}),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{refused}");
    assert!(refused.to_string().contains("match"), "{refused}");
    let (status, report) = api
        .post(
            "/api/parallel/identifiable",
            &json!({"robot": "hexapod", "method": "position"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{report}");
    assert_eq!(report["rank"], 45);
}

#[tokio::test]
async fn a_robot_outside_the_folder_is_not_read() {
    let api = Api::new();
    let outside = tempfile::NamedTempFile::with_suffix(".toml").expect("file");
    std::fs::write(
        outside.path(),
        include_str!("../../../../robots/hexapod.toml"),
    )
    .expect("written");
    let (status, body) = api
        .post(
            "/api/parallel/identifiable",
            &json!({"robot": outside.path().display().to_string(), "method": "frame"}),
        )
        .await;
    assert_ne!(status, StatusCode::OK, "{body}");
    // A serial robot where a parallel one is needed: the ready parallel
    // robots are listed.
    let (status, body) = api
        .post(
            "/api/parallel/identifiable",
            &json!({"robot": "stanford", "method": "frame"}),
        )
        .await;
    assert_ne!(status, StatusCode::OK);
    assert!(body.to_string().contains("hexapod"), "{body}");
}

/// The page's other tracker stations: a second file of poses, uploaded as
/// a tracker 2.3 m away reads them, identified with the first; the
/// station found where it stands.
#[tokio::test]
async fn a_second_stations_file_is_identified_with_the_first() {
    let api = Api::new();
    for (count, seed, save, real) in [
        (40, 11, "first.csv", json!({"real_save_as": "real.toml"})),
        (40, 12, "later.csv", json!({"real": "real.toml"})),
    ] {
        let mut request = json!({"robot": "hexapod", "method": "frame", "count": count,
                                 "noise": 2e-5, "seed": seed, "save_as": save});
        for (key, value) in real.as_object().expect("an object") {
            request[key] = value.clone();
        }
        let (status, body) = api.post("/api/parallel/generate", &request).await;
        assert_eq!(status, StatusCode::OK, "{body}");
    }
    // The later file as a tracker at (0.4, 2.3, -0.2) m, turned 90° about
    // the vertical, reads it: (x, y, z) → (0.4 − y, 2.3 + x, z − 0.2), the
    // orientation turned alike.
    let text = std::fs::read_to_string(api.folder.path().join("later.csv")).expect("data");
    let turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let mut lines = text.lines();
    let mut moved = format!("{}\n", lines.next().expect("header"));
    for line in lines {
        let v: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        let q = turn
            * nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                v[9], v[10], v[11], v[12],
            ));
        let mut row: Vec<f64> = v[..6].to_vec();
        row.extend([0.4 - v[7], 2.3 + v[6], v[8] - 0.2, q.w, q.i, q.j, q.k]);
        let row: Vec<String> = row.iter().map(|value| format!("{value:?}")).collect();
        moved.push_str(&(row.join(",") + "\n"));
    }
    let (status, identified) = api
        .post(
            "/api/parallel/identify",
            &json!({"robot": "hexapod", "method": "frame", "data": {"file": "first.csv"},
                    "stations": [{"csv": {"text": moved, "name": "station2.csv"}}],
                    "sigma": "20um"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{identified}");
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    let station = &identified["stations"][0];
    assert_eq!(station["data"], "station2.csv", "{station}");
    let position = &station["frame"]["position"];
    let off = [0.4, 2.3, -0.2]
        .iter()
        .enumerate()
        .map(|(k, truth)| (position[k].as_f64().expect("a number") - truth).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(off < 1e-3, "the station found {off} m off: {station}");
}

/// The page's measuring leg: generated and identified through the API
/// with its two sockets, the leg found; the method without them refused by
/// name.
#[tokio::test]
async fn a_measuring_leg_is_identified_through_the_api() {
    let api = Api::new();
    let leg = json!({"leg_base": "250mm,-100mm,0", "leg_platform": "-120mm,80mm,0"});
    let mut request = json!({"robot": "hexapod", "method": "leg", "count": 600, "noise": 1e-6,
                             "seed": 5, "save_as": "legs.csv"});
    for (key, value) in leg.as_object().expect("an object") {
        request[key] = value.clone();
    }
    let (status, body) = api.post("/api/parallel/generate", &request).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let mut identify = json!({"robot": "hexapod", "method": "leg", "data": {"file": "legs.csv"},
                              "sigma": "1um"});
    let (status, refused) = api.post("/api/parallel/identify", &identify).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{refused}");
    assert!(refused.to_string().contains("leg_base"), "{refused}");
    for (key, value) in leg.as_object().expect("an object") {
        identify[key] = value.clone();
    }
    let (status, identified) = api.post("/api/parallel/identify", &identify).await;
    assert_eq!(status, StatusCode::OK, "{identified}");
    assert_eq!(
        identified["outcome"], "fits_noise",
        "{}",
        identified["summary"]
    );
    assert!(
        identified["leg"]["length"].as_f64() > Some(0.5),
        "{}",
        identified["leg"]
    );
}
