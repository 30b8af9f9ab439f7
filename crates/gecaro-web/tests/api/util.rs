//! What the API tests share: a router over a temporary folder, and reading its answers.

pub(crate) use std::time::Duration;

pub(crate) use axum::Router;
pub(crate) use axum::body::Body;
pub(crate) use axum::http::{Request, StatusCode, header};
pub(crate) use futures_util::StreamExt;
pub(crate) use gecaro_web::{AppState, POST_ROUTES, Workspace, router};
pub(crate) use http_body_util::BodyExt;
pub(crate) use serde_json::{Value, json};
pub(crate) use tower::ServiceExt;

pub(crate) struct Api {
    pub(crate) app: Router,
    pub(crate) folder: tempfile::TempDir,
}

impl Api {
    pub(crate) fn new() -> Self {
        Self::with_hosts(Vec::new())
    }

    pub(crate) fn with_hosts(hosts: Vec<String>) -> Self {
        let folder = tempfile::tempdir().expect("folder");
        let state = AppState::new(Workspace::new(folder.path()).expect("workspace"), hosts);
        Api {
            app: router(state),
            folder,
        }
    }

    pub(crate) async fn send(
        &self,
        request: Request<Body>,
    ) -> (StatusCode, Vec<u8>, header::HeaderMap) {
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

    pub(crate) async fn get(&self, uri: &str) -> (StatusCode, Value) {
        let request = Request::get(uri).body(Body::empty()).expect("request");
        let (status, bytes, _) = self.send(request).await;
        (
            status,
            serde_json::from_slice(&bytes).unwrap_or(Value::Null),
        )
    }

    pub(crate) async fn post(&self, uri: &str, body: &Value) -> (StatusCode, Value) {
        self.post_raw(uri, body.to_string()).await
    }

    pub(crate) async fn post_raw(&self, uri: &str, body: String) -> (StatusCode, Value) {
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
    pub(crate) async fn download(&self, uri: &str, kind: &str) -> String {
        let request = Request::get(uri).body(Body::empty()).expect("request");
        let (status, bytes, headers) = self.send(request).await;
        assert_eq!(status, StatusCode::OK, "{uri}");
        let given = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(given.starts_with(kind), "{uri}: {given}");
        String::from_utf8(bytes).expect("utf-8")
    }

    /// The names of the files in the served folder.
    pub(crate) fn names(&self) -> Vec<String> {
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

    pub(crate) async fn document(&self, robot: &str) -> Value {
        let (status, view) = self.get(&format!("/api/robots/ready/{robot}")).await;
        assert_eq!(status, StatusCode::OK, "{view}");
        view["document"].clone()
    }

    /// Copies the tracker cell of `examples/tracker-cell` (its study file
    /// and six data files) into the folder; the cell's folder.
    pub(crate) fn with_tracker_cell(&self) -> std::path::PathBuf {
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
    pub(crate) async fn job(&self, uri: &str, body: &Value) -> Result<Value, (StatusCode, Value)> {
        let (status, submitted) = self.post(uri, body).await;
        if status != StatusCode::ACCEPTED {
            return Err((status, submitted));
        }
        Ok(self
            .finished(submitted["job"].as_u64().expect("job number"))
            .await)
    }

    /// Waits for a job to end.
    pub(crate) async fn finished(&self, job: u64) -> Value {
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
    pub(crate) async fn calibrated(&self, document: &Value) -> (Value, Value) {
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
pub(crate) fn data_lines(csv: &str) -> impl Iterator<Item = &str> {
    csv.lines().filter(|line| !line.starts_with('#'))
}

pub(crate) fn error_text(value: &Value) -> &str {
    value["error"]
        .as_str()
        .unwrap_or_else(|| panic!("no error message in {value}"))
}
