//! Base points: the customer's base frame as a drawing gives it (issue 74).
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

use std::path::Path;

use nalgebra::Vector3;

use crate::Error;
use crate::columns::parse_number;
use crate::data_file::DataFormat;

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
const COLUMNS: [&str; 6] = ["x", "y", "z", "base_x", "base_y", "base_z"];

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
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(index, line)| (index + 1, line.trim_end_matches('\r')))
        .filter(|(_, line)| !line.trim().is_empty() && !line.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(format_error(
            "no header: a base-points file starts with name,x,y,z,base_x,base_y,base_z".into(),
        ));
    };
    let separator = format.delimiter.byte(header.as_bytes());
    let decimal_comma = format.decimal_comma(separator).map_err(format_error)?;
    let split = |line: &str| -> Vec<String> {
        line.split(char::from(separator))
            .map(|field| field.trim().trim_matches('"').to_owned())
            .collect()
    };
    let names = split(header);
    let find = |name: &str| {
        let file_name = format.columns.file_name(name);
        names.iter().position(|column| column == file_name)
    };
    let mut columns = [0; 6];
    for (slot, name) in columns.iter_mut().zip(COLUMNS) {
        *slot = find(name).ok_or_else(|| {
            format_error(format!(
                "no column `{}`: a base-points file has the measured point x,y,z and the same \
                 point in the base frame base_x,base_y,base_z (and optionally name); its header \
                 reads {}",
                format.columns.file_name(name),
                names.join(",")
            ))
        })?;
    }
    let name_column = find("name");
    let metres = format.units.length.to_metres();
    let mut points = Vec::new();
    for (line, row) in lines {
        if points.len() == MAX_BASE_POINTS {
            return Err(parse_error(
                line,
                None,
                format!("more than {MAX_BASE_POINTS} points: this is not a base-points file"),
            ));
        }
        let fields = split(row);
        if fields.len() != names.len() {
            return Err(parse_error(
                line,
                None,
                format!(
                    "{} fields where the header has {}",
                    fields.len(),
                    names.len()
                ),
            ));
        }
        let mut values = [0.0; 6];
        for ((value, column), name) in values.iter_mut().zip(columns).zip(COLUMNS) {
            let text = &fields[column];
            let number = parse_number(text, decimal_comma).ok_or_else(|| {
                parse_error(line, Some(name), format!("`{text}` is not a number"))
            })?;
            *value = number * metres;
            if !(value.is_finite() && value.abs() <= MAX_BASE_POINT_DISTANCE) {
                return Err(parse_error(
                    line,
                    Some(name),
                    format!(
                        "{} m is beyond any instrument's reach ({MAX_BASE_POINT_DISTANCE} m): is \
                         the file in millimetres (give its length unit)?",
                        *value
                    ),
                ));
            }
        }
        let name = name_column
            .map(|column| fields[column].clone())
            .filter(|name| !name.is_empty())
            .unwrap_or_else(|| format!("line {line}"));
        points.push(BasePoint {
            name,
            measured: Vector3::new(values[0], values[1], values[2]),
            base: Vector3::new(values[3], values[4], values[5]),
            line,
        });
    }
    if points.is_empty() {
        return Err(format_error(
            "a header but no point: give at least 3 points not on one line".into(),
        ));
    }
    Ok(points)
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
