//! What an identification adds to the plain least-squares system: robust
//! weights per observation and a prior's pseudo-observation rows (the
//! reweighted phase, [`super::reweighting`]), and the gauge row that holds
//! the scale of a study that does not observe it ([`super::scale`]).

use gecaro_core::Robot;

use super::gauge::Gauge;
use crate::observation::ObservationSystem;
use crate::prior::Prior;

/// The prior σ of the parameters the second pass adds: 1 cm, 1°, 1 % (the
/// deviations a calibration meets; the data determine these parameters only
/// weakly, through the real robot's deviations from the nominal structure).
/// Also the weak prior of the damped descent, the σ that expands a
/// regrouped value and chooses an unobserved scale, without a user's prior.
pub const SECOND_PASS_PRIOR: [f64; 3] = [0.01, std::f64::consts::PI / 180.0, 0.01];

/// [`SECOND_PASS_PRIOR`] as a prior.
pub(super) fn second_pass_prior() -> Prior {
    Prior {
        length: SECOND_PASS_PRIOR[0],
        angle: SECOND_PASS_PRIOR[1],
        gain: SECOND_PASS_PRIOR[2],
        overrides: Vec::new(),
    }
}

/// What the reweighted phase adds to the plain system.
#[derive(Clone, Debug, Default)]
pub(super) struct Weighting {
    /// Robust weight per observation (empty: all 1).
    pub(super) observation_weights: Vec<f64>,
    /// Prior rows: column of W_b, row weight `s/σ_k`, vocabulary index.
    pub(super) prior_rows: Vec<PriorRow>,
    /// The row that holds the robot's scale in a step over every
    /// parameter, when the data do not observe it.
    pub(super) gauge: Option<Gauge>,
}

/// One prior pseudo-observation: `weight · Δη = weight · (η_centre − η)`.
#[derive(Copy, Clone, Debug)]
pub(super) struct PriorRow {
    pub(super) column: usize,
    /// The value the prior is centred on.
    pub(super) centre: f64,
    /// The parameter's prior σ (regrouping included).
    pub(super) sigma: f64,
    /// Its vocabulary index.
    pub(super) index: usize,
    /// The row weight: data σ̂ over the prior σ.
    pub(super) weight: f64,
}

impl Weighting {
    /// Appends the gauge row and the prior rows at `robot` to a system
    /// written at `robot`.
    pub(super) fn append_rows(&self, system: &mut ObservationSystem, robot: &Robot) {
        if let Some(gauge) = &self.gauge {
            gauge.append_to(system, robot);
        }
        if self.prior_rows.is_empty() {
            return;
        }
        let rows: Vec<(usize, f64, f64)> = self
            .prior_rows
            .iter()
            .map(|row| {
                let id = robot.parameters().id(row.index);
                (row.column, row.weight, row.centre - robot.parameter(id))
            })
            .collect();
        system.append_rows(&rows);
    }
}
