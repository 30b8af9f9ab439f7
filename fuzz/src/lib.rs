//! The properties gecaro's fuzz targets check, one function per target, so
//! that `tests/replay.rs` runs every seed and every former crash through the
//! same checks in an ordinary `cargo test` (docs/errors.md, "Fuzzing").
//!
//! Each function panics when the property fails; under libFuzzer any panic,
//! even one the server would catch, is a crash.

use std::path::Path;
use std::sync::OnceLock;

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode, header};
use gecaro_calib::{
    methods::{METHODS, MethodOptions},
    study::Study,
};
use gecaro_web::{AppState, POST_ROUTES, Workspace, router};
use http_body_util::BodyExt;
use tower::ServiceExt;

/// The robot-file parser: any text either loads or gives an error naming the
/// file, and whatever loads saves and loads back to the same robot, on which
/// the models run.
pub fn robot_file(bytes: &[u8]) {
    // Robot files are read as UTF-8 text (`read_to_string`): other bytes are
    // refused before the parser sees them.
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let path = Path::new("fuzz.toml");

    // The web page's route: the document as written, then its problems.
    if let Ok(document) = gecaro_io::parse_robot_document(text, path) {
        let _ = document.problems();
    }

    // The command line's route: a valid robot or an error naming the file.
    match gecaro_io::parse_robot_file(text, path) {
        Ok(file) => {
            let saved = gecaro_io::format_robot_file(&file);
            let reloaded = gecaro_io::parse_robot_file(&saved, path)
                .unwrap_or_else(|error| panic!("a saved robot does not load: {error}\n{saved}"));
            assert_eq!(
                reloaded, file,
                "load -> save -> load changed the robot\n{saved}"
            );
            let robot = &file.robot;
            let middle: Vec<f64> = robot
                .joints()
                .iter()
                .map(|joint| 0.5 * (joint.qmin + joint.qmax))
                .collect();
            // No panic; values may be infinite for absurd magnitudes.
            let _ = gecaro_core::parameter_jacobian(robot, &middle);
        }
        Err(error) => assert_names(&error.to_string(), "fuzz.toml"),
    }
}

/// The URDF importer: any text either imports into a robot that saves and
/// loads back, or gives a short error naming the file (the importer bounds
/// depth and element counts before parsing: no stack overflow, no endless
/// allocation, no megabyte-long message).
pub fn urdf_file(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let path = Path::new("fuzz.urdf");
    check_import(
        gecaro_io::import_robot_text(text, path, &gecaro_io::ImportOptions::default()),
        "fuzz.urdf",
    );
}

/// An import's property: a robot that saves and loads back to the same
/// frames, or a short error (under 4 KiB) naming `file`.
fn check_import(imported: Result<gecaro_io::Imported, gecaro_io::Error>, file: &str) {
    match imported {
        Ok(imported) => {
            let saved = gecaro_io::format_robot_file(&imported.file);
            let reloaded = gecaro_io::parse_robot_file(&saved, Path::new("fuzz.toml"))
                .unwrap_or_else(|error| {
                    panic!("an imported robot does not load: {error}\n{saved}")
                });
            assert_eq!(reloaded.robot.frames(), imported.file.robot.frames());
        }
        Err(error) => {
            let message = error.to_string();
            assert_names(&message, file);
            assert!(
                message.len() < 4096,
                "a {}-byte error message",
                message.len()
            );
        }
    }
}

/// The data-file parser and the checks of a study. The first byte picks the
/// method, the second the number of joints (1 to 8), the rest is the file:
/// it loads into a study that passes or fails its checks with an error
/// naming the file.
pub fn data_file(input: &[u8]) {
    let [method_byte, joints_byte, csv @ ..] = input else {
        return;
    };
    let info = &METHODS[usize::from(*method_byte) % METHODS.len()];
    let Ok(method) = info.build(&MethodOptions::default()) else {
        return;
    };
    let joint_count = 1 + usize::from(*joints_byte % 8);
    let letters: String = (0..joint_count)
        .map(|joint| if joint % 3 == 2 { 'P' } else { 'R' })
        .collect();
    let robot = gecaro_core::Robot::template("fuzz", &letters).expect("a template robot");
    let path = Path::new("fuzz.csv");
    let types = gecaro_io::joint_types(&robot);
    let format = gecaro_io::DataFormat::default();
    match gecaro_io::parse_samples(csv, path, &types, method.data_columns(), &format) {
        Ok(data) => {
            let study = Study::single(method, data.samples, "fuzz.csv");
            let _ = study.limit_violations(&robot);
            if let Err(error) = study.check(&robot) {
                assert_names(&error.to_string(), "fuzz.csv");
            }
        }
        Err(error) => assert_names(&error.to_string(), "fuzz.csv"),
    }
}

/// The most time one input of a text reader may take (SYMORO values once
/// parsed in quadratic time: 100 s for a 540 KB sum). Generous for a slow
/// machine; libFuzzer's inputs are a few kilobytes.
const MAX_SECONDS_PER_INPUT: f64 = 5.0;

/// The SYMORO `.par` importer: any text either imports into a robot that
/// saves and loads back, or gives a short error naming the file, in bounded
/// time.
pub fn symoro_file(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let started = std::time::Instant::now();
    let path = Path::new("fuzz.par");
    let options = gecaro_io::ImportOptions {
        format: Some(gecaro_io::RobotFormat::Symoro),
        ..gecaro_io::ImportOptions::default()
    };
    check_import(
        gecaro_io::import_robot_text(text, path, &options),
        "fuzz.par",
    );
    let seconds = started.elapsed().as_secs_f64();
    assert!(
        seconds < MAX_SECONDS_PER_INPUT,
        "{seconds:.1} s for one input"
    );
}

/// A study's files in memory: any robot name is the Stanford arm, any
/// priority file its default matrix, any data file two configurations with
/// every column a method may read.
struct FuzzStudyFiles<'a>(&'a gecaro_app::StudyText);

impl gecaro_app::StudyFiles for FuzzStudyFiles<'_> {
    type Error = gecaro_io::Error;

    fn robot(&self, _: &str) -> Result<gecaro_io::RobotFile, gecaro_io::Error> {
        gecaro_io::load_robot("stanford")
    }

    fn priority(
        &self,
        _: &str,
        robot: &gecaro_core::Robot,
    ) -> Result<gecaro_core::PriorityMatrix, gecaro_io::Error> {
        Ok(robot.priority())
    }

    fn samples(
        &self,
        _: &str,
        joint_types: &[gecaro_core::FrameType],
        columns: &[gecaro_calib::study::DataColumn],
        format: &gecaro_io::DataFormat,
    ) -> Result<(gecaro_io::DataFile, String), gecaro_io::Error> {
        let csv = "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z,set,pair,distance,qw,qx,qy,qz\n\
                   0.1,0.2,0.3,0.1,0.2,0.3,0.5,0.2,0.4,1,1,0.3,1,0,0,0\n\
                   0.3,-0.2,0.5,0.4,-0.1,0.2,0.4,0.3,0.5,1,1,0.4,1,0,0,0\n";
        let data = gecaro_io::parse_samples(
            csv.as_bytes(),
            Path::new("fuzz.csv"),
            joint_types,
            columns,
            format,
        )?;
        Ok((data, "fuzz.csv".into()))
    }

    fn misplaced(&self, field: &gecaro_app::SpecField, message: String) -> gecaro_io::Error {
        self.0.misplaced(field, message)
    }
}

/// The study-file reader: any text either builds a study (which then passes
/// or fails its checks with a message) or gives an error naming the study
/// file, in bounded time; a study that reads writes back to the same
/// statement.
pub fn study_file(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let started = std::time::Instant::now();
    let path = Path::new("fuzz.toml");
    match gecaro_app::StudyText::parse(text.to_owned(), path) {
        Ok(study) => {
            let written = toml::to_string(&study.spec).expect("a stated study writes");
            let again: gecaro_app::StudySpec = toml::from_str(&written).unwrap_or_else(|error| {
                panic!("a written study does not read: {error}\n{written}")
            });
            assert_eq!(format!("{again:?}"), format!("{:?}", study.spec));
            match study
                .spec
                .build(&FuzzStudyFiles(&study), gecaro_app::StudyData::Measured)
            {
                Ok(file) => {
                    let _ = file.study.check(&file.robot.robot);
                }
                Err(error) => {
                    let message = error.to_string();
                    assert!(
                        message.contains("fuzz.toml") || message.contains("fuzz.csv"),
                        "the error names no file: {message}"
                    );
                }
            }
        }
        Err(error) => assert_names(&error.to_string(), "fuzz.toml"),
    }
    let seconds = started.elapsed().as_secs_f64();
    assert!(
        seconds < MAX_SECONDS_PER_INPUT,
        "{seconds:.1} s for one input"
    );
}

/// The GET routes, picked by the first byte from 7 on (0–6 pick one of
/// [`POST_ROUTES`]); the rest of the input is appended to the path.
pub const GET_ROUTES: &[&str] = &[
    "/api/robots/ready/",
    "/api/robots/file?path=",
    "/api/jobs/",
    "/api/files",
    "/api/info",
];

/// The web API's request handling: the first byte picks the route, the rest
/// is the body (POST) or the end of the path (GET). Every request gets an
/// answer that is a success, a 4xx with a message, or 503 (busy) — never a
/// 500, and nothing panics, not even inside a computation.
pub fn web_api(input: &[u8]) {
    let [route, rest @ ..] = input else {
        return;
    };
    let route = usize::from(*route);
    let request = if route < POST_ROUTES.len() {
        Request::post(POST_ROUTES[route])
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(rest.to_vec()))
    } else {
        let prefix = GET_ROUTES[route % GET_ROUTES.len()];
        let Ok(tail) = std::str::from_utf8(rest) else {
            return;
        };
        Request::get(format!("{prefix}{tail}")).body(Body::empty())
    };
    let Ok(mut request) = request else {
        return; // not a request a client could send (an invalid URI)
    };
    request.headers_mut().insert(
        header::HOST,
        header::HeaderValue::from_static("127.0.0.1:8080"),
    );
    let harness = WebHarness::get();
    let (status, body) = harness.runtime.block_on(async {
        let response = harness
            .app
            .clone()
            .oneshot(request)
            .await
            .expect("the router is infallible");
        let status = response.status();
        let body = response
            .into_body()
            .collect()
            .await
            .expect("a body")
            .to_bytes();
        (status, body)
    });
    assert!(
        status.is_success()
            || status.is_client_error()
            || status == StatusCode::SERVICE_UNAVAILABLE,
        "status {status}: {}",
        String::from_utf8_lossy(&body)
    );
}

/// One server for the whole run, as `gecaro serve` has: its folder holds a
/// robot file to open.
struct WebHarness {
    runtime: tokio::runtime::Runtime,
    app: Router,
    _folder: tempfile::TempDir,
}

impl WebHarness {
    fn get() -> &'static WebHarness {
        static HARNESS: OnceLock<WebHarness> = OnceLock::new();
        HARNESS.get_or_init(|| {
            let folder = tempfile::tempdir().expect("a temporary folder");
            std::fs::write(
                folder.path().join("two.toml"),
                "[[frame]]\nsigma = 2\n[[frame]]\nsigma = 0\n[[frame]]\nsigma = 0\nd = 0.5\n\
                 [[frame]]\nsigma = 2\nd = 0.3\n",
            )
            .expect("a robot file");
            let workspace = Workspace::new(folder.path()).expect("a workspace");
            let state = AppState::new(workspace, vec!["127.0.0.1:8080".into()]);
            WebHarness {
                runtime: tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                    .expect("a runtime"),
                app: router(state),
                _folder: folder,
            }
        })
    }
}

fn assert_names(message: &str, file: &str) {
    assert!(
        message.contains(file),
        "the error does not name {file}: {message}"
    );
}
