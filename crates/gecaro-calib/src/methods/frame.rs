//! Frame (location) measure (paper §3.1): the sensor gives position and
//! orientation of frame n+1. All six rows of eq. 7 per configuration:
//! `J(q, η) Δη = Δx(measured, model)`, with Δx of Appendix I (method 2 by default).

use gecaro_core::{OrientationDifference, Robot, orientation_difference};

use super::sensor::{Reading, random_readings, readings_at};
use super::{CalibrationMethod, MethodInfo};
use crate::Error;
use crate::observation::{RowKind, RowWriter, TerminalState};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;

pub(super) const INFO: MethodInfo = MethodInfo {
    name: "frame",
    title: "Frame measure",
    uses_plane: false,
    build: |options| {
        Ok(Box::new(FrameMeasure {
            orientation: options.orientation,
        }))
    },
};

/// Frame measure; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FrameMeasure {
    orientation: OrientationDifference,
}

impl CalibrationMethod for FrameMeasure {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn independent_configurations(&self) -> bool {
        true
    }

    fn data_columns(&self) -> &'static [DataColumn] {
        &[DataColumn::Position, DataColumn::Orientation]
    }

    fn row_count(&self, samples: &[Sample]) -> usize {
        6 * samples.len()
    }

    fn equations_per_configuration(&self) -> f64 {
        6.0
    }

    fn linearise(
        &self,
        samples: &[Sample],
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        for (index, (sample, state)) in samples.iter().zip(states).enumerate() {
            let position = sample.position.unwrap_or_default() - state.pose.translation.vector;
            let measured_rotation = sample.orientation.unwrap_or_default().to_rotation_matrix();
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

    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        random_readings(robot, Reading::Frame, count, noise, sampler)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: &[Sample],
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        readings_at(real, Reading::Frame, planned, noise, sampler)
    }
}
