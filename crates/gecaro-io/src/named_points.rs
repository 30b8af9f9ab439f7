//! Files of named points measured by an instrument (issue 74): base
//! points, and a user frame's points.
//!
//! **Base points**: the customer's base frame as a drawing gives it.
//!
//! A robot's base is where its owner says it is — the mounting plate, the
//! dowel holes of its drawing — not where joint 1's axis puts gecaro's
//! frame 0. A base-points file lists points measured by the instrument
//! (in the calibration's measurement frame) beside the same points in the
//! base frame, from the drawing:
//!
//! ```text
//! name,x,y,z,base_x,base_y,base_z
//! H1,2412.331,-188.062,-301.958,250,250,0
//! H2,2088.409,195.250,-302.441,-250,250,0
//! ```
//!
//! - `x, y, z`: the point as measured (measurement frame); `base_x,
//!   base_y, base_z`: the same point in the base frame. `name` is
//!   optional (the line names a point without one). Other columns are
//!   left alone; `--columns` renames, as for data files.
//! - Lengths in the file's unit (`--length-unit mm`; metres by default);
//!   fields separated by commas, semicolons or tabs, with decimal commas
//!   where the separator is not a comma; `#` lines are comments.
//! - A coordinate beyond [`MAX_BASE_POINT_DISTANCE`] is refused with its
//!   line: no tracker measures that far, and it is a length in the wrong
//!   unit.
//!
//! **A user frame's points** ([`parse_frame_points`]): `name,x,y,z` as
//! measured, either the three points `origin`, `x` (on the +x axis) and
//! `xy` (in the xy plane, +y side), or any number of points with their
//! coordinates in the user frame, `frame_x,frame_y,frame_z`.

use std::path::Path;

use nalgebra::Vector3;

use crate::Error;
use crate::data_file::DataFormat;
use crate::table_text::TextTable;

/// The farthest a base point may be from either frame's origin (m): a
/// laser tracker's range is under 80 m.
pub const MAX_BASE_POINT_DISTANCE: f64 = 100.0;

/// The most points a base-points file holds.
const MAX_BASE_POINTS: usize = 10_000;

/// A point measured beside its place in the base frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BasePoint {
    /// Its name (the `name` column, else `line N`).
    pub name: String,
    /// The point as measured, in the measurement frame (m).
    pub measured: Vector3<f64>,
    /// The same point in the base frame, from the drawing (m).
    pub base: Vector3<f64>,
    /// Its line in the file (1-based).
    pub line: usize,
}

/// The columns a base-points file needs, in gecaro's names.
const BASE_COLUMNS: [&str; 6] = ["x", "y", "z", "base_x", "base_y", "base_z"];

/// A user frame's points: the measured point, and optionally its place in
/// the frame.
const FRAME_COLUMNS: [&str; 3] = ["x", "y", "z"];
const FRAME_REFERENCE: [&str; 3] = ["frame_x", "frame_y", "frame_z"];

/// A point of a user frame's file (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct FramePoint {
    /// Its name (the `name` column, else `line N`).
    pub name: String,
    /// The point as measured (m).
    pub measured: Vector3<f64>,
    /// Its coordinates in the user frame, when the file gives them (m).
    pub frame: Option<Vector3<f64>>,
    /// Its line in the file (1-based).
    pub line: usize,
}

/// One row of a points file: its name, the required columns' values and
/// the optional group's, in metres, and its line.
struct Row {
    name: String,
    values: Vec<f64>,
    optional: Option<Vec<f64>>,
    line: usize,
}

/// Reads the base points of `text` (the file `path`, named in messages).
///
/// # Errors
/// [`Error::Format`] for a missing column or no point; [`Error::Parse`]
/// with the line and column for a value that is not a number, a distance
/// beyond [`MAX_BASE_POINT_DISTANCE`], a row of the wrong length.
///
/// ```
/// use std::path::Path;
/// let text = "name;x;y;z;base_x;base_y;base_z\nH1;1000,5;0;0;0;0;0\n";
/// let format = gecaro_io::DataFormat {
///     units: gecaro_io::DataUnits { length: gecaro_io::LengthUnit::Millimetres, ..Default::default() },
///     ..Default::default()
/// };
/// let points = gecaro_io::parse_base_points(text, Path::new("plate.csv"), &format).unwrap();
/// assert_eq!(points[0].name, "H1");
/// assert!((points[0].measured.x - 1.0005).abs() < 1e-12);
/// ```
pub fn parse_base_points(
    text: &str,
    path: &Path,
    format: &DataFormat,
) -> Result<Vec<BasePoint>, Error> {
    let hint = "a base-points file has the measured point x,y,z and the same point in the base \
                frame base_x,base_y,base_z (and optionally name)";
    Ok(rows(text, path, format, (&BASE_COLUMNS, &[]), hint)?
        .into_iter()
        .map(|row| BasePoint {
            name: row.name,
            measured: Vector3::new(row.values[0], row.values[1], row.values[2]),
            base: Vector3::new(row.values[3], row.values[4], row.values[5]),
            line: row.line,
        })
        .collect())
}

/// Reads a user frame's points (see the module docs).
///
/// # Errors
/// As [`parse_base_points`]; part of `frame_x, frame_y, frame_z`.
pub fn parse_frame_points(
    text: &str,
    path: &Path,
    format: &DataFormat,
) -> Result<Vec<FramePoint>, Error> {
    let hint = "a frame's points file has name,x,y,z (the points origin, x and xy) and \
                optionally each point's place in the frame, frame_x,frame_y,frame_z";
    Ok(
        rows(text, path, format, (&FRAME_COLUMNS, &FRAME_REFERENCE), hint)?
            .into_iter()
            .map(|row| FramePoint {
                name: row.name,
                measured: Vector3::new(row.values[0], row.values[1], row.values[2]),
                frame: row
                    .optional
                    .map(|values| Vector3::new(values[0], values[1], values[2])),
                line: row.line,
            })
            .collect(),
    )
}

/// The rows of a points file with the `required` columns and, when all are
/// there, the `optional` ones (see the module docs); `hint` says what the
/// file holds.
fn rows(
    text: &str,
    path: &Path,
    format: &DataFormat,
    (required, optional): (&[&str], &[&str]),
    hint: &str,
) -> Result<Vec<Row>, Error> {
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let parse_error = |line: usize, field: Option<&str>, message: String| Error::Parse {
        path: path.to_owned(),
        line,
        field: field.map(str::to_owned),
        message,
    };
    let table = TextTable::parse(
        text,
        path,
        format,
        MAX_BASE_POINTS,
        &format!("this is not a points file ({hint})"),
    )?;
    let names = &table.names;
    let find = |name: &str| table.column(format, name);
    let mut columns = Vec::with_capacity(required.len());
    for name in required {
        columns.push((
            *name,
            find(name).ok_or_else(|| {
                format_error(format!(
                    "no column `{}`: {hint}; its header reads {}",
                    format.columns.file_name(name),
                    names.join(",")
                ))
            })?,
        ));
    }
    let found: Vec<(&str, Option<usize>)> =
        optional.iter().map(|name| (*name, find(name))).collect();
    let optional_columns: Option<Vec<(&str, usize)>> = if found.iter().all(|(_, c)| c.is_some()) {
        (!found.is_empty()).then(|| {
            found
                .iter()
                .filter_map(|(name, column)| column.map(|column| (*name, column)))
                .collect()
        })
    } else if found.iter().any(|(_, c)| c.is_some()) {
        return Err(format_error(format!(
            "the columns {} go together: give all of them or none",
            optional.join(", ")
        )));
    } else {
        None
    };
    let name_column = find("name");
    let metres = format.units.length.to_metres();
    let mut rows = Vec::new();
    for (line, fields) in &table.rows {
        let line = *line;
        let read = |(name, column): &(&str, usize)| -> Result<f64, Error> {
            let value = table.number(path, (line, &fields[*column]), name)? * metres;
            if !(value.is_finite() && value.abs() <= MAX_BASE_POINT_DISTANCE) {
                return Err(parse_error(
                    line,
                    Some(name),
                    format!(
                        "{value} m is beyond any instrument's reach ({MAX_BASE_POINT_DISTANCE} \
                         m): is the file in millimetres (give its length unit)?"
                    ),
                ));
            }
            Ok(value)
        };
        let values = columns.iter().map(read).collect::<Result<Vec<_>, _>>()?;
        let optional = optional_columns
            .as_ref()
            .map(|columns| columns.iter().map(read).collect::<Result<Vec<_>, _>>())
            .transpose()?;
        let name = name_column
            .map(|column| fields[column].clone())
            .filter(|name| !name.is_empty())
            .unwrap_or_else(|| format!("line {line}"));
        rows.push(Row {
            name,
            values,
            optional,
            line,
        });
    }
    if rows.is_empty() {
        return Err(format_error(
            "a header but no point: give at least 3 points not on one line".into(),
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::LengthUnit;

    fn millimetres() -> DataFormat {
        let mut format = DataFormat::default();
        format.units.length = LengthUnit::Millimetres;
        format
    }

    #[test]
    fn a_tracker_export_reads_with_its_names_units_and_commas() {
        let text = "# plate holes, tracker 1\nname;x;y;z;base_x;base_y;base_z;note\n\
                    H1;2412,5;-188;-301,9;250;250;0;front\nH2;2088;195;-302;-250;250;0;\n";
        let points =
            parse_base_points(text, Path::new("plate.csv"), &millimetres()).expect("reads");
        assert_eq!(points.len(), 2);
        assert_eq!((points[0].name.as_str(), points[0].line), ("H1", 3));
        assert!((points[0].measured - Vector3::new(2.4125, -0.188, -0.3019)).norm() < 1e-12);
        assert!((points[1].base - Vector3::new(-0.25, 0.25, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn a_frame_s_points_read_with_or_without_their_place() {
        let path = Path::new("fixture.csv");
        let three = "name,x,y,z\norigin,1,2,0\nx,1.5,2,0\nxy,1,2.4,0\n";
        let points = parse_frame_points(three, path, &DataFormat::default()).expect("reads");
        assert_eq!(points.len(), 3);
        assert!(points.iter().all(|point| point.frame.is_none()));
        let placed = "name,x,y,z,frame_x,frame_y,frame_z\nA,1,2,0,0,0,0\n";
        let points = parse_frame_points(placed, path, &DataFormat::default()).expect("reads");
        assert_eq!(points[0].frame, Some(Vector3::zeros()));
        let part = "name,x,y,z,frame_x\nA,1,2,0,0\n";
        let message = parse_frame_points(part, path, &DataFormat::default())
            .expect_err("part")
            .to_string();
        assert!(message.contains("go together"), "{message}");
    }

    #[test]
    fn mistakes_are_named_with_their_line() {
        let path = Path::new("plate.csv");
        let metres = DataFormat::default();
        for (text, expected) in [
            ("x,y,z,base_x,base_y\n", "no column `base_z`"),
            ("x,y,z,base_x,base_y,base_z\n", "no point"),
            (
                "x,y,z,base_x,base_y,base_z\n1,2,3,0,0,0\n1,2,abc,0,0,0\n",
                "plate.csv:3",
            ),
            (
                "x,y,z,base_x,base_y,base_z\n2412,0,0,0,0,0\n",
                "beyond any instrument's reach",
            ),
            (
                "x,y,z,base_x,base_y,base_z\n1,2,3\n",
                "3 fields where the header has 6",
            ),
        ] {
            let message = parse_base_points(text, path, &metres)
                .expect_err(text)
                .to_string();
            assert!(message.contains(expected), "{text}: {message}");
        }
    }
}
