//! The corrected program: the program's own columns, order, units,
//! separator and decimal mark, its joints corrected, then `residual`,
//! `residual_rotation` (when orientations are matched) and `status`.
//!
//! Rows are formatted a block at a time, over the cores, so that a program
//! read a block at a time ([`crate::ProgramReader`]) is written as it is
//! read.

use gecaro_data::parallel::{available_threads, run_parts};
use gecaro_data::program::CompensatedPoint;

use std::io::Write;

use super::layout::{ProgramBlock, ProgramLayout};

/// Targets formatted at once on one core.
pub(super) const FORMAT_BLOCK: usize = 8192;

/// How the corrected program of a [`ProgramLayout`] is written (see the
/// module docs).
#[derive(Clone, Debug)]
pub struct CorrectedProgram<'a> {
    layout: &'a ProgramLayout,
    header: Vec<String>,
    /// Where each joint's corrected value goes.
    joint_columns: Vec<usize>,
    residual: usize,
    rotation: Option<usize>,
    status: usize,
    /// Whether numbers are written with a decimal comma.
    decimal_comma: bool,
}

impl<'a> CorrectedProgram<'a> {
    /// The corrected program of `layout`, with a rotation residual when
    /// `oriented` (the results have one) and numbers written with a decimal
    /// comma when `decimal_comma` (the program's were).
    pub fn new(layout: &'a ProgramLayout, oriented: bool, decimal_comma: bool) -> Self {
        let mut header = layout.header.clone();
        let joint_columns: Vec<usize> = match &layout.joint_columns {
            Some(columns) => columns.clone(),
            None => (0..layout.joint_types.len())
                .map(|j| {
                    header.push(format!("qm{}", j + 1));
                    header.len() - 1
                })
                .collect(),
        };
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
        CorrectedProgram {
            layout,
            header,
            joint_columns,
            residual,
            rotation,
            status,
            decimal_comma,
        }
    }

    /// A CSV writer into memory of `capacity` bytes, with the program's
    /// separator.
    fn writer(&self, capacity: usize) -> csv::Writer<Vec<u8>> {
        csv::WriterBuilder::new()
            .delimiter(self.layout.separator)
            .from_writer(Vec::with_capacity(capacity))
    }

    /// The header line.
    pub fn header(&self) -> Vec<u8> {
        let mut head = self.writer(0);
        // Writing into memory does not fail.
        let _ = head.write_record(&self.header);
        let record = head.into_inner().unwrap_or_default();
        // A program that stated its units states them again (one that did
        // not is written as the controller wrote it: no line added).
        let mut text = if self.layout.units_stated {
            crate::stated_units::units_line(&self.layout.units())
                .unwrap_or_default()
                .into_bytes()
        } else {
            Vec::new()
        };
        text.extend(record);
        text
    }

    /// Writes the rows of `block` to `output`, one result per target,
    /// formatted on all cores a few pieces at a time (the text is not held
    /// whole), in order.
    ///
    /// # Errors
    /// `output`'s.
    ///
    /// # Panics
    /// If `results` does not hold one result per target (a bug of the caller).
    pub fn write_rows(
        &self,
        block: &ProgramBlock,
        results: &[CompensatedPoint],
        output: &mut dyn Write,
    ) -> std::io::Result<()> {
        assert_eq!(results.len(), block.kept.len(), "one result per target");
        let pieces: Vec<(&[Vec<String>], &[CompensatedPoint])> = block
            .kept
            .chunks(FORMAT_BLOCK)
            .zip(results.chunks(FORMAT_BLOCK))
            .collect();
        for group in pieces.chunks(2 * available_threads()) {
            for piece in run_parts(group.to_vec(), |(kept, results)| self.piece(kept, results)) {
                output.write_all(&piece)?;
            }
        }
        Ok(())
    }

    /// The rows of targets whose kept fields are `kept`.
    fn piece(&self, kept: &[Vec<String>], results: &[CompensatedPoint]) -> Vec<u8> {
        let layout = self.layout;
        // A number into its field (reused: a million rows allocate nothing),
        // with the program's own decimal mark, as it was read.
        let decimal_mark = |field: &mut String| {
            if self.decimal_comma
                && let Some(point) = field.find('.')
            {
                field.replace_range(point..=point, ",");
            }
        };
        let put = |field: &mut String, number: std::fmt::Arguments<'_>| {
            use std::fmt::Write as _;
            field.clear();
            // Writing into a String does not fail.
            let _ = field.write_fmt(number);
            decimal_mark(field);
        };
        let mut digits = zmij::Buffer::new();
        let mut put_shortest = |field: &mut String, value: f64| {
            field.clear();
            shortest(value, &mut digits, field);
            decimal_mark(field);
        };
        // Room for rows of 24 bytes a field, so that the text seldom moves.
        let mut piece = self.writer(24 * self.header.len() * results.len());
        let mut fields = vec![String::new(); self.header.len()];
        for (kept, result) in kept.iter().zip(results) {
            for (column, field) in layout.kept_columns.iter().zip(kept) {
                fields[*column].clone_from(field);
            }
            for (j, (column, value)) in self
                .joint_columns
                .iter()
                .zip(&result.motor_positions)
                .enumerate()
            {
                let value = value / layout.units().joint_scale(&layout.joint_types, j);
                put_shortest(&mut fields[*column], value);
            }
            let error = result.position_error / layout.units().length.to_metres();
            put(&mut fields[self.residual], format_args!("{error:.3e}"));
            if let Some(rotation) = self.rotation {
                let error =
                    result.rotation_error.unwrap_or(0.0) / layout.units().angle.to_radians();
                put(&mut fields[rotation], format_args!("{error:.3e}"));
            }
            fields[self.status].clear();
            fields[self.status].push_str(result.status.word());
            // Writing into memory does not fail.
            let _ = piece.write_record(&fields);
        }
        piece.into_inner().unwrap_or_default()
    }
}

/// The joint values [`shortest`] writes with Żmij: there its digits are
/// those of `{:?}` (both the shortest that read back, the same one chosen;
/// compared on 1.5·10⁶ values), where `{:?}` would switch to an exponent
/// below and Żmij's exponents differ (`1e+16`) above.
const PLAIN_DIGITS: std::ops::Range<f64> = 1e-4..1e4;

/// `value` appended to `field` as the shortest text that reads back to it,
/// as `{:?}` writes it: by Żmij within [`PLAIN_DIGITS`] (and for zero), a
/// few times faster, else by `{:?}`.
fn shortest(value: f64, digits: &mut zmij::Buffer, field: &mut String) {
    if value.is_finite() && (value == 0.0 || PLAIN_DIGITS.contains(&value.abs())) {
        field.push_str(digits.format_finite(value));
    } else {
        use std::fmt::Write as _;
        // Writing into a String does not fail.
        let _ = write!(field, "{value:?}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// A joint value is written as `{:?}` writes it, at any magnitude
        /// (so the text reads back to the same value).
        #[test]
        fn joint_values_are_written_as_debug_writes_them(
            mantissa in -1.0f64..1.0,
            exponent in -12i32..14,
        ) {
            let value = mantissa * 10f64.powi(exponent);
            let mut field = String::new();
            shortest(value, &mut zmij::Buffer::new(), &mut field);
            prop_assert_eq!(&field, &format!("{value:?}"));
            prop_assert_eq!(field.parse::<f64>().ok(), Some(value));
        }
    }

    #[test]
    fn zeros_and_the_ends_of_the_plain_range_are_written_as_debug_writes_them() {
        for value in [
            0.0, -0.0, 1e-4, -1e-4, 9.999e-5, 1e4, 9999.999, 1.0, -3.0, 1e20, -2.5e-9,
        ] {
            let mut field = String::new();
            shortest(value, &mut zmij::Buffer::new(), &mut field);
            assert_eq!(field, format!("{value:?}"), "{value:e}");
        }
    }
}
