//! A plan's and an accuracy curve's documents.

use super::identifiable::ObservabilityJson;
use gecaro_calib::{
    curve::CurvePoint,
    planning::{Criterion, DesignQuality, Plan},
};
use serde::Serialize;

/// The document of a plan (`gecaro plan --json`, the page's Plan function).
#[derive(Clone, Debug, Serialize)]
pub struct PlanJson {
    /// The method's name.
    pub method: &'static str,
    /// The criterion's name (d, a, e, o4, o5, test).
    pub criterion: &'static str,
    /// What `value` is.
    pub criterion_meaning: &'static str,
    /// The criterion's value for the plan.
    pub value: f64,
    /// The same for a random choice of as many units from the same pool.
    pub random_value: f64,
    /// Configurations of the plan (kept ones included).
    pub configurations: usize,
    /// Units chosen (configurations, sets or pairs).
    pub units: usize,
    /// Configurations in the pool.
    pub pool: usize,
    /// Configurations kept.
    pub kept: usize,
    /// log det(W_bᵀW_b) of the plan (scaled columns).
    pub log_det: f64,
    /// The same for the random choice.
    pub random_log_det: f64,
    /// The plan's observability indices.
    pub observability: ObservabilityJson,
    /// Exchanges made after the greedy pass.
    pub exchanges: usize,
    /// The base parameters judged (auxiliary unknowns first).
    pub columns: Vec<String>,
}

impl PlanJson {
    /// The document of `plan` by `criterion` for `method`, against the
    /// `random` choice, from a pool of `pool` configurations with `kept` kept.
    pub fn new(
        method: &'static str,
        criterion: &Criterion,
        plan: &Plan,
        random: &DesignQuality,
        pool: usize,
        kept: usize,
    ) -> Self {
        PlanJson {
            method,
            criterion: criterion.name(),
            criterion_meaning: criterion.meaning(),
            value: plan.quality.value,
            random_value: random.value,
            configurations: plan.samples.len(),
            units: plan.chosen.len(),
            pool,
            kept,
            log_det: plan.quality.log_det,
            random_log_det: random.log_det,
            observability: plan.quality.observability.into(),
            exchanges: plan.exchanges,
            columns: plan.columns.clone(),
        }
    }
}

/// One count of an accuracy curve ([`gecaro_calib::curve::accuracy_curve`]).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CurvePointJson {
    /// Configurations measured.
    pub configurations: usize,
    /// Predicted RMS position error of the planned design (m); null when it
    /// determines nothing.
    pub planned: Option<f64>,
    /// The mean over random designs (m); null likewise.
    pub random: Option<f64>,
}

impl From<&CurvePoint> for CurvePointJson {
    fn from(point: &CurvePoint) -> Self {
        CurvePointJson {
            configurations: point.count,
            planned: point.planned,
            random: point.random,
        }
    }
}

/// An accuracy curve (`gecaro plan --curve --json`, the page's Plan function).
#[derive(Clone, Debug, Serialize)]
pub struct CurveJson {
    /// The method's name.
    pub method: &'static str,
    /// The criterion of the plans.
    pub criterion: &'static str,
    /// The sensor's σ (m).
    pub noise: f64,
    /// Candidates in the pool.
    pub pool: usize,
    /// Test poses the errors are predicted at.
    pub test_poses: usize,
    /// Random designs averaged per count.
    pub random_draws: usize,
    /// Predicted RMS position error (metres) per count.
    pub points: Vec<CurvePointJson>,
}
