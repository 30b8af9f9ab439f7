//! Robot programs for compensation: a CSV file of targets, as a controller
//! export or a script writes it, and the same file corrected.
//!
//! A program has joint targets (columns `qm1..qmn`: the configurations the
//! nominal model was programmed with) or Cartesian targets (`x,y,z`, and
//! `qw,qx,qy,qz` for an orientation, world frame); Cartesian targets may
//! carry the program's joints too. Columns are found by name (or through a
//! [`ColumnMap`](crate::ColumnMap)), in the file's units ([`DataUnits`](crate::DataUnits)); every other column
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

mod corrected;
mod layout;
mod reader;
mod written;

use gecaro_core::Robot;
use gecaro_data::program::CompensatedPoint;
use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::data_file::DataFormat;
use crate::input::open_regular;

pub use corrected::CorrectedProgram;
pub use layout::{ProgramBlock, ProgramKind, ProgramLayout};
pub use reader::ProgramReader;
pub use written::{WrittenRow, format_program};

/// A program read whole from a CSV file (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramFile {
    layout: ProgramLayout,
    /// Every target, in the order of the file.
    targets: ProgramBlock,
    /// The targets, in gecaro's units.
    pub points: Vec<gecaro_data::program::ProgramPoint>,
}

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
    let mut reader = ProgramReader::new(&mut input, path, robot, format)?;
    let mut targets = ProgramBlock::default();
    while let Some(block) = reader.next_block()? {
        targets.append(block);
    }
    let layout = reader.layout().clone();
    let mut points = std::mem::take(&mut targets.points);
    points.shrink_to_fit();
    Ok(ProgramFile {
        layout,
        targets,
        points,
    })
}

impl ProgramFile {
    /// The program's columns.
    pub fn layout(&self) -> &ProgramLayout {
        &self.layout
    }

    /// The line of target `index` in the file.
    pub fn line(&self, index: usize) -> usize {
        self.targets.line(index)
    }

    /// The field of the column `name` (as the header writes it, or as the
    /// format's column map names it) at target `index`, as written; `None`
    /// for a column the program does not have or a joint column.
    pub fn field(&self, index: usize, name: &str) -> Option<&str> {
        let layout = &self.layout;
        let column = layout.header.iter().position(|header| header == name)?;
        let kept = layout
            .kept_columns
            .iter()
            .position(|kept| *kept == column)?;
        self.targets.kept.get(index)?.get(kept).map(String::as_str)
    }

    /// Whether the header has a column `name`.
    pub fn has_column(&self, name: &str) -> bool {
        self.layout.header.iter().any(|header| header == name)
    }

    /// The corrected program (see the module docs): one result per target.
    ///
    /// # Panics
    /// If `results` does not hold one result per target (a bug of the caller).
    pub fn format_corrected(&self, results: &[CompensatedPoint]) -> String {
        let oriented = results.iter().any(|result| result.rotation_error.is_some());
        let corrected = CorrectedProgram::new(&self.layout, oriented, self.targets.comma_seen());
        let mut text = corrected.header();
        // Writing into memory does not fail.
        let _ = corrected.write_rows(&self.targets, results, &mut text);
        String::from_utf8(text).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::corrected::FORMAT_BLOCK;
    use super::*;
    use crate::DataUnits;
    use crate::columns::{ColumnMap, Delimiter};
    use crate::robot_file::AngleUnit;
    use gecaro_data::program::CompensationStatus;
    use gecaro_data::program::ProgramTarget;

    /// A target reached at `motor_positions`, `position_error` away.
    /// `text` read as the program `name` in gecaro's own units and columns.
    fn read(text: &[u8], name: &str, robot: &Robot) -> Result<ProgramFile, Error> {
        parse_program(text, Path::new(name), robot, &DataFormat::default())
    }

    fn reached(motor_positions: Vec<f64>, position_error: f64) -> CompensatedPoint {
        CompensatedPoint {
            motor_positions,
            position_error,
            rotation_error: None,
            tool_turn: None,
            status: CompensationStatus::Reached,
        }
    }

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
            ..DataFormat::default()
        }
    }

    /// A plain program (no quote, comment or blank line) is read a vector
    /// at a time, any other the `csv` crate's way: the same targets, kept
    /// fields (text beyond ASCII too) and corrected program, the lines
    /// after a comment one further down.
    #[test]
    fn plain_and_csv_routes_read_a_program_alike() {
        let robot = Robot::template("arm", "RRRRRR").expect("robot");
        let plain = EXPORT.replacen("P1;", "P1 café;", 1);
        let commented = plain.replacen("\nP2", "\n# the second point\nP2", 1);
        let a =
            parse_program(plain.as_bytes(), Path::new("a.csv"), &robot, &format()).expect("plain");
        let b = parse_program(commented.as_bytes(), Path::new("b.csv"), &robot, &format())
            .expect("commented");
        assert_eq!(a.points, b.points);
        assert_eq!((a.line(0), a.line(1)), (2, 3));
        assert_eq!((b.line(0), b.line(1)), (2, 4));
        let results: Vec<CompensatedPoint> = a
            .points
            .iter()
            .map(|point| match &point.target {
                ProgramTarget::Joints(qm) => reached(qm.clone(), 1e-12),
                _ => unreachable!("joint targets"),
            })
            .collect();
        let text = a.format_corrected(&results);
        assert!(text.contains("P1 café;"), "{text}");
        assert_eq!(text, b.format_corrected(&results));
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
            .map(|qm| reached(qm.clone(), 2.5e-11))
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
        let program = read(text.as_bytes(), "long.csv", &robot).expect("read");
        let results: Vec<CompensatedPoint> = (0..count)
            .map(|row| reached(vec![row as f64 * 1e-3, -0.25], 0.0))
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

    #[test]
    fn a_program_read_in_blocks_is_the_program_read_whole() {
        // Blocks of a few lines, with a comment and a blank line between
        // rows: the same targets, lines and corrected text as read whole.
        let robot = Robot::template("arm", "RR").expect("robot");
        let mut text = String::from("# a cell's export\nname,qm1,qm2\n");
        for row in 0..200 {
            text.push_str(&format!("P{row},{}e-3,0.5\n", row));
            if row == 70 {
                text.push_str("# a comment\n\n");
            }
        }
        let format = DataFormat::default();
        let whole =
            parse_program(text.as_bytes(), Path::new("p.csv"), &robot, &format).expect("whole");
        let mut input = text.as_bytes();
        let mut reader =
            ProgramReader::in_chunks(&mut input, Path::new("p.csv"), &robot, &format, 300)
                .expect("header");
        let mut blocks = Vec::new();
        while let Some(block) = reader.next_block().expect("a block") {
            blocks.push(block);
        }
        assert!(blocks.len() > 10, "{} blocks", blocks.len());
        assert_eq!(reader.targets(), 200);
        assert_eq!(reader.bytes_read(), text.len() as u64);
        let results = |block: &ProgramBlock| -> Vec<CompensatedPoint> {
            (0..block.len())
                .map(|index| reached(vec![block.line(index) as f64, 0.25], 0.0))
                .collect()
        };
        let corrected = CorrectedProgram::new(reader.layout(), false, false);
        let mut streamed = corrected.header();
        let mut lines = Vec::new();
        for block in &blocks {
            corrected
                .write_rows(block, &results(block), &mut streamed)
                .expect("in memory");
            lines.extend((0..block.len()).map(|index| block.line(index)));
        }
        let all: Vec<CompensatedPoint> = blocks.iter().flat_map(results).collect();
        assert_eq!(
            String::from_utf8(streamed).expect("text"),
            whole.format_corrected(&all)
        );
        let expected: Vec<usize> = (0..200).map(|index| whole.line(index)).collect();
        assert_eq!(lines, expected);
        assert_eq!((lines[0], lines[70], lines[71]), (3, 73, 76));
    }

    #[test]
    fn a_program_with_quoted_fields_is_read_record_by_record() {
        // A quoted name may hold the separator and a line break: the record
        // is read whole, named by its last line, and written back quoted.
        let robot = Robot::template("arm", "RR").expect("robot");
        let text = "name,qm1,qm2\n\"P,1\",0.1,0.2\n\"two\nlines\",0.3,0.4\nP3,0.5,0.6\n";
        let program = read(text.as_bytes(), "q.csv", &robot).expect("read");
        assert_eq!(program.points.len(), 3);
        assert_eq!(
            (program.line(0), program.line(1), program.line(2)),
            (2, 4, 5)
        );
        let results: Vec<CompensatedPoint> = (0..3)
            .map(|row| reached(vec![row as f64, 0.5], 0.0))
            .collect();
        let corrected = program.format_corrected(&results);
        assert!(corrected.contains("\"P,1\",0.0,0.5,"), "{corrected}");
        assert!(corrected.contains("\"two\nlines\",1.0,0.5,"), "{corrected}");
        let again = read(corrected.as_bytes(), "corrected.csv", &robot).expect("read back");
        assert_eq!(again.points.len(), 3);
    }
}
