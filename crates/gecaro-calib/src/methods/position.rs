//! Position measure (paper §3.1): an external sensor gives the position of the
//! origin of frame n+1 in the world frame. Rows 1–3 of eq. 7 per configuration:
//! `J_P(q, η) Δη = P_measured − P(q, η)`.

use gecaro_core::{JacobianRows, Robot};

use super::sensor::{Reading, random_readings, readings_at};
use super::{CalibrationMethod, MethodInfo};
use crate::Error;
use crate::observation::{RowKind, RowWriter, TerminalState};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;

pub(super) const INFO: MethodInfo = MethodInfo {
    name: "position",
    title: "Position measure",
    uses_plane: false,
    build: |_| Ok(Box::new(PositionMeasure)),
};

/// Position measure; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PositionMeasure;

impl CalibrationMethod for PositionMeasure {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn jacobian_rows(&self) -> JacobianRows {
        JacobianRows::Position
    }

    fn independent_configurations(&self) -> bool {
        true
    }

    fn data_columns(&self) -> &'static [DataColumn] {
        &[DataColumn::Position]
    }

    fn row_count(&self, samples: &[Sample]) -> usize {
        3 * samples.len()
    }

    fn equations_per_configuration(&self) -> f64 {
        3.0
    }

    fn linearise(
        &self,
        samples: &[Sample],
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        for (index, (sample, state)) in samples.iter().zip(states).enumerate() {
            let measured = sample.position.unwrap_or_default();
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

    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        random_readings(robot, Reading::Point, count, noise, sampler)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: &[Sample],
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        readings_at(real, Reading::Point, planned, noise, sampler)
    }
}
