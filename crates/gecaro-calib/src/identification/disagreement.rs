//! A mistake named where it sits: the measurement set of a study that
//! disagrees with the rest.
//!
//! A set labelled with the wrong reflector (or station), another robot's
//! file, a set taken after the cell changed: the whole study exceeds the
//! noise ("1190× the stated noise … no outliers"), the fit spreads the
//! error over every set, and only a per-file RMS shows where it comes
//! from. So:
//!
//! - **every set's σ̂/σ** at the solution is reported: `√(χ²_k/ν_k)` over
//!   the set's rows, the degrees of freedom shared out in proportion to the
//!   rows ([`SetFit`]; the verdict's `sets`);
//! - when the global test fails on a study of at least [`MIN_SETS`] sets
//!   that all state σ (and no more than [`MAX_SETS`] sets and
//!   [`MAX_CONFIGURATIONS`] configurations: each set costs an
//!   identification), each set is **left out** in turn: the study is
//!   identified without it, and the set without which the others fit the
//!   noise — when no other set does that — is named, with its error at the
//!   robot the others give ([`Disagreement`]). A set that is the only one of
//!   its tool or station leaves that frame undetermined without it; it is
//!   judged all the same (the others still fit).

use super::evaluation::errors_at;
use super::result::Identification;
use crate::Error;
use crate::observation::ObservationSystem;
use crate::study::Study;

/// Sets a study needs for one to be left out (with two, each alone fits).
pub const MIN_SETS: usize = 3;

/// Sets beyond which none is left out (each costs an identification).
pub const MAX_SETS: usize = 12;

/// Configurations beyond which no set is left out.
pub const MAX_CONFIGURATIONS: usize = 200_000;

/// One set's fit at the solution.
#[derive(Clone, Debug, PartialEq)]
pub struct SetFit {
    /// The set's label (usually its data file).
    pub label: String,
    /// Its residuals' σ̂ over its stated σ (over 1 for an unweighted set:
    /// metres and radians), `√(χ²_k/ν_k)`.
    pub sigma_ratio: f64,
}

/// Every set's σ̂/σ at the solution of `system` (`freedom` degrees of
/// freedom in all), labelled from `study`.
pub(super) fn set_fits(study: &Study, system: &ObservationSystem, freedom: usize) -> Vec<SetFit> {
    let rows = system.measured_rows().max(1) as f64;
    let share = freedom as f64 / rows;
    study
        .sets
        .iter()
        .enumerate()
        .map(|(index, set)| {
            let (count, squares) = system
                .scaled_rows_of(index)
                .fold((0_usize, 0.0), |(n, sum), (_, e)| (n + 1, sum + e * e));
            SetFit {
                label: set.label.clone(),
                sigma_ratio: (squares / (count as f64 * share).max(f64::MIN_POSITIVE)).sqrt(),
            }
        })
        .collect()
}

/// The set that disagrees with the rest: see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Disagreement {
    /// The set (its index in the study).
    pub set: usize,
    /// Its label.
    pub label: String,
    /// σ̂/σ of the other sets identified without it.
    pub rest_ratio: f64,
    /// The set's RMS error at the robot the others give (metres).
    pub error: f64,
    /// σ̂/σ of the study as a whole.
    pub whole_ratio: f64,
}

impl Disagreement {
    /// The verdict's words.
    pub fn words(&self) -> String {
        format!(
            "{} disagrees with the other sets: identified without it they fit the noise (σ̂/σ = \
             {:.2} against {:.1} with it), and it is {:.4} mm off the robot they give — a set \
             labelled with the wrong tool or station, another robot's data, or a cell changed \
             between the sets?",
            self.label,
            self.rest_ratio,
            self.whole_ratio,
            self.error * 1e3
        )
    }
}

/// The set of `study` that disagrees with the rest, if `result` exceeds
/// the noise and one does (module docs); `identify` identifies a study
/// without a set.
pub(super) fn disagreeing_set(
    study: &Study,
    result: &Identification,
    identify: impl Fn(&Study) -> Result<Identification, Error>,
) -> Option<Disagreement> {
    let test = result.verdict.noise_test?;
    let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    if !test.exceeded()
        || !(MIN_SETS..=MAX_SETS).contains(&study.sets.len())
        || configurations > MAX_CONFIGURATIONS
    {
        return None;
    }
    let without = |left: usize| Study {
        sets: study
            .sets
            .iter()
            .enumerate()
            .filter(|(index, _)| *index != left)
            .map(|(_, set)| set.with_samples(set.samples.clone()))
            .collect(),
        frames: study.frames.clone(),
    };
    // The sets without which the others fit the noise.
    let fitting: Vec<(usize, Identification)> = (0..study.sets.len())
        .filter_map(|left| {
            let rest = identify(&without(left)).ok()?;
            let fits = rest.verdict.noise_test.is_some_and(|test| !test.exceeded());
            fits.then_some((left, rest))
        })
        .collect();
    let [(left, rest)] = fitting.as_slice() else {
        return None;
    };
    let alone = Study {
        sets: vec![study.sets[*left].with_samples(study.sets[*left].samples.clone())],
        frames: rest.frames.clone(),
    };
    let error = errors_at(&rest.calibrated, &alone).ok()?.0.rms;
    Some(Disagreement {
        set: *left,
        label: study.sets[*left].label.clone(),
        rest_ratio: rest.verdict.noise_test?.sigma_ratio,
        error,
        whole_ratio: test.sigma_ratio,
    })
}
