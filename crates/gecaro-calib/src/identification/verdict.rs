//! The verdict of an identification: whether its result can be trusted, in
//! one word and one sentence, computed once here and shown alike by every
//! front end. It also holds [`StopReason`], the iteration's own account of why it
//! stopped, which the verdict reads.
//!
//! A result is judged where its user will meet it, not only by its own
//! residuals, which cannot see what the data do not observe. In order of
//! precedence:
//!
//! 1. **Diverged** or **not converged** (the iteration limit came first): the
//!    best iterate is no solution.
//! 2. **Degenerate data**: fewer distinct configurations than the unknowns
//!    need (distinct configurations × equations per configuration ≤ unknowns);
//!    200 copies of one configuration make one configuration, whatever the
//!    residual says.
//! 3. **Repeated data**: measurements that are exact copies of others (the
//!    same file twice in a study, rows pasted again: every value equal to
//!    the last bit, which two readings of a sensor never are). Copies are no
//!    new information, yet each counts as an observation: the σ shrink and
//!    the global test passes what it should not.
//! 4. **Changed**: outliers that form one block in a set's row order
//!    ([`CellChange`]): the cell changed during the measurement (a reflector
//!    re-seated, a tracker bumped), which a robust loss or a rejection would
//!    otherwise hide. Named with the block's first line.
//! 5. **Underdetermined**: the data leave part of the robot undetermined
//!    ([`Coverage`]): a joint that never moved, a base parameter they do not
//!    excite, or fewer than [`MIN_REDUNDANCY`](super::coverage::MIN_REDUNDANCY)
//!    equations per unknown. The result holds near the measured poses only.
//! 6. **Implausible parameters**: the written robot holds a value no real
//!    robot has ([`super::plausibility`]), each named with its likely cause.
//! 7. **Exceeds the noise**: every measurement set states its sensor σ and
//!    the global test of adjustment theory (Baarda) fails: the weighted sum of
//!    squares `χ² = Σ (r_i/σ_i)²` exceeds the χ²(ν) quantile at
//!    1 − [`NOISE_TEST_LEVEL`] (ν = equations − unknowns), with the stated σ
//!    taken as known to ±[`SIGMA_MARGIN`] (the quantile times
//!    (1 + margin)²). The model, the data or the stated σ is wrong; the ratio
//!    σ̂/σ = √(χ²/ν) says by how much.
//! 8. **Below the noise**: the same test, two-sided: χ² below the χ²(ν)
//!    quantile at [`NOISE_TEST_LEVEL`] divided by (1 + margin)². The stated
//!    σ is too large (then the test cannot see a model error), or the robot
//!    shrank (residuals in metres shrink with it).
//! 9. **Regional**: the fit holds where the data were taken but not over
//!    the region the robot is used in: its predicted error there is above
//!    the noise floor and several times that in the measured region
//!    ([`RegionPrediction`]); the measured joint ranges are named.
//! 10. **Incomplete**: the fit is sound but the methods do not observe the
//!     robot's scale (link and plane methods measure no length) or its tool
//!     (frame link): shape calibrated, the rest not measured.
//! 11. **Fits the noise**: the test passes.
//! 12. **Converged, untested**: no σ was stated; the residual σ is reported in
//!     metres and radians instead.
//!
//! Only the last two are trusted. The sentence names every problem found,
//! the outcome the first of them.
//!
//! With a robust loss the test takes the residuals of the final fit as
//! measured, unweighted, of the observations within the outlier threshold
//! (`tested`), and ν counts their equations.

use super::change::CellChange;
use super::coverage::Coverage;
use super::findings::{Disagreement, RegionPrediction, SetFit, ShiftedJoin};
use super::repeatability::Repeatability;
use super::repeats::Repeats;
use super::words;
use crate::observation::ObservationSystem;
use crate::rows::{RowKind, robust_weight};
use crate::study::{MeasurementSet, Study};

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

/// Significance level of each tail of the global test: a fit that explains
/// the data to the stated noise fails it once in fifty (once in a hundred
/// on each side).
pub const NOISE_TEST_LEVEL: f64 = 0.01;

/// How well a stated σ is taken to be known: the global test asks whether
/// σ̂/σ lies significantly outside [1/(1 + margin), 1 + margin], not
/// whether it differs from 1. Without it the test's resolution, about
/// 2.3·√(2/ν) in σ̂/σ, outgrows any sensor's specification at tracker
/// rates: 20,000 positions of the Stanford arm with σ stated 1 % too small
/// or too large were "exceeds the noise" or "below the noise" (0.1 % at
/// 10⁶ rows), where a datasheet's σ is good to a few per cent at best. A
/// model error hides under the margin only while it is below
/// σ·√((1 + margin)² − 1) = 0.32 σ; at a few hundred rows the test's own
/// quantiles are wider than the margin, and it changes little there.
pub const SIGMA_MARGIN: f64 = 0.05;

/// What the verdict says, from worst to best.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// No step lowered the residual.
    Diverged,
    /// The iteration limit came before convergence.
    NotConverged,
    /// The data hold too few distinct configurations for the unknowns.
    Degenerate,
    /// Converged, but some measurements are exact copies of others.
    Repeated,
    /// Converged, but a block of consecutive observations disagrees with
    /// the rest: the cell changed during the measurement.
    Changed,
    /// Converged, but the data leave part of the robot undetermined (a
    /// joint that never moved, parameters not excited, too few equations).
    Underdetermined,
    /// Converged, but some parameter took a value no real robot has.
    Implausible,
    /// Converged, but the residuals exceed the stated noise (global test failed).
    ExceedsNoise,
    /// Converged, but the residuals are far below the stated noise: σ
    /// overstated, or the robot shrank.
    BelowNoise,
    /// Converged, but the result holds in the measured region only: over
    /// the work region its predicted error is far above the noise.
    Regional,
    /// Converged and consistent, but the methods do not observe the robot's
    /// scale or its tool.
    Incomplete,
    /// Converged, and the residuals agree with the stated noise.
    FitsNoise,
    /// Converged; no σ was stated, so the fit is not tested.
    Untested,
}

impl Outcome {
    /// `diverged`, `not_converged`, `degenerate`, `repeated`, `changed`,
    /// `underdetermined`,
    /// `implausible`, `exceeds_noise`, `below_noise`, `regional`,
    /// `incomplete`, `fits_noise` or `untested`.
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Diverged => "diverged",
            Outcome::NotConverged => "not_converged",
            Outcome::Degenerate => "degenerate",
            Outcome::Repeated => "repeated",
            Outcome::Changed => "changed",
            Outcome::Underdetermined => "underdetermined",
            Outcome::Implausible => "implausible",
            Outcome::ExceedsNoise => "exceeds_noise",
            Outcome::BelowNoise => "below_noise",
            Outcome::Regional => "regional",
            Outcome::Incomplete => "incomplete",
            Outcome::FitsNoise => "fits_noise",
            Outcome::Untested => "untested",
        }
    }

    /// Whether the result may be used: it converged on data that determine
    /// it, observes everything it calibrates, and does not contradict a
    /// stated σ.
    pub fn trusted(self) -> bool {
        matches!(self, Outcome::FitsNoise | Outcome::Untested)
    }

    /// Whether the result is a solution (converged on data that are not
    /// degenerate), trusted or not.
    pub fn solved(self) -> bool {
        !matches!(
            self,
            Outcome::Diverged | Outcome::NotConverged | Outcome::Degenerate
        )
    }
}

/// The global test of the residuals against the stated σ (two-sided).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct NoiseTest {
    /// `χ² = Σ (r_i/σ_i)²` over the weighted data rows.
    pub chi_square: f64,
    /// Its degrees of freedom ν (equations − unknowns).
    pub degrees_of_freedom: usize,
    /// The χ²(ν) quantile at 1 − [`NOISE_TEST_LEVEL`] times (1 +
    /// [`SIGMA_MARGIN`])²: above it the residuals exceed the stated noise.
    pub critical: f64,
    /// The χ²(ν) quantile at [`NOISE_TEST_LEVEL`] divided by (1 +
    /// [`SIGMA_MARGIN`])²: below it the residuals are too small for the
    /// stated noise.
    pub critical_low: f64,
    /// σ̂/σ = √(χ²/ν): how many times the stated noise the residuals are.
    pub sigma_ratio: f64,
    /// critical_low ≤ χ² ≤ critical.
    pub passed: bool,
}

impl NoiseTest {
    /// Whether the residuals exceed the stated noise.
    pub fn exceeded(&self) -> bool {
        self.chi_square > self.critical
    }

    /// Whether the residuals are too small for the stated noise.
    pub fn below(&self) -> bool {
        self.chi_square < self.critical_low
    }
}

/// The verdict of an identification; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// What it says.
    pub outcome: Outcome,
    /// The global test, when every measurement set states its σ.
    pub noise_test: Option<NoiseTest>,
    /// The noise the data's repeated poses measure, and the lack-of-fit
    /// test against it: the judge of the fit, when there are repeats
    /// (whatever σ is stated).
    pub repeatability: Option<Repeatability>,
    /// The residual standard deviation of the length rows (metres), `None`
    /// without length rows.
    pub residual_length: Option<f64>,
    /// The same of the angle rows (radians), `None` without angle rows.
    pub residual_angle: Option<f64>,
    /// Configurations in the data.
    pub configurations: usize,
    /// Distinct configurations among them (per measurement set).
    pub distinct_configurations: usize,
    /// Measurements that are exact copies of another of the same method
    /// (configuration and measured values equal to the last bit), over the
    /// whole study.
    pub copies: usize,
    /// Values of the written robot that no real robot has.
    pub implausible: Vec<Implausible>,
    /// What the data determine and the methods observe.
    pub coverage: Coverage,
    /// Blocks of consecutive observations that disagree with the rest:
    /// the cell changed during the measurement (with the outlier threshold
    /// they were read at).
    pub changes: Vec<CellChange>,
    /// The outlier threshold the changes were found at (robust σ̂).
    pub outlier_threshold: f64,
    /// Every set's σ̂/σ at the solution (studies of several sets).
    pub sets: Vec<SetFit>,
    /// The set that disagrees with the rest, when the global test fails
    /// and leaving one set out makes the others fit.
    pub disagreement: Option<Disagreement>,
    /// A set whose measurements belong to other rows' configurations (a
    /// join off by a few rows), when the fit failed far from the noise.
    pub shifted_join: Option<ShiftedJoin>,
    /// Where the result holds: its predicted error in the measured region
    /// and over the work region (`None` where no prediction is made).
    pub region: Option<RegionPrediction>,
    /// Where the σ the global test uses was measured (repeatability files of
    /// poses revisited), when every set's σ was measured rather than
    /// stated; empty otherwise.
    pub sigma_sources: Vec<String>,
    /// The verdict in one sentence.
    pub summary: String,
}

/// A parameter whose identified value no real robot has.
#[derive(Clone, Debug, PartialEq)]
pub struct Implausible {
    /// Its name (`size` for the robot's size as a whole).
    pub name: String,
    /// Why it is implausible (`moved by 3.2 m, more than the robot's size 1.8 m`).
    pub why: String,
    /// Its likely cause, in words.
    pub cause: String,
}

/// What the verdict is made of, beside the study.
pub(super) struct Evidence<'a> {
    pub(super) stop: StopReason,
    pub(super) iterations: usize,
    /// The system at the solution.
    pub(super) system: &'a ObservationSystem,
    /// Each observation's weight in what the test reads (empty: all 1;
    /// with a robust loss, 0 for the outliers: `tested`).
    pub(super) observation_weights: &'a [f64],
    /// Σ w (r/σ)² over the data rows, with those weights.
    pub(super) data_cost: f64,
    pub(super) degrees_of_freedom: usize,
    /// Identified unknowns.
    pub(super) unknowns: usize,
    /// Every set's σ̂/σ at the solution.
    pub(super) sets: Vec<SetFit>,
    /// The noise repeated poses measure, and the fit judged against it.
    pub(super) repeatability: Option<Repeatability>,
    /// Values of the written robot that no real robot has.
    pub(super) implausible: Vec<Implausible>,
    /// What the data determine and the methods observe.
    pub(super) coverage: Coverage,
    /// What repeats in the study ([`super::repeats::repeats`]).
    pub(super) repeats: Repeats,
}

impl Verdict {
    /// How the σ the global test uses was known: `stated`, or `measured`
    /// (every set's from a repeatability file).
    fn noise_words(&self) -> &'static str {
        if self.sigma_sources.is_empty() {
            "stated"
        } else {
            "measured"
        }
    }

    /// The verdict on `evidence` from `study` (see the module docs).
    pub(super) fn of(study: &Study, evidence: Evidence<'_>) -> Verdict {
        let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
        let repeats = evidence.repeats;
        let (residual_length, residual_angle) = residual_sigmas(&evidence);
        let noise_test = study
            .sets
            .iter()
            .all(MeasurementSet::states_sigma)
            .then(|| noise_test(evidence.data_cost, evidence.degrees_of_freedom));
        let sigma_sources: Vec<String> = study
            .sets
            .iter()
            .map(|set| set.sigma_source.clone())
            .collect::<Option<Vec<String>>>()
            .unwrap_or_default();
        let mut verdict = Verdict {
            outcome: Outcome::Untested,
            sigma_sources,
            noise_test,
            repeatability: evidence.repeatability,
            residual_length,
            residual_angle,
            configurations,
            distinct_configurations: repeats.configurations,
            copies: repeats.copies,
            implausible: evidence.implausible,
            coverage: evidence.coverage,
            changes: Vec::new(),
            outlier_threshold: super::DEFAULT_OUTLIER_THRESHOLD,
            sets: evidence.sets,
            disagreement: None,
            shifted_join: None,
            region: None,
            summary: String::new(),
        };
        verdict.outcome = match evidence.stop {
            StopReason::Diverged => Outcome::Diverged,
            StopReason::IterationLimit => Outcome::NotConverged,
            StopReason::Converged if repeats.equations <= evidence.unknowns as f64 => {
                Outcome::Degenerate
            }
            StopReason::Converged => Outcome::Untested,
        };
        verdict.reconsider(evidence.iterations, evidence.unknowns);
        verdict
    }

    /// The outcome of a solution from its problems (module docs), and the
    /// sentence after `iterations` updates for `unknowns`: after a change
    /// of what the verdict is made of.
    pub(super) fn reconsider(&mut self, iterations: usize, unknowns: usize) {
        if self.outcome.solved() {
            self.outcome = self.problems().first().map_or(
                if self.noise_test.is_some() || self.repeatability.is_some() {
                    Outcome::FitsNoise
                } else {
                    Outcome::Untested
                },
                |(outcome, _)| *outcome,
            );
        }
        self.summary = self.sentence(iterations, unknowns);
    }

    /// The problems of a converged result, in order of precedence (module
    /// docs), each with its clause.
    fn problems(&self) -> Vec<(Outcome, String)> {
        let mut problems = Vec::new();
        if self.copies > 0 {
            problems.push((
                Outcome::Repeated,
                format!(
                    "{} of the {} measurements are exact copies of others (the same file twice, \
                     rows pasted again): copies are no new information, so the σ are too small \
                     and the global test too lenient; remove them",
                    self.copies, self.configurations
                ),
            ));
        }
        if !self.changes.is_empty() {
            problems.push((
                Outcome::Changed,
                self.changes
                    .iter()
                    .map(|change| change.words(self.outlier_threshold))
                    .collect::<Vec<_>>()
                    .join("; "),
            ));
        }
        if self.coverage.underdetermined() {
            problems.push((
                Outcome::Underdetermined,
                self.coverage.underdetermined_words(),
            ));
        }
        if !self.implausible.is_empty() {
            problems.push((
                Outcome::Implausible,
                self.implausible
                    .iter()
                    .map(|p| format!("{}: {} ({})", p.name, p.why, p.cause))
                    .collect::<Vec<_>>()
                    .join("; "),
            ));
        }
        // Repeated poses measure the noise: the lack-of-fit test judges the
        // fit then, whatever σ is stated.
        if let Some(repeats) = self.repeatability.as_ref().filter(|r| !r.passed()) {
            problems.push((
                Outcome::ExceedsNoise,
                format!(
                    "the residuals are {:.1}× the noise the {} repeated poses measure ({}; \
                     lack-of-fit F test at {:.0} %: F {:.2} > {:.2}): the model misses something \
                     the robot does (a compliance, a coupling, a drift), whatever σ is stated",
                    repeats.lack_of_fit.sqrt(),
                    repeats.poses,
                    self.repeat_noise_words(repeats),
                    NOISE_TEST_LEVEL * 100.0,
                    repeats.lack_of_fit,
                    repeats.critical
                ),
            ));
        }
        if let Some(test) = self.noise_test.filter(|_| self.repeatability.is_none()) {
            if test.exceeded() {
                problems.push((
                    Outcome::ExceedsNoise,
                    format!(
                        "the residuals are {:.1}× the {} noise (global test at {:.0} %: χ² \
                         {:.1} > {:.1} for {} degrees of freedom): {}",
                        test.sigma_ratio,
                        self.noise_words(),
                        NOISE_TEST_LEVEL * 100.0,
                        test.chi_square,
                        test.critical,
                        test.degrees_of_freedom,
                        self.shifted_join
                            .as_ref()
                            .map(ShiftedJoin::words)
                            .or_else(|| self.disagreement.as_ref().map(Disagreement::words))
                            .unwrap_or_else(|| format!(
                                "the model, the data or the {} σ is wrong",
                                self.noise_words()
                            ),)
                    ),
                ));
            } else if test.below() {
                problems.push((
                    Outcome::BelowNoise,
                    format!(
                        "the residuals are far below the stated noise (σ̂/σ = {:.2}, global test \
                         at {:.0} %: χ² {:.1} < {:.1} for {} degrees of freedom): the stated σ is \
                         too large, so the test cannot see a model error, or the robot shrank",
                        test.sigma_ratio,
                        NOISE_TEST_LEVEL * 100.0,
                        test.chi_square,
                        test.critical_low,
                        test.degrees_of_freedom
                    ),
                ));
            }
        }
        if let Some(region) = self
            .region
            .as_ref()
            .filter(|region| !region.holds_everywhere)
        {
            problems.push((Outcome::Regional, region.words()));
        }
        if self.coverage.incomplete() {
            problems.push((Outcome::Incomplete, self.coverage.incomplete_words()));
        }
        problems
    }

    /// The summary sentence after `iterations` updates, for `unknowns`.
    pub(super) fn sentence(&self, iterations: usize, unknowns: usize) -> String {
        let plural = if iterations == 1 { "" } else { "s" };
        let converged = format!("converged after {iterations} iteration{plural}");
        let residual = self.residual_words();
        match self.outcome {
            Outcome::Diverged => format!(
                "diverged after {iterations} iteration{plural}: no step lowered the residual; \
                 the result is the best iterate, not a solution"
            ),
            Outcome::NotConverged => format!(
                "not converged: the iteration limit came first, after {iterations} \
                 iteration{plural}; the result is the best iterate, not a solution"
            ),
            Outcome::Degenerate => format!(
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
            _ => {
                let fit = match (self.noise_test, &self.repeatability) {
                    (_, Some(repeats)) if repeats.passed() => format!(
                        "the residuals fit the noise the {} repeated poses measure ({}; \
                         lack-of-fit F test at {:.0} %: F {:.2}){}",
                        repeats.poses,
                        self.repeat_noise_words(repeats),
                        NOISE_TEST_LEVEL * 100.0,
                        repeats.lack_of_fit,
                        self.noise_test.filter(|test| !test.passed).map_or_else(
                            String::new,
                            |_| format!(", the stated σ {:.1}× that", 1.0 / repeats.sigma_ratio)
                        )
                    ),
                    (_, Some(_)) => String::new(),
                    (Some(test), None) if test.passed && !self.sigma_sources.is_empty() => {
                        format!(
                            "the residuals fit the noise measured from the revisited poses of \
                             {} (σ̂/σ = {:.2}, global test at {:.0} %)",
                            self.sigma_sources.join(", "),
                            test.sigma_ratio,
                            NOISE_TEST_LEVEL * 100.0
                        )
                    }
                    (Some(test), None) if test.passed => format!(
                        "the residuals fit the stated noise (σ̂/σ = {:.2}, global test at {:.0} %; \
                         σ as stated, not measured)",
                        test.sigma_ratio,
                        NOISE_TEST_LEVEL * 100.0
                    ),
                    (Some(_), None) => String::new(),
                    (None, None) => {
                        "no σ was stated, so the fit is not tested against the noise".into()
                    }
                };
                let problems: Vec<String> = self
                    .problems()
                    .into_iter()
                    .map(|(_, clause)| clause)
                    .collect();
                let mut sentence = converged;
                if !fit.is_empty() {
                    sentence.push_str("; ");
                    sentence.push_str(&fit);
                }
                if !problems.is_empty() {
                    sentence.push_str(", but ");
                    sentence.push_str(&problems.join("; and "));
                }
                sentence.push_str(&residual);
                sentence
            }
        }
    }

    /// The noise repeated poses measure, in words: `σ 1.02× the stated`,
    /// or in millimetres when no σ was stated.
    fn repeat_noise_words(&self, repeats: &Repeatability) -> String {
        if self.noise_test.is_some() {
            format!("σ {:.2}× the stated", repeats.sigma_ratio)
        } else {
            format!("σ {}", words::millimetres(repeats.sigma_ratio))
        }
    }

    /// `: residual σ 0.012 mm, 0.004°`, or nothing.
    fn residual_words(&self) -> String {
        let mut parts = Vec::new();
        if let Some(length) = self.residual_length {
            parts.push(words::millimetres(length));
        }
        if let Some(angle) = self.residual_angle {
            parts.push(words::degrees(angle));
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!(": residual σ {}", parts.join(", "))
        }
    }
}

/// The global test of `Σ (r/σ)² = data_cost` with ν = `freedom`, the
/// stated σ known to ±[`SIGMA_MARGIN`]: at the margin's ends the statistic
/// is (1 ± margin)² χ²(ν), hence the quantiles scaled by (1 + margin)^±2.
pub(crate) fn noise_test(data_cost: f64, freedom: usize) -> NoiseTest {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let nu = freedom.max(1) as f64;
    let widened = (1.0 + SIGMA_MARGIN).powi(2);
    let (critical_low, critical) = ChiSquared::new(nu)
        .map(|chi| {
            (
                chi.inverse_cdf(NOISE_TEST_LEVEL) / widened,
                chi.inverse_cdf(1.0 - NOISE_TEST_LEVEL) * widened,
            )
        })
        .unwrap_or((0.0, f64::INFINITY));
    NoiseTest {
        chi_square: data_cost,
        degrees_of_freedom: freedom,
        critical,
        critical_low,
        sigma_ratio: (data_cost / nu).sqrt(),
        passed: (critical_low..=critical).contains(&data_cost),
    }
}

/// The residual standard deviations of the length and angle rows, in
/// metres and radians: `√(Σ w r²/(n_k (1 − b/n)))` per kind (w the robust
/// weight of the row's observation, rows of weight 0 left out), the degrees
/// of freedom shared out in proportion to the rows.
fn residual_sigmas(evidence: &Evidence<'_>) -> (Option<f64>, Option<f64>) {
    let system = evidence.system;
    let rows = system.measured_rows();
    let rows = system.residuals()[..rows]
        .iter()
        .zip(&system.kinds()[..rows]);
    // Without robust weights every row weighs 1 (1·r·r is r·r, to the bit),
    // and no row's observation is looked up.
    let sums = if evidence.observation_weights.is_empty() {
        kind_sums(rows.map(|(residual, kind)| (1.0, *residual, *kind)))
    } else {
        let observations = system.row_observations();
        kind_sums(
            rows.zip(observations)
                .map(|((residual, kind), observation)| {
                    let weight = robust_weight(evidence.observation_weights, *observation as usize);
                    (weight, *residual, *kind)
                }),
        )
    };
    let counted = sums[0].0 + sums[1].0;
    let share = evidence.degrees_of_freedom as f64 / counted.max(1) as f64;
    let sigma_of = |(rows, squares): (usize, f64)| {
        (rows > 0).then(|| (squares / (rows as f64 * share).max(f64::MIN_POSITIVE)).sqrt())
    };
    (sigma_of(sums[0]), sigma_of(sums[1]))
}

/// Per kind of row (lengths, angles), the rows counted and their weighted
/// sum of squares `Σ w r²`, in row order, of `(w, r, kind)` rows; rows of
/// observations a robust loss ignores (w = 0) do not count.
fn kind_sums(rows: impl Iterator<Item = (f64, f64, RowKind)>) -> [(usize, f64); 2] {
    let mut sums = [(0_usize, 0.0_f64); 2];
    for (weight, residual, kind) in rows {
        if weight > 0.0 {
            let sum = &mut sums[usize::from(kind == RowKind::Angle)];
            sum.0 += 1;
            sum.1 += weight * residual * residual;
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums per kind leave out rows of weight 0, weigh the others, and
    /// rows of weight 1 sum their squares to the bit, as the route without
    /// robust weights takes them.
    #[test]
    fn kind_sums_count_and_weigh_each_kind() {
        let rows = [
            (1.0, 0.3, RowKind::Length),
            (0.0, 5.0, RowKind::Length),
            (0.25, 0.1, RowKind::Angle),
            (1.0, -0.7, RowKind::Length),
            (0.0, 9.0, RowKind::Angle),
        ];
        let sums = kind_sums(rows.into_iter());
        assert_eq!(sums[0].0, 2);
        assert_eq!(sums[1].0, 1);
        assert_eq!(sums[0].1.to_bits(), (0.3_f64 * 0.3 + 0.7 * 0.7).to_bits());
        assert_eq!(sums[1].1.to_bits(), (0.25_f64 * 0.1 * 0.1).to_bits());
        // Unit weights: the plain sums of squares, bit for bit.
        let residuals = [0.1, 1.0 / 3.0, -2.5e-7, 7.0, 0.123_456_789];
        let kinds = [RowKind::Length, RowKind::Angle, RowKind::Length];
        let unit = kind_sums(
            residuals
                .iter()
                .zip(kinds.iter().cycle())
                .map(|(r, kind)| (1.0, *r, *kind)),
        );
        let (mut lengths, mut angles) = (0.0_f64, 0.0_f64);
        for (r, kind) in residuals.iter().zip(kinds.iter().cycle()) {
            match kind {
                RowKind::Length => lengths += r * r,
                RowKind::Angle => angles += r * r,
            }
        }
        assert_eq!(unit[0].1.to_bits(), lengths.to_bits());
        assert_eq!(unit[1].1.to_bits(), angles.to_bits());
    }
}
