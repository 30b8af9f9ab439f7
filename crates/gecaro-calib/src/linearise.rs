//! A measurement set linearised into the rows of W (eq. 6, 8): its
//! configurations evaluated block by block (each block's states still in
//! cache when the method reads them), large sets over all cores, the rows
//! written whole or folded as they are written ([`crate::fold`]).

use gecaro_core::{Error as ModelError, JacobianRows, KinematicModel, LaneBuffer};

use crate::fold::{FoldKind, FoldedRows, RowFold};
use crate::frames::SetFrames;
use crate::linalg::view;
use crate::samples::SampleSlice;

use crate::method::CalibrationMethod;
use crate::parallel::run_parts_with;
use crate::states::{BLOCK, evaluate_chunk, part_size};

use crate::rows::{ColumnLayout, RowWriter};
use crate::states::TerminalState;

/// Has `method` write its rows for `samples` (whose states are `states`)
/// into `writer` and returns one past the largest observation written,
/// numbered in the whole system (0 when nothing was written).
pub(crate) fn write_rows(
    mut writer: RowWriter<'_>,
    method: &dyn CalibrationMethod,
    samples: SampleSlice<'_>,
    states: &[TerminalState],
    auxiliary: &[f64],
) -> usize {
    method.linearise(samples, states, auxiliary, &mut writer);
    writer.finish(method.name())
}

/// Evaluates and linearises a set of `method`, whose configurations are
/// independent ([`CalibrationMethod::independent_configurations`]), into
/// `writer`: block by block, so that each block's states are still in cache
/// when the method reads them, and large sets over all cores. The rows are
/// those of [`evaluate_states`](crate::states::evaluate_states) followed by [`CalibrationMethod::linearise`]
/// on the whole set, bit for bit; with the set's named `frames`, each state
/// is that of the measured pose ([`crate::frames`]). Returns the end of the observations
/// written (see [`RowWriter::observation_end`]).
///
/// # Errors
/// When a sample's configuration does not fit the robot (the first such sample).
pub(crate) fn linearise_independent(
    model: &KinematicModel,
    method: &dyn CalibrationMethod,
    samples: SampleSlice<'_>,
    auxiliary: &[f64],
    frames: Option<&SetFrames<'_>>,
    writer: RowWriter<'_>,
) -> Result<usize, ModelError> {
    let selection = selected(model, writer.layout, frames);
    let (model, mut writer) = match &selection {
        Some((model, layout)) => (model, RowWriter { layout, ..writer }),
        None => (model, writer),
    };
    if let Some(kind) = writer.fold {
        return linearise_folded(model, method, samples, auxiliary, frames, writer, kind);
    }
    let (rows, evaluated) = jacobian_rows(method, frames);
    // No column reads the Jacobian (the errors alone, as `evaluate` asks):
    // its rows are empty, the kinematics poses only.
    let jacobian = (frames.is_some() || writer.layout.maps_parameters()).then_some(evaluated);
    let parts: Vec<(SampleSlice<'_>, RowWriter<'_>)> = samples
        .chunks(part_size(samples.len()))
        .map(|chunk| {
            (
                chunk,
                writer.split_front(method.row_count(chunk), chunk.len()),
            )
        })
        .collect();
    let ends = run_parts_with(parts, PartBuffers::default, |buffers, (chunk, mut part)| {
        let PartBuffers { states, lanes, .. } = buffers;
        let mut end = 0;
        for block in chunk.chunks(BLOCK) {
            states.resize_with(block.len(), || TerminalState::empty(model));
            evaluate_chunk(model, block, jacobian, &mut states[..block.len()], lanes)?;
            if jacobian.is_none() {
                for state in &mut states[..block.len()] {
                    state.with_empty_jacobian(evaluated);
                }
            }
            if let Some(frames) = frames {
                for state in &mut states[..block.len()] {
                    frames.apply(state, rows.count());
                }
            }
            let block_rows = part.split_front(method.row_count(block), block.len());
            end = end.max(write_rows(
                block_rows,
                method,
                block,
                &states[..block.len()],
                auxiliary,
            ));
        }
        Ok(end)
    });
    ends.into_iter()
        .try_fold(0, |end, part: Result<usize, ModelError>| Ok(end.max(part?)))
}

/// `model` computing only the Jacobian columns that `layout` keeps, and the
/// layout of its rows ([`KinematicModel::selecting`]), when some column of
/// W reads the Jacobian and the set has no named `frames` (whose states
/// need every column, [`crate::frames`]). The rows are the same, bit for
/// bit: the same values, fewer of them computed, copied whole.
fn selected(
    model: &KinematicModel,
    layout: &ColumnLayout,
    frames: Option<&SetFrames<'_>>,
) -> Option<(KinematicModel, ColumnLayout)> {
    if frames.is_some() || !layout.maps_parameters() {
        return None;
    }
    let model = model.selecting(&layout.kept_parameters());
    let layout = layout.for_selected(model.parameter_count());
    Some((model, layout))
}

/// The Jacobian rows `method` reads, and those to evaluate: all six with
/// named `frames` (a named tool moves the point with the flange's rotation).
fn jacobian_rows(
    method: &dyn CalibrationMethod,
    frames: Option<&SetFrames<'_>>,
) -> (JacobianRows, JacobianRows) {
    let rows = method.jacobian_rows();
    (
        rows,
        if frames.is_some() {
            JacobianRows::Full
        } else {
            rows
        },
    )
}

/// Configurations of one part of a folded set of `configurations`: the
/// parts are folded separately (on all cores) and merged in order, so
/// their size, which the data set and not the number of cores, sets the
/// order of the sums. About 16 parts of 512 to 4,096 configurations:
/// 5,000 make ten parts that two cores share evenly (not 4,096 and 904),
/// and a million make parts whose set-up is nothing (figures in
/// docs/performance.md).
fn fold_part(configurations: usize) -> usize {
    configurations.div_ceil(16).clamp(512, 4096)
}

/// Rows of W written before they are folded: a block that stays in cache.
const FOLD_ROWS: usize = 384;

/// What a thread linearising parts of a set keeps from one part to the
/// next ([`run_parts_with`]): the blocks' terminal states and the lanes they
/// are evaluated in; when the rows are folded, the rows held until they are
/// folded and their weighted right-hand sides. The rows only grow (a writer
/// fills its rows whole, `RowWriter::split_front_into`), so their memory is
/// zeroed once, not once a block.
#[derive(Default)]
struct PartBuffers {
    states: Vec<TerminalState>,
    lanes: LaneBuffer,
    rows: Vec<f64>,
    right: Vec<f64>,
}

/// [`linearise_independent`] for a writer that folds its rows ([`crate::fold`]):
/// each part writes blocks of rows into a small buffer, folds them, and
/// hands its sums on; the parts' sums are merged in order into the set's
/// writer.
fn linearise_folded(
    model: &KinematicModel,
    method: &dyn CalibrationMethod,
    samples: SampleSlice<'_>,
    auxiliary: &[f64],
    frames: Option<&SetFrames<'_>>,
    mut writer: RowWriter<'_>,
    kind: FoldKind,
) -> Result<usize, ModelError> {
    let (rows, evaluated) = jacobian_rows(method, frames);
    let columns = writer.columns;
    let parts: Vec<(SampleSlice<'_>, RowWriter<'_>)> = samples
        .chunks(fold_part(samples.len()))
        .map(|chunk| {
            (
                chunk,
                writer.split_front(method.row_count(chunk), chunk.len()),
            )
        })
        .collect();
    let folded = run_parts_with(parts, PartBuffers::default, |buffers, (chunk, mut part)| {
        let mut fold = RowFold::new(columns, kind, method.row_count(chunk));
        let PartBuffers {
            states,
            lanes,
            rows: buffer,
            right,
        } = buffers;
        right.clear();
        let mut end = 0;
        for block in chunk.chunks(BLOCK) {
            states.resize_with(block.len(), || TerminalState::empty(model));
            evaluate_chunk(
                model,
                block,
                Some(evaluated),
                &mut states[..block.len()],
                lanes,
            )?;
            if let Some(frames) = frames {
                for state in &mut states[..block.len()] {
                    frames.apply(state, rows.count());
                }
            }
            let count = method.row_count(block);
            let held = right.len();
            if held > 0 && held + count > FOLD_ROWS {
                fold.push(view(&buffer[..held * columns], held, columns), right);
                right.clear();
            }
            let (start, end_of_rows) = (right.len() * columns, (right.len() + count) * columns);
            if buffer.len() < end_of_rows {
                buffer.resize(end_of_rows, 0.0);
            }
            let mut block_rows =
                part.split_front_into(count, block.len(), &mut buffer[start..end_of_rows]);
            method.linearise(block, &states[..block.len()], auxiliary, &mut block_rows);
            right.extend(block_rows.weighted_residuals());
            end = end.max(block_rows.finish(method.name()));
        }
        if !right.is_empty() {
            let held = right.len();
            fold.push(view(&buffer[..held * columns], held, columns), right);
        }
        Ok((end, fold.finish()))
    });
    let mut end = 0;
    let mut parts = Vec::with_capacity(folded.len());
    for part in folded {
        let (part_end, rows) = part?;
        end = end.max(part_end);
        parts.push(rows);
    }
    if let Some(sink) = writer.sink.take() {
        let merged = std::mem::replace(sink, FoldedRows::empty(columns, kind)).merged(parts);
        *sink = merged;
    }
    Ok(end)
}
