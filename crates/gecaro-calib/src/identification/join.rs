//! A join off by a few rows, found by trying the shifts.
//!
//! A controller's joint log and a tracker's export joined by row number,
//! one of them with a row more at its top: every measured point sits beside
//! the configuration of the row before or after its own. The fit then
//! fails far from any solution ("did not converge … try Levenberg–
//! Marquardt", which does not help) or exceeds the noise a hundredfold.
//! So when an identification fails that way (it did not converge, or its
//! residuals are at least [`FAR_BEYOND`] times the stated noise), each set
//! that measures one configuration at a time (position, frame) is
//! identified again with its measurements moved by ±1 … ±[`MAX_SHIFT`] rows
//! against its configurations (the rows that lose their partner left out).
//! A shift whose identification converges to a residual RMS below a tenth
//! of the one as read — and that fits the noise, when σ is stated — is
//! named, with the direction to move.
//!
//! Each shift costs an identification, so only studies of at most
//! [`MAX_SETS`] sets and [`MAX_CONFIGURATIONS`] configurations are tried.

use super::findings::ShiftedJoin;
use super::result::Identification;
use super::verdict::StopReason;
use crate::Error;
use crate::sample::Sample;
use crate::study::Study;

/// The largest shift tried, in rows either way.
pub const MAX_SHIFT: usize = 3;

/// Residuals this many times the stated noise (or more) are far enough
/// from it for a join to be questioned.
pub const FAR_BEYOND: f64 = 10.0;

/// Sets beyond which no shift is tried.
const MAX_SETS: usize = 4;

/// Configurations beyond which no shift is tried.
const MAX_CONFIGURATIONS: usize = 20_000;

/// Whether `result` failed the way a shifted join makes it fail.
fn questioned(result: &Identification) -> bool {
    result.stop_reason != StopReason::Converged
        || result
            .verdict
            .noise_test
            .is_some_and(|test| test.exceeded() && test.sigma_ratio >= FAR_BEYOND)
}

/// `study` with set `set`'s measurements moved by `shift` rows against its
/// configurations: sample i keeps its configuration and takes the
/// measurement of sample i + `shift` (`None` when too few are left).
fn shifted(study: &Study, set: usize, shift: isize) -> Option<Study> {
    let rows = study.sets[set].samples.to_rows();
    let n = rows.len() as isize;
    let moved: Vec<Sample> = (0..n)
        .filter_map(|i| {
            let from = rows.get(usize::try_from(i + shift).ok()?)?;
            let mut sample = rows[i as usize].clone();
            sample.position = from.position;
            sample.orientation = from.orientation;
            Some(sample)
        })
        .collect();
    (moved.len() >= 3).then(|| {
        let mut study = study.clone();
        study.sets[set] = study.sets[set].with_samples(moved);
        study
    })
}

/// The set of `study` whose measurements belong to other rows, if `result`
/// failed the way that makes it fail and a shift explains it (module docs);
/// `identify` identifies a study.
///
/// # Errors
/// [`Error::Interrupted`] when `identify` is stopped (a shift that cannot be
/// identified is no answer, and no error).
pub(super) fn shifted_join(
    study: &Study,
    result: &Identification,
    mut identify: impl FnMut(&Study) -> Result<Identification, Error>,
) -> Result<Option<ShiftedJoin>, Error> {
    let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    if !questioned(result) || study.sets.len() > MAX_SETS || configurations > MAX_CONFIGURATIONS {
        return Ok(None);
    }
    let rms_as_read = result.rms_after();
    let mut best: Option<ShiftedJoin> = None;
    for (index, set) in study.sets.iter().enumerate() {
        // One configuration, one measurement: position and frame data.
        let single = set
            .method
            .grouped_observations(set.samples.as_slice())
            .is_none();
        let measures = set.samples.as_slice().all_positioned();
        if !single || !measures {
            continue;
        }
        let shifts = (1..=MAX_SHIFT as isize).flat_map(|s| [s, -s]);
        for shift in shifts {
            let Some(moved) = shifted(study, index, shift) else {
                continue;
            };
            let fitted = match identify(&moved) {
                Ok(fitted) => fitted,
                Err(Error::Interrupted) => return Err(Error::Interrupted),
                Err(_) => continue,
            };
            let fits = fitted.stop_reason == StopReason::Converged
                && fitted
                    .verdict
                    .noise_test
                    .is_none_or(|test| !test.exceeded() || test.sigma_ratio < 3.0);
            let rms = fitted.rms_after();
            if fits
                && rms < 0.1 * rms_as_read
                && best.as_ref().is_none_or(|best| rms < best.rms_shifted)
            {
                best = Some(ShiftedJoin {
                    set: index,
                    label: set.label.clone(),
                    shift,
                    rms_as_read,
                    rms_shifted: rms,
                });
            }
        }
    }
    Ok(best)
}
