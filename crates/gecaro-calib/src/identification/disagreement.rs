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
use super::findings::{Disagreement, SetFit};
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

/// Every set's σ̂/σ at the solution of `system` (`freedom` degrees of
/// freedom in all), labelled from `study`; then, for a study that names
/// tools or stations, each tool's and each station's sets pooled (a wrong
/// station shows in every set it measures from).
pub(super) fn set_fits(study: &Study, system: &ObservationSystem, freedom: usize) -> Vec<SetFit> {
    let rows = system.measured_rows().max(1) as f64;
    let share = freedom as f64 / rows;
    let sums: Vec<(usize, f64)> = (0..study.sets.len())
        .map(|index| {
            system
                .scaled_rows_of(index)
                .fold((0_usize, 0.0), |(n, sum), (_, e)| (n + 1, sum + e * e))
        })
        .collect();
    let fit = |label: String, (count, squares): (usize, f64)| SetFit {
        label,
        sigma_ratio: (squares / (count as f64 * share).max(f64::MIN_POSITIVE)).sqrt(),
    };
    let mut fits: Vec<SetFit> = study
        .sets
        .iter()
        .zip(&sums)
        .map(|(set, sum)| fit(set.label.clone(), *sum))
        .collect();
    for (frame_index, frame) in study.frames.iter().enumerate() {
        let pooled = study
            .sets
            .iter()
            .zip(&sums)
            .filter(|(set, _)| set.tool == Some(frame_index) || set.station == Some(frame_index))
            .fold((0, 0.0), |(n, sum), (_, (count, squares))| {
                (n + count, sum + squares)
            });
        if pooled.0 > 0 {
            let role = match frame.role {
                crate::frames::FrameRole::Tool => "tool",
                crate::frames::FrameRole::Station => "station",
            };
            fits.push(fit(format!("{role} {}", frame.name), pooled));
        }
    }
    fits
}

/// The set of `study` that disagrees with the rest, if `result` exceeds
/// the noise and one does (module docs); `identify` identifies a study
/// without a set.
///
/// # Errors
/// [`Error::Interrupted`] when `identify` is stopped (a set that cannot be
/// identified without is no answer, and no error).
pub(super) fn disagreeing_set(
    study: &Study,
    result: &Identification,
    mut identify: impl FnMut(&Study) -> Result<Identification, Error>,
) -> Result<Option<Disagreement>, Error> {
    let Some(test) = result.verdict.noise_test else {
        return Ok(None);
    };
    let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    if !test.exceeded()
        || !(MIN_SETS..=MAX_SETS).contains(&study.sets.len())
        || configurations > MAX_CONFIGURATIONS
    {
        return Ok(None);
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
    let mut fitting: Vec<(usize, Identification)> = Vec::new();
    for left in 0..study.sets.len() {
        let rest = match identify(&without(left)) {
            Ok(rest) => rest,
            Err(Error::Interrupted) => return Err(Error::Interrupted),
            Err(_) => continue,
        };
        if rest.verdict.noise_test.is_some_and(|test| !test.exceeded()) {
            fitting.push((left, rest));
        }
    }
    let [(left, rest)] = fitting.as_slice() else {
        return Ok(None);
    };
    let alone = Study {
        sets: vec![study.sets[*left].with_samples(study.sets[*left].samples.clone())],
        frames: rest.frames.clone(),
    };
    let (Ok((errors, ..)), Some(rest_test)) =
        (errors_at(&rest.calibrated, &alone), rest.verdict.noise_test)
    else {
        return Ok(None);
    };
    Ok(Some(Disagreement {
        set: *left,
        label: study.sets[*left].label.clone(),
        rest_ratio: rest_test.sigma_ratio,
        error: errors.rms,
        whole_ratio: test.sigma_ratio,
    }))
}
