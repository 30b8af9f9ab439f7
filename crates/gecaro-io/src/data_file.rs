//! Measurement data files: CSV with a header, one configuration per row.
//!
//! Columns: `qm1..qmn` (motor variables, radians or metres) always, then the
//! method's own columns ([`DataColumn`]): `x,y,z` (metres) for a position,
//! `qw,qx,qy,qz` (unit quaternion) for an orientation, `set` (link methods:
//! rows with the same id reach the same point/frame), `pair` and `distance`
//! (distance method: two rows per pair, the measured distance on both).
//! Columns may come in any order; lines starting with `#` are comments.
//! Files are read record by record, never whole, so size is only limited by
//! the samples kept in memory.
//!
//! Every error names the file, the line and the column.

use std::io::Read;
use std::path::Path;

use gecaro_calib::{DataColumn, Sample};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::Error;
use crate::output::{OutputPolicy, write_with};

/// Most configurations a data file may hold. Files are streamed, so a larger
/// one (or an endless stream) stops here with an error naming the line,
/// instead of exhausting memory; no calibration needs this many.
pub const MAX_CONFIGURATIONS: usize = 1_000_000;

/// A quaternion whose norm is further than this from 1 is refused (it is not
/// an orientation, or its columns are mixed up).
const UNIT_TOLERANCE: f64 = 1e-6;

/// The header a data file for `joint_count` joints and these columns must have.
pub fn data_headers(joint_count: usize, columns: &[DataColumn]) -> Vec<String> {
    (1..=joint_count)
        .map(|j| format!("qm{j}"))
        .chain(
            columns
                .iter()
                .flat_map(|c| c.headers().iter().map(|h| (*h).to_owned())),
        )
        .collect()
}

/// Reads a data file.
///
/// # Errors
/// [`Error::Read`] when it cannot be opened, [`Error::Parse`] with line and
/// column for any problem of content.
pub fn read_samples(
    path: &Path,
    joint_count: usize,
    columns: &[DataColumn],
) -> Result<Vec<Sample>, Error> {
    let file = std::fs::File::open(path).map_err(|cause| Error::Read {
        path: path.to_owned(),
        cause,
    })?;
    parse_samples(std::io::BufReader::new(file), path, joint_count, columns)
}

/// Parses data from any reader; `path` only names it in messages.
///
/// # Errors
/// [`Error::Parse`] with line and column.
pub fn parse_samples(
    reader: impl Read,
    path: &Path,
    joint_count: usize,
    columns: &[DataColumn],
) -> Result<Vec<Sample>, Error> {
    let expected = data_headers(joint_count, columns);
    let mut csv = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(reader);
    let mut records = csv.records();
    let fail = |line: usize, field: Option<&str>, message: String| {
        Error::parse(path, line, field.map(str::to_owned), message)
    };
    let header = match records.next() {
        None => {
            return Err(fail(
                1,
                None,
                format!(
                    "the file is empty; it needs a header line: {}",
                    expected.join(",")
                ),
            ));
        }
        Some(record) => record.map_err(|error| csv_error(path, &error))?,
    };
    let header_line = line_of(&header);
    let names: Vec<String> = header.iter().map(str::to_owned).collect();
    if names.iter().all(|name| name.parse::<f64>().is_ok()) {
        return Err(fail(
            header_line,
            None,
            format!(
                "missing header: the first line holds numbers; it must name the columns: {}",
                expected.join(",")
            ),
        ));
    }
    let positions =
        column_positions(&names, &expected).map_err(|message| fail(header_line, None, message))?;
    let mut samples = Vec::new();
    for record in records {
        let record = record.map_err(|error| csv_error(path, &error))?;
        let line = line_of(&record);
        if samples.len() == MAX_CONFIGURATIONS {
            return Err(fail(
                line,
                None,
                format!(
                    "more than {MAX_CONFIGURATIONS} configurations; reading stopped here \
                     (calibration needs far fewer: split or subsample the file)"
                ),
            ));
        }
        if record.len() != names.len() {
            return Err(fail(
                line,
                None,
                format!(
                    "{} values for {} columns ({})",
                    record.len(),
                    names.len(),
                    names.join(",")
                ),
            ));
        }
        let value = |name: &str| -> Result<f64, Error> {
            let text = &record[positions[expected.iter().position(|e| e == name).unwrap_or(0)]];
            let number: f64 = text
                .parse()
                .map_err(|_| fail(line, Some(name), format!("`{text}` is not a number")))?;
            if number.is_finite() {
                Ok(number)
            } else {
                Err(fail(
                    line,
                    Some(name),
                    format!("`{text}` is not a finite number"),
                ))
            }
        };
        let identifier = |name: &str| -> Result<u64, Error> {
            let text = &record[positions[expected.iter().position(|e| e == name).unwrap_or(0)]];
            text.parse().map_err(|_| {
                fail(
                    line,
                    Some(name),
                    format!("`{text}` is not an id (a whole number ≥ 0)"),
                )
            })
        };
        let motor_positions = (1..=joint_count)
            .map(|j| value(&format!("qm{j}")))
            .collect::<Result<Vec<f64>, Error>>()?;
        let mut sample = Sample {
            line: Some(line),
            ..Sample::new(motor_positions)
        };
        for column in columns {
            match column {
                DataColumn::Position => {
                    sample.position = Some(Vector3::new(value("x")?, value("y")?, value("z")?));
                }
                DataColumn::Orientation => {
                    let quaternion =
                        Quaternion::new(value("qw")?, value("qx")?, value("qy")?, value("qz")?);
                    let norm = quaternion.norm();
                    if (norm - 1.0).abs() > UNIT_TOLERANCE {
                        return Err(fail(
                            line,
                            Some("qw"),
                            format!(
                                "(qw, qx, qy, qz) has norm {norm:.6}, not 1: it is not a unit quaternion"
                            ),
                        ));
                    }
                    sample.orientation = Some(UnitQuaternion::from_quaternion(quaternion));
                }
                DataColumn::Set => sample.group = Some(identifier("set")?),
                DataColumn::Pair => sample.group = Some(identifier("pair")?),
                DataColumn::Distance => sample.distance = Some(value("distance")?),
            }
        }
        samples.push(sample);
    }
    if samples.is_empty() {
        return Err(fail(
            header_line + 1,
            None,
            "the file has a header but no configurations".into(),
        ));
    }
    Ok(samples)
}

/// For each expected column, its position in the file's header.
fn column_positions(names: &[String], expected: &[String]) -> Result<Vec<usize>, String> {
    let mut positions = Vec::with_capacity(expected.len());
    for wanted in expected {
        match names.iter().position(|name| name == wanted) {
            Some(position) => positions.push(position),
            None => {
                return Err(format!(
                    "missing column `{wanted}`; this method's data need the columns {}",
                    expected.join(",")
                ));
            }
        }
    }
    if let Some(extra) = names.iter().find(|name| !expected.contains(name)) {
        return Err(format!(
            "unexpected column `{extra}`; this method's data have exactly the columns {}",
            expected.join(",")
        ));
    }
    Ok(positions)
}

fn line_of(record: &csv::StringRecord) -> usize {
    record
        .position()
        .map_or(1, |position| position.line() as usize)
}

fn csv_error(path: &Path, error: &csv::Error) -> Error {
    let line = error
        .position()
        .map_or(1, |position| position.line() as usize);
    let message = match error.kind() {
        csv::ErrorKind::Utf8 { .. } => "the file is not UTF-8 text".to_owned(),
        _ => error.to_string(),
    };
    Error::parse(path, line, None, message)
}

/// The CSV text of a data set.
pub fn format_samples(joint_count: usize, columns: &[DataColumn], samples: &[Sample]) -> String {
    let mut text = data_headers(joint_count, columns).join(",");
    text.push('\n');
    for sample in samples {
        let mut fields: Vec<String> = sample
            .motor_positions
            .iter()
            .map(|v| format!("{v:?}"))
            .collect();
        for column in columns {
            match column {
                DataColumn::Position => {
                    let position = sample.position.unwrap_or_default();
                    fields.extend(position.iter().map(|v| format!("{v:?}")));
                }
                DataColumn::Orientation => {
                    let q = sample.orientation.unwrap_or_default();
                    fields.extend([q.w, q.i, q.j, q.k].iter().map(|v| format!("{v:?}")));
                }
                DataColumn::Set | DataColumn::Pair => {
                    fields.push(sample.group.unwrap_or(0).to_string())
                }
                DataColumn::Distance => {
                    fields.push(format!("{:?}", sample.distance.unwrap_or(0.0)))
                }
            }
        }
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

/// Writes a data set atomically (see [`crate::write_atomically`]).
///
/// # Errors
/// As [`crate::write_atomically`].
pub fn write_samples(
    path: &Path,
    joint_count: usize,
    columns: &[DataColumn],
    samples: &[Sample],
    policy: OutputPolicy,
) -> Result<(), Error> {
    let text = format_samples(joint_count, columns, samples);
    write_with(path, policy, |file| {
        std::io::Write::write_all(file, text.as_bytes())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, columns: &[DataColumn]) -> Result<Vec<Sample>, Error> {
        parse_samples(text.as_bytes(), Path::new("data.csv"), 2, columns)
    }

    fn error_of(text: &str, columns: &[DataColumn]) -> String {
        parse(text, columns).expect_err("invalid").to_string()
    }

    #[test]
    fn round_trip_of_every_column() {
        let columns = [
            DataColumn::Position,
            DataColumn::Orientation,
            DataColumn::Pair,
            DataColumn::Distance,
        ];
        let sample = Sample {
            position: Some(Vector3::new(0.1, -0.2, 1.0 / 3.0)),
            orientation: Some(UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3)),
            group: Some(7),
            distance: Some(0.05),
            ..Sample::new(vec![0.5, -1.25])
        };
        let text = format_samples(2, &columns, std::slice::from_ref(&sample));
        let read = parse(&text, &columns).expect("valid");
        assert_eq!(read[0].motor_positions, sample.motor_positions);
        assert_eq!(read[0].position, sample.position);
        assert_eq!(read[0].group, Some(7));
        assert!(
            read[0]
                .orientation
                .expect("read")
                .angle_to(&sample.orientation.expect("set"))
                < 1e-15
        );
        assert_eq!(read[0].line, Some(2));
    }

    #[test]
    fn columns_may_come_in_any_order_with_comments() {
        let text = "# exported from the tracker\nz,qm2,x,qm1,y\n3,2,1,0.5,2\n";
        let read = parse(text, &[DataColumn::Position]).expect("valid");
        assert_eq!(read[0].motor_positions, [0.5, 2.0]);
        assert_eq!(read[0].position, Some(Vector3::new(1.0, 2.0, 3.0)));
    }

    #[test]
    fn bad_files_name_line_and_column() {
        let position = [DataColumn::Position];
        assert!(error_of("", &position).contains("data.csv:1: the file is empty"));
        assert!(error_of("0,0,1,2,3\n", &position).contains("missing header"));
        assert!(error_of("qm1,qm2,x,y\n0,0,1,2\n", &position).contains("missing column `z`"));
        assert!(error_of("qm1,qm2,x,y,z,w\n", &position).contains("unexpected column `w`"));
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,1,2\n", &position)
                .contains("data.csv:2: 4 values for 5 columns")
        );
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,1,2,3\n0,abc,1,2,3\n", &position)
                .contains("data.csv:3: qm2: `abc` is not a number")
        );
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,NaN,2,3\n", &position)
                .contains("x: `NaN` is not a finite number")
        );
        assert!(error_of("qm1,qm2,x,y,z\n", &position).contains("no configurations"));
        let frame = [DataColumn::Position, DataColumn::Orientation];
        assert!(
            error_of("qm1,qm2,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,1,1,0,0\n", &frame)
                .contains("not a unit quaternion")
        );
        assert!(
            error_of("qm1,qm2,set\n0,0,1.5\n", &[DataColumn::Set])
                .contains("set: `1.5` is not an id")
        );
    }
}
