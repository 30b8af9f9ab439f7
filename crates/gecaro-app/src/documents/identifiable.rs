//! The "Identifiable parameters" function's document (Appendix III): each
//! parameter's status, the regrouping relations, the observability indices
//! and the excitation check.

use gecaro_calib::{
    identifiability::{Classified, Identifiability, RankReport},
    observability::Observability,
};
use gecaro_core::Robot;
use serde::Serialize;

/// One parameter's identifiability.
#[derive(Clone, Debug, Serialize)]
pub struct StatusJson {
    /// `theta0`, `alpha3`, `K2`, or an auxiliary unknown (`a`, `b`, …).
    pub name: String,
    /// Its priority (column order of the QR).
    pub priority: u32,
    /// `identifiable`, `regrouped`, `no_effect` or `excluded`.
    pub status: &'static str,
}

impl From<&Classified> for StatusJson {
    fn from(classified: &Classified) -> Self {
        StatusJson {
            name: classified.name.clone(),
            priority: classified.priority,
            status: classified.status.as_str(),
        }
    }
}

/// The rows of a matrix as lists (serde writes fixed-size arrays as tuples,
/// which Python would see as tuples rather than the lists JSON gives).
fn rows_as_lists<S: serde::Serializer>(
    rows: &[[u32; 6]],
    serializer: S,
) -> Result<S::Ok, S::Error> {
    serializer.collect_seq(rows.iter().map(|row| row.as_slice()))
}

/// A parameter absorbed by a base parameter, with its coefficient.
#[derive(Clone, Debug, Serialize)]
pub struct AbsorbedJson {
    /// The absorbed parameter.
    pub name: String,
    /// Its coefficient β in eq. 32.
    pub coefficient: f64,
}

/// A regrouping relation: `base_b = base + Σ coefficient·absorbed` (eq. 32).
#[derive(Clone, Debug, Serialize)]
pub struct RelationJson {
    /// The base parameter.
    pub base: String,
    /// What it absorbs.
    pub absorbed: Vec<AbsorbedJson>,
}

/// The observability indices of W_b, its columns scaled to 1 cm, 1°, 1 %
/// (see [`gecaro_calib::observability::Observability`]; larger is better for all five).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ObservabilityJson {
    /// (σ1⋯σL)^(1/L)/√m (Borm & Menq).
    pub o1: f64,
    /// σL/σ1 (Driels & Pathre).
    pub o2: f64,
    /// σL (Nahvi & Hollerbach).
    pub o3: f64,
    /// σL²/σ1, the noise amplification index (Nahvi & Hollerbach).
    pub o4: f64,
    /// 1/Σ(1/σi) (Sun & Hollerbach).
    pub o5: f64,
}

impl From<Observability> for ObservabilityJson {
    fn from(indices: Observability) -> Self {
        ObservabilityJson {
            o1: indices.o1,
            o2: indices.o2,
            o3: indices.o3,
            o4: indices.o4,
            o5: indices.o5,
        }
    }
}

/// The excitation check of measured data (§4).
#[derive(Clone, Debug, Serialize)]
pub struct ExcitationJson {
    /// Whether the data excite every structural base parameter.
    pub same_base_set: bool,
    /// Structural base parameters the data do not excite.
    pub not_excited: Vec<String>,
    /// Condition number of W_b built from the data (at the nominal parameters).
    pub condition_number: f64,
}

/// The "Identifiable parameters" function's result.
#[derive(Clone, Debug, Serialize)]
pub struct IdentifiableJson {
    /// The study's methods, joined with `+`.
    pub method: String,
    /// The robot's name.
    pub robot: String,
    /// What the rank test ran on.
    pub source: String,
    /// Configurations of that data.
    pub configurations: usize,
    /// Number of identifiable robot parameters.
    pub count: usize,
    /// Condition number of W_b.
    pub condition_number: f64,
    /// Rows of W.
    pub rows: usize,
    /// Independent equations.
    pub equations: usize,
    /// The numerical zero τ.
    pub tolerance: f64,
    /// Smallest |R_ii| kept.
    pub smallest_kept: f64,
    /// Largest |R_ii| rejected.
    pub largest_rejected: f64,
    /// How well the regrouping relations hold.
    pub relation_residual: f64,
    /// Every robot parameter, in vocabulary order.
    pub parameters: Vec<StatusJson>,
    /// The method's own unknowns (plane coefficients).
    pub auxiliary: Vec<StatusJson>,
    /// Regrouping relations.
    pub regrouping: Vec<RelationJson>,
    /// The new priority matrix ((n+2) rows of α, d, θ, r, β, K; 0 = not identified).
    #[serde(serialize_with = "rows_as_lists")]
    pub priority_matrix: Vec<[u32; 6]>,
    /// Observability indices of W_b: of the measured data when given, else of
    /// the random configurations.
    pub observability: ObservabilityJson,
    /// For measured data: the excitation check.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub excitation: Option<ExcitationJson>,
    /// What the set-up keeps from being identified (a measured point on a
    /// joint's axis), before any data are taken.
    pub warnings: Vec<String>,
}

impl IdentifiableJson {
    /// The document of an identifiability analysis of `robot`.
    pub fn new(robot: &Robot, analysis: &Identifiability) -> Self {
        let report: &RankReport = &analysis.report;
        IdentifiableJson {
            method: report.method.clone(),
            robot: robot.name().to_owned(),
            source: analysis.source.clone(),
            configurations: analysis.configurations,
            count: report.count(),
            condition_number: report.condition_number(),
            rows: report.rows,
            equations: report.equations,
            tolerance: report.tolerance,
            smallest_kept: report.smallest_kept,
            largest_rejected: report.largest_rejected,
            relation_residual: report.relation_residual(),
            parameters: report.parameters.iter().map(StatusJson::from).collect(),
            auxiliary: report.auxiliary.iter().map(StatusJson::from).collect(),
            regrouping: report
                .relations()
                .iter()
                .map(|relation| RelationJson {
                    base: relation.base.clone(),
                    absorbed: relation
                        .absorbed
                        .iter()
                        .map(|(name, coefficient)| AbsorbedJson {
                            name: name.clone(),
                            coefficient: *coefficient,
                        })
                        .collect(),
                })
                .collect(),
            priority_matrix: report.priority.rows().to_vec(),
            observability: analysis
                .excitation
                .as_ref()
                .map_or(report, |checked| &checked.report)
                .observability()
                .into(),
            excitation: analysis.excitation.as_ref().map(|checked| ExcitationJson {
                same_base_set: checked.not_excited.is_empty(),
                not_excited: checked.not_excited.clone(),
                condition_number: checked.report.condition_number(),
            }),
            warnings: report.set_up_warnings(robot),
        }
    }
}
