//! Frame link (paper §3.2): sets of configurations that give the same frame
//! n+1 (a tool locked in a fixture). Data: `set` ids. Eq. 12, six rows per
//! configuration, mean-centred per set.

use gecaro_core::JacobianRows;

use super::link::{LinkSets, Linked, dependent_rows, linearise_sets};
use super::sets::check_group_sizes;
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::RowWriter;
use crate::sample::DataColumn;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "frame-link",
    "Frame link",
    &[DataColumn::Set],
    JacobianRows::Full,
    6,
    |options| {
        Ok(Box::new(FrameLink {
            sensor: LinkSets {
                linked: Linked::Frame(options.orientation),
                set_size: options.set_size.unwrap_or(2),
            },
        }))
    },
)
.scale_invariant();

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

    fn check_samples(&self, samples: SampleSlice<'_>) -> Result<(), Error> {
        check_group_sizes(samples, 2, usize::MAX, "set")
    }

    fn dependent_rows(&self, samples: SampleSlice<'_>) -> usize {
        dependent_rows(self.sensor.linked, samples)
    }

    fn equations_per_configuration(&self) -> f64 {
        self.sensor.equations_per_configuration()
    }

    fn linearise(
        &self,
        samples: SampleSlice<'_>,
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        linearise_sets(self.sensor.linked, samples, states, rows);
    }
}
