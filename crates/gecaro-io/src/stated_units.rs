//! A data file's own statement of its units, so that every file gecaro
//! writes in other units than its own reads back as it was written.
//!
//! A file of configurations written for a teach pendant in degrees (`gecaro
//! plan --angle-unit deg`) starts with a comment line that says so:
//!
//! ```text
//! # units: angle_unit = deg, length_unit = m
//! qm1,qm2,qm3,qm4,qm5,qm6
//! 1.28,28.0,0.98,78.6,-164.1,-137.9
//! ```
//!
//! A reader takes the units such a line states (among the comment lines
//! before the header) where the request leaves gecaro's own (metres,
//! radians), and refuses a request that states other ones: without the
//! line, these degrees were read as radians, silently (28 rad for 28°).
//! Files in metres and radians carry no such line.

use crate::columns::DataUnits;
use crate::robot_file::AngleUnit;
use crate::units::LengthUnit;

/// The key that opens the line.
const KEY: &str = "units:";

/// The line stating `units`, when they are not gecaro's own.
pub(crate) fn units_line(units: &DataUnits) -> Option<String> {
    (!units.is_si()).then(|| {
        format!(
            "# units: angle_unit = {}, length_unit = {}\n",
            units.angle.name(),
            units.length.name()
        )
    })
}

/// The units the comment lines before `head`'s header state, with the
/// line that states them (1-based).
///
/// # Errors
/// The line and what is wrong with a units line that names no unit gecaro
/// knows.
pub(crate) fn stated_units(head: &[u8]) -> Result<Option<(usize, DataUnits)>, (usize, String)> {
    for (index, line) in head.split(|byte| *byte == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let Some(comment) = line.strip_prefix('#') else {
            // The header: no statement before it.
            return Ok(None);
        };
        let Some(statement) = comment.trim().strip_prefix(KEY) else {
            continue;
        };
        return parse(statement)
            .map(|units| Some((index + 1, units)))
            .map_err(|message| (index + 1, message));
    }
    Ok(None)
}

fn parse(statement: &str) -> Result<DataUnits, String> {
    let mut units = DataUnits::default();
    for part in statement.split(',') {
        let (key, value) = part.split_once('=').ok_or_else(|| {
            format!(
                "`{}`: a units line states `angle_unit = deg, length_unit = mm`",
                part.trim()
            )
        })?;
        let value = value.trim();
        match key.trim() {
            "angle_unit" => {
                units.angle = AngleUnit::from_name(value)
                    .ok_or_else(|| format!("angle_unit `{value}`: rad or deg"))?;
            }
            "length_unit" => {
                units.length = LengthUnit::from_name(value)
                    .ok_or_else(|| format!("length_unit `{value}`: m or mm"))?;
            }
            other => {
                return Err(format!(
                    "`{other}`: a units line states angle_unit and length_unit"
                ));
            }
        }
    }
    Ok(units)
}

/// The units to read a file in: `requested`, or where it leaves gecaro's
/// own, the file's `stated` ones.
///
/// # Errors
/// A request that states another unit than the file (the message names
/// both).
pub(crate) fn units_to_read(requested: DataUnits, stated: DataUnits) -> Result<DataUnits, String> {
    Ok(DataUnits {
        angle: unit_to_read(requested.angle, stated.angle, "angles", AngleUnit::name)?,
        length: unit_to_read(requested.length, stated.length, "lengths", LengthUnit::name)?,
    })
}

/// One unit to read `what` in: the `requested` one, or where it is gecaro's
/// own (the default), the `stated` one.
fn unit_to_read<U: Copy + Default + PartialEq>(
    requested: U,
    stated: U,
    what: &str,
    name: fn(U) -> &'static str,
) -> Result<U, String> {
    if requested == U::default() || requested == stated {
        Ok(stated)
    } else {
        Err(format!(
            "the file states its {what} in {}, and it is read in {}: read it as it states",
            name(stated),
            name(requested)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_states_what_it_writes_and_reads_back() {
        let degrees = DataUnits {
            angle: AngleUnit::Degrees,
            length: LengthUnit::Metres,
        };
        let line = units_line(&degrees).expect("not SI");
        let text = format!("# gecaro plan\n{line}qm1,qm2\n1,2\n");
        assert_eq!(stated_units(text.as_bytes()), Ok(Some((2, degrees))));
        assert_eq!(
            units_line(&DataUnits::default()),
            None,
            "SI files say nothing"
        );
        // A statement after the header is a comment among rows, not one.
        assert_eq!(stated_units(format!("qm1\n{line}").as_bytes()), Ok(None));
        assert!(stated_units(b"# units: angle_unit = grad\nqm1\n").is_err());
    }

    #[test]
    fn the_file_fills_what_the_request_leaves_and_a_contradiction_is_refused() {
        let degrees = DataUnits {
            angle: AngleUnit::Degrees,
            length: LengthUnit::Metres,
        };
        assert_eq!(units_to_read(DataUnits::default(), degrees), Ok(degrees));
        assert_eq!(units_to_read(degrees, degrees), Ok(degrees));
        let millimetres = DataUnits {
            length: LengthUnit::Millimetres,
            ..DataUnits::default()
        };
        // The file says millimetres and radians; the request, degrees.
        let stated = DataUnits {
            length: LengthUnit::Millimetres,
            angle: AngleUnit::Radians,
        };
        let error = units_to_read(degrees, stated).expect_err("a contradiction");
        assert!(error.contains("states its angles in rad"), "{error}");
        let error = units_to_read(millimetres, degrees).map(|u| u.length);
        assert_eq!(
            error,
            Err(
                "the file states its lengths in m, and it is read in mm: read it as it states"
                    .into()
            )
        );
    }
}
