//! Frame link (paper §3.2): sets of configurations that give the same frame
//! n+1 (a tool locked in a fixture). Data: `set` ids. Eq. 12, six rows per
//! configuration, mean-centred per set.

use super::link::{LinkSets, Linked, dependent_rows, linearise_sets};
use super::sets::check_group_sizes;
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::RowWriter;
use crate::sample::{DataColumn, Sample};
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new("frame-link", "Frame link", false, |options| {
    Ok(Box::new(FrameLink {
        sensor: LinkSets {
            linked: Linked::Frame(options.orientation),
            set_size: options.set_size.unwrap_or(2),
        },
    }))
});

/// Frame link; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FrameLink {
    sensor: LinkSets,
}

impl CalibrationMethod for FrameLink {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        &self.sensor
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
        dependent_rows(self.sensor.linked, samples)
    }

    fn equations_per_configuration(&self) -> f64 {
        6.0 * (1.0 - 1.0 / self.sensor.set_size.max(2) as f64)
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
        linearise_sets(self.sensor.linked, samples, states, rows);
    }
}
