//! Robot files: TOML meant to be written and read by a person.
//!
//! ```toml
//! name = "Stanford"
//! angle_unit = "rad"         # optional: "rad" (default) or "deg"
//! description = "Table 1"    # optional free text
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

use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};

use gecaro_core::{Field, Frame, FrameType, Joint, PriorityMatrix, Robot, RobotSpec};
use nalgebra::DMatrix;
use serde::Deserialize;
use toml::Spanned;

use crate::Error;

/// The unit of the angles written in a robot file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum AngleUnit {
    /// Radians (the default, and what gecaro writes).
    #[default]
    Radians,
    /// Degrees (`angle_unit = "deg"`).
    Degrees,
}

/// A robot as read from or written to a file, with the file-only details.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotFile {
    /// The robot.
    pub robot: Robot,
    /// Free text kept from the file's `description` key.
    pub description: Option<String>,
    /// The unit the file's angles were written in.
    pub angle_unit: AngleUnit,
}

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "angle_unit",
    "frame",
    "coupling",
    "priority",
];
const FRAME_KEYS: &[&str] = &[
    "sigma", "alpha", "d", "theta", "r", "beta", "qmin", "qmax", "offset", "K",
];
const COUPLING_KEYS: &[&str] = &["Cm", "Cj"];
const PRIORITY_KEYS: &[&str] = &["matrix", "priority"];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRobot {
    name: Option<Spanned<String>>,
    description: Option<String>,
    angle_unit: Option<Spanned<String>>,
    frame: Option<Spanned<Vec<Spanned<RawFrame>>>>,
    coupling: Option<Spanned<RawCoupling>>,
    priority: Option<Spanned<RawPriority>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFrame {
    sigma: Option<Spanned<i64>>,
    alpha: Option<Spanned<f64>>,
    d: Option<Spanned<f64>>,
    theta: Option<Spanned<f64>>,
    r: Option<Spanned<f64>>,
    beta: Option<Spanned<f64>>,
    qmin: Option<Spanned<f64>>,
    qmax: Option<Spanned<f64>>,
    offset: Option<Spanned<f64>>,
    #[serde(rename = "K")]
    gain: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct RawCoupling {
    Cm: Option<Spanned<Vec<Spanned<Vec<f64>>>>>,
    Cj: Option<Spanned<Vec<Spanned<Vec<f64>>>>>,
}

/// A priority matrix as written: rows of integer cells, each with its place.
type RawPriorityMatrix = Spanned<Vec<Spanned<Vec<Spanned<i64>>>>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPriority {
    matrix: RawPriorityMatrix,
}

/// Byte ranges of the keys of one table.
type KeySpans = BTreeMap<&'static str, Range<usize>>;

/// Byte ranges of the keys of a robot file, to turn a [`Field`] into a line.
#[derive(Default)]
struct SpanIndex {
    frames_table: Option<Range<usize>>,
    frames: Vec<(Range<usize>, KeySpans)>,
    coupling: KeySpans,
    priority: Option<Range<usize>>,
    priority_rows: Vec<Range<usize>>,
}

impl SpanIndex {
    fn span_of(&self, field: &Field) -> Option<Range<usize>> {
        match field {
            Field::Frame { index, key } => self
                .frames
                .get(*index)
                .map(|(table, keys)| keys.get(key).cloned().unwrap_or_else(|| table.clone())),
            Field::Coupling(name) => self.coupling.get(name).cloned(),
            Field::Priority { row: Some(row) } => self
                .priority_rows
                .get(*row)
                .cloned()
                .or_else(|| self.priority.clone()),
            Field::Priority { row: None } => self.priority.clone(),
            _ => self.frames_table.clone(),
        }
    }
}

/// Where a text came from, to name it in messages.
struct Source<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    fn line_of(&self, offset: usize) -> usize {
        let offset = offset.min(self.text.len());
        self.text[..offset].bytes().filter(|b| *b == b'\n').count() + 1
    }

    fn error_at(
        &self,
        span: Option<Range<usize>>,
        field: Option<String>,
        message: impl Into<String>,
    ) -> Error {
        let line = span.map_or(1, |span| self.line_of(span.start));
        Error::parse(self.path, line, field, message)
    }
}

/// Reads a robot file.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::Parse`] naming the
/// line and key of the first problem otherwise.
pub fn read_robot_file(path: &Path) -> Result<RobotFile, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_owned(),
        source,
    })?;
    parse_robot_file(&text, path)
}

/// Parses the text of a robot file; `path` only names it in messages.
///
/// # Errors
/// [`Error::Parse`] naming the line and key of the first problem.
pub fn parse_robot_file(text: &str, path: &Path) -> Result<RobotFile, Error> {
    let source = Source { path, text };
    let raw: RawRobot = toml::from_str(text).map_err(|error| toml_error(&source, &error))?;
    let angle_unit = match &raw.angle_unit {
        None => AngleUnit::Radians,
        Some(unit) => match unit.get_ref().as_str() {
            "rad" | "radian" | "radians" => AngleUnit::Radians,
            "deg" | "degree" | "degrees" => AngleUnit::Degrees,
            other => {
                return Err(source.error_at(
                    Some(unit.span()),
                    Some("angle_unit".into()),
                    format!("must be \"rad\" or \"deg\", not {other:?}"),
                ));
            }
        },
    };
    let mut spans = SpanIndex::default();
    let raw_frames = match &raw.frame {
        Some(frames) if !frames.get_ref().is_empty() => frames,
        _ => {
            return Err(source.error_at(
                None,
                Some("frame".into()),
                "no [[frame]] tables: a robot needs frames 0..n+1 (base, joints, end-effector)",
            ));
        }
    };
    spans.frames_table = Some(raw_frames.span());
    let mut frames = Vec::new();
    let mut joints = Vec::new();
    let last = raw_frames.get_ref().len() - 1;
    for (index, raw_frame) in raw_frames.get_ref().iter().enumerate() {
        let (frame, joint, keys) = read_frame(&source, index, last, raw_frame, angle_unit)?;
        spans.frames.push((raw_frame.span(), keys));
        frames.push(frame);
        if let Some(joint) = joint {
            joints.push(joint);
        }
    }
    let (motor_coupling, joint_coupling) = match &raw.coupling {
        None => (None, None),
        Some(coupling) => {
            let coupling = coupling.get_ref();
            (
                read_coupling(&source, "Cm", coupling.Cm.as_ref(), &mut spans)?,
                read_coupling(&source, "Cj", coupling.Cj.as_ref(), &mut spans)?,
            )
        }
    };
    let priority = match &raw.priority {
        None => None,
        Some(priority) => Some(read_priority(&source, priority, &mut spans)?),
    };
    let name = raw.name.map(Spanned::into_inner).unwrap_or_else(|| {
        path.file_stem()
            .map_or_else(|| "robot".into(), |s| s.to_string_lossy().into_owned())
    });
    let robot = Robot::new(RobotSpec {
        name,
        frames,
        joints,
        motor_coupling,
        joint_coupling,
        priority,
    })
    .map_err(|error| model_error(&source, &spans, error))?;
    Ok(RobotFile {
        robot,
        description: raw.description,
        angle_unit,
    })
}

fn model_error(source: &Source<'_>, spans: &SpanIndex, error: gecaro_core::Error) -> Error {
    match error {
        gecaro_core::Error::Invalid { field, message } => {
            let label = match &field {
                Field::Frame { index, key } => format!("frame {index}, {key}"),
                Field::Coupling(name) => format!("coupling.{name}"),
                Field::Priority { row: Some(row) } => format!("priority.matrix row {row}"),
                Field::Priority { row: None } => "priority.matrix".into(),
                _ => "frame".into(),
            };
            source.error_at(spans.span_of(&field), Some(label), message)
        }
        other => source.error_at(None, None, other.to_string()),
    }
}

fn read_frame(
    source: &Source<'_>,
    index: usize,
    last: usize,
    raw: &Spanned<RawFrame>,
    unit: AngleUnit,
) -> Result<(Frame, Option<Joint>, KeySpans), Error> {
    let table = raw.get_ref();
    let mut keys = BTreeMap::new();
    let at = |span: Range<usize>, key: &str, message: String| {
        source.error_at(Some(span), Some(format!("frame {index}, {key}")), message)
    };
    let Some(sigma) = &table.sigma else {
        return Err(source.error_at(
            Some(raw.span()),
            Some(format!("frame {index}, sigma")),
            "every frame needs `sigma` (0 revolute, 1 prismatic, 2 fixed)",
        ));
    };
    keys.insert("sigma", sigma.span());
    let frame_type = FrameType::from_sigma(*sigma.get_ref()).ok_or_else(|| {
        at(
            sigma.span(),
            "sigma",
            format!(
                "sigma = {} is not a frame type: 0 revolute, 1 prismatic, 2 fixed",
                sigma.get_ref()
            ),
        )
    })?;
    let mut value = |key: &'static str,
                     field: &Option<Spanned<f64>>,
                     default: f64,
                     angle: bool|
     -> Result<f64, Error> {
        let Some(field) = field else {
            return Ok(default);
        };
        keys.insert(key, field.span());
        let raw_value = *field.get_ref();
        if !raw_value.is_finite() {
            return Err(at(
                field.span(),
                key,
                format!("{raw_value} is not a finite number"),
            ));
        }
        if !angle {
            return Ok(raw_value);
        }
        match unit {
            AngleUnit::Degrees => Ok(raw_value.to_radians()),
            AngleUnit::Radians if raw_value.abs() > TAU + 1e-9 => Err(at(
                field.span(),
                key,
                format!(
                    "{raw_value} rad is more than a full turn; the file's angles are in radians \
                     — if it is written in degrees, add angle_unit = \"deg\" at the top"
                ),
            )),
            AngleUnit::Radians => Ok(raw_value),
        }
    };
    let frame = Frame {
        frame_type,
        alpha: value("alpha", &table.alpha, 0.0, true)?,
        d: value("d", &table.d, 0.0, false)?,
        theta: value("theta", &table.theta, 0.0, true)?,
        r: value("r", &table.r, 0.0, false)?,
        beta: value("beta", &table.beta, 0.0, true)?,
    };
    let is_joint = index != 0 && index != last && frame_type != FrameType::Fixed;
    let joint_angle = frame_type == FrameType::Revolute;
    let joint = if is_joint {
        let defaults = Joint::default_for(frame_type);
        Some(Joint {
            qmin: value("qmin", &table.qmin, defaults.qmin, joint_angle)?,
            qmax: value("qmax", &table.qmax, defaults.qmax, joint_angle)?,
            offset: value("offset", &table.offset, defaults.offset, joint_angle)?,
            gain: value("K", &table.gain, defaults.gain, false)?,
        })
    } else {
        for (key, field) in [
            ("qmin", &table.qmin),
            ("qmax", &table.qmax),
            ("offset", &table.offset),
            ("K", &table.gain),
        ] {
            if let Some(field) = field {
                return Err(at(
                    field.span(),
                    key,
                    format!("frame {index} is fixed (sigma = 2) and has no joint, so no `{key}`"),
                ));
            }
        }
        None
    };
    Ok((frame, joint, keys))
}

type RawMatrix = Spanned<Vec<Spanned<Vec<f64>>>>;

fn read_coupling(
    source: &Source<'_>,
    name: &'static str,
    raw: Option<&RawMatrix>,
    spans: &mut SpanIndex,
) -> Result<Option<DMatrix<f64>>, Error> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    spans.coupling.insert(name, raw.span());
    let rows = raw.get_ref();
    let columns = rows.first().map_or(0, |row| row.get_ref().len());
    for row in rows {
        if row.get_ref().len() != columns {
            return Err(source.error_at(
                Some(row.span()),
                Some(format!("coupling.{name}")),
                format!(
                    "rows of different lengths ({} and {columns}): a coupling matrix is n×n",
                    row.get_ref().len()
                ),
            ));
        }
    }
    Ok(Some(DMatrix::from_fn(rows.len(), columns, |i, j| {
        rows[i].get_ref()[j]
    })))
}

fn read_priority(
    source: &Source<'_>,
    raw: &Spanned<RawPriority>,
    spans: &mut SpanIndex,
) -> Result<PriorityMatrix, Error> {
    let matrix = &raw.get_ref().matrix;
    spans.priority = Some(matrix.span());
    let mut rows = Vec::with_capacity(matrix.get_ref().len());
    for (frame, row) in matrix.get_ref().iter().enumerate() {
        spans.priority_rows.push(row.span());
        let field = Some(format!("priority.matrix row {frame}"));
        let values = row.get_ref();
        if values.len() != 6 {
            return Err(source.error_at(
                Some(row.span()),
                field,
                format!(
                    "has {} entries; each row is [alpha, d, theta, r, beta, K] (6 entries)",
                    values.len()
                ),
            ));
        }
        let mut cells = [0_u32; 6];
        for (cell, value) in cells.iter_mut().zip(values) {
            *cell = u32::try_from(*value.get_ref()).map_err(|_| {
                source.error_at(
                    Some(value.span()),
                    field.clone(),
                    format!(
                        "{} is not a priority: priorities are integers ≥ 0 (0 = do not identify)",
                        value.get_ref()
                    ),
                )
            })?;
        }
        rows.push(cells);
    }
    Ok(PriorityMatrix::from_rows(rows))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPriorityFile {
    matrix: Option<RawPriorityMatrix>,
    priority: Option<Spanned<RawPriority>>,
}

/// Reads a priority matrix from a TOML file holding `matrix = [[...], ...]`,
/// or a `[priority]` table with it (so a robot file's table can be reused),
/// and checks it against `robot`.
///
/// # Errors
/// [`Error::Read`], or [`Error::Parse`] with the line of the problem.
pub fn read_priority_file(path: &Path, robot: &Robot) -> Result<PriorityMatrix, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_owned(),
        source,
    })?;
    let source = Source { path, text: &text };
    let raw: RawPriorityFile =
        toml::from_str(&text).map_err(|error| toml_error(&source, &error))?;
    let table = match (raw.matrix, raw.priority) {
        (Some(matrix), None) => {
            let span = matrix.span();
            Spanned::new(span, RawPriority { matrix })
        }
        (None, Some(table)) => table,
        _ => {
            return Err(source.error_at(
                None,
                Some("matrix".into()),
                "a priority file holds `matrix = [[alpha, d, theta, r, beta, K], ...]` (one row per \
                 frame), at the top or in a [priority] table",
            ));
        }
    };
    let mut spans = SpanIndex::default();
    let priority = read_priority(&source, &table, &mut spans)?;
    priority
        .validate(robot.parameters())
        .map_err(|error| model_error(&source, &spans, error))?;
    Ok(priority)
}

fn toml_error(source: &Source<'_>, error: &toml::de::Error) -> Error {
    let message = error.message().trim().to_owned();
    let message = match unknown_key(&message) {
        Some(key) => {
            let known = TOP_KEYS
                .iter()
                .chain(FRAME_KEYS)
                .chain(COUPLING_KEYS)
                .chain(PRIORITY_KEYS);
            let closest = known
                .map(|candidate| (strsim::levenshtein(&key, candidate), *candidate))
                .filter(|(distance, _)| *distance <= 2.max(key.len() / 3))
                .min_by_key(|(distance, _)| *distance);
            match closest {
                Some((_, candidate)) => {
                    format!("unknown key `{key}` (did you mean `{candidate}`?)")
                }
                None => format!("unknown key `{key}`; {}", expected_list(&message)),
            }
        }
        None => message,
    };
    source.error_at(error.span(), None, message)
}

/// The key of serde's "unknown field `x`, expected ..." message.
fn unknown_key(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    Some(rest[..rest.find('`')?].to_owned())
}

fn expected_list(message: &str) -> String {
    message
        .split_once(", ")
        .map_or_else(String::new, |(_, expected)| {
            expected.replace("expected", "known keys are")
        })
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
    text
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

/// A name for text that does not come from a file, such as a ready robot.
pub(crate) fn virtual_path(name: &str) -> PathBuf {
    PathBuf::from(format!("<{name}>"))
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
