//! The two link methods of the paper (§3.2), one type ([`LinkMethod`]):
//!
//! - **Point link**: sets of configurations whose terminal points coincide
//!   (a ball in a socket, a tip on a fixed mark). Only joint sensors are
//!   needed. Data: `set` ids. Rows 1–3 of eq. 12, mean-centred per set.
//! - **Frame link**: sets of configurations that give the same frame n+1 (a
//!   tool locked in a fixture). Data: `set` ids. Eq. 12, six rows per
//!   configuration, mean-centred per set.
//!
//! What the sets have in common ([`Linked`]) is all that tells them apart;
//! their rows and their simulated sessions are [`super::link`]'s.

use gecaro_core::JacobianRows;

use super::link::{LinkSets, Linked, dependent_rows, linearise_sets};
use super::sets::check_group_sizes;
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::RowWriter;
use crate::sample::DataColumn;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const POINT_LINK: MethodInfo = MethodInfo::new(
    "point-link",
    "Point link",
    &[DataColumn::Set],
    JacobianRows::Position,
    3,
    |options| {
        Ok(Box::new(LinkMethod {
            info: &POINT_LINK,
            sensor: LinkSets {
                linked: Linked::Point,
                set_size: options.set_size.unwrap_or(4),
            },
        }))
    },
)
.scale_invariant();

pub(super) const FRAME_LINK: MethodInfo = MethodInfo::new(
    "frame-link",
    "Frame link",
    &[DataColumn::Set],
    JacobianRows::Full,
    6,
    |options| {
        Ok(Box::new(LinkMethod {
            info: &FRAME_LINK,
            sensor: LinkSets {
                linked: Linked::Frame(options.orientation),
                set_size: options.set_size.unwrap_or(2),
            },
        }))
    },
)
.scale_invariant();

/// Point link or frame link; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct LinkMethod {
    info: &'static MethodInfo,
    sensor: LinkSets,
}

impl CalibrationMethod for LinkMethod {
    fn info(&self) -> &'static MethodInfo {
        self.info
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
