//! Robot files: TOML meant to be written and read by a person.
//!
//! ```toml
//! name = "Stanford"
//! angle_unit = "rad"         # optional: "rad" (default) or "deg"
//! description = "Table 1"    # optional free text
//! gravity = [0, 0, -9.80665] # optional: m/s² in the world frame (this default)
//!
//! [[frame]]                  # frame 0, the base; frames in order 0..n+1
//! sigma = 2
//! theta = 1.5707963267948966
//! r = 0.5
//!
//! [[frame]]                  # frame 1, a joint
//! sigma = 0                  # 0 revolute, 1 prismatic, 2 fixed
//! alpha = 0.1
//! qmin = -3.14159
//! qmax = 3.14159
//! # omitted: alpha = d = theta = r = beta = 0, K = 1, offset = 0,
//! # qmin/qmax = ±π (revolute) or 0..1 m (prismatic)
//!
//! [[frame]]                  # frame 2, with the mass of link 2 (optional:
//! sigma = 0                  # the loads of elastic joints)
//! mass = 4.2                 # kg
//! com = [0.12, 0.0, 0.03]    # its centre in frame 2 (m); the origin if omitted
//! compliance = 4e-6          # optional: rad/(N·m) (m/N if prismatic), in any
//!                            # angle unit; on any joint it makes the robot
//!                            # elastic, the other joints at 0 (issue 38)
//! measured = [-0.26, 0.26]   # optional: the range of q2 a calibration's data
//!                            # covered, in qmin's unit (written when the
//!                            # result holds there only; compensate and
//!                            # evaluate flag poses outside it)
//!
//! [coupling]                 # optional, n×n each, identity by default (eq. 4)
//! Cm = [[1.0, 0.0], [0.0, 1.0]]
//! Cj = [[1.0, 0.0], [0.0, 1.0]]
//!
//! [priority]                 # optional: (n+2) rows of [alpha, d, theta, r, beta, K]
//! matrix = [[0, 0, 2, 4, 0, 0], ...]
//! ```
//!
//! With `angle_unit = "deg"`, α, θ, β and the limits and offset of revolute
//! joints are in degrees. In radians, an angle larger than 2π in magnitude is
//! refused as a likely degrees/radians mix-up. Unknown keys are refused with
//! the closest known key. gecaro writes files in radians with every digit
//! (Rust's shortest round-trip form), so load → save → load is the identity.

use std::fmt::Write as _;
use std::path::Path;

use gecaro_core::{FrameType, PriorityMatrix, Robot};
use nalgebra::DMatrix;
use serde::Deserialize;

use crate::Error;
use crate::document::{PriorityDocument, RobotDocument};
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::problem::{DocumentError, Location, model_error};
use crate::robot_file::{AngleUnit, RobotFile, fallback_name};
use crate::toml_source::Source;
use crate::urdf::names::UrdfDocument;

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "angle_unit",
    "frame",
    "coupling",
    "priority",
    "urdf",
    "gravity",
    "tool_frame_observed",
    "tools",
];
const FRAME_KEYS: &[&str] = &[
    "sigma",
    "alpha",
    "d",
    "theta",
    "r",
    "beta",
    "qmin",
    "qmax",
    "offset",
    "K",
    "mass",
    "com",
    "compliance",
    "measured",
];
const COUPLING_KEYS: &[&str] = &["Cm", "Cj"];
const PRIORITY_KEYS: &[&str] = &["matrix", "priority"];

/// Reads a robot file.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::Parse`] naming the
/// line and key of the first problem otherwise.
pub fn read_robot_file(path: &Path) -> Result<RobotFile, Error> {
    let text = read_text(path, MAX_DESCRIPTION_BYTES)?;
    parse_robot_file(&text, path)
}

/// Parses the text of a robot file; `path` only names it in messages.
///
/// # Errors
/// [`Error::Parse`] naming the line and key of the first problem.
pub fn parse_robot_file(text: &str, path: &Path) -> Result<RobotFile, Error> {
    // A URDF or a SYMORO file where gecaro's TOML is read: named as such,
    // not as a TOML syntax error on its first line.
    if let Some(format) = crate::interchange::RobotFormat::guess(path) {
        return Err(Error::Format {
            path: path.to_owned(),
            message: format!(
                "a {} file, not a gecaro robot file (TOML): convert it with `gecaro robot import \
                 {} -o robot.toml`",
                match format {
                    crate::interchange::RobotFormat::Urdf => "URDF",
                    _ => "SYMORO",
                },
                path.display()
            ),
        });
    }
    if crate::parallel_file::is_parallel_robot_text(text) {
        return Err(parallel_robot_here(path));
    }
    let source = Source { path, text };
    let document = parse_robot_document(text, path)?;
    document
        .to_robot_file(&fallback_name(path))
        .map_err(|error| source.document_error(error))
}

/// The error of a parallel robot's file where a serial robot's is read.
pub(crate) fn parallel_robot_here(path: &Path) -> Error {
    Error::Format {
        path: path.to_owned(),
        message: "a parallel robot (`kind = \"parallel\"`: a Gough–Stewart platform or a \
                  Delta), where this job needs a serial robot's frames; a parallel robot is \
                  read by `robot show`, `robot check`, `generate`, `identifiable`, `plan`, \
                  `predict`, `identify`, `report`, `evaluate` and `compensate`"
            .into(),
    }
}

/// Parses the text of a robot file into its document, without checking the
/// model's rules (the web page shows an invalid robot to be fixed); `path`
/// only names it in messages.
///
/// # Errors
/// [`Error::Parse`] for TOML syntax errors, unknown keys and values of the
/// wrong type, naming the line.
pub fn parse_robot_document(text: &str, path: &Path) -> Result<RobotDocument, Error> {
    let source = Source { path, text };
    toml::from_str(text).map_err(|error| toml_error(&source, &error))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PriorityFileDocument {
    matrix: Option<Vec<Vec<i64>>>,
    priority: Option<PriorityDocument>,
}

/// Reads a priority matrix from a TOML file holding `matrix = [[...], ...]`,
/// or a `[priority]` table with it (so a robot file's table can be reused),
/// and checks it against `robot`.
///
/// # Errors
/// [`Error::Read`], or [`Error::Parse`] with the line of the problem.
pub fn read_priority_file(path: &Path, robot: &Robot) -> Result<PriorityMatrix, Error> {
    let text = read_text(path, MAX_DESCRIPTION_BYTES)?;
    parse_priority_file(&text, path, robot)
}

/// [`read_priority_file`] from the file's text; `path` names it in messages.
///
/// # Errors
/// As [`read_priority_file`].
pub fn parse_priority_file(
    text: &str,
    path: &Path,
    robot: &Robot,
) -> Result<PriorityMatrix, Error> {
    let source = Source { path, text };
    let file: PriorityFileDocument =
        toml::from_str(text).map_err(|error| toml_error(&source, &error))?;
    let document = match (file.matrix, file.priority) {
        (Some(matrix), None) => PriorityDocument { matrix },
        (None, Some(table)) => table,
        _ => {
            return Err(Error::parse(
                path,
                1,
                Some("matrix".into()),
                "a priority file holds `matrix = [[alpha, d, theta, r, beta, K], ...]` (one row per \
                 frame), at the top or in a [priority] table",
            ));
        }
    };
    // Rows are located relative to the `matrix` key, wherever it is.
    let matrix_line = text
        .lines()
        .position(|line| line.trim_start().starts_with("matrix"))
        .map_or(1, |i| i + 1);
    let row_line = |row: Option<usize>| {
        row.and_then(|row| {
            text.lines()
                .enumerate()
                .skip(matrix_line)
                .filter(|(_, line)| line.trim_start().starts_with('['))
                .nth(row)
                .map(|(i, _)| i + 1)
        })
        .unwrap_or(matrix_line)
    };
    let fail = |error: DocumentError| {
        let row = match &error.location {
            Location::Priority { row } => *row,
            _ => None,
        };
        Error::parse(
            path,
            row_line(row),
            Some(error.location.to_string()),
            error.message,
        )
    };
    let priority = document.read().map_err(fail)?;
    priority
        .validate(robot.parameters())
        .map_err(|error| fail(model_error(error)))?;
    Ok(priority)
}

fn toml_error(source: &Source<'_>, error: &toml::de::Error) -> Error {
    source.toml_error(error, &[TOP_KEYS, FRAME_KEYS, COUPLING_KEYS, PRIORITY_KEYS])
}

/// The text of the robot file `path` is to hold, read back first: a robot
/// that would not load (a length beyond ±1 km left by a runaway
/// identification, a gain set to 1e300) is refused before anything is
/// written, so every robot file gecaro writes loads again.
///
/// # Errors
/// [`Error::Format`] naming `path` and the value at fault.
pub fn robot_file_text(file: &RobotFile, path: &Path) -> Result<String, Error> {
    let refuse = |message: String| Error::Format {
        path: path.to_owned(),
        message: format!("not written: the robot would not load again ({message})"),
    };
    file.robot
        .check_stated()
        .map_err(|error| refuse(error.to_string()))?;
    let text = format_robot_file(file);
    parse_robot_file(&text, path).map_err(|error| refuse(error.to_string()))?;
    Ok(text)
}

/// Writes a robot file's text (see the module docs for the format).
pub fn format_robot_file(file: &RobotFile) -> String {
    let robot = &file.robot;
    let unit = file.angle_unit;
    let angle = |value: f64| match unit {
        AngleUnit::Radians => value,
        AngleUnit::Degrees => value.to_degrees(),
    };
    let mut text = String::new();
    let unit_name = match unit {
        AngleUnit::Radians => "radians",
        AngleUnit::Degrees => "degrees",
    };
    let _ = writeln!(
        text,
        "# gecaro robot file: Khalil–Kleinfinger frames 0..n+1 (GECARO eq. 3).\n\
         # Lengths in metres, angles in {unit_name}; sigma = 0 revolute, 1 prismatic, 2 fixed."
    );
    let _ = writeln!(text, "name = {}", toml_string(robot.name()));
    if let Some(description) = &file.description {
        let _ = writeln!(text, "description = {}", toml_string(description));
    }
    if unit == AngleUnit::Degrees {
        let _ = writeln!(text, "angle_unit = \"deg\"");
    }
    let gravity = file.stated_gravity();
    if gravity != gecaro_core::upright_gravity() {
        let _ = writeln!(
            text,
            "gravity = [{}, {}, {}] # m/s², world frame",
            float(gravity.x),
            float(gravity.y),
            float(gravity.z)
        );
    }
    if !file.tool_frame_observed {
        let _ = writeln!(
            text,
            "tool_frame_observed = false # every set of the calibration measured a named tool: \
             frame n+1 is the nominal's, the tools below are calibrated"
        );
    }
    let last = robot.frames().len() - 1;
    for (j, frame) in robot.frames().iter().enumerate() {
        let role = match (j, frame.frame_type) {
            (0, _) => "base".to_owned(),
            (j, _) if j == last => "end-effector".to_owned(),
            (j, FrameType::Prismatic) => format!("joint {j}, prismatic"),
            (j, _) => format!("joint {j}, revolute"),
        };
        let _ = writeln!(text, "\n[[frame]] # frame {j}: {role}");
        let _ = writeln!(text, "sigma = {}", frame.frame_type.sigma());
        if j != 0 {
            let _ = writeln!(text, "alpha = {}", float(angle(frame.alpha)));
            let _ = writeln!(text, "d = {}", float(frame.d));
        }
        let _ = writeln!(text, "theta = {}", float(angle(frame.theta)));
        let _ = writeln!(text, "r = {}", float(frame.r));
        if j != 0 {
            let _ = writeln!(text, "beta = {}", float(angle(frame.beta)));
        }
        if j >= 1 && j <= robot.joint_count() {
            let joint = &robot.joints()[j - 1];
            let joint_angle = |value: f64| match frame.frame_type {
                FrameType::Revolute => angle(value),
                _ => value,
            };
            let _ = writeln!(text, "qmin = {}", float(joint_angle(joint.qmin)));
            let _ = writeln!(text, "qmax = {}", float(joint_angle(joint.qmax)));
            let _ = writeln!(text, "offset = {}", float(joint_angle(joint.offset)));
            let _ = writeln!(text, "K = {}", float(joint.gain));
            if let Some(compliances) = robot.compliances() {
                let unit = match frame.frame_type {
                    FrameType::Prismatic => "m/N",
                    _ => "rad/(N·m)",
                };
                let _ = writeln!(text, "compliance = {} # {unit}", float(compliances[j - 1]));
            }
            if let Some(region) = &file.measured_region {
                let (min, max) = region.range(j - 1);
                let _ = writeln!(
                    text,
                    "measured = [{}, {}] # the range the calibration's data covered",
                    float(joint_angle(min)),
                    float(joint_angle(max))
                );
            }
        }
        if let Some(link) = file.masses.link(j) {
            let _ = writeln!(text, "mass = {} # kg", float(link.mass));
            let _ = writeln!(
                text,
                "com = [{}, {}, {}] # centre of mass in frame {j} (m)",
                float(link.com.x),
                float(link.com.y),
                float(link.com.z)
            );
        }
    }
    let n = robot.joint_count();
    let identity = DMatrix::<f64>::identity(n, n);
    let couplings = [
        ("Cm", robot.motor_coupling()),
        ("Cj", robot.joint_coupling()),
    ];
    if couplings.iter().any(|(_, matrix)| **matrix != identity) {
        let _ = writeln!(text, "\n[coupling] # q = Cj·diag(K)·Cm·qm + offset (eq. 4)");
        for (name, matrix) in couplings {
            let rows: Vec<String> = matrix
                .row_iter()
                .map(|row| {
                    format!(
                        "[{}]",
                        row.iter().map(|v| float(*v)).collect::<Vec<_>>().join(", ")
                    )
                })
                .collect();
            let _ = writeln!(text, "{name} = [{}]", rows.join(", "));
        }
    }
    if let Some(priority) = robot.priority_override() {
        let _ = writeln!(
            text,
            "\n[priority] # rows: frames 0..n+1; columns: alpha, d, theta, r, beta, K"
        );
        let _ = writeln!(text, "matrix = [");
        for row in priority.rows() {
            let cells: Vec<String> = row.iter().map(ToString::to_string).collect();
            let _ = writeln!(text, "    [{}],", cells.join(", "));
        }
        let _ = writeln!(text, "]");
    }
    for tool in &file.tools {
        let [x, y, z, w, i, j, k] = crate::pose::to_seven(&tool.pose);
        let _ = writeln!(
            text,
            "\n[tools.{}] # identified with the robot: its pose in frame n+1\n\
             position = [{}, {}, {}] # m\nquaternion = [{}, {}, {}, {}] # w, x, y, z",
            toml_key(&tool.name),
            float(x),
            float(y),
            float(z),
            float(w),
            float(i),
            float(j),
            float(k)
        );
    }
    if let Some(names) = &file.urdf {
        #[derive(serde::Serialize)]
        struct Table<'a> {
            urdf: &'a UrdfDocument,
        }
        let document = UrdfDocument::from_names(names);
        if let Ok(table) = toml::to_string(&Table { urdf: &document }) {
            let _ = writeln!(
                text,
                "\n# Names and link frames of the URDF this robot was imported from, for\n\
                 # `gecaro robot export --to urdf` (link_frame: the link in frame j, x y z qw qx qy qz).\n{table}"
            );
        }
    }
    text
}

/// A TOML key: bare when it may be, quoted otherwise.
fn toml_key(name: &str) -> String {
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        name.to_owned()
    } else {
        toml_string(name)
    }
}

/// A float in TOML form that reads back to the same bits.
fn float(value: f64) -> String {
    // `{:?}` is Rust's shortest round-trip form and always has a '.' or an exponent.
    let text = format!("{value:?}");
    if value.is_finite() {
        text
    } else {
        "nan".into()
    }
}

fn toml_string(text: &str) -> String {
    toml::Value::String(text.to_owned()).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const STANFORD: &str = r#"
name = "Stanford"
[[frame]]
sigma = 2
theta = 1.5707963267948966
r = 0.5
[[frame]]
sigma = 0
alpha = 0.1
qmin = -3.14159
qmax = 3.14159
[[frame]]
sigma = 0
alpha = -1.5707963267948966
r = 0.2
[[frame]]
sigma = 1
alpha = 1.5707963267948966
[[frame]]
sigma = 0
[[frame]]
sigma = 0
alpha = -1.5707963267948966
[[frame]]
sigma = 0
alpha = 1.5707963267948966
[[frame]]
sigma = 2
alpha = 1.3
d = 0.2
theta = 1.5707963267948966
r = 0.1
"#;

    fn parse(text: &str) -> Result<RobotFile, Error> {
        parse_robot_file(text, Path::new("robot.toml"))
    }

    fn parse_error(text: &str) -> (usize, String) {
        match parse(text) {
            Err(Error::Parse {
                line,
                field,
                message,
                ..
            }) => (
                line,
                format!("{}{message}", field.map(|f| f + ": ").unwrap_or_default()),
            ),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    #[allow(clippy::approx_constant)] // the example file writes the limit as -3.14159
    fn the_issue_example_loads() {
        let file = parse(STANFORD).expect("valid");
        assert_eq!(file.robot.joint_letters(), "RRPRRR");
        assert_eq!(file.robot.joints()[0].qmin, -3.14159);
        assert_eq!(file.robot.joints()[2].gain, 1.0);
    }

    #[test]
    fn save_then_load_is_the_identity() {
        let file = parse(STANFORD).expect("valid");
        let again = parse(&format_robot_file(&file)).expect("valid");
        assert_eq!(file, again);
    }

    #[test]
    fn masses_and_gravity_read_back_and_bad_ones_name_their_line() {
        // Link 2's mass with its centre, the tool's at its origin, a tilted
        // gravity: written, read back to the same file.
        let text = STANFORD
            .replacen(
                "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2",
                "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2\nmass = 4.5\ncom = [0.1, 0, -0.02]",
                1,
            )
            .replacen("r = 0.1\n", "r = 0.1\nmass = 12\n", 1);
        let text = format!("gravity = [0.1, 0.0, -9.8]\n{text}");
        let file = parse(&text).expect("valid");
        let link = file.masses.link(2).expect("link 2");
        assert_eq!((link.mass, link.com.x, link.com.z), (4.5, 0.1, -0.02));
        let tool = file.masses.link(7).expect("the tool");
        assert_eq!((tool.mass, tool.com.norm()), (12.0, 0.0));
        assert_eq!(file.masses.gravity().x, 0.1);
        let written = format_robot_file(&file);
        assert!(written.contains("mass = 4.5 # kg"), "{written}");
        assert_eq!(parse(&written).expect("valid"), file);
        // Without masses, nothing is written.
        assert!(!format_robot_file(&parse(STANFORD).expect("valid")).contains("compliance"));
        assert!(!format_robot_file(&parse(STANFORD).expect("valid")).contains("mass"));
        // A negative mass, a centre without its mass, a centre of two values.
        let (line, message) = parse_error(&text.replace("mass = 4.5", "mass = -4.5"));
        assert!(
            message.contains("frame 2") && message.contains("not a link's mass"),
            "{line}: {message}"
        );
        assert_eq!(line, 17, "{message}");
        let (_, message) = parse_error(&text.replace("mass = 4.5\n", ""));
        assert!(message.contains("without its `mass`"), "{message}");
        let (line, message) = parse_error(&text.replace("[0.1, 0, -0.02]", "[0.1, 0]"));
        assert_eq!(line, 18, "{message}");
        // Values no robot has (issue 75): refused, naming what.
        for (from, to, words) in [
            ("mass = 4.5", "mass = 1e300", "not a link's mass"),
            ("[0.1, 0, -0.02]", "[1e300, 0, 0]", "from its frame"),
            (
                "gravity = [0.1, 0.0, -9.8]",
                "gravity = [0, 0, -1e300]",
                "10 g",
            ),
            (
                "compliance = 4e-6",
                "compliance = 0.5",
                "no joint's compliance",
            ),
        ] {
            let text = if from.starts_with("compliance") {
                STANFORD.replacen(
                    "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2",
                    "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2\ncompliance = 4e-6",
                    1,
                )
            } else {
                text.clone()
            };
            assert!(text.contains(from), "{from}");
            let (_, message) = parse_error(&text.replace(from, to));
            assert!(message.contains(words), "{to}: {message}");
        }
    }

    /// A compliance on one joint makes the robot elastic (the others at 0);
    /// written back on every joint and read to the same robot; on a fixed
    /// frame, or not a number, it is refused at its line.
    #[test]
    fn compliances_make_an_elastic_robot_and_read_back() {
        let text = STANFORD.replacen(
            "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2",
            "[[frame]]\nsigma = 0\nalpha = -1.5707963267948966\nr = 0.2\ncompliance = 4e-6",
            1,
        );
        let file = parse(&text).expect("valid");
        assert_eq!(
            file.robot.compliances(),
            Some(&[0.0, 4e-6, 0.0, 0.0, 0.0, 0.0][..])
        );
        // 43, the six compliances and gravity's two tilts.
        assert_eq!(file.robot.parameters().len(), 51);
        let written = format_robot_file(&file);
        assert_eq!(written.matches("compliance = ").count(), 6, "{written}");
        assert!(
            written.contains("compliance = 4e-6 # rad/(N·m)"),
            "{written}"
        );
        assert!(written.contains("# m/N"), "{written}");
        assert_eq!(parse(&written).expect("valid"), file);
        // Gravity's identified tilt is written as the gravity it leans to.
        let mut tilted = file.clone();
        let tilt = gecaro_core::ParameterId::new(gecaro_core::ParameterKind::GravityTilt, 2);
        tilted.robot.set_parameter(tilt, 0.03).expect("tilt");
        let read = parse(&format_robot_file(&tilted)).expect("valid");
        assert_eq!(read.robot.gravity_tilt(), [0.0; 2]);
        assert_eq!(
            read.masses.gravity(),
            file.masses.tilted([0.0, 0.03]).gravity()
        );
        assert!(read.masses.gravity().x < -0.2, "{}", read.masses.gravity());
        // The JSON document (the page's, Python's) states the same gravity.
        let document = crate::RobotDocument::from_robot_file(&tilted);
        let back = document.to_robot_file("tilted").expect("valid");
        assert_eq!(back.masses.gravity(), read.masses.gravity());
        assert_eq!(
            tilted.clone().with_gravity_tilt_folded().masses.gravity(),
            read.masses.gravity()
        );
        let (line, message) =
            parse_error(&text.replacen("r = 0.1\n", "r = 0.1\ncompliance = 1\n", 1));
        assert!(
            message.contains("no joint to be compliant"),
            "{line}: {message}"
        );
        let (line, message) =
            parse_error(&text.replace("compliance = 4e-6", "compliance = \"soft\""));
        assert_eq!(line, 16, "{message}");
    }

    #[test]
    fn errors_name_line_and_key() {
        let text = STANFORD.replace("sigma = 1\n", "sigma = 3\n");
        let (line, message) = parse_error(&text);
        assert_eq!(line, 17);
        assert!(
            message.contains("frame 3, sigma") && message.contains("sigma = 3"),
            "{message}"
        );

        let text = STANFORD.replace("alpha = 0.1", "alpah = 0.1");
        let (line, message) = parse_error(&text);
        assert_eq!(line, 9);
        assert!(message.contains("did you mean `alpha`"), "{message}");

        let text = STANFORD.replace("alpha = 0.1", "alpha = 90");
        let (_, message) = parse_error(&text);
        assert!(message.contains("angle_unit"), "{message}");

        let text = STANFORD.replace("alpha = 0.1", "alpha = nan");
        let (line, message) = parse_error(&text);
        assert_eq!(line, 9);
        assert!(message.contains("not a finite number"), "{message}");

        let text = STANFORD.replace("qmax = 3.14159", "qmax = -3.2");
        let (line, message) = parse_error(&text);
        assert_eq!(line, 10, "{message}");
        assert!(
            message.contains("qmin = -3.14159 is greater than qmax = -3.2"),
            "{message}"
        );
    }

    #[test]
    fn degrees_are_converted() {
        let text = STANFORD
            .replace(
                "name = \"Stanford\"",
                "name = \"Stanford\"\nangle_unit = \"deg\"",
            )
            .replace("alpha = 0.1", "alpha = 90");
        let file = parse(&text.replace("1.5707963267948966", "90")).expect("valid");
        assert_eq!(file.robot.frames()[1].alpha, 90f64.to_radians());
        assert!((file.robot.frames()[7].theta - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let again = parse(&format_robot_file(&file)).expect("valid");
        for (a, b) in file.robot.frames().iter().zip(again.robot.frames()) {
            assert!((a.alpha - b.alpha).abs() < 1e-15 && (a.theta - b.theta).abs() < 1e-15);
        }
    }
}
