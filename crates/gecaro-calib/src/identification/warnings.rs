//! The warnings of an identification beyond its verdict: poor excitation,
//! strongly correlated parameters, an unobserved scale, parameters moved
//! outside the base set (see [`super::Identification::warnings`]).
//!
//! A warning is a [`Warning`]: what it is and the data it needs. Code tells
//! warnings apart by their kind, never by their words; the words are
//! written once, by its `Display`, which every front end prints (issue 77).

use std::fmt;

use super::parameter::IdentifiedParameter;
use crate::linalg::NormalEquations;
use crate::prior::Prior;

/// Above this condition number of W_b the data are called poorly exciting.
pub const POOR_CONDITIONING: f64 = 1e4;

/// Above this |ρ| two identified parameters are named as strongly
/// correlated ([`Identification::correlated`](super::Identification::correlated); FIGAROH lists such pairs too).
pub const STRONG_CORRELATION: f64 = 0.95;

/// What an identification warns of beyond its verdict, with what each
/// warning needs to be said ([`fmt::Display`] says it).
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// The measurement set-up leaves parameters unseen (a tool point on a
    /// joint's axis, say): the words of
    /// [`RankReport::set_up_warnings`](crate::identifiability::RankReport::set_up_warnings).
    SetUp(String),
    /// Pairs of identified parameters whose estimates correlate beyond
    /// [`STRONG_CORRELATION`], strongest first: (first, second, ρ).
    Correlated(Vec<(String, String, f64)>),
    /// Parameters the data do not excite, left at their nominal values.
    NotExcited(Vec<String>),
    /// W_b is poorly conditioned (above [`POOR_CONDITIONING`]); the least
    /// determined parameters with their σ, worst first.
    PoorExcitation {
        /// Condition number of W_b.
        condition_number: f64,
        /// Up to three parameters and their σ.
        least_determined: Vec<(String, f64)>,
    },
    /// This many parameters outside the base set were moved too.
    MovedOutsideBaseSet(usize),
    /// Observations beyond `threshold` σ̂ were rejected and the rest
    /// identified again.
    OutliersRejected {
        /// How many observations.
        count: usize,
        /// The threshold, in σ̂.
        threshold: f64,
    },
    /// Where the result holds: its predicted error over the work region
    /// (the region check), in words.
    Region(String),
    /// A split of two parameters the data cannot tell apart was held
    /// (a split held), in words.
    SplitHeld(String),
    /// The nominal robot was far from the measurements: the frames were
    /// first fitted in closed form; `named_frames`: the study's stated
    /// stations and tools among them.
    ClosedFormStart {
        /// Whether stated stations or tools moved.
        named_frames: bool,
    },
    /// A damped descent over every parameter the priority matrix allows
    /// took the RMS error from `from` to `to` (metres).
    FullModelDescent {
        /// Parameters the descent moved.
        parameters: usize,
        /// RMS error before it (m).
        from: f64,
        /// RMS error after it (m).
        to: f64,
    },
    /// Parameters identifiable at the calibrated robot only, identified in
    /// a second pass held by the prior `prior`.
    SecondPass {
        /// The parameters.
        parameters: Vec<String>,
        /// The prior that holds them.
        prior: Prior,
    },
    /// Parameters set by the data outside the base set and regrouped,
    /// identified beside it held by the prior `prior`.
    Joined {
        /// The parameters.
        parameters: Vec<String>,
        /// The prior that holds them.
        prior: Prior,
    },
    /// A coarse start was taken (large data started on a spread subsample), in words.
    CoarseStart(String),
    /// The robust loss's scale is off the residuals' (in words).
    LossScale(String),
    /// No set measures a length: the scale was kept closest to the
    /// nominal one.
    ScaleNotMeasured {
        /// The size the paper's base set alone gave, relative to the kept.
        base_set_scale: f64,
        /// The scale's relative σ.
        std: f64,
    },
    /// The methods do not observe frame 0: the base is the nominal one.
    BaseNotObserved,
}

impl Warning {
    /// Whether the warning is about the nominal robot's structure (the
    /// set-up, the excitation of the nominal base set), which a second
    /// pass keeps from the first.
    pub fn of_nominal_structure(&self) -> bool {
        matches!(self, Warning::SetUp(_) | Warning::PoorExcitation { .. })
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::SetUp(words)
            | Warning::Region(words)
            | Warning::SplitHeld(words)
            | Warning::CoarseStart(words)
            | Warning::LossScale(words) => f.write_str(words),
            Warning::Correlated(correlated) => {
                let listed: Vec<String> = correlated
                    .iter()
                    .take(5)
                    .map(|(a, b, rho)| format!("{a}–{b} ({rho:+.3})"))
                    .collect();
                write!(
                    f,
                    "{} pair{} of parameters {} strongly correlated (|ρ| > {STRONG_CORRELATION}): \
                     {}{}; the data tell each pair apart poorly, and their errors compensate \
                     each other",
                    correlated.len(),
                    if correlated.len() == 1 { "" } else { "s" },
                    if correlated.len() == 1 { "is" } else { "are" },
                    listed.join(", "),
                    if correlated.len() > 5 { ", …" } else { "" }
                )
            }
            Warning::NotExcited(names) => write!(
                f,
                "the data do not excite {}: not identified, left at their nominal values",
                names.join(", ")
            ),
            Warning::PoorExcitation {
                condition_number,
                least_determined,
            } => {
                let worst: Vec<String> = least_determined
                    .iter()
                    .map(|(name, std)| format!("{name} (σ {std:.1e})"))
                    .collect();
                write!(
                    f,
                    "the data excite the robot poorly: condition number of W_b \
                     {condition_number:.1e} (above {POOR_CONDITIONING:.0e}); the least determined \
                     parameters are {}; add configurations that move these joints more",
                    worst.join(", ")
                )
            }
            Warning::MovedOutsideBaseSet(count) => write!(
                f,
                "{count} parameters outside the base set were moved too: with them at nominal, \
                 the base set (chosen at the nominal geometry) cannot reproduce these data"
            ),
            Warning::OutliersRejected { count, threshold } => write!(
                f,
                "{count} observations beyond {threshold} σ̂ were rejected and the rest identified \
                 again"
            ),
            Warning::ClosedFormStart {
                named_frames: false,
            } => f.write_str(
                "the nominal robot was far from the measurements: the measurement frame and the \
                 tool point were first fitted in closed form (Horn/Kabsch), and the iterations \
                 started there (iteration 1)",
            ),
            Warning::ClosedFormStart { named_frames: true } => f.write_str(
                "the robot's base in the data's frame, or the stated stations and tools, were far \
                 from the measurements: they were first fitted in closed form (Horn/Kabsch for \
                 the world frame and each station, least squares for each tool point), and the \
                 iterations started there (iteration 1)",
            ),
            Warning::FullModelDescent {
                parameters,
                from,
                to,
            } => write!(
                f,
                "parameters outside the base set still mattered: a damped descent over all \
                 {parameters} parameters the priority matrix allows (Levenberg–Marquardt) took \
                 the RMS error from {} to {}; what it moved outside the base set is listed as \
                 moved",
                super::words::millimetres(*from),
                super::words::millimetres(*to),
            ),
            Warning::SecondPass { parameters, prior } => write!(
                f,
                "{} identifiable at the calibrated robot but not at the nominal one (its \
                 structure holds there only): identified in a second pass, held by a prior of \
                 {prior}",
                parameters.join(", ")
            ),
            Warning::Joined { parameters, prior } => write!(
                f,
                "{} set by the data outside the base set (the closed-form start, the \
                 continuation or the damped descent moved them) and regrouped with base \
                 parameters: identified beside the base set, held by a prior of {prior}",
                parameters.join(", ")
            ),
            Warning::ScaleNotMeasured {
                base_set_scale,
                std,
            } => write!(
                f,
                "the robot's scale is not measured (no set measures a length): the paper's base \
                 set alone gave a robot {base_set_scale:.3}× the size kept; its lengths were \
                 scaled to be closest to the nominal ones (scale known to ±{:.2} %)",
                100.0 * std
            ),
            Warning::BaseNotObserved => f.write_str(
                "these methods do not observe where the robot stands in the measurement frame \
                 (frame 0 has no effect on them): its base is the nominal one; register it in \
                 the cell before using the calibrated robot in world coordinates",
            ),
        }
    }
}

/// The warning that names strongly correlated pairs (none without them).
pub(super) fn correlation_warning(correlated: &[(String, String, f64)]) -> Option<Warning> {
    (!correlated.is_empty()).then(|| Warning::Correlated(correlated.to_vec()))
}

/// The pairs of columns (named `names`, in column order) whose estimates
/// correlate beyond [`STRONG_CORRELATION`], strongest first (none when the
/// normal equations are not positive definite).
pub(super) fn strongly_correlated(
    normal: &NormalEquations,
    names: &[&str],
) -> Vec<(String, String, f64)> {
    let Some(correlations) = normal.correlations() else {
        return Vec::new();
    };
    let n = names.len();
    let mut pairs: Vec<(String, String, f64)> = (0..n)
        .flat_map(|i| ((i + 1)..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let rho = correlations.get(i * n + j).copied()?;
            (rho.abs() > STRONG_CORRELATION)
                .then(|| (names[i].to_owned(), names[j].to_owned(), rho))
        })
        .collect();
    pairs.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    pairs
}

/// The warnings of an identification (see [`Identification::warnings`](super::Identification::warnings))
/// beyond the set-up's ([`RankReport::set_up_warnings`](crate::identifiability::RankReport::set_up_warnings)).
pub(super) fn warnings_of(
    not_excited: &[String],
    condition_number: f64,
    parameters: &[IdentifiedParameter],
    moved: &[IdentifiedParameter],
) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if !not_excited.is_empty() {
        warnings.push(Warning::NotExcited(not_excited.to_vec()));
    }
    if condition_number > POOR_CONDITIONING {
        let mut relative: Vec<(&IdentifiedParameter, f64)> = parameters
            .iter()
            .map(|p| {
                (
                    p,
                    p.std / (p.identified.abs() + if p.name.starts_with('K') { 1.0 } else { 1e-3 }),
                )
            })
            .collect();
        relative.sort_by(|a, b| b.1.total_cmp(&a.1));
        warnings.push(Warning::PoorExcitation {
            condition_number,
            least_determined: relative
                .iter()
                .take(3)
                .map(|(p, _)| (p.name.clone(), p.std))
                .collect(),
        });
    }
    if !moved.is_empty() {
        warnings.push(Warning::MovedOutsideBaseSet(moved.len()));
    }
    warnings
}
