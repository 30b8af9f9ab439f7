//! The fit's unknowns after the platform's parameters, in this order: each
//! later station's correction (six, [`super::stations`]), then a measuring
//! leg's `a, b, l` (seven, [`super::leg`]).

use super::leg::{LEG_UNKNOWNS, MeasuringLeg};
use super::stations::StationFrames;

/// The auxiliary unknowns of a fit and their current values.
#[derive(Clone, Debug, Default)]
pub(super) struct Auxiliary {
    /// The stations that measured the samples, with their corrections.
    pub(super) stations: StationFrames,
    /// The measuring leg, for the `leg` measure.
    pub(super) leg: Option<MeasuringLeg>,
}

impl Auxiliary {
    /// None: one station, no leg.
    pub(super) fn none() -> Self {
        Self::default()
    }

    /// How many there are.
    pub(super) fn count(&self) -> usize {
        self.stations.unknowns() + self.leg.map_or(0, |_| LEG_UNKNOWNS)
    }

    /// Their values to start from: no correction, the leg as stated.
    pub(super) fn start(&self) -> Vec<f64> {
        let mut values = vec![0.0; self.stations.unknowns()];
        if let Some(leg) = &self.leg {
            values.extend(leg.unknowns());
        }
        values
    }

    /// The same unknowns at `values` (the fit's values after the
    /// platform's parameters).
    pub(super) fn at(&self, values: &[f64]) -> Self {
        let corrections = self.stations.unknowns();
        Self {
            stations: self.stations.at(&values[..corrections]),
            leg: self
                .leg
                .map(|leg| leg.with_unknowns(&values[corrections..corrections + LEG_UNKNOWNS])),
        }
    }

    /// The leg's first column among `parameters` and these unknowns.
    pub(super) fn leg_column(&self, parameters: usize) -> usize {
        parameters + self.stations.unknowns()
    }

    /// The same unknowns for the samples kept by `keep` (their indices).
    pub(super) fn kept(&self, keep: impl Fn(usize) -> bool) -> Self {
        Self {
            stations: self.stations.kept(keep),
            leg: self.leg,
        }
    }
}
