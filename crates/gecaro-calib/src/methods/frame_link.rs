//! Frame link (paper §3.2): sets of configurations that give the same frame
//! n+1 (a tool locked in a fixture). Data: `set` ids. Eq. 12, six rows per
//! configuration, mean-centred per set.

use gecaro_core::{OrientationDifference, Robot};

use super::link::{Linked, dependent_rows, generate_sets, linearise_sets, measure_sets};
use super::{CalibrationMethod, MethodInfo, check_group_sizes};
use crate::Error;
use crate::observation::{RowWriter, TerminalState};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;

pub(super) const INFO: MethodInfo = MethodInfo {
    name: "frame-link",
    title: "Frame link",
    uses_plane: false,
    build: |options| {
        Ok(Box::new(FrameLink {
            set_size: options.set_size.unwrap_or(2),
            orientation: options.orientation,
        }))
    },
};

/// Frame link; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FrameLink {
    set_size: usize,
    orientation: OrientationDifference,
}

impl FrameLink {
    fn linked(&self) -> Linked {
        Linked::Frame(self.orientation)
    }
}

impl CalibrationMethod for FrameLink {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn data_columns(&self) -> &'static [DataColumn] {
        &[DataColumn::Set]
    }

    fn check_samples(&self, samples: &[Sample]) -> Result<(), Error> {
        check_group_sizes(samples, 2, usize::MAX, "set")
    }

    fn row_count(&self, samples: &[Sample]) -> usize {
        6 * samples.len()
    }

    fn dependent_rows(&self, samples: &[Sample]) -> usize {
        dependent_rows(self.linked(), samples)
    }

    fn equations_per_configuration(&self) -> f64 {
        6.0 * (1.0 - 1.0 / self.set_size.max(2) as f64)
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
        linearise_sets(self.linked(), samples, states, rows);
    }

    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        generate_sets(self.linked(), robot, count, self.set_size, noise, sampler)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: &[Sample],
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        measure_sets(self.linked(), real, planned, noise, sampler)
    }
}
