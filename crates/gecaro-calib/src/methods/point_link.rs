//! Point link (paper §3.2): sets of configurations whose terminal points
//! coincide (a ball in a socket, a tip on a fixed mark). Only joint sensors
//! are needed. Data: `set` ids. Rows 1–3 of eq. 12, mean-centred per set.

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
    "point-link",
    "Point link",
    &[DataColumn::Set],
    JacobianRows::Position,
    3,
    |options| {
        Ok(Box::new(PointLink {
            sensor: LinkSets {
                linked: Linked::Point,
                set_size: options.set_size.unwrap_or(4),
            },
        }))
    },
)
.scale_invariant();

/// Point link; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PointLink {
    sensor: LinkSets,
}

impl CalibrationMethod for PointLink {
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
        dependent_rows(Linked::Point, samples)
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
        linearise_sets(Linked::Point, samples, states, rows);
    }
}
