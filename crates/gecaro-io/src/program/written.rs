//! A program gecaro writes: rows of keys (a test's pose and cycle, say),
//! the joints `qm1..qmn` and the Cartesian target `x,y,z[,qw,qx,qy,qz]` of
//! frame n+1 — in the units, column names, separator and decimal mark a
//! [`DataFormat`] asks for, as [`crate::read_program`] reads it back (the
//! keys are kept columns there, [`ProgramFile::field`](super::ProgramFile::field)).

use gecaro_core::FrameType;
use nalgebra::IsometryMatrix3;

use crate::data_file::{DataFormat, written_numbers};
use crate::stated_units::units_line;

/// One row of a written program.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenRow<'a> {
    /// The fields of the key columns, as written.
    pub keys: Vec<String>,
    /// Motor values qm (m, rad).
    pub motor_positions: &'a [f64],
    /// The target of frame n+1 (world frame, m).
    pub target: &'a IsometryMatrix3<f64>,
}

/// The CSV text of a program of `rows` for a robot of `joint_types` (from
/// [`crate::joint_types`]): the columns `keys`, then the joints, then the
/// target's position and, when `oriented`, its quaternion (w ≥ 0); written
/// as `format` asks (a units line when its units are not gecaro's, its
/// column names, its separator and decimal mark).
pub fn format_program(
    joint_types: &[FrameType],
    keys: &[&str],
    rows: &[WrittenRow<'_>],
    oriented: bool,
    format: &DataFormat,
) -> String {
    let (separator, number) = written_numbers(format);
    let mut names: Vec<String> = keys.iter().map(|key| (*key).to_owned()).collect();
    names.extend((1..=joint_types.len()).map(|j| format!("qm{j}")));
    let cartesian: &[&str] = if oriented {
        &["x", "y", "z", "qw", "qx", "qy", "qz"]
    } else {
        &["x", "y", "z"]
    };
    names.extend(cartesian.iter().map(|name| (*name).to_owned()));
    let header: Vec<&str> = names
        .iter()
        .map(|name| format.columns.file_name(name))
        .collect();
    let mut text = units_line(&format.units).unwrap_or_default();
    let separator = separator.to_string();
    text.push_str(&header.join(&separator));
    text.push('\n');
    let length = format.units.length.to_metres();
    for row in rows {
        let mut fields = row.keys.clone();
        fields.extend(
            format
                .units
                .configuration_from_si(joint_types, row.motor_positions)
                .into_iter()
                .map(number),
        );
        fields.extend(
            row.target
                .translation
                .vector
                .iter()
                .map(|value| number(value / length)),
        );
        if oriented {
            let q = nalgebra::UnitQuaternion::from_rotation_matrix(&row.target.rotation);
            let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
            fields.extend([q.w, q.i, q.j, q.k].map(|value| number(sign * value)));
        }
        text.push_str(&fields.join(&separator));
        text.push('\n');
    }
    text
}
