//! Denavit–Hartenberg tables in CSV: a header naming the columns (units
//! may be part of a name: `a_mm`, `alpha_deg`), `base` and `tool` rows.

use std::path::Path;

use super::table::{DhConvention, Row, Table, TableUnits, Units, joint_type};
use crate::Error;
use crate::input::{csv_reader, next_record};
use crate::robot_file::AngleUnit;
use crate::units::LengthUnit;

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

pub(super) fn parse_csv(
    text: &str,
    path: &Path,
    defaults: TableUnits,
    convention: DhConvention,
) -> Result<Table, Error> {
    let (mut reader, _) = csv_reader(text.as_bytes(), crate::Delimiter::Comma);
    let Some((header, header_line)) = next_record(&mut reader, path)? else {
        return Err(Error::parse(
            path,
            1,
            None,
            "the file is empty; it needs a header line: type,a,alpha,d,theta",
        ));
    };
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
    while let Some((record, line)) = next_record(&mut reader, path)? {
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
