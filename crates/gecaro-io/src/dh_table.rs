//! Denavit–Hartenberg tables, as datasheets give them: standard DH
//! (`Rz(θ)·Tz(d)·Tx(a)·Rx(α)` per row) and Craig's modified DH
//! (`Rx(α)·Tx(a)·Rz(θ)·Tz(d)` per row, the Khalil–Kleinfinger form without β).
//!
//! TOML:
//!
//! ```toml
//! name = "PUMA 560"
//! convention = "dh"            # "dh" (standard) or "mdh" (Craig's modified)
//! angle_unit = "deg"           # "rad" (default) or "deg"
//! length_unit = "mm"           # "m" (default) or "mm"
//! [base]                       # optional: the table's first frame in the world (URDF xyz, rpy)
//! xyz = [0, 0, 0]
//! rpy = [0, 0, 0]
//! [tool]                       # optional: the tool in the table's last frame
//! xyz = [0, 0, 56.25]
//! rpy = [0, 0, 0]
//! [[joint]]                    # one row per joint, base to tip
//! type = "R"                   # R (revolute: q is added to theta) or P (prismatic: q is added to d)
//! a = 0
//! alpha = -90
//! d = 0
//! theta = 0                    # the value at q = 0 (the joint's offset)
//! qmin = -160                  # optional limits of q (joint unit: angle or length)
//! qmax = 160
//! ```
//!
//! CSV: a header naming the columns `type,a,alpha,d,theta` and optionally
//! `qmin,qmax` and `name` (a label), in any order; a column's unit may be
//! part of its name (`a_mm`, `alpha_deg`, `d_m`, `theta_rad`). Rows of type
//! `base` (first) and `tool` (last) give fixed steps in the table's convention.
//! The convention comes from `--from dh|mdh`.
//!
//! The joint variables are the table's: q_j is added to θ_j or d_j, and
//! gecaro's frame j has that same q_j. Standard DH rows map to frames shifted
//! by one (row j's a, α belong to frame j+1); the base and tool transforms
//! enter through [`gecaro_core::Robot::reframed`].

use std::path::Path;

use gecaro_core::{Frame, FrameType, Joint, Robot, RobotSpec, frame_transform};
use nalgebra::{IsometryMatrix3, Vector3};
use serde::{Deserialize, Serialize};
use toml::Spanned;

use crate::Error;
use crate::input::{csv_error, csv_reader};
use crate::interchange::{Exported, Imported, joint_calibration};
use crate::pose::{from_xyz_rpy, rpy};
use crate::robot_file::{AngleUnit, RobotFile};
use crate::units::LengthUnit;

/// Which Denavit–Hartenberg convention a table uses.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum DhConvention {
    /// Standard: `Rz(θ)·Tz(d)·Tx(a)·Rx(α)` per row.
    Standard,
    /// Craig's modified: `Rx(α)·Tx(a)·Rz(θ)·Tz(d)` per row.
    Modified,
}

impl DhConvention {
    fn name(self) -> &'static str {
        match self {
            DhConvention::Standard => "dh",
            DhConvention::Modified => "mdh",
        }
    }

    fn from_name(name: &str) -> Option<Self> {
        match name {
            "dh" | "standard" => Some(DhConvention::Standard),
            "mdh" | "modified" | "craig" => Some(DhConvention::Modified),
            _ => None,
        }
    }

    /// The transform of one row at q = 0 (SI units).
    fn step(self, row: &Step) -> IsometryMatrix3<f64> {
        match self {
            DhConvention::Standard => {
                IsometryMatrix3::rotation(Vector3::z() * row.theta)
                    * IsometryMatrix3::translation(row.a, 0.0, row.d)
                    * IsometryMatrix3::rotation(Vector3::x() * row.alpha)
            }
            DhConvention::Modified => frame_transform(
                &Frame {
                    alpha: row.alpha,
                    d: row.a,
                    theta: row.theta,
                    r: row.d,
                    ..Frame::new(FrameType::Fixed)
                },
                0.0,
            ),
        }
    }
}

/// Units for table columns that do not state theirs.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct TableUnits {
    /// Angles (default radians).
    pub angle: Option<AngleUnit>,
    /// Lengths (default metres).
    pub length: Option<LengthUnit>,
}

/// One row in SI units.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
struct Step {
    a: f64,
    alpha: f64,
    d: f64,
    theta: f64,
}

#[derive(Clone, Debug)]
struct Row {
    frame_type: FrameType,
    step: Step,
    limits: (Option<f64>, Option<f64>),
}

/// A table read from TOML or CSV, in SI units.
struct Table {
    name: Option<String>,
    description: Option<String>,
    convention: Option<DhConvention>,
    world_from_base: Option<IsometryMatrix3<f64>>,
    last_from_tool: Option<IsometryMatrix3<f64>>,
    rows: Vec<Row>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct TransformDocument {
    #[serde(default)]
    xyz: [f64; 3],
    #[serde(default)]
    rpy: [f64; 3],
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RowDocument {
    #[serde(rename = "type")]
    joint_type: String,
    #[serde(default)]
    a: f64,
    #[serde(default)]
    alpha: f64,
    #[serde(default)]
    d: f64,
    #[serde(default)]
    theta: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    qmin: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    qmax: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableDocument {
    name: Option<String>,
    description: Option<String>,
    convention: Option<Spanned<String>>,
    angle_unit: Option<Spanned<String>>,
    length_unit: Option<Spanned<String>>,
    base: Option<Spanned<TransformDocument>>,
    tool: Option<Spanned<TransformDocument>>,
    #[serde(default)]
    joint: Vec<Spanned<RowDocument>>,
}

/// The document gecaro writes (same keys as read).
#[derive(Serialize)]
struct TableOutput {
    name: String,
    description: String,
    convention: &'static str,
    angle_unit: &'static str,
    length_unit: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    base: Option<TransformDocument>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tool: Option<TransformDocument>,
    joint: Vec<RowDocument>,
}

struct Units {
    angle: f64,
    length: f64,
}

impl Units {
    fn step(&self, a: f64, alpha: f64, d: f64, theta: f64) -> Step {
        Step {
            a: a * self.length,
            alpha: alpha * self.angle,
            d: d * self.length,
            theta: theta * self.angle,
        }
    }

    fn transform(&self, transform: &TransformDocument) -> IsometryMatrix3<f64> {
        let xyz = transform.xyz.map(|v| v * self.length);
        let rpy = transform.rpy.map(|v| v * self.angle);
        from_xyz_rpy(xyz, rpy)
    }

    fn joint(&self, frame_type: FrameType) -> f64 {
        match frame_type {
            FrameType::Prismatic => self.length,
            _ => self.angle,
        }
    }
}

fn joint_type(text: &str) -> Option<FrameType> {
    match text.trim().to_ascii_lowercase().as_str() {
        "r" | "revolute" => Some(FrameType::Revolute),
        "p" | "prismatic" => Some(FrameType::Prismatic),
        _ => None,
    }
}

fn parse_toml(text: &str, path: &Path, defaults: TableUnits) -> Result<Table, Error> {
    let line_of = |offset: usize| text[..offset.min(text.len())].matches('\n').count() + 1;
    // The line of `field` in the table whose header is at `span` (its keys
    // run to the next header), else the header's line.
    let fail = |span: std::ops::Range<usize>, field: &str, message: String| {
        let table = &text[span.start.min(text.len())..];
        let offset = table
            .lines()
            .scan(0, |at, line| {
                let start = *at;
                *at += line.len() + 1;
                Some((start, line))
            })
            .take_while(|(start, line)| *start == 0 || !line.trim_start().starts_with('['))
            .find(|(_, line)| {
                line.split('=')
                    .next()
                    .is_some_and(|key| key.trim() == field)
            })
            .map_or(0, |(start, _)| start);
        Error::parse(
            path,
            line_of(span.start + offset),
            Some(field.to_owned()),
            message,
        )
    };
    let document: TableDocument = toml::from_str(text).map_err(|error| {
        let line = error.span().map_or(1, |span| line_of(span.start));
        Error::parse(path, line, None, error.message().trim().to_owned())
    })?;
    let angle = match &document.angle_unit {
        None => defaults.angle.unwrap_or_default(),
        Some(unit) => AngleUnit::from_name(unit.get_ref()).ok_or_else(|| {
            fail(
                unit.span(),
                "angle_unit",
                format!("must be \"rad\" or \"deg\", not {:?}", unit.get_ref()),
            )
        })?,
    };
    let length = match &document.length_unit {
        None => defaults.length.unwrap_or_default(),
        Some(unit) => LengthUnit::from_name(unit.get_ref()).ok_or_else(|| {
            fail(
                unit.span(),
                "length_unit",
                format!("must be \"m\" or \"mm\", not {:?}", unit.get_ref()),
            )
        })?,
    };
    let units = Units {
        angle: angle.to_radians(),
        length: length.to_metres(),
    };
    let convention = match &document.convention {
        None => None,
        Some(name) => Some(DhConvention::from_name(name.get_ref()).ok_or_else(|| {
            fail(
                name.span(),
                "convention",
                format!("must be \"dh\" or \"mdh\", not {:?}", name.get_ref()),
            )
        })?),
    };
    let transform = |document: &Option<Spanned<TransformDocument>>, key: &str| {
        document
            .as_ref()
            .map(|spanned| {
                let values = spanned.get_ref();
                if values.xyz.iter().chain(&values.rpy).all(|v| v.is_finite()) {
                    Ok(units.transform(values))
                } else {
                    Err(fail(
                        spanned.span(),
                        key,
                        "holds a value that is not a finite number".into(),
                    ))
                }
            })
            .transpose()
    };
    let mut rows = Vec::with_capacity(document.joint.len());
    for spanned in &document.joint {
        let row = spanned.get_ref();
        let at = |field: &str, message: String| fail(spanned.span(), field, message);
        let frame_type = joint_type(&row.joint_type).ok_or_else(|| {
            at(
                "type",
                format!(
                    "must be \"R\" (revolute) or \"P\" (prismatic), not {:?}",
                    row.joint_type
                ),
            )
        })?;
        for (key, value) in [
            ("a", Some(row.a)),
            ("alpha", Some(row.alpha)),
            ("d", Some(row.d)),
            ("theta", Some(row.theta)),
            ("qmin", row.qmin),
            ("qmax", row.qmax),
        ] {
            if value.is_some_and(|v| !v.is_finite()) {
                return Err(at(
                    key,
                    format!("{} is not a finite number", value.unwrap_or_default()),
                ));
            }
        }
        let scale = units.joint(frame_type);
        rows.push(Row {
            frame_type,
            step: units.step(row.a, row.alpha, row.d, row.theta),
            limits: (row.qmin.map(|v| v * scale), row.qmax.map(|v| v * scale)),
        });
    }
    if rows.is_empty() {
        return Err(Error::parse(
            path,
            1,
            None,
            "no [[joint]] rows: a table needs one row per joint",
        ));
    }
    Ok(Table {
        name: document.name,
        description: document.description,
        convention,
        world_from_base: transform(&document.base, "base")?,
        last_from_tool: transform(&document.tool, "tool")?,
        rows,
    })
}

/// A CSV column name and its unit suffix.
fn split_unit(header: &str) -> (&str, Option<&str>) {
    for suffix in ["_deg", "_rad", "_mm", "_m"] {
        if let Some(stem) = header.strip_suffix(suffix) {
            return (stem, Some(&suffix[1..]));
        }
    }
    (header, None)
}

/// The one unit the columns' suffixes give, or the default.
fn column_unit<U: PartialEq + Copy>(
    suffixes: &[(&str, &str)],
    read: impl Fn(&str) -> Option<U>,
    default: Option<U>,
) -> Result<Option<U>, String> {
    let mut found: Option<(U, &str)> = None;
    for (column, suffix) in suffixes {
        let Some(unit) = read(suffix) else { continue };
        match found {
            Some((other, first)) if other != unit => {
                return Err(format!(
                    "columns `{first}` and `{column}` are in different units: one unit per table"
                ));
            }
            _ => found = Some((unit, column)),
        }
    }
    Ok(found.map(|(unit, _)| unit).or(default))
}

fn parse_csv(
    text: &str,
    path: &Path,
    defaults: TableUnits,
    convention: DhConvention,
) -> Result<Table, Error> {
    let mut reader = csv_reader(text.as_bytes());
    let mut records = reader.records();
    let csv_error = |error: csv::Error| csv_error(path, &error);
    let Some(header) = records.next().transpose().map_err(csv_error)? else {
        return Err(Error::parse(
            path,
            1,
            None,
            "the file is empty; it needs a header line: type,a,alpha,d,theta",
        ));
    };
    let header_line = header.position().map_or(1, |p| p.line() as usize);
    let header_error = |column: Option<&str>, message: String| {
        Error::parse(path, header_line, column.map(str::to_owned), message)
    };
    let mut columns = Vec::new();
    let mut suffixes = Vec::new();
    for name in header.iter().map(str::trim) {
        let (stem, unit) = split_unit(name);
        let fits = match unit {
            None => true,
            Some("deg" | "rad") => matches!(stem, "alpha" | "theta"),
            Some(_) => matches!(stem, "a" | "d"),
        };
        if ![
            "type", "a", "alpha", "d", "theta", "qmin", "qmax", "name", "joint",
        ]
        .contains(&stem)
        {
            return Err(header_error(
                Some(name),
                "unknown column; a DH table has type,a,alpha,d,theta and optionally qmin,qmax,name"
                    .into(),
            ));
        }
        if !fits {
            return Err(header_error(
                Some(name),
                "this unit does not fit the column (angles: _deg or _rad, lengths: _mm or _m; \
                 limits take the unit of their joint)"
                    .into(),
            ));
        }
        if let Some(unit) = unit {
            suffixes.push((name, unit));
        }
        columns.push(stem);
    }
    if let Some(missing) = ["type", "a", "alpha", "d", "theta"]
        .into_iter()
        .find(|required| !columns.contains(required))
    {
        return Err(header_error(
            None,
            format!("missing column `{missing}`; a DH table has type,a,alpha,d,theta"),
        ));
    }
    let angle = column_unit(&suffixes, AngleUnit::from_name, defaults.angle)
        .map_err(|message| header_error(None, message))?;
    let length = column_unit(&suffixes, LengthUnit::from_name, defaults.length)
        .map_err(|message| header_error(None, message))?;
    let units = Units {
        angle: angle.unwrap_or_default().to_radians(),
        length: length.unwrap_or_default().to_metres(),
    };
    let mut table = Table {
        name: None,
        description: None,
        convention: Some(convention),
        world_from_base: None,
        last_from_tool: None,
        rows: Vec::new(),
    };
    for record in records {
        let record = record.map_err(csv_error)?;
        let line = record.position().map_or(1, |p| p.line() as usize);
        let fail = |column: Option<&str>, message: String| {
            Error::parse(path, line, column.map(str::to_owned), message)
        };
        if record.len() != columns.len() {
            return Err(fail(
                None,
                format!(
                    "{} values for {} columns ({})",
                    record.len(),
                    columns.len(),
                    header.iter().collect::<Vec<_>>().join(",")
                ),
            ));
        }
        if table.last_from_tool.is_some() {
            return Err(fail(
                None,
                "a row after the `tool` row: the tool comes last".into(),
            ));
        }
        let cell = |name: &str| {
            columns
                .iter()
                .position(|c| *c == name)
                .map(|i| record[i].trim())
        };
        let number = |name: &str| -> Result<Option<f64>, Error> {
            match cell(name) {
                None | Some("") => Ok(None),
                Some(text) => match text.parse::<f64>() {
                    Ok(value) if value.is_finite() => Ok(Some(value)),
                    _ => Err(fail(Some(name), format!("`{text}` is not a finite number"))),
                },
            }
        };
        let step = units.step(
            number("a")?.unwrap_or(0.0),
            number("alpha")?.unwrap_or(0.0),
            number("d")?.unwrap_or(0.0),
            number("theta")?.unwrap_or(0.0),
        );
        let kind = cell("type").unwrap_or_default();
        match kind.to_ascii_lowercase().as_str() {
            "base" if table.rows.is_empty() && table.world_from_base.is_none() => {
                table.world_from_base = Some(convention.step(&step));
            }
            "base" => {
                return Err(fail(
                    Some("type"),
                    "the `base` row must be the first row".into(),
                ));
            }
            "tool" => table.last_from_tool = Some(convention.step(&step)),
            _ => {
                let frame_type = joint_type(kind).ok_or_else(|| {
                    fail(
                        Some("type"),
                        format!("`{kind}`: a row is R, P, base or tool"),
                    )
                })?;
                let scale = units.joint(frame_type);
                table.rows.push(Row {
                    frame_type,
                    step,
                    limits: (
                        number("qmin")?.map(|v| v * scale),
                        number("qmax")?.map(|v| v * scale),
                    ),
                });
            }
        }
    }
    if table.rows.is_empty() {
        return Err(Error::parse(
            path,
            header_line + 1,
            None,
            "no joint rows (type R or P)",
        ));
    }
    Ok(table)
}

/// The frames 0..n+1 of a table, before its base and tool transforms.
fn table_frames(rows: &[Row], convention: DhConvention) -> Vec<Frame> {
    let n = rows.len();
    let mut frames = vec![Frame::new(FrameType::Fixed)];
    for (j, row) in rows.iter().enumerate() {
        let frame = match convention {
            // Row j's a and α belong to the next frame; frame 1 starts on axis 1.
            DhConvention::Standard => {
                let previous = j.checked_sub(1).map(|i| rows[i].step).unwrap_or_default();
                Frame {
                    alpha: previous.alpha,
                    d: previous.a,
                    theta: row.step.theta,
                    r: row.step.d,
                    ..Frame::new(row.frame_type)
                }
            }
            DhConvention::Modified => Frame {
                alpha: row.step.alpha,
                d: row.step.a,
                theta: row.step.theta,
                r: row.step.d,
                ..Frame::new(row.frame_type)
            },
        };
        frames.push(frame);
    }
    frames.push(match convention {
        DhConvention::Standard => Frame {
            alpha: rows[n - 1].step.alpha,
            d: rows[n - 1].step.a,
            ..Frame::new(FrameType::Fixed)
        },
        DhConvention::Modified => Frame::new(FrameType::Fixed),
    });
    frames
}

/// Imports a DH or MDH table (TOML, or CSV when `is_csv`); `convention`
/// comes from the command line and must agree with the file's.
pub(crate) fn import_table(
    text: &str,
    path: &Path,
    convention: Option<DhConvention>,
    is_csv: bool,
    units: TableUnits,
) -> Result<Imported, Error> {
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let table = if is_csv {
        let convention = convention.ok_or_else(|| {
            format_error(
                "a CSV table does not say its convention: give --from dh (standard) or --from mdh \
                 (Craig's modified)"
                    .into(),
            )
        })?;
        parse_csv(text, path, units, convention)?
    } else {
        parse_toml(text, path, units)?
    };
    let convention = match (convention, table.convention) {
        (Some(given), Some(file)) if given != file => {
            return Err(format_error(format!(
                "the file says convention = \"{}\", the command line {}",
                file.name(),
                given.name()
            )));
        }
        (Some(convention), _) | (None, Some(convention)) => convention,
        (None, None) => {
            return Err(format_error(
                "the table does not say its convention: add convention = \"dh\" or \"mdh\", or \
                 give --from dh|mdh"
                    .into(),
            ));
        }
    };
    let mut notes = Vec::new();
    let joints = table
        .rows
        .iter()
        .enumerate()
        .map(|(index, row)| {
            let defaults = Joint::default_for(row.frame_type);
            let (qmin, qmax) = match row.limits {
                (Some(qmin), Some(qmax)) => (qmin, qmax),
                _ => {
                    notes.push(format!(
                        "joint {}: no limits in the table; defaults used",
                        index + 1
                    ));
                    (defaults.qmin, defaults.qmax)
                }
            };
            Joint {
                qmin,
                qmax,
                ..defaults
            }
        })
        .collect();
    let name = table
        .name
        .clone()
        .unwrap_or_else(|| crate::robot_file::fallback_name(path));
    let robot = Robot::new(RobotSpec {
        name,
        frames: table_frames(&table.rows, convention),
        joints,
        motor_coupling: None,
        joint_coupling: None,
        priority: None,
    })
    .map_err(|error| format_error(error.to_string()))?;
    let identity = IsometryMatrix3::identity();
    let world = table.world_from_base.unwrap_or(identity);
    let tool = table.last_from_tool.unwrap_or(identity);
    let robot = robot
        .reframed(&world, &tool)
        .map_err(|error| format_error(error.to_string()))?;
    let description = table.description.clone().unwrap_or_else(|| {
        format!(
            "imported from {} ({} table, {} joints)",
            path.file_name()
                .map_or_else(String::new, |f| f.to_string_lossy().into_owned()),
            match convention {
                DhConvention::Standard => "standard DH",
                DhConvention::Modified => "modified DH",
            },
            table.rows.len()
        )
    });
    Ok(Imported {
        file: RobotFile {
            robot,
            description: Some(description),
            angle_unit: AngleUnit::Radians,
            urdf: None,
        },
        notes,
    })
}

fn transform_document(pose: &IsometryMatrix3<f64>) -> Option<TransformDocument> {
    (*pose != IsometryMatrix3::identity()).then(|| TransformDocument {
        xyz: pose.translation.vector.into(),
        rpy: rpy(&pose.rotation),
    })
}

/// The DH or MDH table of a robot (SI units), with its offsets folded into
/// θ (or d): the table's joint values are q − offset.
///
/// # Errors
/// A frame with β ≠ 0 (not expressible in a DH table), naming it.
pub(crate) fn export_table(file: &RobotFile, convention: DhConvention) -> Result<Exported, String> {
    let robot = &file.robot;
    let frames = robot.frames();
    let n = robot.joint_count();
    if let Some((j, frame)) = frames.iter().enumerate().find(|(_, f)| f.beta != 0.0) {
        return Err(format!(
            "frame {j} has beta = {} rad: Hayati's β has no place in a DH table; export to URDF instead",
            frame.beta
        ));
    }
    let mut notes = Vec::new();
    let fold = |j: usize, frame: &Frame| -> (f64, f64) {
        let offset = robot.joints()[j - 1].offset;
        match frame.frame_type {
            FrameType::Prismatic => (frame.theta, frame.r + offset),
            _ => (frame.theta + offset, frame.r),
        }
    };
    if robot.joints().iter().any(|joint| joint.offset != 0.0) {
        notes.push("joint offsets are folded into theta (d for prismatic joints): the table's joint value is q − offset".into());
    }
    let row = |j: usize, a: f64, alpha: f64| {
        let frame = &frames[j];
        let (theta, d) = fold(j, frame);
        let joint = &robot.joints()[j - 1];
        let offset = joint.offset;
        RowDocument {
            joint_type: match frame.frame_type {
                FrameType::Prismatic => "P".into(),
                _ => "R".into(),
            },
            a,
            alpha,
            d,
            theta,
            qmin: Some(joint.qmin - offset),
            qmax: Some(joint.qmax - offset),
        }
    };
    let zero = |frame: &Frame| frame_transform(frame, 0.0);
    let (base, rows, tool) = match convention {
        DhConvention::Modified => (
            zero(&frames[0]),
            (1..=n)
                .map(|j| row(j, frames[j].d, frames[j].alpha))
                .collect(),
            zero(&frames[n + 1]),
        ),
        DhConvention::Standard => (
            zero(&frames[0])
                * zero(&Frame {
                    alpha: frames[1].alpha,
                    d: frames[1].d,
                    ..Frame::new(FrameType::Fixed)
                }),
            (1..=n)
                .map(|j| row(j, frames[j + 1].d, frames[j + 1].alpha))
                .collect(),
            zero(&Frame {
                theta: frames[n + 1].theta,
                r: frames[n + 1].r,
                ..Frame::new(FrameType::Fixed)
            }),
        ),
    };
    let output = TableOutput {
        name: robot.name().to_owned(),
        description: format!(
            "{} as a {} table, written by gecaro robot export",
            robot.name(),
            match convention {
                DhConvention::Standard => "standard DH",
                DhConvention::Modified => "modified DH",
            }
        ),
        convention: convention.name(),
        angle_unit: "rad",
        length_unit: "m",
        base: transform_document(&base),
        tool: transform_document(&tool),
        joint: rows,
    };
    let text = toml::to_string(&output).map_err(|error| error.to_string())?;
    let joint_names: Vec<String> = (1..=n).map(|j| format!("joint {j}")).collect();
    let joint_calibration = joint_calibration(robot, &joint_names, "table");
    if joint_calibration.is_some() {
        notes.push(
            "gains K or couplings are not expressible in a DH table: its joint values are \
             q = Cj·diag(K)·Cm·qm, a map written to the joint calibration file for the driver"
                .into(),
        );
    }
    Ok(Exported {
        text: format!(
            "# {} table (gecaro robot export): one [[joint]] per joint; q is added to theta (R) or d (P).\n{text}",
            match convention {
                DhConvention::Standard =>
                    "Standard Denavit–Hartenberg: Rz(theta)·Tz(d)·Tx(a)·Rx(alpha) per row",
                DhConvention::Modified =>
                    "Modified (Craig) Denavit–Hartenberg: Rx(alpha)·Tx(a)·Rz(theta)·Tz(d) per row",
            }
        ),
        joint_calibration,
        notes,
    })
}
