//! Repeated data in a study: how many of its configurations are distinct,
//! and how many of its measurements are exact copies of others. The
//! verdict ([`super::verdict`]) reads both: 200 copies of one configuration
//! make one configuration, and a measurement equal to another to the last
//! bit (which two readings of a sensor never are) is no new information.
//!
//! Both counts are exact, in three passes: the first and the last read the
//! items in memory order (the last also reads, for each item, the first
//! item of its fingerprint); the second sorts a list of pairs, not the
//! items:
//!
//! 1. every item's 64-bit fingerprint (rustc-hash's multiply–rotate hash of
//!    its values' bits, −0 as 0), computed once, in memory order;
//! 2. the (fingerprint, item) pairs sorted: items of one fingerprint are
//!    neighbours, and each learns the first item of its fingerprint;
//! 3. each item compared value by value with that first item, in memory
//!    order (the first items are few when the items repeat, and stay in
//!    the cache; an item first of its fingerprint is not compared). Should
//!    two different items share a fingerprint, each fingerprint's items are
//!    sorted by value and counted instead.
//!
//! A hash table of the items seen does the same in expected linear time,
//! but its probes, and the comparisons with items seen anywhere in memory,
//! are cache misses: several times slower on 10⁶ positions repeating
//! 20,000 configurations (docs/performance.md, "Repeats counted in memory
//! order"). At 10⁶ items
//! the fingerprints take 8 MB, the sorted pairs 16 MB and the first items
//! 8 MB.

use std::cell::RefCell;
use std::cmp::Ordering;
use std::hash::Hasher;

use crate::samples::SampleRef;
use crate::study::Study;

/// What repeats in a study.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Repeats {
    /// Distinct configurations, per measurement set, summed.
    pub(super) configurations: usize,
    /// The independent equations those configurations can give at most.
    pub(super) equations: f64,
    /// Measurements that repeat an earlier one of the same method exactly:
    /// configuration, group and measured values equal to the last bit, over
    /// every set.
    pub(super) copies: usize,
}

/// The repeats of `study` (module docs).
pub(super) fn repeats(study: &Study) -> Repeats {
    let mut configurations = 0;
    let mut equations = 0.0;
    for set in &study.sets {
        let configuration = |index: usize| set.samples.get(index).motor_positions();
        let prints: Vec<u64> = (0..set.samples.len())
            .map(|index| fingerprint(bits(configuration(index))))
            .collect();
        let unique = count_distinct(&prints, |a, b| {
            bits(configuration(a)).cmp(bits(configuration(b)))
        });
        configurations += unique;
        equations += unique as f64 * set.method.equations_per_configuration();
    }
    let measurements: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    // An exact copy repeats a configuration of its method's sets: none
    // when every set's configurations are distinct and no two sets share a
    // method (a million measurements are not hashed again).
    let methods: std::collections::BTreeSet<&str> =
        study.sets.iter().map(|set| set.method.name()).collect();
    let copies = if configurations == measurements && methods.len() == study.sets.len() {
        0
    } else {
        copies(study)
    };
    Repeats {
        configurations,
        equations,
        copies,
    }
}

/// Measurements that repeat an earlier one of the same method exactly.
fn copies(study: &Study) -> usize {
    // The measurements are numbered across the sets; a number is found
    // back by the sets' first numbers (a few sets: no list of a million
    // pairs).
    let firsts: Vec<usize> = study
        .sets
        .iter()
        .scan(0, |first, set| {
            let this = *first;
            *first += set.samples.len();
            Some(this)
        })
        .collect();
    let locate = |index: usize| {
        let set = firsts.partition_point(|&first| first <= index) - 1;
        (set, index - firsts[set])
    };
    let sample = |(set, index): (usize, usize)| study.sets[set].samples.get(index);
    let method = |(set, _): (usize, usize)| study.sets[set].method.name();
    // Sets of one method compare with each other: the method's name is
    // hashed with each measurement.
    let mut prints = Vec::with_capacity(study.sets.iter().map(|set| set.samples.len()).sum());
    for set in &study.sets {
        let name = fingerprint(set.method.name().bytes().map(u64::from));
        prints.extend(set.samples.iter().map(|measurement| {
            let mut hasher = rustc_hash::FxHasher::default();
            hasher.write_u64(name);
            measurement_words(measurement, |word| hasher.write_u64(word));
            hasher.finish()
        }));
    }
    // Two buffers of words, filled again for each comparison.
    let words = RefCell::new((Vec::new(), Vec::new()));
    let unique = count_distinct(&prints, |a, b| {
        let (a, b) = (locate(a), locate(b));
        method(a).cmp(method(b)).then_with(|| {
            let mut words = words.borrow_mut();
            let (first, second) = &mut *words;
            first.clear();
            second.clear();
            measurement_words(sample(a), |word| first.push(word));
            measurement_words(sample(b), |word| second.push(word));
            first.as_slice().cmp(second.as_slice())
        })
    });
    prints.len() - unique
}

/// What a measurement is made of, handed to `word` as 64-bit words: its
/// configuration, group and measured values as bits (−0 as 0), a missing
/// group or value as a tag. One encoding for the fingerprint and for the
/// exact comparison; written value by value (a chain of iterators costs
/// more than the hash).
fn measurement_words(sample: SampleRef<'_>, mut word: impl FnMut(u64)) {
    bits(sample.motor_positions()).for_each(&mut word);
    let (group, position) = (sample.group(), sample.position());
    let (orientation, distance) = (sample.orientation(), sample.distance());
    word(u64::from(group.is_some()));
    word(group.unwrap_or(0));
    word(u64::from(position.is_some()));
    word(u64::from(orientation.is_some()));
    word(u64::from(distance.is_some()));
    for value in position.iter().flat_map(|p| p.iter()) {
        word((value + 0.0).to_bits());
    }
    for value in orientation.iter().flat_map(|q| q.coords.iter()) {
        word((value + 0.0).to_bits());
    }
    if let Some(value) = distance {
        word((value + 0.0).to_bits());
    }
}

/// The number of distinct items among `prints.len()`, item `i` with the
/// fingerprint `prints[i]` (equal items have equal ones) and the total
/// order `compare` (module docs). Exact whatever the fingerprints.
fn count_distinct(prints: &[u64], compare: impl Fn(usize, usize) -> Ordering) -> usize {
    // Items by fingerprint, each with the first item of its fingerprint.
    let mut keys: Vec<(u64, usize)> = prints.iter().copied().zip(0..).collect();
    keys.sort_unstable();
    let mut first = vec![0; prints.len()];
    let mut distinct = 0;
    for run in keys.chunk_by(|a, b| a.0 == b.0) {
        distinct += 1;
        for &(_, item) in run {
            first[item] = run[0].1;
        }
    }
    // Each item equal to the first of its fingerprint, checked in memory
    // order: the firsts are few when the items repeat, and read from the
    // cache.
    let all_equal = first
        .iter()
        .enumerate()
        .all(|(item, &first)| first == item || compare(first, item).is_eq());
    if all_equal {
        distinct
    } else {
        count_distinct_sorted(keys, compare)
    }
}

/// The number of distinct items of `keys` (fingerprint, item), sorted:
/// each run of a fingerprint sorted by `compare`, equal neighbours counted
/// once.
fn count_distinct_sorted(
    mut keys: Vec<(u64, usize)>,
    compare: impl Fn(usize, usize) -> Ordering,
) -> usize {
    keys.chunk_by_mut(|a, b| a.0 == b.0)
        .map(|run| {
            run.sort_unstable_by(|a, b| compare(a.1, b.1));
            1 + run
                .windows(2)
                .filter(|pair| compare(pair[0].1, pair[1].1).is_ne())
                .count()
        })
        .sum()
}

/// A 64-bit fingerprint of `values` (rustc-hash's multiply–rotate hash:
/// fast, not collision-proof; [`count_distinct`] compares ties).
fn fingerprint(values: impl Iterator<Item = u64>) -> u64 {
    let mut hasher = rustc_hash::FxHasher::default();
    values.for_each(|value| hasher.write_u64(value));
    hasher.finish()
}

/// The bits of a configuration's values, −0 as 0.
fn bits(configuration: &[f64]) -> impl Iterator<Item = u64> + '_ {
    configuration.iter().map(|value| (value + 0.0).to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distinct items are counted exactly whatever their fingerprints: with
    /// every fingerprint equal, and with honest ones.
    #[test]
    fn distinct_items_are_counted_exactly_whatever_the_fingerprints() {
        let values: [u64; 11] = [3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5];
        let compare = |a: usize, b: usize| values[a].cmp(&values[b]);
        assert_eq!(count_distinct(&[7; 11], compare), 7);
        let honest: Vec<u64> = values
            .iter()
            .map(|&value| fingerprint([value].into_iter()))
            .collect();
        assert_eq!(count_distinct(&honest, compare), 7);
        // Interleaved collisions (fingerprint by parity) stay exact.
        let parity: Vec<u64> = values.iter().map(|value| value % 2).collect();
        assert_eq!(count_distinct(&parity, compare), 7);
        assert_eq!(count_distinct(&[], compare), 0);
    }
}
