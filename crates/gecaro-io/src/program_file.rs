//! Robot programs for compensation: a CSV file of targets, as a controller
//! export or a script writes it, and the same file corrected.
//!
//! A program has joint targets (columns `qm1..qmn`: the configurations the
//! nominal model was programmed with) or Cartesian targets (`x,y,z`, and
//! `qw,qx,qy,qz` for an orientation, world frame); Cartesian targets may
//! carry the program's joints too. Columns are found by name (or through a
//! [`ColumnMap`]), in the file's units ([`DataUnits`]); every other column
//! (time stamps, point names, speeds) is kept as written.
//!
//! The corrected program is the same file with the corrected joint values
//! in the program's own `qm` columns (under its own names), order and units
//! (added at the end when the program had none), then `residual` (position,
//! the file's length unit), `residual_rotation` (the file's angle unit, when
//! orientations are matched) and `status` (`ok`, `reconfigured`,
//! `outside-limits`, `not-reached`) — written with the program's own field
//! separator and decimal mark, so that the controller reads it as it wrote
//! it (and gecaro reads it back).

use gecaro_calib::compensation::{CompensatedPoint, ProgramPoint, ProgramTarget};
use gecaro_calib::parallel::{available_threads, run_parts};
use gecaro_core::{FrameType, Robot};
use nalgebra::{IsometryMatrix3, Translation3, Vector3};
use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::columns::{DataUnits, joint_types, locate, not_a_number, parse_number};
use crate::data_file::DataFormat;
use crate::data_rows::{CHUNK_BYTES, PART_MIN_BYTES};
use crate::input::{
    LineLimit, MAX_LINE_BYTES, csv_reader, csv_reader_with, for_each_record, next_record,
    open_regular,
};
use crate::line_chunks::{LineChunks, line_parts};

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

/// A program read from a CSV file (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramFile {
    header: Vec<String>,
    /// Per target, the fields of the columns the corrected program keeps
    /// as written (all but the joints'; none for a joint program).
    kept: Vec<Vec<String>>,
    /// The positions of those columns in the header.
    kept_columns: Vec<usize>,
    lines: Vec<usize>,
    /// Positions of `qm1..qmn` in the header, if the program has them.
    joint_columns: Option<Vec<usize>>,
    kind: ProgramKind,
    units: DataUnits,
    joint_types: Vec<FrameType>,
    /// The field separator of the file.
    separator: u8,
    /// Whether the file writes its numbers with a decimal comma.
    decimal_comma: bool,
    /// The targets, in gecaro's units.
    pub points: Vec<ProgramPoint>,
    /// Columns kept as they are (not read by gecaro).
    pub unused_columns: Vec<String>,
}

/// Targets formatted at once on one core ([`ProgramFile::format_corrected`]).
const FORMAT_BLOCK: usize = 8192;

/// Most targets a program may hold (as many as a data file's configurations).
const MAX_TARGETS: usize = crate::data_rows::MAX_CONFIGURATIONS;

/// Reads a program for `robot` written as `format` says (units, column
/// names, separator, decimal mark).
///
/// # Errors
/// [`Error::Read`] when it cannot be opened (or is not a regular file),
/// [`Error::Parse`] with line and column for any problem of content.
pub fn read_program(path: &Path, robot: &Robot, format: &DataFormat) -> Result<ProgramFile, Error> {
    let (file, _) = open_regular(path)?;
    parse_program(file, path, robot, format)
}

/// [`read_program`] from a reader; `path` names the program in messages.
///
/// # Errors
/// As [`read_program`].
pub fn parse_program(
    mut input: impl Read,
    path: &Path,
    robot: &Robot,
    format: &DataFormat,
) -> Result<ProgramFile, Error> {
    // The head of the file, whose rows are read in parts on all cores (and
    // then the rest in chunks) when it holds no quote.
    let mut head = Vec::new();
    (&mut input)
        .take(CHUNK_BYTES as u64)
        .read_to_end(&mut head)
        .map_err(|cause| Error::Read {
            path: path.to_owned(),
            cause,
        })?;
    let (units, map) = (format.units, &format.columns);
    let (mut reader, separator) = csv_reader((&head[..]).chain(&mut input), format.delimiter);
    let decimal_comma = format
        .decimal_comma(separator)
        .map_err(|message| Error::parse(path, 1, None, message))?;
    let n = robot.joint_count();
    let joint_names: Vec<String> = (1..=n).map(|j| format!("qm{j}")).collect();
    let expected = format!("{} and/or x,y,z[,qw,qx,qy,qz]", joint_names.join(","));
    let Some((header, header_line)) = next_record(&mut reader, path)? else {
        return Err(Error::parse(
            path,
            1,
            None,
            format!("the file is empty; a program's header names {expected}"),
        ));
    };
    let header: Vec<String> = header.iter().map(|name| name.trim().to_owned()).collect();
    let fail_header = |message: String| Error::parse(path, header_line, None, message);
    let cartesian: Vec<String> = ["x", "y", "z", "qw", "qx", "qy", "qz"]
        .map(String::from)
        .to_vec();
    let wanted: Vec<String> = joint_names.iter().chain(&cartesian).cloned().collect();
    if let Some(message) = map.unused(&header, &wanted) {
        return Err(fail_header(message));
    }
    let layout = locate(&header, &wanted, map);
    let (joints, rest) = layout.positions.split_at(n);
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
                "no target columns; a program's header names {expected}"
            )));
        }
    };
    let types = joint_types(robot);
    let kept_columns: Vec<usize> = (0..header.len())
        .filter(|column| {
            joint_columns
                .as_ref()
                .is_none_or(|joints| !joints.contains(column))
        })
        .collect();
    let targets = TargetColumns {
        path,
        header: &header,
        kind,
        joints: joint_columns.as_deref(),
        position: position_columns.as_deref(),
        orientation: orientation_columns.as_deref(),
        kept: &kept_columns,
        units,
        joint_types: &types,
        decimal_comma,
    };
    let mut read = ReadTargets::default();
    if memchr::memchr(b'"', &head).is_some() {
        // Quoted fields may hold line breaks: one pass over the stream.
        let error = for_each_record(&mut reader, path, 0, |record, line| {
            read.add(&targets, record, line)?;
            if read.points.len() > MAX_TARGETS {
                return Err(too_many_targets(path, line));
            }
            Ok(())
        });
        if let Some(error) = error {
            return Err(error);
        }
    } else {
        let start = (reader.position().byte() as usize).min(head.len());
        let lines_before = memchr::memchr_iter(b'\n', &head[..start]).count();
        drop(reader);
        let mut chunks =
            LineChunks::new((head, start), &mut input, lines_before, CHUNK_BYTES, path);
        while let Some((chunk, lines)) = chunks.next_chunk()? {
            // A short chunk is one part: a thread costs more.
            let count = if chunk.len() < PART_MIN_BYTES {
                1
            } else {
                available_threads()
            };
            let parts = run_parts(
                line_parts(chunk, lines, count),
                |(bytes, lines_before, _)| {
                    let mut csv = csv_reader_with(LineLimit::new(bytes, MAX_LINE_BYTES), separator);
                    let mut part = ReadTargets::default();
                    let error = for_each_record(&mut csv, path, lines_before, |record, line| {
                        part.add(&targets, record, line)
                    });
                    (part, error)
                },
            );
            for (part, error) in parts {
                let room = MAX_TARGETS - read.points.len();
                if part.points.len() > room {
                    return Err(too_many_targets(path, part.lines[room]));
                }
                read.append(part);
                if let Some(error) = error {
                    return Err(error);
                }
            }
        }
    }
    let mut program = ProgramFile {
        header: header.clone(),
        kept: read.kept,
        kept_columns,
        lines: read.lines,
        joint_columns,
        kind,
        units,
        joint_types: types,
        separator,
        decimal_comma: read.comma_seen,
        points: read.points,
        unused_columns: layout.unused.clone(),
    };
    if program.points.is_empty() {
        return Err(Error::parse(
            path,
            header_line + 1,
            None,
            "the program has a header but no targets",
        ));
    }
    program.points.shrink_to_fit();
    Ok(program)
}

/// The error of one target beyond [`MAX_TARGETS`], at `line`.
fn too_many_targets(path: &Path, line: usize) -> Error {
    Error::parse(
        path,
        line,
        None,
        format!("more than {MAX_TARGETS} targets; reading stopped here (split the program)"),
    )
}

/// Where a program's targets are in its records, and in what units.
struct TargetColumns<'a> {
    path: &'a Path,
    header: &'a [String],
    kind: ProgramKind,
    joints: Option<&'a [usize]>,
    position: Option<&'a [usize]>,
    orientation: Option<&'a [usize]>,
    /// The columns the corrected program keeps as written.
    kept: &'a [usize],
    units: DataUnits,
    joint_types: &'a [FrameType],
    decimal_comma: bool,
}

/// Targets read, in order, with what the corrected program needs of them.
#[derive(Default)]
struct ReadTargets {
    points: Vec<ProgramPoint>,
    kept: Vec<Vec<String>>,
    lines: Vec<usize>,
    /// Whether a number read had a decimal comma: the corrected program is
    /// written with the same mark.
    comma_seen: bool,
}

impl ReadTargets {
    /// The target of `record`, at `line` of the file.
    fn add(
        &mut self,
        columns: &TargetColumns<'_>,
        record: &csv::StringRecord,
        line: usize,
    ) -> Result<(), Error> {
        let TargetColumns {
            path,
            header,
            kind,
            units,
            decimal_comma,
            ..
        } = *columns;
        if record.len() != header.len() {
            return Err(Error::parse(
                path,
                line,
                None,
                format!(
                    "{} values for {} columns ({})",
                    record.len(),
                    header.len(),
                    header.join(",")
                ),
            ));
        }
        let mut comma_seen = false;
        let mut number = |column: usize| -> Result<f64, Error> {
            let text = record[column].trim();
            if decimal_comma && text.contains(',') {
                comma_seen = true;
            }
            match parse_number(text, decimal_comma) {
                Some(value) if value.is_finite() => Ok(value),
                Some(_) => Err(Error::parse(
                    path,
                    line,
                    Some(header[column].clone()),
                    format!("`{text}` is not a finite number"),
                )),
                None => Err(Error::parse(
                    path,
                    line,
                    Some(header[column].clone()),
                    not_a_number(text, decimal_comma),
                )),
            }
        };
        let joints = columns
            .joints
            .map(|joints| {
                joints
                    .iter()
                    .enumerate()
                    .map(|(j, column)| {
                        Ok(number(*column)? * units.joint_scale(columns.joint_types, j))
                    })
                    .collect::<Result<Vec<f64>, Error>>()
            })
            .transpose()?;
        let position = columns
            .position
            .map(|position| -> Result<Vector3<f64>, Error> {
                Ok(Vector3::new(
                    number(position[0])?,
                    number(position[1])?,
                    number(position[2])?,
                ) * units.length.to_metres())
            })
            .transpose()?;
        let target = match (kind, position) {
            (ProgramKind::Joints, _) | (_, None) => {
                ProgramTarget::Joints(joints.clone().unwrap_or_default())
            }
            (ProgramKind::Position, Some(position)) => ProgramTarget::Position(position),
            (ProgramKind::Pose, Some(position)) => {
                let orientation = columns.orientation.unwrap_or(&[]);
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
        let joints = match kind {
            ProgramKind::Joints => None,
            _ => joints,
        };
        self.points.push(ProgramPoint { target, joints });
        self.kept.push(
            columns
                .kept
                .iter()
                .map(|column| record[*column].to_owned())
                .collect(),
        );
        self.lines.push(line);
        self.comma_seen |= comma_seen;
        Ok(())
    }

    /// The targets of a later part after these.
    fn append(&mut self, later: ReadTargets) {
        self.points.extend(later.points);
        self.kept.extend(later.kept);
        self.lines.extend(later.lines);
        self.comma_seen |= later.comma_seen;
    }
}

impl ProgramFile {
    /// What the targets are.
    pub fn kind(&self) -> ProgramKind {
        self.kind
    }

    /// The line of target `index` in the file.
    pub fn line(&self, index: usize) -> usize {
        self.lines[index]
    }

    /// The units of the file.
    pub fn units(&self) -> DataUnits {
        self.units
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

    /// The corrected program (see the module docs): one result per target.
    ///
    /// # Panics
    /// If `results` does not hold one result per target (a bug of the caller).
    pub fn format_corrected(&self, results: &[CompensatedPoint]) -> String {
        assert_eq!(results.len(), self.kept.len(), "one result per target");
        let n = self.joint_types.len();
        let mut header = self.header.clone();
        let joint_columns: Vec<usize> = match &self.joint_columns {
            Some(columns) => columns.clone(),
            None => (0..n)
                .map(|j| {
                    header.push(format!("qm{}", j + 1));
                    header.len() - 1
                })
                .collect(),
        };
        let oriented = results.iter().any(|result| result.rotation_error.is_some());
        let column =
            |name: &str, header: &mut Vec<String>| match header.iter().position(|h| h == name) {
                Some(position) => position,
                None => {
                    header.push(name.to_owned());
                    header.len() - 1
                }
            };
        let residual = column("residual", &mut header);
        let rotation = oriented.then(|| column("residual_rotation", &mut header));
        let status = column("status", &mut header);
        // A number into its field (reused: a million rows allocate nothing),
        // with the program's own decimal mark, as it was read.
        let put = |field: &mut String, number: std::fmt::Arguments<'_>| {
            use std::fmt::Write as _;
            field.clear();
            // Writing into a String does not fail.
            let _ = field.write_fmt(number);
            if self.decimal_comma
                && let Some(point) = field.find('.')
            {
                field.replace_range(point..=point, ",");
            }
        };
        let writer = || {
            csv::WriterBuilder::new()
                .delimiter(self.separator)
                .from_writer(Vec::new())
        };
        // Writing into memory does not fail.
        let text = |writer: csv::Writer<Vec<u8>>| writer.into_inner().unwrap_or_default();
        let mut head = writer();
        let _ = head.write_record(&header);
        let mut corrected = text(head);
        // Blocks of targets formatted on all cores, a few at a time (the
        // text is not held twice), joined in order.
        let blocks: Vec<(&[Vec<String>], &[CompensatedPoint])> = self
            .kept
            .chunks(FORMAT_BLOCK)
            .zip(results.chunks(FORMAT_BLOCK))
            .collect();
        let format_block = |(kept, results): (&[Vec<String>], &[CompensatedPoint])| {
            let mut block = writer();
            let mut fields = vec![String::new(); header.len()];
            for (kept, result) in kept.iter().zip(results) {
                for (column, field) in self.kept_columns.iter().zip(kept) {
                    fields[*column].clone_from(field);
                }
                for (j, (column, value)) in joint_columns
                    .iter()
                    .zip(&result.motor_positions)
                    .enumerate()
                {
                    let value = value / self.units.joint_scale(&self.joint_types, j);
                    put(&mut fields[*column], format_args!("{value:?}"));
                }
                let error = result.position_error / self.units.length.to_metres();
                put(&mut fields[residual], format_args!("{error:.3e}"));
                if let Some(rotation) = rotation {
                    let error =
                        result.rotation_error.unwrap_or(0.0) / self.units.angle.to_radians();
                    put(&mut fields[rotation], format_args!("{error:.3e}"));
                }
                fields[status].clear();
                fields[status].push_str(result.status.word());
                let _ = block.write_record(&fields);
            }
            text(block)
        };
        for group in blocks.chunks(2 * available_threads()) {
            for block in run_parts(group.to_vec(), format_block) {
                corrected.extend_from_slice(&block);
            }
        }
        String::from_utf8(corrected).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::columns::{ColumnMap, Delimiter};
    use crate::robot_file::AngleUnit;
    use gecaro_calib::compensation::CompensationStatus;

    /// A controller's export: `;`, decimal commas, degrees, its own joint
    /// names, a point name and a speed.
    const EXPORT: &str = "Point;A1;A2;A3;A4;A5;A6;Speed\n\
                          P1;10,5;-20,25;30;40,125;-50;60;0,5\n\
                          P2;-10;20,5;-30;4;5,75;-6;1\n";

    fn format() -> DataFormat {
        DataFormat {
            units: DataUnits {
                angle: AngleUnit::Degrees,
                ..DataUnits::default()
            },
            columns: ColumnMap::parse("qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6")
                .expect("columns"),
            delimiter: Delimiter::Detect,
            decimal_comma: None,
        }
    }

    #[test]
    fn the_corrected_program_is_written_as_the_program_was() {
        let robot = Robot::template("arm", "RRRRRR").expect("robot");
        let program = parse_program(EXPORT.as_bytes(), Path::new("job.csv"), &robot, &format())
            .expect("read");
        let corrected: Vec<Vec<f64>> = program
            .points
            .iter()
            .map(|point| match &point.target {
                ProgramTarget::Joints(qm) => qm.iter().map(|q| q + 1e-3).collect(),
                _ => unreachable!("joint targets"),
            })
            .collect();
        let results: Vec<CompensatedPoint> = corrected
            .iter()
            .map(|qm| CompensatedPoint {
                motor_positions: qm.clone(),
                position_error: 2.5e-11,
                rotation_error: None,
                status: CompensationStatus::Reached,
            })
            .collect();
        let text = program.format_corrected(&results);
        let mut lines = text.lines();
        assert_eq!(
            lines.next(),
            Some("Point;A1;A2;A3;A4;A5;A6;Speed;residual;status")
        );
        let first = lines.next().expect("a row");
        assert!(first.starts_with("P1;10,5572"), "{first}");
        assert!(first.ends_with(";0,5;2,500e-11;ok"), "{first}");
        // Read back as it was read: the corrected joints.
        let again = parse_program(
            text.as_bytes(),
            Path::new("corrected.csv"),
            &robot,
            &format(),
        )
        .expect("read back");
        for (point, expected) in again.points.iter().zip(&corrected) {
            let ProgramTarget::Joints(qm) = &point.target else {
                unreachable!("joint targets")
            };
            for (a, b) in qm.iter().zip(expected) {
                assert!((a - b).abs() < 1e-12, "{a} vs {b}");
            }
        }
    }

    #[test]
    fn a_long_program_is_corrected_row_for_row_in_order() {
        // Blocks formatted on several cores are joined in the program's order.
        let robot = Robot::template("arm", "RR").expect("robot");
        let count = 3 * FORMAT_BLOCK + 5;
        let mut text = String::from("name,qm1,qm2,speed\n");
        for row in 0..count {
            text.push_str(&format!("P{row},{}e-6,0.5,{}\n", row, row % 7));
        }
        let program = parse_program(
            text.as_bytes(),
            Path::new("long.csv"),
            &robot,
            &DataFormat::default(),
        )
        .expect("read");
        let results: Vec<CompensatedPoint> = (0..count)
            .map(|row| CompensatedPoint {
                motor_positions: vec![row as f64 * 1e-3, -0.25],
                position_error: 0.0,
                rotation_error: None,
                status: CompensationStatus::Reached,
            })
            .collect();
        let corrected = program.format_corrected(&results);
        let mut lines = corrected.lines();
        assert_eq!(lines.next(), Some("name,qm1,qm2,speed,residual,status"));
        for (row, line) in lines.enumerate() {
            let expected = format!(
                "P{row},{:?},-0.25,{},0.000e0,ok",
                row as f64 * 1e-3,
                row % 7
            );
            assert_eq!(line, expected);
        }
        assert_eq!(corrected.lines().count(), count + 1);
    }
}
