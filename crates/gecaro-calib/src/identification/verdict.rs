//! The verdict of an identification: whether its result can be trusted, in
//! one word and one sentence, computed once here and shown alike by every
//! front end. It also holds [`StopReason`], the iteration's own account of why it
//! stopped, which the verdict reads.
//!
//! In order of precedence:
//!
//! 1. **Diverged** or **not converged** (the iteration limit came first): the
//!    best iterate is no solution.
//! 2. **Degenerate data**: fewer distinct configurations than the unknowns
//!    need (distinct configurations × equations per configuration ≤ unknowns);
//!    200 copies of one configuration make one configuration, whatever the
//!    residual says.
//! 3. **Implausible parameters**: a physical (not regrouped) parameter whose
//!    deviation no real robot has ([`Implausible`]): a length moved by more
//!    than the robot's size (the sum of its |d| and |r|, at least 0.1 m; ten
//!    times that for frames 0 and 1, which place the robot in a measurement
//!    frame that may stand anywhere in the cell), an angle turned by more than
//!    45° (beyond frames 0 and 1), a gain off by more than 20 %, or a
//!    deviation beyond 5 σ of a stated prior. Each is named with its likely
//!    cause: not determined by the data (deviation within 3 σ), a
//!    measurement frame far from the nominal (frames 0 and 1, which place the
//!    robot in the world) or a tool far from it (frame n+1), or a model error
//!    elsewhere that the parameter absorbs.
//! 4. **Exceeds the noise**: every measurement set states its sensor σ and
//!    the global test of adjustment theory (Baarda) fails: the weighted sum of
//!    squares `χ² = Σ (r_i/σ_i)²` exceeds the χ²(ν) quantile at
//!    [`NOISE_TEST_LEVEL`] (ν = equations − unknowns). The model, the data or
//!    the stated σ is wrong; the ratio σ̂/σ = √(χ²/ν) says by how much.
//! 5. **Fits the noise**: the same test passes.
//! 6. **Converged, untested**: no σ was stated; the residual σ is reported in
//!    metres and radians instead.
//!
//! With a robust loss the test takes the weighted residuals of the final fit
//! (outliers weigh little or nothing) and ν counts the equations of the
//! observations with a weight.

use gecaro_core::{ParameterKind, Robot};

use super::parameter::IdentifiedParameter;
use crate::observation::ObservationSystem;
use crate::prior::Prior;
use crate::rows::RowKind;
use crate::study::Study;

/// Why the iteration stopped.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The last correction was negligible.
    Converged,
    /// The iteration limit was reached first.
    IterationLimit,
    /// No step lowered the residual: the linearisation does not hold from here.
    Diverged,
}

impl StopReason {
    /// `converged`, `iteration_limit` or `diverged`.
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration_limit",
            StopReason::Diverged => "diverged",
        }
    }
}

/// Significance level of the global test: a fit that explains the data to
/// the stated noise fails it once in a hundred.
pub const NOISE_TEST_LEVEL: f64 = 0.01;

/// What the verdict says, from worst to best.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// No step lowered the residual.
    Diverged,
    /// The iteration limit came before convergence.
    NotConverged,
    /// The data hold too few distinct configurations for the unknowns.
    Degenerate,
    /// Converged, but some parameter took a value no real robot has.
    Implausible,
    /// Converged, but the residuals exceed the stated noise (global test failed).
    ExceedsNoise,
    /// Converged, and the residuals agree with the stated noise.
    FitsNoise,
    /// Converged; no σ was stated, so the fit is not tested.
    Untested,
}

impl Outcome {
    /// `diverged`, `not_converged`, `degenerate`, `exceeds_noise`,
    /// `fits_noise` or `untested`.
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Diverged => "diverged",
            Outcome::NotConverged => "not_converged",
            Outcome::Degenerate => "degenerate",
            Outcome::Implausible => "implausible",
            Outcome::ExceedsNoise => "exceeds_noise",
            Outcome::FitsNoise => "fits_noise",
            Outcome::Untested => "untested",
        }
    }

    /// Whether the result may be used: it converged on data that determine
    /// it, and does not contradict a stated σ.
    pub fn trusted(self) -> bool {
        matches!(self, Outcome::FitsNoise | Outcome::Untested)
    }
}

/// The global test of the residuals against the stated σ.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct NoiseTest {
    /// `χ² = Σ (r_i/σ_i)²` over the weighted data rows.
    pub chi_square: f64,
    /// Its degrees of freedom ν (equations − unknowns).
    pub degrees_of_freedom: usize,
    /// The χ²(ν) quantile at 1 − [`NOISE_TEST_LEVEL`].
    pub critical: f64,
    /// σ̂/σ = √(χ²/ν): how many times the stated noise the residuals are.
    pub sigma_ratio: f64,
    /// χ² ≤ critical.
    pub passed: bool,
}

/// The verdict of an identification; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// What it says.
    pub outcome: Outcome,
    /// The global test, when every measurement set states its σ.
    pub noise_test: Option<NoiseTest>,
    /// The residual standard deviation of the length rows (metres), `None`
    /// without length rows.
    pub residual_length: Option<f64>,
    /// The same of the angle rows (radians), `None` without angle rows.
    pub residual_angle: Option<f64>,
    /// Configurations in the data.
    pub configurations: usize,
    /// Distinct configurations among them (per measurement set).
    pub distinct_configurations: usize,
    /// Parameters with values no real robot has (see the module docs).
    pub implausible: Vec<Implausible>,
    /// The verdict in one sentence.
    pub summary: String,
}

/// A parameter whose identified value no real robot has.
#[derive(Clone, Debug, PartialEq)]
pub struct Implausible {
    /// Its name.
    pub name: String,
    /// Why it is implausible (`moved by 3.2 m, more than the robot's size 1.8 m`).
    pub why: String,
    /// Its likely cause, in words.
    pub cause: String,
}

/// What the verdict is made of, beside the study.
pub(super) struct Evidence<'a> {
    /// The nominal robot (its size bounds the lengths).
    pub(super) nominal: &'a Robot,
    /// The identified parameters.
    pub(super) parameters: &'a [IdentifiedParameter],
    /// The prior, if one was given.
    pub(super) prior: Option<&'a Prior>,
    pub(super) stop: StopReason,
    pub(super) iterations: usize,
    /// The system at the solution.
    pub(super) system: &'a ObservationSystem,
    /// Each observation's weight in the final fit (empty: all 1).
    pub(super) observation_weights: &'a [f64],
    /// Σ w (r/σ)² over the data rows.
    pub(super) data_cost: f64,
    pub(super) degrees_of_freedom: usize,
    /// Identified unknowns.
    pub(super) unknowns: usize,
}

impl Verdict {
    /// The verdict on `evidence` from `study` (see the module docs).
    pub(super) fn of(study: &Study, evidence: &Evidence<'_>) -> Verdict {
        let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
        let (distinct_configurations, distinct_equations) = distinct(study);
        let (residual_length, residual_angle) = residual_sigmas(evidence);
        let noise_test = study
            .sets
            .iter()
            .all(|set| set.sigma.is_some())
            .then(|| noise_test(evidence.data_cost, evidence.degrees_of_freedom));
        let implausible = implausible(evidence);
        let outcome = match evidence.stop {
            StopReason::Diverged => Outcome::Diverged,
            StopReason::IterationLimit => Outcome::NotConverged,
            StopReason::Converged if distinct_equations <= evidence.unknowns as f64 => {
                Outcome::Degenerate
            }
            StopReason::Converged if !implausible.is_empty() => Outcome::Implausible,
            StopReason::Converged => match noise_test {
                Some(test) if !test.passed => Outcome::ExceedsNoise,
                Some(_) => Outcome::FitsNoise,
                None => Outcome::Untested,
            },
        };
        let mut verdict = Verdict {
            outcome,
            noise_test,
            residual_length,
            residual_angle,
            configurations,
            distinct_configurations,
            implausible,
            summary: String::new(),
        };
        verdict.summary = verdict.sentence(evidence.iterations, evidence.unknowns);
        verdict
    }

    /// The summary sentence after `iterations` updates, for `unknowns`.
    pub(super) fn sentence(&self, iterations: usize, unknowns: usize) -> String {
        let converged = format!(
            "converged after {iterations} iteration{}",
            if iterations == 1 { "" } else { "s" }
        );
        let residual = self.residual_words();
        match (self.outcome, self.noise_test) {
            (Outcome::Diverged, _) => format!(
                "diverged after {iterations} iterations: no step lowered the residual; the \
                 result is the best iterate, not a solution"
            ),
            (Outcome::NotConverged, _) => format!(
                "not converged: the iteration limit came first, after {iterations} \
                 iterations; the result is the best iterate, not a solution"
            ),
            (Outcome::Degenerate, _) => format!(
                "degenerate data: {} distinct configuration{} of {} cannot determine {unknowns} \
                 unknowns, whatever the residual",
                self.distinct_configurations,
                if self.distinct_configurations == 1 {
                    ""
                } else {
                    "s"
                },
                self.configurations
            ),
            (Outcome::Implausible, test) => format!(
                "{converged}, but {}{}",
                self.implausible
                    .iter()
                    .map(|p| format!("{} {} ({})", p.name, p.why, p.cause))
                    .collect::<Vec<_>>()
                    .join("; "),
                match test {
                    Some(test) if !test.passed => format!(
                        "; and the residuals are {:.1}× the stated noise",
                        test.sigma_ratio
                    ),
                    _ => String::new(),
                }
            ),
            (Outcome::ExceedsNoise, Some(test)) => format!(
                "{converged}, but the residuals are {:.1}× the stated noise (global test at \
                 {:.0} %: χ² {:.1} > {:.1} for {} degrees of freedom): the model, the data or \
                 the stated σ is wrong{residual}",
                test.sigma_ratio,
                NOISE_TEST_LEVEL * 100.0,
                test.chi_square,
                test.critical,
                test.degrees_of_freedom
            ),
            (Outcome::FitsNoise, Some(test)) => format!(
                "{converged}; the residuals fit the stated noise (σ̂/σ = {:.2}, global test at \
                 {:.0} %){residual}",
                test.sigma_ratio,
                NOISE_TEST_LEVEL * 100.0
            ),
            _ => format!(
                "{converged}; no σ was stated, so the fit is not tested against the noise{residual}"
            ),
        }
    }

    /// `: residual σ 0.012 mm, 0.004°`, or nothing.
    fn residual_words(&self) -> String {
        let mut parts = Vec::new();
        if let Some(length) = self.residual_length {
            parts.push(format!("{:.4} mm", length * 1e3));
        }
        if let Some(angle) = self.residual_angle {
            parts.push(format!("{:.4}°", angle.to_degrees()));
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!(": residual σ {}", parts.join(", "))
        }
    }
}

/// The global test of `Σ (r/σ)² = data_cost` with ν = `freedom`.
fn noise_test(data_cost: f64, freedom: usize) -> NoiseTest {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let nu = freedom.max(1) as f64;
    let critical = ChiSquared::new(nu)
        .map(|chi| chi.inverse_cdf(1.0 - NOISE_TEST_LEVEL))
        .unwrap_or(f64::INFINITY);
    NoiseTest {
        chi_square: data_cost,
        degrees_of_freedom: freedom,
        critical,
        sigma_ratio: (data_cost / nu).sqrt(),
        passed: data_cost <= critical,
    }
}

/// Distinct configurations (per set, summed), and the independent equations
/// they can give at most.
fn distinct(study: &Study) -> (usize, f64) {
    let mut count = 0;
    let mut equations = 0.0;
    for set in &study.sets {
        // Sorted by their bits (−0 as 0), equal neighbours dropped: exact,
        // and no allocation per configuration.
        let mut unique: Vec<&[f64]> = set
            .samples
            .iter()
            .map(|sample| sample.motor_positions.as_slice())
            .collect();
        unique.sort_unstable_by(|a, b| bits(a).cmp(bits(b)));
        unique.dedup_by(|a, b| bits(a).eq(bits(b)));
        count += unique.len();
        equations += unique.len() as f64 * set.method.equations_per_configuration();
    }
    (count, equations)
}

/// The bits of a configuration's values, −0 as 0.
fn bits(configuration: &[f64]) -> impl Iterator<Item = u64> + '_ {
    configuration.iter().map(|value| (value + 0.0).to_bits())
}

/// The residual standard deviations of the length and angle rows, in
/// metres and radians: `√(Σ w r²/(n_k (1 − b/n)))` per kind (w the robust
/// weight of the row's observation, rows of weight 0 left out), the degrees
/// of freedom shared out in proportion to the rows.
fn residual_sigmas(evidence: &Evidence<'_>) -> (Option<f64>, Option<f64>) {
    let system = evidence.system;
    let rows = system.measured_rows();
    let residuals = system.residuals();
    let kinds = system.kinds();
    let observations = system.row_observations();
    let weight = |row: usize| {
        evidence
            .observation_weights
            .get(observations[row])
            .copied()
            .unwrap_or(1.0)
    };
    // Rows of observations a robust loss ignores do not count.
    let counted = (0..rows).filter(|row| weight(*row) > 0.0).count();
    let share = evidence.degrees_of_freedom as f64 / counted.max(1) as f64;
    let sigma_of = |kind: RowKind| {
        let rows: Vec<usize> = (0..rows)
            .filter(|row| kinds[*row] == kind && weight(*row) > 0.0)
            .collect();
        (!rows.is_empty()).then(|| {
            let squares: f64 = rows
                .iter()
                .map(|row| weight(*row) * residuals[*row] * residuals[*row])
                .sum();
            (squares / (rows.len() as f64 * share).max(f64::MIN_POSITIVE)).sqrt()
        })
    };
    (sigma_of(RowKind::Length), sigma_of(RowKind::Angle))
}

/// The robot's size: the sum of its frames' |d| and |r|, at least 0.1 m.
fn robot_size(robot: &Robot) -> f64 {
    robot
        .frames()
        .iter()
        .map(|frame| frame.d.abs() + frame.r.abs())
        .sum::<f64>()
        .max(0.1)
}

/// The physical parameters with values no real robot has (module docs).
fn implausible(evidence: &Evidence<'_>) -> Vec<Implausible> {
    use std::f64::consts::{PI, TAU};
    const ANGLE_LIMIT: f64 = PI / 4.0;
    const GAIN_LIMIT: f64 = 0.2;
    const PRIOR_LIMIT: f64 = 5.0;
    const CELL: f64 = 10.0;
    let size = robot_size(evidence.nominal);
    let last = evidence.nominal.frames().len() - 1;
    evidence
        .parameters
        .iter()
        .filter(|p| !p.is_regrouped())
        .filter_map(|p| {
            let id = p.parameter?;
            let mut deviation = p.identified - p.nominal;
            // Frames 0 and 1 place the robot in the measurement frame, which
            // may stand anywhere in the cell (a tracker metres away, turned
            // any way): only lengths beyond the cell are implausible there.
            let placement = id.frame <= 1;
            let reach = if placement { CELL * size } else { size };
            let why = match id.kind {
                ParameterKind::D | ParameterKind::R if deviation.abs() > reach => format!(
                    "moved by {deviation:.3} m, more than {} ({reach:.2} m)",
                    if placement {
                        "a robot cell"
                    } else {
                        "the robot's size"
                    }
                ),
                ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta
                    if !placement
                        && (deviation - TAU * (deviation / TAU).round()).abs() > ANGLE_LIMIT =>
                {
                    deviation -= TAU * (deviation / TAU).round();
                    format!("turned by {:.1}°", deviation.to_degrees())
                }
                ParameterKind::Gain if deviation.abs() > GAIN_LIMIT * p.nominal.abs() => format!(
                    "off by {:+.1} %",
                    100.0 * deviation / p.nominal.abs().max(f64::MIN_POSITIVE)
                ),
                _ => match (evidence.prior, p.prior_std) {
                    (Some(_), Some(prior)) if deviation.abs() > PRIOR_LIMIT * prior => {
                        format!("moved {:.1} times its prior σ", deviation.abs() / prior)
                    }
                    _ => return None,
                },
            };
            let against_prior = why.contains("prior σ");
            let cause = if against_prior {
                "the data contradict the prior: widen it, or look for a model error that this \
                 parameter absorbs"
                    .to_owned()
            } else if deviation.abs() < 3.0 * p.std || !p.std.is_finite() {
                format!(
                    "not determined by these data, σ {:.2e}: add configurations that move it, \
                     or a prior",
                    p.std
                )
            } else if id.frame <= 1 {
                "the measurement frame (world frame) is far from the nominal one, or the base \
                 is tilted: state it in the robot file (robot reframe, world frame) and \
                 identify again"
                    .to_owned()
            } else if id.frame == last {
                "the tool is far from the nominal one: state it in the robot file (robot \
                 reframe, tool frame) and identify again"
                    .to_owned()
            } else {
                "determined by the data: a model error elsewhere (an unmodelled tilt, \
                 coupling or compliance, a wrong nominal) is absorbed here"
                    .to_owned()
            };
            Some(Implausible {
                name: p.name.clone(),
                why,
                cause,
            })
        })
        .collect()
}
