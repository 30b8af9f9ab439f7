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

use crate::sampler::spread_indices;
use crate::study::Study;

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
