//! Position measure (paper §3.1): an external sensor gives the position of the
//! origin of frame n+1 in the world frame. Rows 1–3 of eq. 7 per configuration:
//! `J_P(q, η) Δη = P_measured − P(q, η)`.

use gecaro_core::JacobianRows;

use super::readings::Reading;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::{RowKind, RowWriter};
use crate::sample::DataColumn;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "position",
    "Position measure",
    &[DataColumn::Position],
    JacobianRows::Position,
    3,
    |_| Ok(Box::new(PositionMeasure)),
)
.independent();

/// Position measure; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PositionMeasure;

impl CalibrationMethod for PositionMeasure {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        &Reading::Point
    }

    fn linearise(
        &self,
        samples: SampleSlice<'_>,
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        for (index, (sample, state)) in samples.iter().zip(states).enumerate() {
            let measured = sample.position().unwrap_or_default();
            let difference = measured - state.pose.translation.vector;
            for axis in 0..3 {
                rows.push(
                    RowKind::Length,
                    index,
                    difference[axis],
                    state.jacobian_row(axis),
                    &[],
                );
            }
        }
    }
}
