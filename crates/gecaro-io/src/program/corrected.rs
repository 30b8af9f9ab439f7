//! The corrected program: the program's own columns, order, units,
//! separator and decimal mark, its joints corrected, then `residual`,
//! `residual_rotation` (when orientations are matched) and `status`.
//!
//! Rows are formatted a block at a time, over the cores, so that a program
//! read a block at a time ([`crate::ProgramReader`]) is written as it is
//! read.

use gecaro_calib::compensation::CompensatedPoint;
use gecaro_calib::parallel::{available_threads, run_parts};

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
        head.into_inner().unwrap_or_default()
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
                put(&mut fields[*column], format_args!("{value:?}"));
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
