//! What a program's header says: where its targets are, in what units, and
//! which columns the corrected program keeps as written; and the targets of
//! its rows, a block at a time.

use gecaro_core::{FrameType, Robot};
use gecaro_data::program::{ProgramPoint, ProgramTarget};
use nalgebra::{IsometryMatrix3, Translation3, Vector3};
use std::path::Path;

use crate::Error;
use crate::columns::{DataUnits, field_number, joint_types, locate, not_a_number};
use crate::data_file::DataFormat;
use crate::input::NOT_TEXT;
use crate::plain_body::RecordFields;

/// What a program's targets are.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ProgramKind {
    /// Joint configurations.
    Joints,
    /// Points of frame n+1.
    Position,
    /// Poses of frame n+1.
    Pose,
}

/// A program's columns, read from its header (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramLayout {
    pub(super) header: Vec<String>,
    /// The line of the header in the file.
    pub(super) header_line: usize,
    /// The columns the corrected program keeps as written (all but the
    /// joints'; none for a joint program).
    pub(super) kept_columns: Vec<usize>,
    /// Positions of `qm1..qmn` in the header, if the program has them.
    pub(super) joint_columns: Option<Vec<usize>>,
    position_columns: Option<Vec<usize>>,
    orientation_columns: Option<Vec<usize>>,
    kind: ProgramKind,
    units: DataUnits,
    pub(super) joint_types: Vec<FrameType>,
    /// The field separator of the file.
    pub(super) separator: u8,
    /// Whether numbers may be written with a decimal comma.
    decimal_comma: bool,
    /// Columns kept as they are (not read by gecaro).
    pub(super) unused_columns: Vec<String>,
    /// Whether the file stated its units in a units line (the corrected
    /// program states them again).
    pub(super) units_stated: bool,
}

/// The columns a program of a robot of `joint_count` joints names, as
/// messages say them: `qm1,…,qmn and/or x,y,z[,qw,qx,qy,qz]`.
pub(super) fn target_columns(joint_count: usize) -> String {
    let joints: Vec<String> = (1..=joint_count).map(|j| format!("qm{j}")).collect();
    format!("{} and/or x,y,z[,qw,qx,qy,qz]", joints.join(","))
}

impl ProgramLayout {
    /// The layout of the program whose header, at `header_line` of `path`,
    /// is `header`, for `robot`, written as `format` says with `separator`.
    ///
    /// # Errors
    /// [`Error::Parse`] at the header: columns missing, unknown, or no target.
    pub(super) fn new(
        header: &csv::StringRecord,
        (path, header_line): (&Path, usize),
        robot: &Robot,
        format: &DataFormat,
        separator: u8,
    ) -> Result<Self, Error> {
        let decimal_comma = format
            .decimal_comma(separator)
            .map_err(|message| Error::parse(path, 1, None, message))?;
        let map = &format.columns;
        let n = robot.joint_count();
        let joint_names: Vec<String> = (1..=n).map(|j| format!("qm{j}")).collect();
        let header: Vec<String> = header.iter().map(|name| name.trim().to_owned()).collect();
        let fail_header = |message: String| Error::parse(path, header_line, None, message);
        let cartesian: Vec<String> = ["x", "y", "z", "qw", "qx", "qy", "qz"]
            .map(String::from)
            .to_vec();
        let wanted: Vec<String> = joint_names.iter().chain(&cartesian).cloned().collect();
        if let Some(message) = map.unused(&header, &wanted).or_else(|| map.clash(&wanted)) {
            return Err(fail_header(message));
        }
        let located = locate(&header, &wanted, map);
        let (joints, rest) = located.positions.split_at(n);
        let (position, orientation) = rest.split_at(3);
        let all_or_none = |group: &[Option<usize>],
                           names: &[String],
                           what: &str|
         -> Result<Option<Vec<usize>>, Error> {
            let found: Vec<usize> = group.iter().flatten().copied().collect();
            if found.is_empty() {
                return Ok(None);
            }
            if found.len() < group.len() {
                let missing: Vec<&str> = group
                    .iter()
                    .zip(names)
                    .filter(|(position, _)| position.is_none())
                    .map(|(_, name)| map.file_name(name))
                    .collect();
                return Err(fail_header(format!(
                    "{what}: missing column(s) {}",
                    missing.join(",")
                )));
            }
            Ok(Some(found))
        };
        let joint_columns = all_or_none(joints, &joint_names, "the joints")?;
        let position_columns = all_or_none(position, &cartesian[..3], "the position")?;
        let orientation_columns = all_or_none(orientation, &cartesian[3..], "the orientation")?;
        let kind = match (&position_columns, &orientation_columns, &joint_columns) {
            (Some(_), Some(_), _) => ProgramKind::Pose,
            (Some(_), None, _) => ProgramKind::Position,
            (None, Some(_), _) => {
                return Err(fail_header(
                    "an orientation (qw,qx,qy,qz) needs its position (x,y,z)".into(),
                ));
            }
            (None, None, Some(_)) => ProgramKind::Joints,
            (None, None, None) => {
                return Err(fail_header(format!(
                    "no target columns; a program's header names {}",
                    target_columns(n)
                )));
            }
        };
        let kept_columns: Vec<usize> = (0..header.len())
            .filter(|column| {
                joint_columns
                    .as_ref()
                    .is_none_or(|joints| !joints.contains(column))
            })
            .collect();
        Ok(ProgramLayout {
            header,
            header_line,
            kept_columns,
            joint_columns,
            position_columns,
            orientation_columns,
            kind,
            units: format.units,
            joint_types: joint_types(robot),
            separator,
            decimal_comma,
            unused_columns: located.unused,
            units_stated: false,
        })
    }

    /// What the targets are.
    pub fn kind(&self) -> ProgramKind {
        self.kind
    }

    /// The units of the file.
    pub fn units(&self) -> DataUnits {
        self.units
    }

    /// Columns kept as they are (not read by gecaro).
    pub fn unused_columns(&self) -> &[String] {
        &self.unused_columns
    }

    /// A value of joint `j` (0-based) in the file's unit, and that unit.
    pub fn joint_in_file_unit(&self, j: usize, value: f64) -> (f64, &'static str) {
        let scale = self.units.joint_scale(&self.joint_types, j);
        let unit = match self.joint_types.get(j) {
            Some(FrameType::Prismatic) => self.units.length.name(),
            _ => self.units.angle.name(),
        };
        (value / scale, unit)
    }
}

/// Targets read, in the order of the file, with what the corrected program
/// needs of them: a whole program, or a block of a program streamed
/// ([`crate::ProgramReader`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProgramBlock {
    /// The targets, in gecaro's units.
    pub points: Vec<ProgramPoint>,
    /// Per target, the fields of the layout's kept columns.
    pub(super) kept: Vec<Vec<String>>,
    /// Per target, its line in the file.
    pub(super) lines: Vec<usize>,
    /// Whether a number read had a decimal comma: the corrected program is
    /// written with the same mark.
    pub(super) comma_seen: bool,
}

impl ProgramBlock {
    /// An empty block with room for `targets` targets.
    pub(super) fn with_capacity(targets: usize) -> Self {
        ProgramBlock {
            points: Vec::with_capacity(targets),
            kept: Vec::with_capacity(targets),
            lines: Vec::with_capacity(targets),
            comma_seen: false,
        }
    }

    /// Targets in the block.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// Whether the block holds no target.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The line in the file of target `index` of the block.
    pub fn line(&self, index: usize) -> usize {
        self.lines[index]
    }

    /// Whether a number of the block was written with a decimal comma.
    pub fn comma_seen(&self) -> bool {
        self.comma_seen
    }

    /// Adds the target of `record`, at `line` of `path`, read as `layout`
    /// says.
    pub(super) fn add(
        &mut self,
        layout: &ProgramLayout,
        path: &Path,
        record: &impl RecordFields,
        line: usize,
    ) -> Result<(), Error> {
        let ProgramLayout {
            header,
            kind,
            units,
            decimal_comma,
            ..
        } = layout;
        if !record.is_text() {
            return Err(Error::parse(path, line, None, NOT_TEXT));
        }
        // (Every field is text once the record is.)
        let field = |column: usize| String::from_utf8_lossy(record.field(column));
        if record.field_count() != header.len() {
            return Err(Error::parse(
                path,
                line,
                None,
                format!(
                    "{} values for {} columns ({})",
                    record.field_count(),
                    header.len(),
                    header.join(",")
                ),
            ));
        }
        let mut comma_seen = false;
        let mut number = |column: usize| -> Result<f64, Error> {
            let bytes = record.field(column);
            if *decimal_comma && bytes.contains(&b',') {
                comma_seen = true;
            }
            // (The bytes at once, as a data file's; the same double as the text's.)
            match field_number(bytes, *decimal_comma) {
                Some(value) if value.is_finite() => Ok(value),
                Some(_) => Err(Error::parse(
                    path,
                    line,
                    Some(header[column].clone()),
                    format!("`{}` is not a finite number", field(column).trim()),
                )),
                None => Err(Error::parse(
                    path,
                    line,
                    Some(header[column].clone()),
                    not_a_number(field(column).trim(), *decimal_comma),
                )),
            }
        };
        let mut joints = layout
            .joint_columns
            .as_ref()
            .map(|joints| -> Result<Vec<f64>, Error> {
                // (Sized at once: collected through a `Result`, the vector
                // would grow, and move, a target at a time.)
                let mut values = Vec::with_capacity(joints.len());
                for (j, column) in joints.iter().enumerate() {
                    values.push(number(*column)? * units.joint_scale(&layout.joint_types, j));
                }
                Ok(values)
            })
            .transpose()?;
        let position = layout
            .position_columns
            .as_ref()
            .map(|position| -> Result<Vector3<f64>, Error> {
                Ok(Vector3::new(
                    number(position[0])?,
                    number(position[1])?,
                    number(position[2])?,
                ) * units.length.to_metres())
            })
            .transpose()?;
        let target = match (kind, position) {
            // A joint program's joints are its targets: moved there, not
            // copied (none are kept beside them).
            (ProgramKind::Joints, _) => ProgramTarget::Joints(joints.take().unwrap_or_default()),
            (_, None) => ProgramTarget::Joints(joints.clone().unwrap_or_default()),
            (ProgramKind::Position, Some(position)) => ProgramTarget::Position(position),
            (ProgramKind::Pose, Some(position)) => {
                let orientation = layout.orientation_columns.as_deref().unwrap_or(&[]);
                let rotation = crate::pose::unit_quaternion(
                    number(orientation[0])?,
                    number(orientation[1])?,
                    number(orientation[2])?,
                    number(orientation[3])?,
                )
                .map_err(|message| {
                    Error::parse(path, line, Some(header[orientation[0]].clone()), message)
                })?;
                ProgramTarget::Pose(IsometryMatrix3::from_parts(
                    Translation3::from(position),
                    rotation.to_rotation_matrix(),
                ))
            }
        };
        self.points.push(ProgramPoint { target, joints });
        self.kept.push(
            layout
                .kept_columns
                .iter()
                .map(|column| field(*column).into_owned())
                .collect(),
        );
        self.lines.push(line);
        self.comma_seen |= comma_seen;
        Ok(())
    }

    /// The targets of a later block after these.
    pub(super) fn append(&mut self, later: ProgramBlock) {
        self.points.extend(later.points);
        self.kept.extend(later.kept);
        self.lines.extend(later.lines);
        self.comma_seen |= later.comma_seen;
    }
}
