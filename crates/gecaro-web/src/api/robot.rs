//! The Robot menu: the ready robots and the folder's files, New, Open, Save,
//! the check of an edited table, and the poses of the frames for the view.

use axum::extract::{Path as UrlPath, Query, State};
use gecaro_calib::{methods::METHODS, study::DataColumn};
use gecaro_core::{FrameType, Robot, forward_kinematics};
use gecaro_io::{
    DocumentError, RobotDocument, RobotFile, fallback_name, parse_robot_document, ready_robot,
    ready_robots,
};
use serde::{Deserialize, Serialize};

use super::json::Json;
use crate::error::ApiError;
use crate::limits::MAX_TABLE_JOINTS;
use crate::state::AppState;
use crate::workspace::Listing;

/// A method as the menus show it.
#[derive(Serialize)]
pub(crate) struct MethodView {
    name: &'static str,
    title: &'static str,
    /// CSV columns after `qm1..qmn`.
    columns: Vec<&'static str>,
    uses_plane: bool,
    uses_sets: bool,
    uses_orientation: bool,
    /// Whether the method's measurements see elastic joints' sag (a
    /// compliance level, a payload and a gravity tilt apply to its data).
    elastic: bool,
}

/// The defaults a request takes for what it does not say, as the command
/// line and Python take them: the page's fields start at them.
#[derive(Serialize)]
struct Defaults {
    max_iterations: usize,
    seed: u64,
    outlier_threshold: f64,
    /// Cycles of an ISO 9283 test.
    cycles: usize,
    /// Poses a parallel robot's generation and analysis draw.
    parallel_poses: usize,
}

/// What the page needs to start.
#[derive(Serialize)]
pub(crate) struct Info {
    version: &'static str,
    folder: String,
    ready: Vec<&'static str>,
    methods: Vec<MethodView>,
    /// What one request may ask for (the application layer's bounds), so
    /// that the page checks its fields against the same numbers.
    limits: Limits,
    defaults: Defaults,
}

/// The bounds of [`gecaro_app::limits`] the page's fields are checked against.
#[derive(Serialize)]
struct Limits {
    /// Configurations generated or planned, and candidates of a pool.
    generate: usize,
    /// Random configurations of an identifiability analysis.
    random: usize,
    /// Iterations of one identification.
    iterations: usize,
    /// Cross-validation folds.
    folds: usize,
    /// Cycles of an ISO 9283 test.
    cycles: usize,
}

pub(crate) async fn info(State(state): State<AppState>) -> Json<Info> {
    let methods = METHODS
        .iter()
        .map(|info| {
            // Options do not change a method's columns: build with defaults.
            let method = gecaro_calib::methods::method(
                info.name,
                &gecaro_calib::methods::MethodOptions::default(),
            )
            .ok();
            let columns = method
                .as_ref()
                .map(|method| method.data_columns().to_vec())
                .unwrap_or_default();
            MethodView {
                name: info.name,
                title: info.title,
                columns: columns
                    .iter()
                    .flat_map(|c| c.headers().iter().copied())
                    .collect(),
                uses_plane: info.uses_plane,
                uses_sets: columns.contains(&DataColumn::Set),
                uses_orientation: columns.contains(&DataColumn::Orientation),
                elastic: method.is_some_and(|method| method.sensor().yields_to_loads()),
            }
        })
        .collect();
    Json(Info {
        version: env!("CARGO_PKG_VERSION"),
        folder: state.workspace().root().display().to_string(),
        ready: ready_robots().iter().map(|ready| ready.name).collect(),
        methods,
        limits: Limits {
            generate: gecaro_app::limits::MAX_GENERATE,
            random: gecaro_app::limits::MAX_RANDOM,
            iterations: gecaro_app::limits::MAX_ITERATIONS,
            folds: gecaro_app::limits::MAX_FOLDS,
            cycles: gecaro_app::MAX_CYCLES,
        },
        defaults: Defaults {
            max_iterations: gecaro_calib::identification::DEFAULT_MAX_ITERATIONS,
            seed: gecaro_calib::simulation::DEFAULT_SEED,
            outlier_threshold: gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD,
            cycles: gecaro_calib::iso9283::DEFAULT_CYCLES,
            parallel_poses: gecaro_app::parallel::DEFAULT_POSES,
        },
    })
}

pub(crate) async fn files(State(state): State<AppState>) -> Result<Json<Listing>, ApiError> {
    state
        .files(|state| Ok(Json(state.workspace().list())))
        .await
}

/// One joint's range, in metres or radians.
#[derive(Serialize)]
struct JointView {
    revolute: bool,
    qmin: f64,
    qmax: f64,
}

/// What the page shows of a valid robot beyond its table.
#[derive(Serialize)]
pub(crate) struct Summary {
    name: String,
    letters: String,
    joints: Vec<JointView>,
    /// The priority matrix in force (the document's, or the paper's defaults).
    priority: Vec<[u32; 6]>,
    /// Whether `priority` is the default one.
    default_priority: bool,
    parameter_count: usize,
    /// A plane through the middle of the workspace (normal of Table 2), to
    /// start the plane methods from.
    plane_normal: [f64; 3],
    plane_point: Option<[f64; 3]>,
}

fn summary(robot: &Robot) -> Summary {
    Summary {
        name: robot.name().to_owned(),
        letters: robot.joint_letters(),
        joints: robot
            .joints()
            .iter()
            .zip(&robot.frames()[1..])
            .map(|(joint, frame)| JointView {
                revolute: frame.frame_type == FrameType::Revolute,
                qmin: joint.qmin,
                qmax: joint.qmax,
            })
            .collect(),
        priority: robot.priority().rows().to_vec(),
        default_priority: robot.priority_override().is_none(),
        parameter_count: robot.parameters().len(),
        plane_normal: gecaro_calib::table2::TABLE2_PLANE_NORMAL,
        plane_point: gecaro_calib::table2::default_plane(robot)
            .ok()
            .map(|plane| plane.point().into()),
    }
}

/// A robot for the page: where it came from, its document, and either its
/// summary (valid) or its problems.
#[derive(Serialize)]
pub(crate) struct RobotView {
    /// `ready`, `file`, `imported` (converted from another format: saving
    /// writes a new robot file), `uploaded` (from the page, not a file of
    /// the folder: saving asks for a name) or `new`.
    origin: &'static str,
    /// The ready robot's or file's name.
    #[serde(skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    document: RobotDocument,
    problems: Vec<DocumentError>,
    #[serde(skip_serializing_if = "Option::is_none")]
    summary: Option<Summary>,
    /// What a conversion did (folded joints, couplings, default limits).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    notes: Vec<String>,
    /// The opened file's version (a fingerprint of its bytes): a save that
    /// sends it back is refused (409) when the file changed since.
    #[serde(skip_serializing_if = "Option::is_none")]
    version: Option<String>,
}

/// The version of a file's text: a 64-bit fingerprint of its bytes, in hex.
/// It only tells two contents apart (SipHash with fixed keys); a change of
/// the hash between server versions costs one needless question.
fn version_of(text: &str) -> String {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::hash::DefaultHasher::new();
    text.hash(&mut hasher);
    format!("{:016x}", hasher.finish())
}

fn view(origin: &'static str, name: Option<String>, document: RobotDocument) -> RobotView {
    let checked = robot_file(&document);
    let (problems, summary) = match checked {
        Ok(file) => (Vec::new(), Some(summary(&file.robot))),
        Err(ApiError::InvalidRobot(problems)) => (problems, None),
        Err(_) => (Vec::new(), None),
    };
    RobotView {
        origin,
        name,
        document,
        problems,
        summary,
        notes: Vec::new(),
        version: None,
    }
}

pub(crate) async fn ready(UrlPath(name): UrlPath<String>) -> Result<Json<RobotView>, ApiError> {
    let file = ready_robot(&name).ok_or_else(|| {
        let names: Vec<&str> = ready_robots().iter().map(|r| r.name).collect();
        ApiError::NotFound(format!(
            "no ready robot {name:?}; ready robots: {}",
            names.join(", ")
        ))
    })??;
    Ok(Json(view(
        "ready",
        Some(name),
        RobotDocument::from_robot_file(&file),
    )))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileQuery {
    name: String,
    /// URDF: the base link (default: the root).
    base: Option<String>,
    /// URDF: the tip link (default: the leaf with the most moving joints).
    tip: Option<String>,
}

/// Opens a robot file of the folder: a gecaro robot file as it is; a URDF,
/// a SYMORO `.par` file or a DH table (TOML with `convention`) converted
/// into a robot (origin `imported`, with the conversion's notes).
pub(crate) async fn open_file(
    State(state): State<AppState>,
    query: Result<Query<FileQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Json<RobotView>, ApiError> {
    let Query(FileQuery { name, base, tip }) = query?;
    state
        .compute(move |state| {
            let (_, text) = state.workspace().read_text(&name, &ROBOT_EXTENSIONS)?;
            let mut robot = robot_of_text(state, &name, &text, false, (base, tip))?;
            robot.name = Some(name);
            robot.version = Some(version_of(&text));
            Ok(Json(robot))
        })
        .await
}

/// What a robot file opened from the page ends in: a gecaro robot file or a
/// DH table (`.toml`), a URDF, a SYMORO `.par` file.
const ROBOT_EXTENSIONS: [&str; 3] = ["toml", "urdf", "par"];

/// A robot file uploaded from the page (not in the served folder).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct UploadRequest {
    /// The file's name as the browser gives it (`my-arm.urdf`): its
    /// extension tells the format.
    name: String,
    /// Its content.
    text: String,
    base: Option<String>,
    tip: Option<String>,
}

/// Opens an uploaded robot file as [`open_file`] opens one of the folder;
/// nothing is written, and the robot belongs to no file of the folder
/// (Save asks for a name).
pub(crate) async fn upload(
    State(state): State<AppState>,
    Json(request): Json<UploadRequest>,
) -> Result<Json<RobotView>, ApiError> {
    let UploadRequest {
        name,
        text,
        base,
        tip,
    } = request;
    let robot_file = std::path::Path::new(&name)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ROBOT_EXTENSIONS.iter().any(|r| r.eq_ignore_ascii_case(e)));
    if !robot_file {
        return Err(ApiError::BadRequest(format!(
            "{name}: a robot file ends in .toml (a gecaro robot file or a DH table), .urdf or .par (SYMORO)"
        )));
    }
    state
        .compute(move |state| Ok(Json(robot_of_text(state, &name, &text, true, (base, tip))?)))
        .await
}

/// The robot of a file's `text` (named `name`): a gecaro robot file as it
/// is; a URDF, a SYMORO `.par` file or a DH table (TOML with `convention`)
/// converted (origin `imported`, with the conversion's notes). `uploaded`:
/// the text came from the page, not from the folder.
fn robot_of_text(
    state: &AppState,
    name: &str,
    text: &str,
    uploaded: bool,
    (base, tip): (Option<String>, Option<String>),
) -> Result<RobotView, ApiError> {
    let label = std::path::Path::new(name);
    let is_table = |text: &str| text.contains("[[joint]]") && !text.contains("[[frame]]");
    let origin = if uploaded { "uploaded" } else { "file" };
    // `ARM.TOML` is a robot file as `arm.toml` is (issue 75: it was read as
    // a DH table).
    if label
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
        && !is_table(text)
    {
        let mut document = parse_robot_document(text, label)?;
        if document.name.is_none() {
            document.name = Some(fallback_name(label));
        }
        return Ok(view(origin, None, document));
    }
    let mut import = gecaro_app::ImportRequest::new(name.to_owned());
    import.base = base;
    import.tip = tip;
    if uploaded {
        import.text = Some(text.to_owned());
    }
    let imported = import.run(state.workspace())?.imported;
    let mut robot = view(
        if uploaded { "uploaded" } else { "imported" },
        None,
        RobotDocument::from_robot_file(&imported.file),
    );
    robot.notes = imported.notes;
    Ok(robot)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RobotRequest {
    robot: RobotDocument,
}

/// Checks an edited table: its problems, or its summary.
pub(crate) async fn check(Json(request): Json<RobotRequest>) -> Json<RobotView> {
    Json(view("edited", None, request.robot))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NewRequest {
    /// Joint letters, R and P (`RRPRRR`).
    joints: String,
    name: Option<String>,
}

pub(crate) async fn new(Json(request): Json<NewRequest>) -> Result<Json<RobotView>, ApiError> {
    if request.joints.len() > MAX_TABLE_JOINTS {
        return Err(ApiError::BadRequest(format!(
            "{} joints: the server takes robots of up to {MAX_TABLE_JOINTS} joints",
            request.joints.len()
        )));
    }
    let name = request
        .name
        .unwrap_or_else(|| format!("new {} arm", request.joints.to_uppercase()));
    let robot = Robot::template(name, &request.joints)
        .map_err(|error| ApiError::BadRequest(error.to_string()))?;
    let file = RobotFile {
        description: Some(format!("{} arm (template)", request.joints.to_uppercase())),
        ..RobotFile::of(robot)
    };
    Ok(Json(view(
        "new",
        None,
        RobotDocument::from_robot_file(&file),
    )))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SaveRequest {
    robot: RobotDocument,
    /// The file, relative to the folder, ending in `.toml` (a robot file) or
    /// `.urdf` (the robot as a URDF, names kept from an imported one).
    name: String,
    #[serde(default)]
    overwrite: bool,
    /// The version of the file when it was opened (`version` of the open):
    /// the save is refused (409) if the file changed since.
    expected_version: Option<String>,
}

#[derive(Serialize)]
pub(crate) struct Saved {
    name: String,
    path: String,
    /// The saved file's version, for the next save.
    version: String,
    /// The joint calibration written beside a URDF, when gains or couplings
    /// are not expressible in it.
    #[serde(skip_serializing_if = "Option::is_none")]
    joint_calibration: Option<String>,
    /// What the conversion changed (URDF).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    notes: Vec<String>,
}

/// Saves a valid robot to a file of the folder (atomically): a robot file,
/// or a URDF with its joint calibration beside it when needed.
pub(crate) async fn save(
    State(state): State<AppState>,
    Json(request): Json<SaveRequest>,
) -> Result<Json<Saved>, ApiError> {
    let file = robot_file(&request.robot)?;
    state
        .files(move |state| {
            let workspace = state.workspace();
            // One save at a time from the check of the version to the last
            // file written (a URDF and its joint calibration).
            workspace.writing_pair(|| {
                if let Some(expected) = &request.expected_version {
                    match workspace.read_text(&request.name, &["toml", "urdf"]) {
                        Ok((_, current)) if version_of(&current) != *expected => {
                            return Err(ApiError::Conflict(format!(
                                "{} changed since it was opened (saved from elsewhere): reload \
                                 it to see that change, or save again to replace it with yours",
                                request.name
                            )));
                        }
                        // Unchanged, or removed since: saved as asked.
                        _ => {}
                    }
                }
                let mut saved = save_file(workspace, &request, file)?;
                let (_, written) = workspace.read_text(&request.name, &["toml", "urdf"])?;
                saved.version = version_of(&written);
                Ok(Json(saved))
            })
        })
        .await
}

/// Writes the robot file or the URDF (and its joint calibration) of `request`.
fn save_file(
    workspace: &crate::workspace::Workspace,
    request: &SaveRequest,
    file: RobotFile,
) -> Result<Saved, ApiError> {
    let as_urdf = std::path::Path::new(&request.name)
        .extension()
        .is_some_and(|extension| extension == "urdf");
    if !as_urdf {
        let text = gecaro_io::robot_file_text(&file, std::path::Path::new(&request.name))?;
        let path = workspace.write(&request.name, "toml", text.as_bytes(), request.overwrite)?;
        return Ok(Saved {
            name: request.name.clone(),
            path: path.display().to_string(),
            version: String::new(),
            joint_calibration: None,
            notes: Vec::new(),
        });
    }
    let mut export =
        gecaro_app::ExportRequest::new(gecaro_app::RobotSource::Loaded(Box::new(file)), "urdf");
    export.output.save_as = Some(request.name.clone());
    export.output.overwrite = request.overwrite;
    let exported = export.run(workspace)?;
    let calibration_name = exported
        .exported
        .joint_calibration
        .as_ref()
        .map(|_| gecaro_app::joint_calibration_name(&request.name));
    let path = workspace.display_path(&request.name)?;
    Ok(Saved {
        name: request.name.clone(),
        path: path.display().to_string(),
        version: String::new(),
        joint_calibration: calibration_name,
        notes: exported.exported.notes,
    })
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PoseRequest {
    robot: RobotDocument,
    /// Joint variables q (radians or metres), one per joint.
    q: Vec<f64>,
}

/// A frame's pose: origin and axes in the world frame.
#[derive(Serialize)]
pub(crate) struct FramePose {
    origin: [f64; 3],
    x: [f64; 3],
    y: [f64; 3],
    z: [f64; 3],
}

#[derive(Serialize)]
pub(crate) struct Pose {
    /// Frames 0..n+1.
    frames: Vec<FramePose>,
    /// The motor variables of the configuration (eq. 4 inverted).
    motor: Vec<f64>,
}

/// The frames at a joint configuration, for the robot view.
pub(crate) async fn pose(Json(request): Json<PoseRequest>) -> Result<Json<Pose>, ApiError> {
    let robot = robot_file(&request.robot)?.robot;
    let motor = robot.motor_positions(&request.q)?;
    let chain = forward_kinematics(&robot, motor.as_slice())?;
    let column = |pose: &nalgebra::IsometryMatrix3<f64>, axis: usize| -> [f64; 3] {
        let c = pose.rotation.matrix().column(axis);
        [c[0], c[1], c[2]]
    };
    let frames = chain
        .poses()
        .iter()
        .map(|pose| {
            let t = pose.translation.vector;
            FramePose {
                origin: [t.x, t.y, t.z],
                x: column(pose, 0),
                y: column(pose, 1),
                z: column(pose, 2),
            }
        })
        .collect();
    Ok(Json(Pose {
        frames,
        motor: motor.iter().copied().collect(),
    }))
}

/// The validated robot of a document.
///
/// # Errors
/// [`ApiError::InvalidRobot`] with every problem of the document.
pub(crate) fn robot_file(document: &RobotDocument) -> Result<RobotFile, ApiError> {
    Ok(gecaro_app::robot_of_document(document)?)
}
