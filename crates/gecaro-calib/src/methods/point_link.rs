//! Point link (paper §3.2): sets of configurations whose terminal points
//! coincide (a ball in a socket, a tip on a fixed mark). Only joint sensors
//! are needed. Data: `set` ids. Rows 1–3 of eq. 12, mean-centred per set.

use gecaro_core::{JacobianRows, Robot};

use super::link::{Linked, dependent_rows, generate_sets, linearise_sets, measure_sets};
use super::{CalibrationMethod, MethodInfo, check_group_sizes};
use crate::Error;
use crate::observation::{RowWriter, TerminalState};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;

pub(super) const INFO: MethodInfo = MethodInfo {
    name: "point-link",
    title: "Point link",
    uses_plane: false,
    build: |options| {
        Ok(Box::new(PointLink {
            set_size: options.set_size.unwrap_or(4),
        }))
    },
};

/// Point link; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PointLink {
    set_size: usize,
}

impl CalibrationMethod for PointLink {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn jacobian_rows(&self) -> JacobianRows {
        JacobianRows::Position
    }

    fn data_columns(&self) -> &'static [DataColumn] {
        &[DataColumn::Set]
    }

    fn check_samples(&self, samples: &[Sample]) -> Result<(), Error> {
        check_group_sizes(samples, 2, usize::MAX, "set")
    }

    fn row_count(&self, samples: &[Sample]) -> usize {
        3 * samples.len()
    }

    fn dependent_rows(&self, samples: &[Sample]) -> usize {
        dependent_rows(Linked::Point, samples)
    }

    fn equations_per_configuration(&self) -> f64 {
        3.0 * (1.0 - 1.0 / self.set_size.max(2) as f64)
    }

    fn scale_invariant(&self) -> bool {
        true
    }

    fn linearise(
        &self,
        samples: &[Sample],
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        linearise_sets(Linked::Point, samples, states, rows);
    }

    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        generate_sets(Linked::Point, robot, count, self.set_size, noise, sampler)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: &[Sample],
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        measure_sets(Linked::Point, real, planned, noise, sampler)
    }
}
