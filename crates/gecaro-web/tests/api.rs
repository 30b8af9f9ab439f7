//! The JSON API on its own (docs/api.md): every route, through the router,
//! without a network.

use std::time::Duration;

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode, header};
use futures_util::StreamExt;
use gecaro_web::{AppState, POST_ROUTES, Workspace, router};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use tower::ServiceExt;

struct Api {
    app: Router,
    folder: tempfile::TempDir,
}

impl Api {
    fn new() -> Self {
        Self::with_hosts(Vec::new())
    }

    fn with_hosts(hosts: Vec<String>) -> Self {
        let folder = tempfile::tempdir().expect("folder");
        let state = AppState::new(Workspace::new(folder.path()).expect("workspace"), hosts);
        Api {
            app: router(state),
            folder,
        }
    }

    async fn send(&self, request: Request<Body>) -> (StatusCode, Vec<u8>, header::HeaderMap) {
        let response = self.app.clone().oneshot(request).await.expect("infallible");
        let status = response.status();
        let headers = response.headers().clone();
        let bytes = response
            .into_body()
            .collect()
            .await
            .expect("body")
            .to_bytes();
        (status, bytes.to_vec(), headers)
    }

    async fn get(&self, uri: &str) -> (StatusCode, Value) {
        let request = Request::get(uri).body(Body::empty()).expect("request");
        let (status, bytes, _) = self.send(request).await;
        (
            status,
            serde_json::from_slice(&bytes).unwrap_or(Value::Null),
        )
    }

    async fn post(&self, uri: &str, body: &Value) -> (StatusCode, Value) {
        self.post_raw(uri, body.to_string()).await
    }

    async fn post_raw(&self, uri: &str, body: String) -> (StatusCode, Value) {
        let request = Request::post(uri)
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(body))
            .expect("request");
        let (status, bytes, _) = self.send(request).await;
        let value = serde_json::from_slice(&bytes)
            .unwrap_or_else(|_| panic!("{uri}: not JSON: {}", String::from_utf8_lossy(&bytes)));
        (status, value)
    }

    /// The text of a download at `uri`, checked to be `kind`
    /// (`text/html`, …).
    async fn download(&self, uri: &str, kind: &str) -> String {
        let request = Request::get(uri).body(Body::empty()).expect("request");
        let (status, bytes, headers) = self.send(request).await;
        assert_eq!(status, StatusCode::OK, "{uri}");
        let given = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(given.starts_with(kind), "{uri}: {given}");
        String::from_utf8(bytes).expect("utf-8")
    }

    /// The names of the files in the served folder.
    fn names(&self) -> Vec<String> {
        std::fs::read_dir(self.folder.path())
            .expect("list")
            .map(|entry| {
                entry
                    .expect("entry")
                    .file_name()
                    .to_string_lossy()
                    .into_owned()
            })
            .collect()
    }

    async fn document(&self, robot: &str) -> Value {
        let (status, view) = self.get(&format!("/api/robots/ready/{robot}")).await;
        assert_eq!(status, StatusCode::OK, "{view}");
        view["document"].clone()
    }

    /// Copies the tracker cell of `examples/tracker-cell` (its study file
    /// and six data files) into the folder; the cell's folder.
    fn with_tracker_cell(&self) -> std::path::PathBuf {
        let cell =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/tracker-cell");
        for entry in std::fs::read_dir(&cell).expect("cell") {
            let path = entry.expect("entry").path();
            std::fs::copy(
                &path,
                self.folder.path().join(path.file_name().expect("name")),
            )
            .expect("copy");
        }
        cell
    }

    /// Posts work that runs as a job (`202` with its number) and waits for
    /// it: the job's view once it ended (`state` "done" with its `result`,
    /// or "failed" with its `error`); the status and body of a request
    /// refused before it started.
    async fn job(&self, uri: &str, body: &Value) -> Result<Value, (StatusCode, Value)> {
        let (status, submitted) = self.post(uri, body).await;
        if status != StatusCode::ACCEPTED {
            return Err((status, submitted));
        }
        Ok(self
            .finished(submitted["job"].as_u64().expect("job number"))
            .await)
    }

    /// Waits for a job to end.
    async fn finished(&self, job: u64) -> Value {
        for _ in 0..600 {
            let (status, view) = self.get(&format!("/api/jobs/{job}")).await;
            assert_eq!(status, StatusCode::OK, "{view}");
            if view["state"] == "done" || view["state"] == "failed" || view["state"] == "cancelled"
            {
                return view;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        panic!("job {job} did not finish within 30 s");
    }

    /// Position data of `document`'s real robot (40 configurations, level-1
    /// errors, seed 3) and the robot identified from them (its document).
    async fn calibrated(&self, document: &Value) -> (Value, Value) {
        let (_, training) = self
            .post(
                "/api/generate",
                &json!({ "robot": document, "method": { "name": "position" }, "count": 40, "error_level": 1.0, "seed": 3 }),
            )
            .await;
        let (_, submitted) = self
            .post(
                "/api/identify",
                &json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": training["csv"], "name": "train.csv" } } }),
            )
            .await;
        let view = self.finished(submitted["job"].as_u64().expect("job")).await;
        (training, view["result"]["calibrated"].clone())
    }
}

/// The lines of a data file, its comments (a generated file's origin) left out.
fn data_lines(csv: &str) -> impl Iterator<Item = &str> {
    csv.lines().filter(|line| !line.starts_with('#'))
}

fn error_text(value: &Value) -> &str {
    value["error"]
        .as_str()
        .unwrap_or_else(|| panic!("no error message in {value}"))
}

#[tokio::test]
async fn info_lists_the_ready_robots_and_the_seven_methods() {
    let api = Api::new();
    let (status, info) = api.get("/api/info").await;
    assert_eq!(status, StatusCode::OK);
    let methods: Vec<&str> = info["methods"]
        .as_array()
        .expect("methods")
        .iter()
        .map(|m| m["name"].as_str().expect("name"))
        .collect();
    assert_eq!(
        methods,
        [
            "position",
            "frame",
            "point-link",
            "frame-link",
            "plane1",
            "plane2",
            "distance"
        ]
    );
    assert_eq!(
        info["methods"][1]["columns"],
        json!(["x", "y", "z", "qw", "qx", "qy", "qz"])
    );
    assert_eq!(info["methods"][4]["uses_plane"], true);
    // The page checks its fields against the application layer's bounds.
    assert_eq!(
        info["limits"]["generate"],
        json!(gecaro_app::limits::MAX_GENERATE)
    );
    assert_eq!(
        info["limits"]["folds"],
        json!(gecaro_app::limits::MAX_FOLDS)
    );
    assert!(
        info["ready"]
            .as_array()
            .expect("ready")
            .contains(&json!("stanford"))
    );
}

/// The page's modules as the browser loads them: from `/js/main.js`, every
/// relative import is served (as JavaScript), so no module is missing from
/// the binary.
#[tokio::test]
async fn every_module_the_page_imports_is_served() {
    let api = Api::new();
    let mut pending = vec!["main.js".to_string()];
    let mut seen = std::collections::BTreeSet::new();
    while let Some(path) = pending.pop() {
        if !seen.insert(path.clone()) {
            continue;
        }
        let (status, bytes, headers) = api
            .send(
                Request::get(format!("/js/{path}"))
                    .body(Body::empty())
                    .expect("request"),
            )
            .await;
        assert_eq!(status, StatusCode::OK, "/js/{path}");
        let content_type = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(content_type.starts_with("text/javascript"), "{path}");
        let text = String::from_utf8(bytes.to_vec()).expect("utf-8");
        let folder = path.rsplit_once('/').map_or("", |(folder, _)| folder);
        for line in text.lines().filter(|l| l.starts_with("import ")) {
            let target = line
                .rsplit(" from '")
                .next()
                .expect("from")
                .trim_end_matches("';");
            let mut parts: Vec<&str> = folder.split('/').filter(|p| !p.is_empty()).collect();
            for part in target.split('/') {
                match part {
                    "." => {}
                    ".." => {
                        parts.pop();
                    }
                    name => parts.push(name),
                }
            }
            pending.push(parts.join("/"));
        }
    }
    assert!(seen.len() > 20, "{seen:?}");
    let (status, _) = api.get("/js/no-such-module.js").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn the_page_and_its_assets_are_served_with_safe_headers() {
    let api = Api::new();
    for (path, kind) in [
        ("/", "text/html"),
        ("/js/main.js", "text/javascript"),
        ("/js/panels/identify.js", "text/javascript"),
        ("/style.css", "text/css"),
    ] {
        let (status, bytes, headers) = api
            .send(Request::get(path).body(Body::empty()).expect("request"))
            .await;
        assert_eq!(status, StatusCode::OK, "{path}");
        assert!(!bytes.is_empty());
        let content_type = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(content_type.starts_with(kind), "{path}: {content_type}");
        assert_eq!(headers[header::X_CONTENT_TYPE_OPTIONS], "nosniff");
        assert!(headers.contains_key(header::CONTENT_SECURITY_POLICY));
    }
    let (status, body) = api.get("/no/such/page").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error_text(&body).contains("no such"));
}

#[tokio::test]
async fn robots_are_opened_checked_and_their_problems_located() {
    let api = Api::new();
    let (status, view) = api.get("/api/robots/ready/stanford").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(view["summary"]["letters"], "RRPRRR");
    assert_eq!(view["summary"]["parameter_count"], 43);
    assert_eq!(view["problems"], json!([]));
    let (status, missing) = api.get("/api/robots/ready/r2d2").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error_text(&missing).contains("stanford"));

    let mut document = view["document"].clone();
    document["frame"][2]["sigma"] = json!(7);
    document["frame"][4]["alpha"] = json!(100.0);
    let (status, checked) = api
        .post("/api/robots/check", &json!({ "robot": document }))
        .await;
    assert_eq!(status, StatusCode::OK);
    assert!(checked.get("summary").is_none());
    let problems = checked["problems"].as_array().expect("problems");
    assert_eq!(problems.len(), 2, "{checked}");
    assert_eq!(
        problems[0]["location"],
        json!({ "kind": "frame", "frame": 2, "key": "sigma" })
    );
    assert_eq!(
        problems[1]["location"],
        json!({ "kind": "frame", "frame": 4, "key": "alpha" })
    );
    assert!(
        problems[1]["message"]
            .as_str()
            .expect("text")
            .contains("angle_unit")
    );

    // The same document, refused by a computing route with the same problems.
    let (status, refused) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "position" } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(refused["problems"].as_array().expect("problems").len(), 2);
}

#[tokio::test]
async fn new_robots_follow_the_joint_letters() {
    let api = Api::new();
    let (status, view) = api
        .post(
            "/api/robots/new",
            &json!({ "joints": "RRPR", "name": "Mine" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{view}");
    assert_eq!(view["summary"]["letters"], "RRPR");
    assert_eq!(view["document"]["name"], "Mine");
    let (status, refused) = api
        .post("/api/robots/new", &json!({ "joints": "RXR" }))
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&refused).contains("joint 2 is `X`"));
}

#[tokio::test]
async fn saves_stay_inside_the_folder_and_never_break_a_file() {
    let api = Api::new();
    let document = api.document("puma560").await;
    let save = |name: &str, overwrite: bool| json!({ "robot": document, "name": name, "overwrite": overwrite });
    let (status, saved) = api
        .post("/api/robots/save", &save("puma.toml", false))
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    let path = api.folder.path().join("puma.toml");
    let written = std::fs::read_to_string(&path).expect("saved");
    let loaded = gecaro_io::read_robot_file(&path).expect("a valid robot file");
    assert_eq!(loaded.robot.joint_letters(), "RRRRRR");

    // Exists: 409 without overwrite, file untouched.
    let (status, conflict) = api
        .post("/api/robots/save", &save("puma.toml", false))
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert!(error_text(&conflict).contains("already exists"));
    // An invalid robot is not saved over a good file.
    let mut broken = document.clone();
    broken["frame"][1]["qmin"] = json!(3.0);
    broken["frame"][1]["qmax"] = json!(-3.0);
    let (status, refused) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": broken, "name": "puma.toml", "overwrite": true }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{refused}");
    assert_eq!(std::fs::read_to_string(&path).expect("kept"), written);
    // Outside the folder, hidden, or not a robot file: 403.
    for name in [
        "../escape.toml",
        "/tmp/escape.toml",
        ".hidden.toml",
        "robot.txt",
        "a/../../x.toml",
    ] {
        let (status, body) = api.post("/api/robots/save", &save(name, true)).await;
        assert_eq!(status, StatusCode::FORBIDDEN, "{name}: {body}");
    }
    assert!(
        !api.folder
            .path()
            .parent()
            .expect("parent")
            .join("escape.toml")
            .exists()
    );

    // Listed, and opened back to the same document.
    let (_, files) = api.get("/api/files").await;
    assert_eq!(files["robots"], json!(["puma.toml"]));
    let (status, opened) = api.get("/api/robots/file?name=puma.toml").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(opened["origin"], "file");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    let (status, _) = api.get("/api/robots/file?name=../etc/passwd.toml").await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let (status, _) = api.get("/api/robots/file?name=nothing.toml").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _) = api.get("/api/robots/file").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);

    // A file with a TOML mistake: 422 naming the line.
    std::fs::write(
        api.folder.path().join("bad.toml"),
        "name = \"x\"\n[[frame]]\nsigma = \n",
    )
    .expect("write");
    let (status, bad) = api.get("/api/robots/file?name=bad.toml").await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&bad).contains("bad.toml:3"), "{bad}");
}

/// The listing names each data file's columns (from its header, past its
/// comment lines and in its own separator), so that a method's menu lists
/// the files it can read; a file with no complete header line has none.
#[tokio::test]
async fn data_files_are_listed_with_their_columns() {
    let api = Api::new();
    let folder = api.folder.path();
    std::fs::write(
        folder.join("positions.csv"),
        "# gecaro generate: stanford\nqm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0,0,0,0,1,2,3\n",
    )
    .expect("write");
    std::fs::write(
        folder.join("tracker.csv"),
        "\u{feff}\"time\";\"A1\";\"X_mm\"\n0;0,1;12,5\n",
    )
    .expect("write");
    std::fs::write(folder.join("empty.csv"), "# nothing but a comment\n").expect("write");
    let (status, files) = api.get("/api/files").await;
    assert_eq!(status, StatusCode::OK, "{files}");
    assert_eq!(
        files["data"],
        json!(["empty.csv", "positions.csv", "tracker.csv"])
    );
    assert_eq!(
        files["data_columns"],
        json!({
            "positions.csv": ["qm1", "qm2", "qm3", "qm4", "qm5", "qm6", "x", "y", "z"],
            "tracker.csv": ["time", "A1", "X_mm"],
        })
    );
}

#[tokio::test]
async fn urdf_dh_and_symoro_files_open_converted_and_robots_save_as_urdf() {
    let api = Api::new();
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data");
    for (from, to) in [
        ("urdf/kuka_kr16_2.urdf", "kr16.urdf"),
        ("urdf/panda.urdf", "panda.urdf"),
        ("robots/stanford.par", "stanford.par"),
        ("robots/puma560_mdh.toml", "puma-table.toml"),
    ] {
        std::fs::copy(data.join(from), api.folder.path().join(to)).expect("copy");
    }
    let (_, files) = api.get("/api/files").await;
    assert_eq!(
        files["imports"],
        json!(["kr16.urdf", "panda.urdf", "stanford.par"])
    );
    assert_eq!(files["robots"], json!(["puma-table.toml"]));

    // Converted, shown in the table, with what the conversion did.
    let (status, kuka) = api.get("/api/robots/file?name=kr16.urdf").await;
    assert_eq!(status, StatusCode::OK, "{kuka}");
    assert_eq!(kuka["origin"], "imported");
    assert_eq!(kuka["summary"]["letters"], "RRRRRR");
    assert!(
        kuka["notes"][0].as_str().expect("note").contains("folded"),
        "{kuka}"
    );
    for (name, letters) in [("stanford.par", "RRPRRR"), ("puma-table.toml", "RRRRRR")] {
        let (status, opened) = api.get(&format!("/api/robots/file?name={name}")).await;
        assert_eq!(status, StatusCode::OK, "{name}: {opened}");
        assert_eq!(opened["summary"]["letters"], letters);
    }
    // A branching URDF: the error names the leaves; a tip resolves it.
    let (status, branching) = api.get("/api/robots/file?name=panda.urdf").await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(
        error_text(&branching).contains("choose the tip link"),
        "{branching}"
    );
    let (status, panda) = api
        .get("/api/robots/file?name=panda.urdf&tip=ball_link")
        .await;
    assert_eq!(status, StatusCode::OK, "{panda}");
    assert_eq!(panda["summary"]["letters"], "RRRRRRR");

    // Save as URDF: the original names come back; a gain goes beside it.
    let mut document = kuka["document"].clone();
    let (status, saved) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "out.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert!(saved.get("joint_calibration").is_none());
    let text = std::fs::read_to_string(api.folder.path().join("out.urdf")).expect("written");
    assert!(
        text.contains("name=\"joint_a6-tool0\"") && text.contains("name=\"link_3\""),
        "{text}"
    );
    document["frame"][2]["K"] = json!(1.002);
    let (status, saved) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_eq!(saved["joint_calibration"], "geared.joint_calibration.yaml");
    assert!(
        api.folder
            .path()
            .join("geared.joint_calibration.yaml")
            .is_file()
    );
    let (status, _) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(
        status,
        StatusCode::CONFLICT,
        "an existing URDF is kept without overwrite"
    );
    // Neither file is written when one of the two exists.
    std::fs::remove_file(api.folder.path().join("geared.joint_calibration.yaml")).expect("remove");
    let (status, _) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert!(
        !api.folder
            .path()
            .join("geared.joint_calibration.yaml")
            .exists()
    );
    // Issue 35 §1: a URDF that is a link or a folder, saved over with
    // overwrite, is refused before anything is written: the joint
    // calibration that was there stays as it was.
    let kept = "joints: [\"kept\"]\n";
    for (target, expected) in [
        ("linked", StatusCode::FORBIDDEN),
        ("folder", StatusCode::CONFLICT),
    ] {
        let urdf = api.folder.path().join(format!("{target}.urdf"));
        if target == "linked" {
            #[cfg(unix)]
            std::os::unix::fs::symlink(api.folder.path().join("out.urdf"), &urdf).expect("link");
        } else {
            std::fs::create_dir(&urdf).expect("folder");
        }
        let calibration = api
            .folder
            .path()
            .join(format!("{target}.joint_calibration.yaml"));
        std::fs::write(&calibration, kept).expect("calibration");
        let (status, body) = api
            .post(
                "/api/robots/save",
                &json!({ "robot": document, "name": format!("{target}.urdf"), "overwrite": true }),
            )
            .await;
        assert_eq!(status, expected, "{target}: {body}");
        assert_eq!(
            std::fs::read_to_string(&calibration).expect("still there"),
            kept,
            "{target}: the calibration beside it is untouched"
        );
    }
}

#[tokio::test]
async fn poses_give_every_frame() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (status, pose) = api
        .post(
            "/api/robots/pose",
            &json!({ "robot": document, "q": [0.0, 0.0, 0.5, 0.0, 0.0, 0.0] }),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    let frames = pose["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), 8);
    // Matches the direct geometric model of the library (and the CLI's fk test).
    let tool = &frames[7]["origin"];
    let expected = [-0.0505392, 0.2, 1.0344655];
    for (axis, want) in expected.iter().enumerate() {
        assert!(
            (tool[axis].as_f64().expect("number") - want).abs() < 1e-7,
            "{tool}"
        );
    }
    let (status, wrong) = api
        .post(
            "/api/robots/pose",
            &json!({ "robot": document, "q": [0.0] }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&wrong).contains("6 motor values"));
}

#[tokio::test]
async fn identifiable_parameters_match_table_2() {
    let api = Api::new();
    let document = api.document("stanford").await;
    for (method, expected) in [("position", 31), ("frame", 34), ("distance", 25)] {
        let (status, report) = api
            .post(
                "/api/identifiable",
                &json!({ "robot": document, "method": { "name": method } }),
            )
            .await;
        assert_eq!(status, StatusCode::OK, "{report}");
        assert_eq!(report["count"], expected, "{method}");
        assert_eq!(
            report["parameters"].as_array().expect("parameters").len(),
            43
        );
    }
    let (status, plane) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "plane2", "plane_normal": [0.3, 0.5, 0.81], "plane_point": [0.3, 0.2, 0.6] } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{plane}");
    assert!(
        plane["regrouping"]
            .as_array()
            .is_some_and(|r| !r.is_empty())
    );
}

#[tokio::test]
async fn generation_is_reproducible_and_saves_into_the_folder() {
    let api = Api::new();
    let document = api.document("scara").await;
    let request = json!({
        "robot": document,
        "method": { "name": "position" },
        "count": 12,
        "error_level": 2.0,
        "noise": 1e-5,
        "seed": 7,
    });
    let (status, first) = api.post("/api/generate", &request).await;
    assert_eq!(status, StatusCode::OK, "{first}");
    let (_, second) = api.post("/api/generate", &request).await;
    assert_eq!(first["csv"], second["csv"], "same seed, same data");
    let csv = first["csv"].as_str().expect("csv");
    // The file says where its data came from, then the header and the rows.
    assert!(
        csv.starts_with("# gecaro generate: 12 position measurements of a real robot drawn from"),
        "{csv}"
    );
    assert_eq!(data_lines(csv).count(), 13);
    assert!(csv.contains("\nqm1,qm2,qm3,qm4,x,y,z\n"));
    assert!(first["displacement_rms"].as_f64().expect("rms") > 1e-3);
    assert_eq!(first["real"]["frame"].as_array().expect("frames").len(), 6);

    let mut saving = request.clone();
    saving["save_as"] = json!("scara.csv");
    let (status, saved) = api.post("/api/generate", &saving).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(saved["saved"], "scara.csv");
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("scara.csv")).expect("file"),
        csv
    );
    let (status, _) = api.post("/api/generate", &saving).await;
    assert_eq!(status, StatusCode::CONFLICT);

    for (field, value, status) in [
        ("count", json!(0), StatusCode::BAD_REQUEST),
        ("count", json!(10_000_000), StatusCode::BAD_REQUEST),
        ("noise", json!(-1.0), StatusCode::BAD_REQUEST),
        ("count", json!("many"), StatusCode::BAD_REQUEST),
    ] {
        let mut bad = request.clone();
        bad[field] = value.clone();
        let (got, body) = api.post("/api/generate", &bad).await;
        assert_eq!(got, status, "{field} = {value}: {body}");
    }
}

#[tokio::test]
async fn plan_chooses_configurations_draws_the_curve_and_refuses_bad_requests() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let request = json!({
        "robot": document,
        "method": { "name": "distance" },
        "count": 60,
        "criterion": "o5",
        "pool": 400,
        "curve": [60, 120],
        "save_as": "planned.csv",
    });
    let job = api.job("/api/plan", &request).await.expect("started");
    assert_eq!(job["state"], "done", "{job}");
    // Its progress named the last part and its steps, all done.
    assert_eq!(job["phase"], "choosing the configurations", "{job}");
    assert_eq!(job["steps"]["done"], job["steps"]["total"], "{job}");
    let planned = &job["result"];
    assert_eq!(planned["configurations"], 60);
    assert_eq!(planned["units"], 30);
    assert_eq!(planned["criterion"], "o5");
    assert!(
        planned["value"].as_f64().expect("value")
            > planned["random_value"].as_f64().expect("random")
    );
    let csv = planned["csv"].as_str().expect("csv");
    assert!(csv.starts_with("qm1,qm2,qm3,qm4,qm5,qm6,pair\n"), "{csv}");
    assert_eq!(csv.lines().count(), 61);
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("planned.csv")).expect("saved"),
        csv
    );
    let points = planned["curve"]["points"].as_array().expect("points");
    assert_eq!(points.len(), 2);
    let value = |point: &serde_json::Value, key: &str| point[key].as_f64().expect(key);
    assert!(value(&points[1], "planned") < value(&points[0], "planned"));
    assert!(
        points
            .iter()
            .all(|p| value(p, "planned") < value(p, "random"))
    );
    assert!(
        planned["curve"]["svg"]
            .as_str()
            .expect("svg")
            .starts_with("<svg")
    );
    // The same request again would overwrite: refused.
    let (status, _) = api.post("/api/plan", &request).await;
    assert_eq!(status, StatusCode::CONFLICT);
    for (field, value) in [
        ("count", json!(0)),
        ("pool", json!(10_000_000)),
        ("criterion", json!("z")),
        ("curve", json!([0, 10])),
        ("curve", json!([10, 1_000_000_000])),
        ("noise", json!(-1.0)),
        ("noise", json!(1e308)),
    ] {
        let mut bad = request.clone();
        bad[field] = value.clone();
        bad["save_as"] = json!(null);
        let (got, body) = api.post("/api/plan", &bad).await;
        assert_eq!(got, StatusCode::BAD_REQUEST, "{field} = {value}: {body}");
    }
    // More than the pool holds: found by the work, the failed job says so.
    let mut too_many = request.clone();
    too_many["count"] = json!(1000);
    too_many["curve"] = json!([]);
    too_many["save_as"] = json!(null);
    let job = api.job("/api/plan", &too_many).await.expect("started");
    assert_eq!(job["state"], "failed", "{job}");
    assert!(
        job["error"].as_str().is_some_and(|e| e.contains("pool")),
        "{job}"
    );
    // A plan has no report.
    let (status, body) = api.get(&format!("/api/jobs/{}/report", job["id"])).await;
    assert!(status.is_client_error(), "{status}: {body}");
}

/// Issue 37 §3: a length unit mistaken is named before any fitting, on the
/// page as on the command line — not a fit that diverges.
#[tokio::test]
async fn a_unit_mistake_is_named_before_fitting() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 30, "seed": 4 }),
        )
        .await;
    let csv = generated["csv"].as_str().expect("csv");
    // Metre data declared in millimetres.
    let view = api
        .job(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" },
                     "data": { "csv": { "text": csv, "name": "gen.csv" } },
                     "format": { "length_unit": "mm" } }),
        )
        .await
        .expect("started");
    assert_eq!(view["state"], "failed", "{view}");
    let error = view["error"].as_str().expect("error");
    assert!(
        error.contains("gen.csv") && error.contains("Metres read as millimetres?"),
        "{error}"
    );
    assert!(
        view["history"].as_array().expect("history").is_empty(),
        "no iteration ran"
    );
}

#[tokio::test]
async fn identification_runs_as_a_job_with_progress_plots_and_report() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 40, "error_level": 2.0, "seed": 3 }),
        )
        .await;
    let csv = generated["csv"].as_str().expect("csv");
    let (status, submitted) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": csv, "name": "gen.csv" } } }),
        )
        .await;
    assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
    let job = submitted["job"].as_u64().expect("job number");
    let view = api.finished(job).await;
    assert_eq!(view["state"], "done", "{view}");
    let result = &view["result"];
    let identification = &result["identification"];
    assert_eq!(identification["converged"], true);
    assert_eq!(
        identification["parameters"]
            .as_array()
            .expect("parameters")
            .len(),
        31
    );
    assert!(identification["rms_after"].as_f64().expect("rms") < 1e-9);
    assert_eq!(
        view["history"].as_array().expect("history").len(),
        identification["rms_history"]
            .as_array()
            .expect("history")
            .len()
    );
    for plot in [
        "convergence",
        "errors_histogram",
        "errors_per_configuration",
    ] {
        assert!(
            result["plots"][plot]
                .as_str()
                .expect("svg")
                .starts_with("<svg"),
            "{plot}"
        );
    }
    // No σ stated: the convergence plot's axis is in millimetres.
    assert!(
        result["plots"]["convergence"]
            .as_str()
            .expect("svg")
            .contains("residual RMS (mm"),
    );
    // The calibrated robot is a valid document that predicts the data.
    let (status, checked) = api
        .post(
            "/api/robots/check",
            &json!({ "robot": result["calibrated"] }),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(checked["problems"], json!([]));
    assert_eq!(result["calibrated_name"], "stanford-calibrated.toml");

    let html = api
        .download(&format!("/api/jobs/{job}/report"), "text/html")
        .await;
    assert!(html.contains("<h2>Convergence</h2>") && html.contains("gen.csv"));
    // Each dot of the per-configuration plot names its file line (on hover).
    let per_configuration = result["plots"]["errors_per_configuration"]
        .as_str()
        .expect("svg");
    assert!(
        per_configuration.contains("<title>gen.csv: configuration 1 (line 3): before "),
        "{}",
        &per_configuration[..per_configuration.len().min(3000)]
    );

    // The residuals, one row per configuration with its line, as a CSV file
    // whose "after" errors are the identification's.
    let text = api
        .download(&format!("/api/jobs/{job}/residuals.csv"), "text/csv")
        .await;
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let header = rows.headers().expect("header").clone();
    assert_eq!(&header[4], "lines");
    let records: Vec<csv::StringRecord> = rows.records().map(|r| r.expect("row")).collect();
    assert_eq!(records.len(), 40);
    assert_eq!(&records[0][1], "gen.csv");
    assert_eq!(&records[0][4], "3", "the first configuration is on line 3");
    let largest_after = records
        .iter()
        .map(|r| r[6].parse::<f64>().expect("number"))
        .fold(0.0, f64::max);
    let reported = identification["after"]["max"].as_f64().expect("max") * 1e3;
    assert!(
        (largest_after - reported).abs() <= 1e-9 * reported.max(1e-12),
        "{largest_after} vs {reported}"
    );

    let (status, _) = api.get("/api/jobs/999999").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _) = api.get("/api/jobs/abc").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
}

/// The Evaluate function: the table's robot and the calibrated one on the
/// same held-out file, in the tracker's own units and column names.
#[tokio::test]
async fn evaluation_compares_two_robots_on_held_out_data() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (training, calibrated) = api.calibrated(&document).await;
    // The same real robot, the same configurations (seed 3 again).
    let (_, held_out) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 40, "error_level": 1.0, "seed": 3 }),
        )
        .await;
    assert_eq!(held_out["csv"], training["csv"]);
    // The held-out file as a tracker writes it: millimetres, other names, `;`.
    let csv = held_out["csv"].as_str().expect("csv");
    let mut lines = data_lines(csv);
    let header = lines
        .next()
        .expect("header")
        .replace("x", "X_mm")
        .replace("y", "Y_mm")
        .replace("z", "Z_mm");
    let mut text = header.replace(',', ";") + "\n";
    for line in lines {
        let fields: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(index, field)| {
                let value: f64 = field.parse().expect("number");
                // Positions and the prismatic joint 3 in millimetres.
                if index >= 6 || index == 2 {
                    (value * 1e3).to_string()
                } else {
                    value.to_string()
                }
            })
            .collect();
        text += &(fields.join(";") + "\n");
    }
    let request = json!({
        "robot": document,
        "compared": calibrated,
        "method": { "name": "position" },
        "data": { "csv": { "text": text, "name": "check.csv" } },
        "format": { "length_unit": "mm", "columns": "x=X_mm,y=Y_mm,z=Z_mm" },
    });
    let (status, evaluated) = api.post("/api/evaluate", &request).await;
    assert_eq!(status, StatusCode::OK, "{evaluated}");
    let nominal = evaluated["errors"]["rms"].as_f64().expect("rms");
    let after = evaluated["compared"]["rms"].as_f64().expect("rms");
    assert!(
        nominal > 1e-3 && after < 1e-9,
        "nominal {nominal}, calibrated {after}"
    );
    for plot in ["errors_histogram", "errors_per_configuration"] {
        assert!(
            evaluated["plots"][plot]
                .as_str()
                .expect("svg")
                .starts_with("<svg")
        );
    }
    // Without the column names, the file is refused with its own words.
    let mut bad = request.clone();
    bad["format"] = json!({ "length_unit": "mm" });
    let (status, body) = api.post("/api/evaluate", &bad).await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("missing column `x`"), "{body}");
}

#[tokio::test]
async fn a_program_is_compensated_target_by_target_and_saved_beside_it() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (training, calibrated) = api.calibrated(&document).await;
    // A controller's program: named points, joints in degrees (the
    // prismatic joint 3 in metres), a speed column, from the training poses.
    let csv = training["csv"].as_str().expect("csv");
    let mut text = String::from("point,qm1,qm2,qm3,qm4,qm5,qm6,speed\n");
    for (i, line) in data_lines(csv).skip(1).take(12).enumerate() {
        let q: Vec<f64> = line
            .split(',')
            .take(6)
            .map(|v| v.parse().expect("number"))
            .collect();
        let degrees: Vec<String> = q
            .iter()
            .enumerate()
            .map(|(j, v)| {
                if j == 2 {
                    v.to_string()
                } else {
                    v.to_degrees().to_string()
                }
            })
            .collect();
        text += &format!("P{i},{},250\n", degrees.join(","));
    }
    let request = json!({
        "nominal": document,
        "calibrated": calibrated,
        "program": { "csv": { "text": text, "name": "weld.csv" } },
        "format": { "angle_unit": "deg" },
        "match": "position",
        "save_as": "weld-compensated.csv",
    });
    let (status, compensated) = api.post("/api/compensate", &request).await;
    assert_eq!(status, StatusCode::OK, "{compensated}");
    assert_eq!(compensated["targets"], 12);
    assert_eq!(compensated["reached"], 12, "{compensated}");
    assert_eq!(compensated["points"].as_array().expect("points").len(), 12);
    assert_eq!(compensated["points"][0]["line"], 2, "lines of the file");
    assert_eq!(compensated["file_name"], "weld-compensated.csv");
    assert_eq!(
        compensated["output"], "weld-compensated.csv",
        "the name in the folder"
    );
    // The corrected file keeps the program's columns and units, corrected.
    let corrected = compensated["csv"].as_str().expect("csv");
    assert_eq!(corrected.lines().count(), 13);
    assert!(
        corrected
            .lines()
            .next()
            .expect("header")
            .starts_with("point,")
    );
    let row = corrected.lines().nth(1).expect("row");
    assert!(
        row.starts_with("P0,") && row.contains(",250"),
        "{corrected}"
    );
    assert!(
        compensated["largest_correction"]
            .as_f64()
            .expect("correction")
            > 0.0
    );
    assert!(api.names().contains(&"weld-compensated.csv".to_owned()));
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("weld-compensated.csv")).expect("saved"),
        corrected
    );
    // Saved once: the same name again is refused, nothing overwritten.
    let (status, body) = api.post("/api/compensate", &request).await;
    assert!(status.is_client_error(), "{body}");
    // A Cartesian target 5 m away is flagged, never dropped.
    let cartesian = json!({
        "nominal": document,
        "calibrated": calibrated,
        "program": { "csv": { "text": "x,y,z\n0.5,0.2,0.3\n5,0,0\n", "name": "points.csv" } },
    });
    let (status, flagged) = api.post("/api/compensate", &cartesian).await;
    assert_eq!(status, StatusCode::OK, "{flagged}");
    // (The Stanford's prismatic joint reaches it, 4.9 m out: beyond its limit.)
    assert_eq!(flagged["reached"], 1, "{flagged}");
    assert_eq!(flagged["outside_limits"], json!([3]), "{flagged}");
    // Without a calibrated robot the request is refused by its field.
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "program": { "csv": { "text": text } } }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("calibrated"), "{body}");
    // The position match says how far it turned the tool.
    assert!(
        compensated["largest_tool_turn"].as_f64().is_some() && compensated["turned"].is_array(),
        "{compensated}"
    );
    // A robot calibrated by a reflector study: frame n+1 was not observed,
    // so the program is compensated for a reflector it names, not tool0.
    let mut reflected = calibrated.clone();
    reflected["tool_frame_observed"] = json!(false);
    reflected["tools"] = json!({ "smr_a": { "position": [0.0, 0.0, 0.1] } });
    let program = json!({ "csv": { "text": text, "name": "weld.csv" } });
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": reflected, "program": program,
                     "format": { "angle_unit": "deg" }, "match": "position" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(
        error_text(&body).contains("is not calibrated") && error_text(&body).contains("smr_a"),
        "{body}"
    );
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": reflected, "program": program,
                     "format": { "angle_unit": "deg" }, "match": "position",
                     "tool": "smr_a", "max_tool_turn": "180deg" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(body["reached"], 12, "{body}");
    // The owner's base by four plate points (here where the nominal's is),
    // an upload in mm with `;` and decimal commas: the registration is
    // stated with the result.
    let plate = "name;x;y;z;base_x;base_y;base_z\nH1;250;250;0;250;250;0\n\
                 H2;-250;250;0,01;-250;250;0\nH3;-250;-250;0;-250;-250;0\nH4;250;-250;0;250;-250;0\n";
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_points": { "csv": { "text": plate, "name": "plate.csv" } },
                     "base_points_format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let registration = &body["registration"];
    assert_eq!(registration["points"][1]["name"], "H2", "{body}");
    assert!(
        registration["max"].as_f64().expect("m") < 1e-5,
        "{registration}"
    );
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_points": { "csv": { "text": "x;y;z;base_x;base_y;base_z\n2500;0;0;0;0;0\n", "name": "plate.csv" } } }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("plate.csv:2"), "{body}");
    // The maker's base by the circles of joints 1 and 2, the points where
    // the calibrated robot puts them (its axes as the table's robot puts
    // them: nothing to move), uploaded in mm.
    let start = [0.0, 0.4, 0.5, 0.3, -0.6, 0.2];
    let mut circles = String::from("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n");
    let turned: Vec<(usize, f64)> = (-4..=4)
        .map(|k| (0, f64::from(k) * 0.3))
        .chain((-4..=3).map(|k| (1, 0.4 + f64::from(k) * 0.15)))
        .collect();
    for (joint, value) in turned {
        let mut q = start;
        q[joint] = value;
        if joint == 1 {
            q[0] = 0.25;
        }
        let (status, pose) = api
            .post("/api/robots/pose", &json!({ "robot": document, "q": q }))
            .await;
        assert_eq!(status, StatusCode::OK, "{pose}");
        let frames = pose["frames"].as_array().expect("frames");
        let tool = &frames[frames.len() - 1]["origin"];
        let mm = |axis: usize| tool[axis].as_f64().expect("number") * 1e3;
        let joints: Vec<String> = q.iter().map(f64::to_string).collect();
        circles += &format!("{},{},{},{}\n", joints.join(","), mm(0), mm(1), mm(2));
    }
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": document, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_circles": { "csv": { "text": circles, "name": "circles.csv" } },
                     "base_points_format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let registration = &body["registration"];
    assert_eq!(registration["by"], "circles", "{body}");
    assert_eq!(registration["points"][0]["name"], "joint 1", "{body}");
    assert!(
        registration["max"].as_f64().expect("m") < 1e-6,
        "{registration}"
    );
    // The base by its points or by the convention, not both.
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" }, "rebase": true,
                     "base_points": { "csv": { "text": plate, "name": "plate.csv" } } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("give one of them"), "{body}");
}

/// A 7-joint arm's data with a 6-joint robot: refused, not run with the
/// seventh joint ignored.
#[tokio::test]
async fn another_robots_data_are_refused() {
    let api = Api::new();
    let panda = api.document("panda").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": panda, "method": { "name": "position" }, "count": 20, "seed": 1 }),
        )
        .await;
    let stanford = api.document("stanford").await;
    let (status, body) = api
        .post(
            "/api/identify",
            &json!({ "robot": stanford, "method": { "name": "position" }, "data": { "csv": { "text": generated["csv"], "name": "panda.csv" } } }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(
        error_text(&body).contains("`qm7`, and the robot has 6 joints"),
        "{body}"
    );
}

/// A cancelled job stops and says so; cancelling a finished one changes nothing.
#[tokio::test]
async fn jobs_can_be_cancelled() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 3000, "error_level": 1.0, "seed": 2 }),
        )
        .await;
    // Twenty folds of cross-validation on 3000 configurations: long enough.
    let (_, submitted) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" }, "cv": 20, "data": { "csv": { "text": generated["csv"], "name": "long.csv" } } }),
        )
        .await;
    let job = submitted["job"].as_u64().expect("job");
    let (status, view) = api
        .post(&format!("/api/jobs/{job}/cancel"), &json!({}))
        .await;
    assert_eq!(status, StatusCode::OK, "{view}");
    let view = api.finished(job).await;
    assert_eq!(view["state"], "cancelled", "{view}");
    let (status, _) = api.get(&format!("/api/jobs/{job}/report")).await;
    assert_eq!(status, StatusCode::CONFLICT);
    // A finished job stays finished.
    let (_, small) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": generated["csv"], "name": "long.csv" } } }),
        )
        .await;
    let small = small["job"].as_u64().expect("job");
    assert_eq!(api.finished(small).await["state"], "done");
    let (_, view) = api
        .post(&format!("/api/jobs/{small}/cancel"), &json!({}))
        .await;
    assert_eq!(view["state"], "done");
    let (status, _) = api.post("/api/jobs/999999/cancel", &json!({})).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

/// No job is lost under load (issue 75: 802 of 1,000 jobs answered 404 to
/// the client that started them): 12 clients submit 5 identifications
/// each, cancel every third, poll every 20 ms until it ends, then fetch
/// the report; a 503 (every kept job still owed to its client) is retried.
/// Every client finds its every job until it has seen it end.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn no_job_is_lost_under_load() {
    let api = std::sync::Arc::new(Api::new());
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 30, "error_level": 1.0, "seed": 4 }),
        )
        .await;
    let request = json!({ "robot": document, "method": { "name": "position" },
                          "data": { "csv": { "text": generated["csv"], "name": "small.csv" } } });
    let mut clients = Vec::new();
    for client in 0..12u64 {
        let (api, request) = (std::sync::Arc::clone(&api), request.clone());
        clients.push(tokio::spawn(async move {
            let mut seen = Vec::new();
            for round in 0..5u64 {
                let mut tries = 0;
                let job = loop {
                    let (status, submitted) = api.post("/api/identify", &request).await;
                    if status == StatusCode::ACCEPTED {
                        break submitted["job"].as_u64().expect("job");
                    }
                    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{submitted}");
                    tries += 1;
                    assert!(tries < 2000, "never admitted");
                    tokio::time::sleep(Duration::from_millis(20)).await;
                };
                if (client + round) % 3 == 0 {
                    api.post(&format!("/api/jobs/{job}/cancel"), &json!({}))
                        .await;
                }
                let state = loop {
                    let (status, view) = api.get(&format!("/api/jobs/{job}")).await;
                    assert_eq!(
                        status,
                        StatusCode::OK,
                        "client {client}: job {job} lost: {view}"
                    );
                    let state = view["state"].as_str().expect("state").to_owned();
                    if state != "queued" && state != "running" {
                        break state;
                    }
                    tokio::time::sleep(Duration::from_millis(20)).await;
                };
                if state == "done" {
                    let (status, _) = api.get(&format!("/api/jobs/{job}/report")).await;
                    assert_eq!(status, StatusCode::OK, "client {client}: report of {job}");
                }
                seen.push(state);
            }
            seen
        }));
    }
    let mut ended = 0;
    for client in clients {
        ended += client.await.expect("client").len();
    }
    assert_eq!(ended, 60);
}

#[tokio::test]
async fn bad_data_is_an_answer_not_a_failed_job() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let identify =
        |data: Value| json!({ "robot": document, "method": { "name": "position" }, "data": data });
    let cases = [
        (json!({ "csv": { "text": "qm1,qm2\n1,2\n" } }), "qm3"),
        (
            json!({ "csv": { "text": "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0.5,0,0,0,1,2,nan\n" } }),
            "uploaded data:2: z",
        ),
        (json!({ "file": "missing.csv" }), "no file"),
    ];
    for (data, expected) in cases {
        let (status, body) = api.post("/api/identify", &identify(data.clone())).await;
        assert!(status.is_client_error(), "{data}: {status} {body}");
        assert!(error_text(&body).contains(expected), "{data}: {body}");
    }
    let (status, body) = api
        .post("/api/identify", &identify(json!({ "file": "../x.csv" })))
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{body}");
    // Well-formed but too few: found by the identification itself, a failed job.
    let one = json!({ "csv": { "text": "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0.5,0,0,0,1,2,3\n" } });
    let (status, submitted) = api.post("/api/identify", &identify(one)).await;
    assert_eq!(status, StatusCode::ACCEPTED);
    let view = api.finished(submitted["job"].as_u64().expect("job")).await;
    assert_eq!(view["state"], "failed");
    assert!(
        view["error"]
            .as_str()
            .expect("error")
            .contains("too few equations"),
        "{view}"
    );
    let (status, _) = api
        .get(&format!("/api/jobs/{}/report", submitted["job"]))
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
}

#[tokio::test]
async fn malformed_requests_get_4xx_with_a_message() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (status, body) = api.post_raw("/api/identifiable", "{not json".into()).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(!error_text(&body).is_empty());
    let (status, body) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "laser" } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&body).contains("position"), "{body}");
    let (status, body) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "position" }, "colour": 1 }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&body).contains("colour"), "{body}");
    let (status, body) = api
        .post("/api/identifiable", &json!({ "robot": document, "method": { "name": "plane1", "plane_normal": [0, 0, 0], "plane_point": [0, 0, 0] } }))
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    // Without a JSON content type.
    let request = Request::post("/api/robots/check")
        .body(Body::from("{}"))
        .expect("request");
    let (status, _, _) = api.send(request).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    // Too large.
    let huge = format!(
        "{{\"robot\": {{\"name\": \"{}\"}}}}",
        "x".repeat(gecaro_web::limits::MAX_BODY_BYTES + 10)
    );
    let (status, body) = api.post_raw("/api/robots/check", huge).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{body}");
    // Too many joints.
    let mut long = document.clone();
    let joint = long["frame"][1].clone();
    let frames = long["frame"].as_array_mut().expect("frames");
    for _ in 0..40 {
        frames.insert(1, joint.clone());
    }
    let (status, body) = api
        .post("/api/robots/pose", &json!({ "robot": long, "q": [] }))
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&body).contains("32 joints"), "{body}");
}

#[tokio::test]
async fn garbage_never_gets_a_server_error() {
    let api = Api::new();
    let document = api.document("stanford").await;
    // The list is the router's: every route exists (else the checks below
    // would pass on 404s).
    for route in POST_ROUTES {
        let (status, answer) = api.post(route, &json!({})).await;
        assert!(
            status != StatusCode::NOT_FOUND && status != StatusCode::METHOD_NOT_ALLOWED,
            "{route}: {status} {answer}"
        );
    }
    let bodies = [
        json!(null),
        json!([]),
        json!({}),
        json!({ "robot": null }),
        json!({ "robot": {} }),
        json!({ "robot": { "frame": [] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }, { "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": -1 }, { "sigma": 0 }, { "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }, { "sigma": 0, "qmin": 1e308, "qmax": -1e308 }, { "sigma": 2 }] } }),
        json!({ "robot": document, "q": [1e308, -1e308, 1e300, 0, 0, 0] }),
        json!({ "robot": document, "method": { "name": "position" }, "count": 1 }),
        json!({ "robot": document, "method": { "name": "plane1" }, "count": 3 }),
        json!({ "robot": document, "method": { "name": "point-link", "set_size": 1 }, "count": 3 }),
        json!({ "robot": document, "method": { "name": "distance" }, "data": { "csv": { "text": "" } } }),
        json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": "\u{0}\u{1}" } } }),
        json!({ "robot": document, "name": "", "joints": "" }),
        json!({ "robot": document, "name": "x".repeat(5000), "overwrite": true }),
        json!({ "joints": "R".repeat(100) }),
    ];
    for route in POST_ROUTES {
        for body in &bodies {
            let (status, answer) = api.post(route, body).await;
            assert!(
                status.is_success() || status.is_client_error(),
                "{route} {body}: {status} {answer}"
            );
            if !status.is_success() {
                assert!(!error_text(&answer).is_empty());
            }
        }
    }
}

#[tokio::test]
async fn requests_for_other_hosts_and_cross_site_writes_are_refused() {
    let api = Api::with_hosts(vec!["127.0.0.1:8080".into(), "localhost:8080".into()]);
    let get = |host: &str| {
        Request::get("/api/info")
            .header(header::HOST, host)
            .body(Body::empty())
            .expect("request")
    };
    assert_eq!(api.send(get("127.0.0.1:8080")).await.0, StatusCode::OK);
    assert_eq!(api.send(get("localhost:8080")).await.0, StatusCode::OK);
    assert_eq!(
        api.send(get("attacker.example:8080")).await.0,
        StatusCode::FORBIDDEN
    );
    // Host names are case-insensitive.
    assert_eq!(api.send(get("LOCALHOST:8080")).await.0, StatusCode::OK);
    // A second Host header is not a way in.
    let doubled = Request::get("/api/info")
        .header(header::HOST, "127.0.0.1:8080")
        .header(header::HOST, "evil.example")
        .body(Body::empty())
        .expect("request");
    assert_eq!(api.send(doubled).await.0, StatusCode::BAD_REQUEST);
    let new = |origin: &str| {
        Request::post("/api/robots/new")
            .header(header::HOST, "127.0.0.1:8080")
            .header(header::ORIGIN, origin)
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(r#"{"joints": "RR"}"#))
            .expect("request")
    };
    assert_eq!(
        api.send(new("http://127.0.0.1:8080")).await.0,
        StatusCode::OK
    );
    assert_eq!(
        api.send(new("https://attacker.example")).await.0,
        StatusCode::FORBIDDEN
    );
    // Nor a second Origin header behind an allowed one.
    let doubled = Request::post("/api/robots/new")
        .header(header::HOST, "127.0.0.1:8080")
        .header(header::ORIGIN, "http://127.0.0.1:8080")
        .header(header::ORIGIN, "https://attacker.example")
        .header(header::CONTENT_TYPE, "application/json")
        .body(Body::from(r#"{"joints": "RR"}"#))
        .expect("request");
    assert_eq!(api.send(doubled).await.0, StatusCode::BAD_REQUEST);
}

#[tokio::test]
async fn a_stalled_request_times_out_with_a_message() {
    let folder = tempfile::tempdir().expect("folder");
    let state = AppState::new(
        Workspace::new(folder.path()).expect("workspace"),
        Vec::new(),
    )
    .with_request_timeout(Duration::from_millis(200));
    let app = router(state);
    // A body that never finishes arriving.
    let stalled = futures_util::stream::pending::<Result<bytes::Bytes, std::io::Error>>();
    let request = Request::post("/api/robots/check")
        .header(header::CONTENT_TYPE, "application/json")
        .body(Body::from_stream(stalled))
        .expect("request");
    let response = app.oneshot(request).await.expect("infallible");
    assert_eq!(response.status(), StatusCode::REQUEST_TIMEOUT);
    let bytes = response
        .into_body()
        .collect()
        .await
        .expect("body")
        .to_bytes();
    let body: Value = serde_json::from_slice(&bytes).expect("JSON");
    assert!(error_text(&body).contains("longer than 0.2 s"), "{body}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn parallel_saves_of_one_file_never_corrupt_it() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let puma = api.document("puma560").await;
    let mut saves = Vec::new();
    for index in 0..40 {
        let robot = if index % 2 == 0 {
            stanford.clone()
        } else {
            puma.clone()
        };
        let app = api.app.clone();
        saves.push(tokio::spawn(async move {
            let body = json!({ "robot": robot, "name": "shared.toml", "overwrite": true });
            let request = Request::post("/api/robots/save")
                .header(header::CONTENT_TYPE, "application/json")
                .body(Body::from(body.to_string()))
                .expect("request");
            app.oneshot(request).await.expect("infallible").status()
        }));
    }
    for save in saves {
        assert_eq!(save.await.expect("task"), StatusCode::OK);
    }
    // One of the two robots, whole; no temporary file left behind.
    let path = api.folder.path().join("shared.toml");
    let saved = gecaro_io::read_robot_file(&path).expect("a valid robot file");
    assert!(["RRPRRR", "RRRRRR"].contains(&saved.robot.joint_letters().as_str()));
    let names = api.names();
    assert_eq!(names, ["shared.toml"]);
}

#[tokio::test]
async fn identification_takes_a_robust_loss_a_prior_and_cross_validation() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 60, "error_level": 1.0, "noise": 1e-4, "seed": 5 }),
        )
        .await;
    // Two gross readings: 20 mm off in x (rows 4 and 31 of the data).
    let mut lines: Vec<String> = data_lines(generated["csv"].as_str().expect("csv"))
        .map(str::to_owned)
        .collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let x = header.iter().position(|h| *h == "x").expect("x column");
    for row in [3, 30] {
        let mut fields: Vec<String> = lines[row].split(',').map(str::to_owned).collect();
        fields[x] = (fields[x].parse::<f64>().expect("x") + 0.02).to_string();
        lines[row] = fields.join(",");
    }
    let csv = lines.join("\n");
    let request = |extra: serde_json::Value| {
        let mut request = json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": csv, "name": "gross.csv" } } });
        for (key, value) in extra.as_object().expect("object") {
            request[key] = value.clone();
        }
        request
    };
    let (status, submitted) = api
        .post(
            "/api/identify",
            &request(json!({ "loss": "tukey", "prior": "5mm,0.5deg,1%", "cv": 3, "seed": 2 })),
        )
        .await;
    assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
    let view = api.finished(submitted["job"].as_u64().expect("job")).await;
    assert_eq!(view["state"], "done", "{view}");
    let identification = &view["result"]["identification"];
    assert_eq!(identification["loss"]["kind"], "tukey");
    let outliers = identification["outliers"].as_array().expect("outliers");
    let mut observations: Vec<u64> = outliers
        .iter()
        .filter(|o| o["weight"] == 0.0)
        .map(|o| o["observation"].as_u64().expect("number"))
        .collect();
    observations.sort_unstable();
    assert_eq!(observations, [3, 30], "{outliers:?}");
    assert!(
        identification["parameters"][0]["prior_std"]
            .as_f64()
            .is_some()
    );
    let validation = &identification["cross_validation"];
    assert_eq!(validation["per_fold"].as_array().expect("folds").len(), 3);
    // Bad options are answers, not failed jobs.
    for (extra, expected) in [
        (json!({ "loss": "l1" }), "unknown loss"),
        (json!({ "prior": "5mm" }), "prior:"),
        (json!({ "cv": 1 }), "cv 1"),
        (json!({ "loss_scale": 2.0 }), "l2 has no scale"),
    ] {
        let (status, body) = api.post("/api/identify", &request(extra)).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
        assert!(
            body["error"].as_str().expect("message").contains(expected),
            "{body}"
        );
    }
}

/// Small data are compared with the neighbouring models unasked: the
/// kinematic model of a robot whose gains are off is told the full one;
/// `check_model: false` skips it, a value that is not a boolean is a 400.
#[tokio::test]
async fn small_data_are_told_a_model_that_predicts_better() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 100, "error_level": 1.0, "noise": 2e-5, "seed": 5 }),
        )
        .await;
    let request = |check: Value| {
        json!({ "robot": document, "method": { "name": "position" }, "model": "kinematic",
                "sigma": "20um", "check_model": check,
                "data": { "csv": { "text": generated["csv"], "name": "small.csv" } } })
    };
    let mut advice = Vec::new();
    for check in [Value::Null, json!(false)] {
        let (status, submitted) = api.post("/api/identify", &request(check)).await;
        assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
        let view = api.finished(submitted["job"].as_u64().expect("job")).await;
        assert_eq!(view["state"], "done", "{view}");
        advice.push(view["result"]["identification"]["model_advice"].clone());
    }
    assert_eq!(advice[0][0]["model"], "full", "{}", advice[0]);
    assert_eq!(advice[0][0]["instead_of"], "kinematic");
    assert_eq!(advice[1], json!([]));
    let (status, body) = api.post("/api/identify", &request(json!("yes"))).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
}

/// Identification jobs never hold up the page's quick requests: with eight
/// jobs queued or running, the folder's listing answers while some are still
/// at work (before, it waited behind all of them for a computing slot).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_listing_answers_while_jobs_run() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let (status, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "frame" }, "count": 3000, "error_level": 1.0, "seed": 5 }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{generated}");
    let csv = generated["csv"].as_str().expect("csv");
    let request = json!({ "robot": document, "method": { "name": "frame" }, "data": { "csv": { "text": csv, "name": "gen.csv" } } });
    let mut jobs = Vec::new();
    for _ in 0..8 {
        let (status, submitted) = api.post("/api/identify", &request).await;
        assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
        jobs.push(submitted["job"].as_u64().expect("job number"));
    }
    let (status, listing) = api.get("/api/files").await;
    assert_eq!(status, StatusCode::OK, "{listing}");
    let mut active = 0;
    for job in &jobs {
        let (_, view) = api.get(&format!("/api/jobs/{job}")).await;
        if view["state"] == "queued" || view["state"] == "running" {
            active += 1;
        }
    }
    // Before, the listing waited for a computing slot behind the queued jobs
    // and answered when at most one was left.
    assert!(
        active >= 4,
        "only {active} of 8 jobs were at work when the listing answered"
    );
    for job in jobs {
        assert_eq!(api.finished(job).await["state"], "done");
    }
}

/// Values that cannot give finite output, hostile robot files in the folder:
/// each is a 4xx with a message, and the server lives on.
#[tokio::test]
async fn hostile_values_and_files_are_answers_not_crashes() {
    let api = Api::new();
    let document = api.document("stanford").await;
    for (field, value) in [
        ("error_level", json!(1e308)),
        ("noise", json!(1e308)),
        ("count", json!(1_000_000_000_000u64)),
    ] {
        let mut request =
            json!({ "robot": document, "method": { "name": "position" }, "count": 10 });
        request[field] = value.clone();
        let (status, body) = api.post("/api/generate", &request).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{field} = {value}: {body}");
    }
    let mut unlimited = document.clone();
    unlimited["frame"][1]["qmax"] = json!(1e308);
    let (status, body) = api
        .post(
            "/api/generate",
            &json!({ "robot": unlimited, "method": { "name": "position" }, "count": 10 }),
        )
        .await;
    assert!(status.is_client_error(), "{status}: {body}");
    // A URDF nested 5,000 deep and one of 100,000 joints, opened from the folder.
    std::fs::write(
        api.folder.path().join("deep.urdf"),
        format!(
            "<robot name=\"d\">{}{}</robot>",
            "<a>".repeat(5000),
            "</a>".repeat(5000)
        ),
    )
    .expect("write");
    let joints: String = (1..=100_000)
        .map(|i| {
            format!(
                "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/>\
                 <child link=\"l{i}\"/><axis xyz=\"0 0 1\"/></joint>",
                i - 1
            )
        })
        .collect();
    std::fs::write(
        api.folder.path().join("huge.urdf"),
        format!("<robot name=\"h\"><link name=\"l0\"/>{joints}</robot>"),
    )
    .expect("write");
    for name in ["deep.urdf", "huge.urdf"] {
        let (status, body) = api.get(&format!("/api/robots/file?name={name}")).await;
        assert!(status.is_client_error(), "{name}: {status} {body}");
        assert!(error_text(&body).contains(name), "{body}");
    }
    let (status, _) = api.get("/api/info").await;
    assert_eq!(status, StatusCode::OK);
}

/// Data as a European spreadsheet writes them (`;` between fields, decimal
/// commas): the separator is found, and the identification is the same.
#[tokio::test]
async fn semicolon_files_with_decimal_commas_identify_alike() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 40, "error_level": 1.0, "noise": 1e-5, "seed": 4 }),
        )
        .await;
    let csv = generated["csv"].as_str().expect("csv").to_owned();
    let european = csv.replace(',', ";").replace('.', ",");
    let mut rms = Vec::new();
    for (text, format) in [
        (csv.clone(), json!({})),
        (european.clone(), json!({})),
        (
            european,
            json!({ "delimiter": "semicolon", "decimal_comma": true }),
        ),
    ] {
        let (status, submitted) = api
            .post(
                "/api/identify",
                &json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": text, "name": "gen.csv" } }, "format": format }),
            )
            .await;
        assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
        let view = api.finished(submitted["job"].as_u64().expect("job")).await;
        assert_eq!(view["state"], "done", "{view}");
        rms.push(
            view["result"]["identification"]["rms_after"]
                .as_f64()
                .expect("rms"),
        );
    }
    assert_eq!(rms[0], rms[1]);
    assert_eq!(rms[0], rms[2]);
}

/// Points generation and planning in a cell, as the command line's `--floor`
/// and `--station`: a cell that leaves nothing is an answer, not a hang.
#[tokio::test]
async fn generation_and_plans_stay_in_the_cell() {
    let api = Api::new();
    let document = api.document("ur10e").await;
    let cell = json!({ "floor": 0.0, "station": [2.3, 0.0, 0.4], "max_incidence": "30deg" });
    let (status, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "frame" }, "count": 30, "cell": cell }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{generated}");
    let planned = api
        .job(
            "/api/plan",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 10, "cell": { "floor": 0.0 } }),
        )
        .await
        .expect("started");
    assert_eq!(planned["state"], "done", "{planned}");
    let (status, body) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 5, "cell": { "floor": 5.0 } }),
        )
        .await;
    assert!(status.is_client_error(), "{status}: {body}");
    assert!(
        error_text(&body).contains("leaves next to nothing"),
        "{body}"
    );
    let (status, body) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 5, "cell": { "max_incidence": "30deg" } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
}

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

/// Eight clients saving one URDF at once, each robot needing its joint
/// calibration beside it: the URDF and the yaml left are always one
/// client's (they were written under separate locks: 5–8 of 20 trials
/// mixed them).
#[tokio::test]
async fn parallel_saves_of_a_urdf_and_its_calibration_stay_a_pair() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let robots: Vec<Value> = (0..8)
        .map(|k| {
            let mut robot = stanford.clone();
            // A gain the URDF cannot carry (the yaml does), and a tool the
            // URDF does: both say which client wrote them.
            robot["frame"][1]["K"] = json!(1.01 + 0.01 * f64::from(k));
            robot["frame"][7]["r"] = json!(0.1 + 0.01 * f64::from(k));
            robot
        })
        .collect();
    for trial in 0..5 {
        let mut saves = Vec::new();
        for robot in &robots {
            let app = api.app.clone();
            let body = json!({ "robot": robot, "name": "pair.urdf", "overwrite": true });
            saves.push(tokio::spawn(async move {
                let request = Request::post("/api/robots/save")
                    .header(header::CONTENT_TYPE, "application/json")
                    .body(Body::from(body.to_string()))
                    .expect("request");
                app.oneshot(request).await.expect("infallible").status()
            }));
        }
        for save in saves {
            assert_eq!(save.await.expect("task"), StatusCode::OK);
        }
        let mut imported = gecaro_io::import_robot(
            &api.folder.path().join("pair.urdf"),
            &gecaro_io::ImportOptions::default(),
        )
        .expect("the pair imports");
        let yaml = api.folder.path().join("pair.joint_calibration.yaml");
        let text = std::fs::read_to_string(&yaml).expect("a joint calibration");
        gecaro_io::apply_joint_calibration(&mut imported.file, &text, &yaml).expect("applies");
        let robot = &imported.file.robot;
        // The yaml's map q = M·qm (imported as a coupling): M₁₁ is K1.
        let m11 = robot
            .joint_positions(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
            .expect("q")[0];
        let by_gain = ((m11 - 1.01) / 0.01).round();
        let qm = [0.3, -0.5, 0.6, 0.2, 1.0, -0.4];
        let reach = |robot: &gecaro_core::Robot| {
            gecaro_core::terminal_pose(robot, &qm)
                .expect("pose")
                .translation
                .vector
        };
        let by_tool = robots
            .iter()
            .position(|document| {
                let file: gecaro_io::RobotDocument =
                    serde_json::from_value(document.clone()).expect("document");
                let candidate = file.to_robot_file("k").expect("robot").robot;
                // Same joint values: the gain is undone through qm/K.
                let mut same_gain = candidate.clone();
                let parameters = same_gain.parameters();
                let id = parameters.id(parameters.index_of_name("K1").expect("K1"));
                same_gain.set_parameter(id, m11).expect("gain");
                (reach(&same_gain) - reach(robot)).norm() < 1e-6
            })
            .expect("the URDF is one client's");
        assert_eq!(
            by_gain as usize, by_tool,
            "trial {trial}: URDF and yaml of two clients"
        );
    }
}

/// Two people editing one file: the second save of the one who opened it
/// first is refused (409) with the choice, not silently lost; the version a
/// save answers lets the next save through.
#[tokio::test]
async fn a_file_changed_since_it_was_opened_is_not_overwritten_silently() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let save = |robot: &Value, expected: Option<&str>| json!({ "robot": robot, "name": "arm.toml", "overwrite": true, "expected_version": expected });
    let (status, _) = api.post("/api/robots/save", &save(&stanford, None)).await;
    assert_eq!(status, StatusCode::OK);
    // Alice and Bob open it.
    let (status, alice) = api.get("/api/robots/file?name=arm.toml").await;
    assert_eq!(status, StatusCode::OK, "{alice}");
    let (_, bob) = api.get("/api/robots/file?name=arm.toml").await;
    let opened = alice["version"].as_str().expect("a version").to_owned();
    assert_eq!(bob["version"], alice["version"]);
    // Bob saves his edit.
    let mut edited = bob["document"].clone();
    edited["frame"][3]["d"] = json!(0.05);
    let (status, saved) = api
        .post("/api/robots/save", &save(&edited, Some(&opened)))
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_ne!(saved["version"].as_str(), Some(opened.as_str()));
    // Alice's save from the version she opened is refused, Bob's edit kept.
    let mut hers = alice["document"].clone();
    hers["frame"][2]["alpha"] = json!(0.5);
    let (status, body) = api
        .post("/api/robots/save", &save(&hers, Some(&opened)))
        .await;
    assert_eq!(status, StatusCode::CONFLICT, "{body}");
    assert!(
        error_text(&body).contains("arm.toml changed since it was opened"),
        "{body}"
    );
    let kept = gecaro_io::read_robot_file(&api.folder.path().join("arm.toml")).expect("kept");
    assert!((kept.robot.frames()[3].d - 0.05).abs() < 1e-12);
    // Saving from the version the last save answered goes through.
    let current = saved["version"].as_str().expect("version");
    let (status, _) = api
        .post("/api/robots/save", &save(&edited, Some(current)))
        .await;
    assert_eq!(status, StatusCode::OK);
}

/// A client that sends its headers and part of a body, then stops: answered
/// 408 once the body is overdue (5 s), not after the request timeout
/// (300 s), so that such clients cannot hold every connection.
#[tokio::test]
async fn a_body_that_stops_arriving_is_let_go() {
    let api = Api::new();
    let part = futures_util::stream::once(async {
        Ok::<_, std::io::Error>(bytes::Bytes::from_static(b"{\"joints\": "))
    })
    .chain(futures_util::stream::pending());
    let request = Request::post("/api/robots/new")
        .header(header::CONTENT_TYPE, "application/json")
        .header(header::CONTENT_LENGTH, "40")
        .body(Body::from_stream(part))
        .expect("request");
    let started = std::time::Instant::now();
    let (status, bytes, _) = api.send(request).await;
    assert_eq!(status, StatusCode::REQUEST_TIMEOUT);
    assert!(started.elapsed() < Duration::from_secs(20));
    let body: Value = serde_json::from_slice(&bytes).expect("JSON");
    assert!(
        error_text(&body).contains("body stopped arriving"),
        "{body}"
    );
}

/// A generation whose client went away stops at its next configuration: it
/// frees its computing slot at once and writes nothing (before, every slot
/// stayed taken until the generations ended, and their files appeared after).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_abandoned_generation_frees_its_slot_and_writes_nothing() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let slots = std::thread::available_parallelism().map_or(2, std::num::NonZero::get);
    for index in 0..slots {
        // Frame-link sets are drawn by the inverse model: 20,000 rows take
        // seconds in release, minutes in a test build.
        let body = json!({
            "robot": document, "method": { "name": "frame-link" }, "count": 20000,
            "seed": index, "save_as": format!("abandoned-{index}.csv"),
        });
        let request = Request::post("/api/generate")
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(body.to_string()))
            .expect("request");
        let leaving =
            tokio::time::timeout(Duration::from_millis(300), api.app.clone().oneshot(request))
                .await;
        assert!(leaving.is_err(), "the generation ended within 300 ms");
    }
    // Every computing slot was taken by a generation; this one needs a slot.
    let quick = json!({ "robot": document, "method": { "name": "position" }, "count": 30 });
    let (status, answer) =
        tokio::time::timeout(Duration::from_secs(60), api.post("/api/generate", &quick))
            .await
            .expect("a slot was freed by the abandoned generations");
    assert_eq!(status, StatusCode::OK, "{answer}");
    let names = api.names();
    assert!(names.is_empty(), "written after the client left: {names:?}");
}

/// A robot file uploaded from the page opens as one of the folder would,
/// and nothing is written into the folder.
#[tokio::test]
async fn an_uploaded_robot_file_opens_without_touching_the_folder() {
    let api = Api::new();
    let urdf = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/urdf/panda.urdf"),
    )
    .expect("panda.urdf");
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "panda.urdf", "text": urdf, "tip": "panda_link8" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["origin"], "uploaded");
    assert!(opened["name"].is_null(), "no file of the folder: {opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRRR");
    // A gecaro robot file, and its mistakes named at their line.
    let puma = gecaro_io::robot_file_text(
        &gecaro_io::load_robot("puma560").expect("ready robot"),
        std::path::Path::new("puma.toml"),
    )
    .expect("text");
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "puma.toml", "text": puma }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    // `ARM.TOML` as the command line reads it (issue 75: read as a DH
    // table, "unknown field `frame`").
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "PUMA.TOML", "text": puma }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    let (status, bad) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "bad.toml", "text": "name = \"x\"\n[[frame]]\nsigma = \n" }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&bad).contains("bad.toml:3"), "{bad}");
    let (status, _) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "robot.exe", "text": "x" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(api.names().is_empty(), "nothing written");
}

/// Elastic joints from the page: a real robot with compliances measured
/// with three payloads, identified with the elastic model; the calibrated
/// document states the compliances, and the table's compliance reads back.
#[tokio::test]
async fn an_elastic_robot_is_simulated_and_identified_through_the_api() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let generate = |payload: &str, seed: u64, real: Option<&Value>| {
        let mut request = json!({ "robot": document, "method": { "name": "position" },
                                  "count": 40, "noise": 2e-5, "seed": seed, "payload": payload });
        match real {
            Some(real) => request["real"] = real.clone(),
            None => request["compliance_level"] = json!(1.0),
        }
        request
    };
    let (status, first) = api.post("/api/generate", &generate("0kg", 1, None)).await;
    assert_eq!(status, StatusCode::OK, "{first}");
    let real = first["real"].clone();
    let compliances: Vec<f64> = real["frame"]
        .as_array()
        .expect("frames")
        .iter()
        .filter_map(|frame| frame["compliance"].as_f64())
        .collect();
    assert_eq!(compliances.len(), 6, "{real}");
    let mut rows: Vec<String> = data_lines(first["csv"].as_str().expect("csv"))
        .map(str::to_owned)
        .collect();
    assert!(rows[0].ends_with("payload_mass,payload_x,payload_y,payload_z"));
    for (payload, seed) in [("10kg,0,0,100mm", 2), ("20kg,0,0,100mm", 3)] {
        let (status, more) = api
            .post("/api/generate", &generate(payload, seed, Some(&real)))
            .await;
        assert_eq!(status, StatusCode::OK, "{more}");
        rows.extend(
            data_lines(more["csv"].as_str().expect("csv"))
                .skip(1)
                .map(str::to_owned),
        );
    }
    // Elastic, then with gravity's tilt asked for too (the level cell's
    // data find none): both fit the stated noise.
    let mut views = Vec::new();
    for model in ["elastic", "elastic-gravity"] {
        let request = json!({ "robot": document, "method": { "name": "position" },
                              "model": model, "sigma": "20um",
                              "data": { "csv": { "text": rows.join("\n"), "name": "payloads.csv" } } });
        let view = api.job("/api/identify", &request).await.expect("started");
        assert_eq!(view["state"], "done", "{view}");
        let outcome = &view["result"]["identification"]["verdict"]["outcome"];
        assert_eq!(outcome, "fits_noise", "{model}: {view}");
        views.push(view);
    }
    let view = &views[0];
    let identification = &view["result"]["identification"];
    let c2 = identification["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .find(|p| p["name"] == "c2")
        .expect("c2 identified");
    let (value, std) = (
        c2["identified"].as_f64().expect("value"),
        c2["std"].as_f64().expect("σ"),
    );
    assert!(
        (value - compliances[1]).abs() < 3.0 * std,
        "{c2} vs {}",
        compliances[1]
    );
    let calibrated = &view["result"]["calibrated"];
    assert_eq!(
        calibrated["frame"][2]["compliance"], c2["identified"],
        "{calibrated}"
    );
    // The calibrated document, compliances and all, is a robot the table takes.
    let (status, checked) = api
        .post("/api/robots/check", &json!({ "robot": calibrated }))
        .await;
    assert_eq!(status, StatusCode::OK, "{checked}");
    assert!(
        checked["problems"].as_array().expect("problems").is_empty(),
        "{checked}"
    );
    let identification = &views[1]["result"]["identification"];
    for tilt in identification["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .filter(|p| p["name"].as_str().is_some_and(|n| n.starts_with("tilt")))
    {
        let (value, std) = (tilt["identified"].as_f64(), tilt["std"].as_f64());
        assert!(
            value.zip(std).is_some_and(|(v, s)| v.abs() < 3.0 * s),
            "{tilt}"
        );
    }
}

/// The page's plan offers each candidate with each payload: the plan states
/// each row's payload; a payload for a link method is refused by its field.
#[tokio::test]
async fn a_plan_chooses_payloads_for_an_elastic_robot() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let view = api
        .job(
            "/api/plan",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 30,
                     "pool": 150, "payloads": ["0kg", "20kg,0,0,100mm"] }),
        )
        .await
        .expect("started");
    assert_eq!(view["state"], "done", "{view}");
    let csv = view["result"]["csv"].as_str().expect("csv");
    let mut lines = data_lines(csv);
    assert!(
        lines.next().expect("header").ends_with("payload_z"),
        "{csv}"
    );
    assert!(lines.any(|line| line.contains(",20.0,")), "{csv}");
    let refused = api
        .job(
            "/api/plan",
            &json!({ "robot": document, "method": { "name": "distance" }, "count": 30,
                     "payloads": ["5kg"] }),
        )
        .await;
    let message = match refused {
        Err((status, body)) => {
            assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
            error_text(&body).to_owned()
        }
        Ok(view) => view["error"].as_str().expect("failed job").to_owned(),
    };
    assert!(message.contains("payloads"), "{message}");
}

/// The payload traps (issue 74) are refused by the page's fields as by the
/// command line: a mixed-unit centre in a plan, a payload heavier than the
/// arm in generate; the field is named.
#[tokio::test]
async fn a_payload_no_arm_carries_is_refused_by_its_field() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let refused = api
        .job(
            "/api/plan",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 30,
                     "payloads": ["0kg", "12kg,-32.3,17.3,-17.3mm"] }),
        )
        .await;
    let message = match refused {
        Err((status, body)) => {
            assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
            error_text(&body).to_owned()
        }
        Ok(view) => view["error"].as_str().expect("failed job").to_owned(),
    };
    assert!(
        message.contains("payloads") && message.contains("mixes units"),
        "{message}"
    );
    let (status, body) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 5,
                     "compliance_level": 1.0, "payload": "1200kg" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    let message = error_text(&body);
    assert!(message.contains("a payload of 1200 kg"), "{message}");
}

/// `/api/join` (issue 74): an export in mm with `;` and decimal commas, a
/// log in degrees with a row nothing measured, joined by name and saved in
/// the folder; by row order, the counts that differ are named.
#[tokio::test]
async fn an_export_and_a_log_are_joined_through_the_api() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let mut export = String::from("Point;X;Y;Z\n");
    let mut log = String::from("Name,qm1,qm2,qm3,qm4,qm5,qm6\nHOME,0,0,0.5,0,0,0\n");
    for i in 0..12 {
        let t = f64::from(i);
        let q = [
            (0.7 * t).sin(),
            (0.4 * t).cos() - 0.5,
            0.4 + 0.1 * (0.9 * t).sin(),
            (1.3 * t).sin(),
            0.8 * (0.5 * t).cos(),
            0.3 * t - 1.5,
        ];
        let (status, pose) = api
            .post("/api/robots/pose", &json!({ "robot": document, "q": q }))
            .await;
        assert_eq!(status, StatusCode::OK, "{pose}");
        let frames = pose["frames"].as_array().expect("frames");
        let tool = &frames[frames.len() - 1]["origin"];
        let mm =
            |axis: usize| format!("{:.6}", tool[axis].as_f64().expect("m") * 1e3).replace('.', ",");
        export += &format!("P{i};{};{};{}\n", mm(0), mm(1), mm(2));
        let degrees: Vec<String> = q
            .iter()
            .enumerate()
            .map(|(j, v)| {
                if j == 2 {
                    v.to_string()
                } else {
                    v.to_degrees().to_string()
                }
            })
            .collect();
        log += &format!("P{i},{}\n", degrees.join(","));
    }
    let request = |key: bool, save_as: &str| {
        let mut request = json!({
            "robot": document,
            "tracker": { "csv": { "text": export, "name": "export.csv" } },
            "log": { "csv": { "text": log, "name": "log.csv" } },
            "tracker_format": { "length_unit": "mm", "columns": "x=X,y=Y,z=Z" },
            "log_format": { "angle_unit": "deg" },
            "save_as": save_as,
        });
        if key {
            request["key"] = json!("Point");
            request["log_key"] = json!("Name");
        }
        request
    };
    let (status, body) = api.post("/api/join", &request(true, "joined.csv")).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(body["rows"], 12, "{body}");
    assert_eq!(body["unmeasured"][0]["key"], "HOME", "{body}");
    assert!(body["distance_rms"].as_f64().expect("m") < 1e-5, "{body}");
    assert!(api.names().contains(&"joined.csv".to_owned()));
    // By row order, the export is one row short of the log: named.
    let (status, body) = api.post("/api/join", &request(false, "by_order.csv")).await;
    assert!(status.is_client_error(), "{body}");
    assert!(
        error_text(&body).contains("12 measured points and 13 log rows"),
        "{body}"
    );
}

/// The owner's frames from the page (issue 74): a tool point taught from
/// a pivot's joint values (an upload, degrees), as `gecaro tcp`; a pivot
/// about one axis refused by its field; a user frame from three points.
#[tokio::test]
async fn a_tool_point_and_a_user_frame_are_made_through_the_api() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let robot = gecaro_io::load_robot("industrial6").expect("robot").robot;
    let tool = nalgebra::Vector3::new(0.015, -0.02, 0.18);
    let tooled = robot
        .reframed(
            &nalgebra::IsometryMatrix3::identity(),
            &nalgebra::IsometryMatrix3::translation(tool.x, tool.y, tool.z),
        )
        .expect("tooled");
    let mut text = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for (rx, ry) in [
        (0.4, 0.0),
        (-0.4, 0.0),
        (0.0, 0.4),
        (0.0, -0.4),
        (0.3, 0.3),
        (-0.3, 0.2),
    ] {
        let rotation = nalgebra::Rotation3::from_euler_angles(rx, ry, 0.0)
            * nalgebra::Rotation3::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        let target = nalgebra::IsometryMatrix3::from_parts(
            nalgebra::Translation3::new(0.75, 0.1, 0.3),
            rotation,
        );
        let solution = gecaro_core::inverse_kinematics(
            &tooled,
            &gecaro_core::Target::Frame(target),
            &[0.0, -0.3, 0.9, 0.0, 0.9, 0.0],
            &gecaro_core::InverseOptions::default(),
        )
        .expect("reached");
        let row: Vec<String> = solution
            .motor_positions
            .iter()
            .map(|q| q.to_degrees().to_string())
            .collect();
        text += &(row.join(",") + "\n");
    }
    let (status, taught) = api
        .post(
            "/api/tcp",
            &json!({ "robot": document, "data": { "csv": { "text": text, "name": "pivot.csv" } },
                     "format": { "angle_unit": "deg" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{taught}");
    for axis in 0..3 {
        let found = taught["tool"][axis].as_f64().expect("m");
        assert!((found - tool[axis]).abs() < 1e-6, "{taught}");
    }
    let about_axis: String = (0..5)
        .map(|i| format!("0,-17,52,0,52,{}\n", 30 * i))
        .collect();
    let (status, body) = api
        .post(
            "/api/tcp",
            &json!({ "robot": document, "format": { "angle_unit": "deg" },
                     "data": { "csv": { "text": format!("qm1,qm2,qm3,qm4,qm5,qm6\n{about_axis}"), "name": "pivot.csv" } } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("not determined"), "{body}");
    let (status, frame) = api
        .post(
            "/api/frame",
            &json!({ "points": { "csv": { "text": "name;x;y;z\norigin;1000;2000;500\nx;1000;2500;500\nxy;200;2100;500\n", "name": "fixture.csv" } },
                     "format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{frame}");
    assert_eq!(frame["way"], "three points");
    assert!(
        (frame["position"][1].as_f64().expect("m") - 2.0).abs() < 1e-12,
        "{frame}"
    );
    // Data measured from a tracker 2 m away: named, then registered on 30 %.
    let world = nalgebra::IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(2.0, 0.5, -0.2),
        nalgebra::Rotation3::from_euler_angles(0.0, 0.0, 1.2),
    );
    let seen = gecaro_io::RobotFile::of(
        robot
            .reframed(&world, &nalgebra::IsometryMatrix3::identity())
            .expect("seen"),
    );
    let real = serde_json::to_value(gecaro_io::RobotDocument::from_robot_file(&seen)).expect("doc");
    let (status, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 40,
                     "noise": 2e-5, "seed": 2, "real": real }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{generated}");
    let data = json!({ "csv": { "text": generated["csv"], "name": "other.csv" } });
    let (status, plain) = api
        .post(
            "/api/evaluate",
            &json!({ "robot": document, "method": { "name": "position" }, "data": data }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{plain}");
    assert!(
        plain["notes"].to_string().contains("another frame"),
        "{plain}"
    );
    let (status, registered) = api
        .post(
            "/api/evaluate",
            &json!({ "robot": document, "method": { "name": "position" }, "data": data,
                     "register": "30%" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{registered}");
    assert!(
        registered["errors"]["rms"].as_f64().expect("m") < 6e-5,
        "{registered}"
    );
}

/// ISO 9283's test from the page (issue 78): planned into the folder (the
/// program's text beside the plan), a measured upload evaluated against it
/// in millimetres with a stated frame, a bad cube refused by its field.
#[tokio::test]
async fn an_iso9283_test_is_planned_and_evaluated_through_the_api() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let (status, plan) = api
        .post(
            "/api/iso9283/plan",
            &json!({ "robot": document, "cycles": 3, "directions": 3, "save_as": "test.csv" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{plan}");
    assert_eq!(plan["rows"], 90);
    assert_eq!(plan["measured_rows"], 45);
    let program = plan["program"].as_str().expect("program");
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("test.csv")).expect("saved"),
        program
    );
    // A tracker 1 m along x saw each visit 0.05 mm off along z.
    let mut measured = String::from("pose;cycle;direction;x;y;z\n");
    for line in program.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        if fields[3] != "1" {
            continue;
        }
        let at = |i: usize| fields[i].parse::<f64>().expect("number") * 1e3;
        measured.push_str(&format!(
            "{};{};{};{};{};{}\n",
            fields[0],
            fields[1],
            fields[2],
            (at(10) - 1000.0).to_string().replace('.', ","),
            at(11).to_string().replace('.', ","),
            (at(12) + 0.05).to_string().replace('.', ",")
        ));
    }
    let (status, report) = api
        .post(
            "/api/iso9283/evaluate",
            &json!({ "program": { "file": "test.csv" },
                     "data": { "csv": { "text": measured, "name": "tracker.csv" } },
                     "format": { "length_unit": "mm" }, "frame": "1m,0,0",
                     "conditions": { "speed": "50 %" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{report}");
    let before = &report["before"];
    assert_eq!(before["registration"], "stated");
    assert_eq!(before["directions"], 3);
    for pose in before["poses"].as_array().expect("poses") {
        assert!(
            (pose["ap"]["z"].as_f64().expect("m") - 5e-5).abs() < 1e-9,
            "{pose}"
        );
        assert!(pose["vap"]["p"].as_f64().expect("m") < 1e-9, "{pose}");
    }
    assert_eq!(report["conditions"]["speed"], "50 %");
    let (status, body) = api
        .post(
            "/api/iso9283/plan",
            &json!({ "robot": document, "cube": "1,0,0.5,0.3mm" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("cube"), "{body}");
}
