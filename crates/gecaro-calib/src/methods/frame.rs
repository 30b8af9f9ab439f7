//! Frame (location) measure (paper §3.1): the sensor gives position and
//! orientation of frame n+1. All six rows of eq. 7 per configuration:
//! `J(q, η) Δη = Δx(measured, model)`, with Δx of Appendix I (method 2 by default).

use gecaro_core::{JacobianRows, OrientationDifference, orientation_difference};

use super::readings::Reading;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::{RowKind, RowWriter};
use crate::sample::DataColumn;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "frame",
    "Frame measure",
    &[DataColumn::Position, DataColumn::Orientation],
    JacobianRows::Full,
    6,
    |options| {
        Ok(Box::new(FrameMeasure {
            orientation: options.orientation,
        }))
    },
)
.independent();

/// Frame measure; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FrameMeasure {
    orientation: OrientationDifference,
}

impl CalibrationMethod for FrameMeasure {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        &Reading::Frame
    }

    fn linearise(
        &self,
        samples: SampleSlice<'_>,
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        for (index, (sample, state)) in samples.iter().zip(states).enumerate() {
            let position = sample.position().unwrap_or_default() - state.pose.translation.vector;
            let measured_rotation = sample
                .orientation()
                .unwrap_or_default()
                .to_rotation_matrix();
            let rotation =
                orientation_difference(&measured_rotation, &state.pose.rotation, self.orientation);
            for axis in 0..6 {
                let (kind, residual) = if axis < 3 {
                    (RowKind::Length, position[axis])
                } else {
                    (RowKind::Angle, rotation[axis - 3])
                };
                rows.push(kind, index, residual, state.jacobian_row(axis), &[]);
            }
        }
    }
}
