//! One request through the three front ends' layers: the command line, the
//! web API and the application layer called directly (as Python calls it;
//! `crates/gecaro-py/tests` compares Python with the command line) give the
//! same document, number for number.

use assert_cmd::Command;
use axum::body::Body;
use axum::http::{Request, StatusCode, header};
use gecaro_app::{GenerateRequest, IdentifyRequest, LocalFiles, MethodSpec, RobotSource};
use gecaro_calib::Quiet;
use gecaro_web::{AppState, Workspace, router};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use tower::ServiceExt;

/// Position data of a Stanford arm with errors, in millimetres and degrees
/// under an instrument's column names, written into `folder`.
fn tracker_file(folder: &std::path::Path) -> String {
    let mut request = GenerateRequest::new(
        RobotSource::Named("stanford".into()),
        MethodSpec::named("position"),
        40,
    );
    request.noise = 2e-5;
    request.seed = Some(7);
    let generated = request
        .run(&LocalFiles, &mut gecaro_calib::Quiet)
        .expect("generated");
    let mut text = String::from("A1,A2,A3,A4,A5,A6,X,Y,Z,stamp\n");
    for (row, sample) in generated.samples.iter().enumerate() {
        let q = &sample.motor_positions();
        let p = sample.position().expect("position") * 1e3;
        // Joint 3 is prismatic: metres to millimetres like the positions.
        text.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},t{row}\n",
            q[0].to_degrees(),
            q[1].to_degrees(),
            q[2] * 1e3,
            q[3].to_degrees(),
            q[4].to_degrees(),
            q[5].to_degrees(),
            p.x,
            p.y,
            p.z
        ));
    }
    std::fs::write(folder.join("tracker.csv"), text).expect("written");
    "tracker.csv".into()
}

const COLUMNS: &str = "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6,x=X,y=Y,z=Z";

async fn web_identification(folder: &std::path::Path, request: &Value) -> Value {
    let app = router(AppState::new(
        Workspace::new(folder).expect("workspace"),
        Vec::new(),
    ));
    let send = |request: Request<Body>| {
        let app = app.clone();
        async move {
            let response = app.oneshot(request).await.expect("infallible");
            let status = response.status();
            let bytes = response
                .into_body()
                .collect()
                .await
                .expect("body")
                .to_bytes();
            (
                status,
                serde_json::from_slice::<Value>(&bytes).expect("JSON"),
            )
        }
    };
    let (status, submitted) = send(
        Request::post("/api/identify")
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(request.to_string()))
            .expect("request"),
    )
    .await;
    assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
    let job = submitted["job"].as_u64().expect("job");
    for _ in 0..1200 {
        let (_, view) = send(
            Request::get(format!("/api/jobs/{job}"))
                .body(Body::empty())
                .expect("request"),
        )
        .await;
        match view["state"].as_str() {
            Some("done") => return view["result"]["identification"].clone(),
            Some("failed") => panic!("the job failed: {view}"),
            _ => tokio::time::sleep(std::time::Duration::from_millis(25)).await,
        }
    }
    panic!("the job did not finish");
}

/// Whether two documents are the same: every name, string and count equal,
/// every number equal to within a few units in the last place. (Two
/// processes can differ in the last bits: the dense algebra's SIMD paths
/// follow the alignment of the data in memory.)
fn same(a: &Value, b: &Value, what: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().expect("number"), y.as_f64().expect("number"));
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1e-300),
                "{what}: {x} != {y}"
            );
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{what}: lengths");
            for (x, y) in x.iter().zip(y) {
                same(x, y, what);
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{what}: fields"
            );
            for (key, x) in x {
                same(x, &y[key], &format!("{what}: {key}"));
            }
        }
        _ => assert_eq!(a, b, "{what}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_identification_request_gives_the_same_document_everywhere() {
    let folder = tempfile::tempdir().expect("folder");
    let data = tracker_file(folder.path());
    // The request as the web page sends it: an instrument's file, a robust
    // loss, a prior, a model and a cross-validation.
    let request = json!({
        "robot": "stanford",
        "method": { "name": "position" },
        "data": { "file": data },
        "format": { "length_unit": "mm", "angle_unit": "deg", "columns": COLUMNS },
        "loss": "huber",
        "prior": "5mm,0.5deg,1%",
        "model": "no-gains",
        "cv": 3,
        "seed": 4,
    });
    let web = web_identification(folder.path(), &request).await;

    let command = Command::cargo_bin("gecaro")
        .expect("binary")
        .current_dir(folder.path())
        .args([
            "identify",
            "stanford",
            "--method",
            "position",
            "--data",
            "tracker.csv",
            "--length-unit",
            "mm",
            "--angle-unit",
            "deg",
            "--columns",
            COLUMNS,
            "--loss",
            "huber",
            "--prior",
            "5mm,0.5deg,1%",
            "--model",
            "no-gains",
            "--cv",
            "3",
            "--seed",
            "4",
            "--json",
        ])
        .output()
        .expect("runs");
    assert!(
        command.status.success(),
        "{}",
        String::from_utf8_lossy(&command.stderr)
    );
    let cli: Value = serde_json::from_slice(&command.stdout).expect("JSON");

    // The application layer as Python calls it, from the same JSON.
    let mut direct: IdentifyRequest = serde_json::from_value(request).expect("a request");
    direct.measurements.data = Some(gecaro_app::DataSource::File(
        folder.path().join("tracker.csv").display().to_string(),
    ));
    let identified = direct.run(&LocalFiles, &mut Quiet).expect("identified");
    let app = serde_json::to_value(identified.document()).expect("JSON");

    same(&cli, &web, "command line and web API");
    // The data file's label differs (a path, not the folder's name) only in
    // the outliers' file names; there are none here.
    same(&app, &web, "application layer and web API");
    assert_eq!(web["loss"]["kind"], "huber");
    assert!(web["prior"].is_object());
    assert!(
        web["parameters"]
            .as_array()
            .expect("parameters")
            .iter()
            .all(|p| !p["name"].as_str().expect("name").starts_with('K'))
    );
    assert_eq!(web["cross_validation"]["folds"], 3);
}
