//! Bounded subsamples of large studies, for the parts of an identification
//! that need not read every observation: the score tests (a few hundred
//! observations) and the coarse start of large data ([`super::coarse`]).
//!
//! The units are a method's independent observations: configurations, or
//! the groups of a grouped method (pairs). A subsample takes about `limit`
//! of them, spread over the sets in proportion to their sizes and over each
//! set by [`spread_indices`]: one unit drawn at random in each of `limit`
//! equal stretches, seeded, so that no cycle of the data aligns with them.

use std::borrow::Cow;

use nalgebra::Vector3;

use crate::sampler::{spread_indices, spread_items};
use crate::samples::{SampleRef, SampleSlice};
use crate::study::Study;

/// The motor positions and measured point of at most `limit` of the
/// samples of `slices` that have a point, in order, as [`spread_items`]
/// picks them among those: by index when every sample has a point (a
/// million samples are not walked to count them), else as they go by.
pub(super) fn spread_points<'a>(
    slices: &[SampleSlice<'a>],
    limit: usize,
) -> Vec<(&'a [f64], Vector3<f64>)> {
    let point = |sample: SampleRef<'a>| Some((sample.motor_positions(), sample.position()?));
    if slices.iter().all(|slice| slice.all_positioned()) {
        let mut picked = Vec::new();
        let (mut slice, mut before) = (0, 0);
        let total = slices.iter().map(|slice| slice.len()).sum();
        for index in spread_indices(total, limit) {
            while index >= before + slices[slice].len() {
                before += slices[slice].len();
                slice += 1;
            }
            picked.extend(point(slices[slice].get(index - before)));
        }
        return picked;
    }
    let points = || {
        slices
            .iter()
            .flat_map(|slice| slice.iter().filter_map(point))
    };
    spread_items(points(), points().count(), limit).collect()
}

/// `study` without the `dropped` samples (per set), and with about `limit`
/// of its units (configurations, sets, pairs) when it has more, spread over
/// its sets in proportion to their sizes ([`spread_indices`]): a set or pair
/// left with a single configuration goes, as in [`Study::without_samples`].
/// On large data the units are chosen first, so that only they are copied.
pub(super) fn spread_subsample<'a>(
    study: &'a Study,
    dropped: &[Vec<usize>],
    limit: usize,
) -> Cow<'a, Study> {
    let units: Vec<Option<Vec<Vec<usize>>>> = study
        .sets
        .iter()
        .map(|set| {
            crate::methods::grouped(set.method.as_ref())
                .then(|| crate::methods::units(set.method.as_ref(), set.samples.as_slice()))
        })
        .collect();
    let count = |index: usize| {
        units[index]
            .as_ref()
            .map_or(study.sets[index].samples.len(), Vec::len)
    };
    let total: usize = (0..study.sets.len()).map(count).sum();
    if total <= limit {
        return if dropped.iter().all(Vec::is_empty) {
            Cow::Borrowed(study)
        } else {
            Cow::Owned(study.without_samples(dropped))
        };
    }
    let sets = study
        .sets
        .iter()
        .enumerate()
        .map(|(index, set)| {
            let mut gone: Vec<usize> = dropped.get(index).cloned().unwrap_or_default();
            gone.sort_unstable();
            let kept = |sample: &usize| gone.binary_search(sample).is_err();
            let chosen = spread_indices(count(index), (count(index) * limit).div_ceil(total));
            let mut samples = Vec::with_capacity(chosen.len());
            for unit in chosen {
                match &units[index] {
                    None => {
                        if kept(&unit) {
                            samples.push(unit);
                        }
                    }
                    Some(units) => {
                        let members: Vec<usize> =
                            units[unit].iter().copied().filter(kept).collect();
                        if units[unit].len() < 2 || members.len() >= 2 {
                            samples.extend(members);
                        }
                    }
                }
            }
            set.with_samples(set.samples.gather(&samples))
        })
        .collect();
    Cow::Owned(Study {
        sets,
        frames: study.frames.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;
    use crate::samples::Samples;

    /// Samples `0..len` from `first`, each with its point when `positioned`
    /// says so.
    fn samples(first: usize, len: usize, positioned: impl Fn(usize) -> bool) -> Samples {
        let rows: Vec<Sample> = (first..first + len)
            .map(|index| {
                let mut row = Sample::new(vec![index as f64, 0.5]);
                row.position = positioned(index).then(|| Vector3::new(index as f64, 1.0, 2.0));
                row
            })
            .collect();
        Samples::from(rows.as_slice())
    }

    /// Picked by index, the points are those picked as they go by.
    #[test]
    fn points_picked_by_index_are_those_walked() {
        let sets = [
            samples(0, 700, |_| true),
            samples(700, 0, |_| true),
            samples(700, 1300, |_| true),
        ];
        let slices: Vec<SampleSlice<'_>> = sets.iter().map(Samples::as_slice).collect();
        assert!(slices.iter().all(|slice| slice.all_positioned()));
        let walked = |limit: usize| -> Vec<(Vec<f64>, Vector3<f64>)> {
            let points = || {
                slices.iter().flat_map(|slice| {
                    slice.iter().filter_map(|sample| {
                        Some((sample.motor_positions().to_vec(), sample.position()?))
                    })
                })
            };
            spread_items(points(), points().count(), limit).collect()
        };
        for limit in [1, 7, 500, 1999, 2000, 5000] {
            let picked: Vec<(Vec<f64>, Vector3<f64>)> = spread_points(&slices, limit)
                .into_iter()
                .map(|(motors, point)| (motors.to_vec(), point))
                .collect();
            assert_eq!(picked, walked(limit), "limit {limit}");
            assert_eq!(picked.len(), limit.min(2000));
        }
        // A sample without its point: walked, and it is never picked.
        let gappy = samples(0, 900, |index| index % 3 != 0);
        assert!(!gappy.as_slice().all_positioned());
        let picked = spread_points(&[gappy.as_slice()], 100);
        assert_eq!(picked.len(), 100);
        assert!(
            picked
                .iter()
                .all(|(motors, _)| !(motors[0] as usize).is_multiple_of(3))
        );
    }
}
