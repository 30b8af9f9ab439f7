//! A change of the cell during a platform's measurement: the observations
//! that stand out of the first fit, read in the data's row order, forming
//! one block (a reflector re-seated, the tracker bumped, the platform's
//! base knocked) — the test of a serial robot's sets
//! ([`crate::identification::CellChange`]), on the one data file of a
//! parallel robot. A robust loss or `--reject` would hide it: the rows
//! after the change weigh nothing and the fit "fits the noise" of the cell
//! as it was.

use gecaro_data::sample::Sample;

use super::measure::PlatformMeasure;
use crate::identification::{CellChange, change_among};

/// The block of consecutive observations of `samples` (measured by
/// `measure`) among those standing out of a fit, `standing_out` (their
/// indices, any order), when they form one; its lines are the data
/// file's. The label is left empty: the front end names the file.
pub(super) fn changed_block(
    samples: &[Sample],
    measure: PlatformMeasure,
    standing_out: &[usize],
) -> Option<CellChange> {
    let taken = measure.samples_per_observation();
    let mut positions = standing_out.to_vec();
    positions.sort_unstable();
    let line = |k: usize, last: bool| {
        let first = positions[k] * taken;
        samples
            .get(if last { first + taken - 1 } else { first })
            .and_then(|sample| sample.line)
    };
    change_among((0, ""), &positions, samples.len() / taken, line)
}
