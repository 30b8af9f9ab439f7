//! An instrument's export joined with a controller's log (issue 74): the
//! points a tracker measured beside the joint values the robot stood at,
//! as one data file (`gecaro join`).
//!
//! - **The tracker's file**: `x, y, z` (and, when it measured
//!   orientations, `qw, qx, qy, qz`, or `rx, ry, rz` in the form its
//!   rotation format names — Euler angles or a rotation vector, in its angle
//!   unit — written as quaternions), in its length unit; other columns left
//!   alone. `rx, ry, rz` columns without a rotation format are refused, not
//!   dropped: the join would be silently position-only.
//! - **The controller's log**: `qm1 … qmn` in its angle unit (prismatic
//!   joints in its length unit); other columns left alone.
//! - Both as they are written: commas, semicolons or tabs, decimal commas,
//!   their own column names (`--tracker-columns x=X_mm`,
//!   `--log-columns qm1=A1`).
//! - **By a key** (a point's name or number, in a column of each): every
//!   measured point joins the one log row of its key; a key twice in a
//!   file, or a measured point the log lacks, is refused with its line;
//!   log rows nothing measured are left out and named.
//! - **By row order** (no key): the files must have as many rows.
//!
//! The result is a data file in gecaro's units (metres, radians), as
//! `identify --data` reads it, with a comment naming what was joined.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use gecaro_core::FrameType;
use nalgebra::Vector3;

use crate::Error;
use crate::data_file::DataFormat;
use crate::data_rows::MAX_CONFIGURATIONS;
use crate::named_points::MAX_BASE_POINT_DISTANCE;
use crate::rotation::RotationFormat;
use crate::table_text::TextTable;

/// How two files are joined (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct JoinSpec {
    /// The robot's joint types, joint 1 first (the log's columns and units).
    pub joint_types: Vec<FrameType>,
    /// The key column of the tracker's file (its name in the file), or
    /// `None` to join by row order.
    pub key: Option<String>,
    /// The key column of the log, when its name differs.
    pub log_key: Option<String>,
    /// The tracker's file: its length unit, column names, separator.
    pub tracker: DataFormat,
    /// The log: its angle (and length) unit, column names, separator.
    pub log: DataFormat,
}

/// Two files joined.
#[derive(Clone, Debug, PartialEq)]
pub struct Joined {
    /// The data file's text (gecaro's units).
    pub text: String,
    /// Each joined row's configuration (gecaro's units), the tracker's order.
    pub configurations: Vec<Vec<f64>>,
    /// Each joined row's point (m).
    pub points: Vec<Vector3<f64>>,
    /// Whether the rows carry orientations.
    pub orientations: bool,
    /// The keys of log rows nothing measured (left out), with their lines.
    pub unmeasured: Vec<(String, usize)>,
}

/// The joint columns of a log, in gecaro's names.
fn joint_names(count: usize) -> Vec<String> {
    (1..=count).map(|j| format!("qm{j}")).collect()
}

/// Each key of `table`'s `column` with its row and line.
///
/// # Errors
/// An empty key, or a key twice (both lines named).
fn key_index<'t>(
    table: &'t TextTable,
    path: &Path,
    column: usize,
) -> Result<HashMap<&'t str, (usize, usize)>, Error> {
    let mut seen: HashMap<&str, (usize, usize)> = HashMap::new();
    for (row, (line, fields)) in table.rows.iter().enumerate() {
        let value = fields[column].as_str();
        let error = |message: String| Error::Parse {
            path: path.to_owned(),
            line: *line,
            field: None,
            message,
        };
        if value.is_empty() {
            return Err(error("no key".into()));
        }
        if let Some((_, first)) = seen.insert(value, (row, *line)) {
            return Err(error(format!(
                "key `{value}` again (first on line {first}): which is it?"
            )));
        }
    }
    Ok(seen)
}

/// Joins `tracker` and `log` (each its text and path) as `spec` says.
///
/// # Errors
/// [`Error::Format`] for a missing column or mismatched counts,
/// [`Error::Parse`] with the line of a value that is not a number, a point
/// beyond any instrument's reach, a key given twice or a measured point the
/// log lacks.
///
/// ```
/// use std::path::Path;
/// let tracker = "point;X;Y;Z\nP2;1000,5;0;0\nP1;0;1000;0\n";
/// let log = "point,qm1\nP1,0.1\nP2,0.2\nP3,0.3\n";
/// let mut spec = gecaro_io::JoinSpec {
///     joint_types: vec![gecaro_core::FrameType::Revolute],
///     key: Some("point".into()),
///     ..Default::default()
/// };
/// spec.tracker.columns = gecaro_io::ColumnMap::parse("x=X,y=Y,z=Z").unwrap();
/// spec.tracker.units.length = gecaro_io::LengthUnit::Millimetres;
/// let joined = gecaro_io::join_tables(
///     (tracker, Path::new("tracker.csv")),
///     (log, Path::new("log.csv")),
///     &spec,
/// )
/// .unwrap();
/// assert_eq!(joined.configurations, vec![vec![0.2], vec![0.1]]);
/// assert!((joined.points[0].x - 1.0005).abs() < 1e-12);
/// assert_eq!(joined.unmeasured, vec![("P3".to_owned(), 4)]);
/// ```
pub fn join_tables(
    (tracker_text, tracker_path): (&str, &Path),
    (log_text, log_path): (&str, &Path),
    spec: &JoinSpec,
) -> Result<Joined, Error> {
    let format_error = |path: &Path, message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let tracker = TextTable::parse(
        tracker_text,
        tracker_path,
        &spec.tracker,
        MAX_CONFIGURATIONS,
        "an instrument's export has x, y, z (and qw, qx, qy, qz) per measured point",
    )?;
    let log = TextTable::parse(
        log_text,
        log_path,
        &spec.log,
        MAX_CONFIGURATIONS,
        "a controller's log has qm1 … qmn per configuration",
    )?;
    let columns = |table: &TextTable, format: &DataFormat, path: &Path, names: &[String]| {
        names
            .iter()
            .map(|name| {
                table.column(format, name).ok_or_else(|| {
                    format_error(
                        path,
                        format!(
                            "no column `{}` (rename with the columns option: {name}=…); its \
                             header reads {}",
                            format.columns.file_name(name),
                            table.names.join(",")
                        ),
                    )
                })
            })
            .collect::<Result<Vec<usize>, Error>>()
    };
    let position: Vec<String> = ["x", "y", "z"].map(String::from).to_vec();
    let quaternion: Vec<String> = ["qw", "qx", "qy", "qz"].map(String::from).to_vec();
    let point_columns = columns(&tracker, &spec.tracker, tracker_path, &position)?;
    // The orientations as the export writes them: quaternions, or three
    // angles in the form the rotation format names.
    let rotation = spec.tracker.rotation;
    let given: Vec<String> = rotation
        .columns()
        .iter()
        .map(|name| name.to_string())
        .collect();
    let present = |names: &[&str]| {
        names
            .iter()
            .any(|name| tracker.column(&spec.tracker, name).is_some())
    };
    if rotation == RotationFormat::Quaternion && present(&["rx", "ry", "rz"]) {
        return Err(format_error(
            tracker_path,
            "has rx, ry, rz columns but no rotation format: give their form (rpy, euler-xyz,              euler-zyz or rotation-vector) and their angle unit, or the join would drop the              orientations"
                .into(),
        ));
    }
    let has_orientation = present(rotation.columns());
    if rotation != RotationFormat::Quaternion && !has_orientation {
        return Err(format_error(
            tracker_path,
            format!(
                "no rx, ry, rz columns for the rotation format {} (rename them with the columns                  option: rx=A,…); its header reads {}",
                rotation.name(),
                tracker.names.join(",")
            ),
        ));
    }
    let orientation_columns = if has_orientation {
        Some(columns(&tracker, &spec.tracker, tracker_path, &given)?)
    } else {
        None
    };
    let joints = joint_names(spec.joint_types.len());
    let joint_columns = columns(&log, &spec.log, log_path, &joints)?;
    // Each tracker row's log row, and the log's key column.
    let (pairs, log_keys): (Vec<(usize, usize)>, Option<usize>) = match &spec.key {
        None => {
            if tracker.rows.len() != log.rows.len() {
                return Err(format_error(
                    tracker_path,
                    format!(
                        "{} measured points and {} log rows ({}): joined by row order they must \
                         be as many; when one file has rows the other lacks, join by a key column \
                         (a point's name or number in both)",
                        tracker.rows.len(),
                        log.rows.len(),
                        log_path.display()
                    ),
                ));
            }
            ((0..tracker.rows.len()).map(|i| (i, i)).collect(), None)
        }
        Some(key) => {
            let log_key = spec.log_key.as_deref().unwrap_or(key);
            let key_column = |table: &TextTable, path: &Path, name: &str| {
                table
                    .names
                    .iter()
                    .position(|column| column == name)
                    .ok_or_else(|| {
                        format_error(
                            path,
                            format!(
                                "no key column `{name}`; its header reads {}",
                                table.names.join(",")
                            ),
                        )
                    })
            };
            let (tracker_key, log_key_column) = (
                key_column(&tracker, tracker_path, key)?,
                key_column(&log, log_path, log_key)?,
            );
            // A key twice among the measured points is refused too.
            key_index(&tracker, tracker_path, tracker_key)?;
            let logged = key_index(&log, log_path, log_key_column)?;
            let mut pairs = Vec::with_capacity(tracker.rows.len());
            let mut missing = Vec::new();
            for (row, (line, fields)) in tracker.rows.iter().enumerate() {
                match logged.get(fields[tracker_key].as_str()) {
                    Some((log_row, _)) => pairs.push((row, *log_row)),
                    None => missing.push(format!("`{}` (line {line})", fields[tracker_key])),
                }
            }
            if !missing.is_empty() {
                return Err(format_error(
                    tracker_path,
                    format!(
                        "{} measured point(s) have no row in {}: {}{}",
                        missing.len(),
                        log_path.display(),
                        missing[..missing.len().min(5)].join(", "),
                        if missing.len() > 5 { ", …" } else { "" }
                    ),
                ));
            }
            (pairs, Some(log_key_column))
        }
    };
    let metres = spec.tracker.units.length.to_metres();
    let mut configurations = Vec::with_capacity(pairs.len());
    let mut points = Vec::with_capacity(pairs.len());
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# joined by gecaro join: the points of {} with the joints of {}, {}",
        tracker_path.display(),
        log_path.display(),
        match &spec.key {
            Some(key) => format!("by the key `{key}`"),
            None => "by row order".into(),
        }
    );
    let mut header = joints.clone();
    header.extend(position.iter().cloned());
    if has_orientation {
        header.extend(quaternion.iter().cloned());
    }
    let _ = writeln!(text, "{}", header.join(","));
    for (tracker_row, log_row) in &pairs {
        let (line, fields) = &tracker.rows[*tracker_row];
        let (log_line, log_fields) = &log.rows[*log_row];
        let mut values = Vec::with_capacity(header.len());
        let mut configuration = Vec::with_capacity(joints.len());
        for ((name, column), joint_type) in joints.iter().zip(&joint_columns).zip(&spec.joint_types)
        {
            let scale = match joint_type {
                FrameType::Prismatic => spec.log.units.length.to_metres(),
                _ => spec.log.units.angle.to_radians(),
            };
            let value = log.number(log_path, (*log_line, &log_fields[*column]), name)? * scale;
            configuration.push(value);
            values.push(value);
        }
        let mut point = Vector3::zeros();
        for (axis, (name, column)) in position.iter().zip(&point_columns).enumerate() {
            let value = tracker.number(tracker_path, (*line, &fields[*column]), name)? * metres;
            if !(value.is_finite() && value.abs() <= MAX_BASE_POINT_DISTANCE) {
                return Err(Error::Parse {
                    path: tracker_path.to_owned(),
                    line: *line,
                    field: Some(name.clone()),
                    message: format!(
                        "{value} m is beyond any instrument's reach ({MAX_BASE_POINT_DISTANCE} \
                         m): is the file in millimetres (give its length unit)?"
                    ),
                });
            }
            point[axis] = value;
            values.push(value);
        }
        if let Some(columns) = &orientation_columns {
            let read = given
                .iter()
                .zip(columns)
                .map(|(name, column)| tracker.number(tracker_path, (*line, &fields[*column]), name))
                .collect::<Result<Vec<f64>, Error>>()?;
            if rotation == RotationFormat::Quaternion {
                values.extend(read);
            } else {
                let radians = spec.tracker.units.angle.to_radians();
                let turned = rotation.orientation([read[0], read[1], read[2]].map(|a| a * radians));
                values.extend([turned.w, turned.i, turned.j, turned.k]);
            }
        }
        let row: Vec<String> = values.iter().map(f64::to_string).collect();
        let _ = writeln!(text, "{}", row.join(","));
        configurations.push(configuration);
        points.push(point);
    }
    let used: std::collections::HashSet<usize> = pairs.iter().map(|(_, row)| *row).collect();
    let unmeasured = log_keys.map_or_else(Vec::new, |column| {
        log.rows
            .iter()
            .enumerate()
            .filter(|(row, _)| !used.contains(row))
            .map(|(_, (line, fields))| (fields[column].clone(), *line))
            .collect()
    });
    Ok(Joined {
        text,
        configurations,
        points,
        orientations: has_orientation,
        unmeasured,
    })
}
