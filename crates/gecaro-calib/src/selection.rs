//! The median of values that can be gone through more than once, without
//! holding them: a million residuals need not be copied to find their
//! median and their median absolute deviation.
//!
//! ## Method
//!
//! Values are ordered as [`f64::total_cmp`] orders them, through a `u64`
//! key of the same order ([`order_key`]). A pass counts the keys of the
//! candidates by their next 16 bits (65,536 bins, the first pass by sign,
//! exponent and four mantissa bits); the bin that holds the wanted rank
//! becomes the candidates. When both middle ranks of an even count fall in
//! neighbouring bins, one more pass finds the largest of the lower and the
//! smallest of the upper. Once at most [`COLLECTED`] candidates are left
//! (usually after the first pass: a bin holds a sixteenth of an octave),
//! they are collected and selected in place. Up to [`SELECTED_AT_ONCE`]
//! values are collected and selected without a counting pass: they take no
//! more memory than the counts, and selecting them costs less than clearing
//! and scanning 65,536 fresh counts (at m = 5,000 the counts were a tenth
//! of the page faults of a whole `gecaro identify`).
//!
//! The result is the exact median, the same value, bit for bit, as
//! selection on a copy of all values: the middle value (odd count) or the
//! mean of the two middle values (even count). Memory is 512 KiB of counts
//! and the collected candidates; time is two to five passes.

use std::ops::Range;

use crate::parallel::{available_threads, run_parts};

/// Candidates collected for the final selection, at most (32 KiB of
/// values); more are split by another pass.
const COLLECTED: usize = 4096;

/// Runs of parts a thread counts, each into its own table of counts.
const RUNS_PER_THREAD: usize = 2;

/// Bits of the key counted by each pass.
const DIGIT: u32 = 16;

/// Values selected at once, without a counting pass, at most: as many as
/// the pass has counts (the same 512 KiB).
const SELECTED_AT_ONCE: usize = 1 << DIGIT;

/// A key whose unsigned order is [`f64::total_cmp`]'s order of the values.
fn order_key(value: f64) -> u64 {
    let bits = value.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// The value of an [`order_key`].
fn key_value(key: u64) -> f64 {
    f64::from_bits(if key >> 63 == 1 {
        key & !(1 << 63)
    } else {
        !key
    })
}

/// The median of the `count` values (at least one) that every call of
/// `values` yields: see the module docs.
///
/// # Panics
/// When `values` yields fewer than `count` values.
#[cfg(test)]
pub(crate) fn median_of<I: Iterator<Item = f64>>(
    count: usize,
    values: impl Fn() -> I + Sync,
) -> f64 {
    median_of_parts(count, 1, |_| values())
}

/// The median of the `count` values (at least one) that `values(0)`, …,
/// `values(parts − 1)` yield between them, each pass reading the parts on
/// all cores ([`run_parts`]). The passes count exactly and the last
/// selects by value, so the median is the same, bit for bit, for any
/// split of the values into parts (tested).
///
/// # Panics
/// When the parts yield fewer than `count` values, or `parts` is 0.
pub(crate) fn median_of_parts<I: Iterator<Item = f64>>(
    count: usize,
    parts: usize,
    values: impl Fn(usize) -> I + Sync,
) -> f64 {
    assert!(count > 0, "the median of no values");
    assert!(parts > 0, "values in no part");
    let upper = count / 2;
    let lower = if count % 2 == 1 { upper } else { upper - 1 };
    let (lower, upper) = ranked_pair((count, parts), &values, lower, upper);
    if count % 2 == 1 {
        upper
    } else {
        0.5 * (lower + upper)
    }
}

/// `parts` parts in [`RUNS_PER_THREAD`] contiguous runs a thread (fewer
/// for few parts): enough for a core that starts late to take fewer.
fn part_runs(parts: usize) -> Vec<Range<usize>> {
    let runs = (available_threads() * RUNS_PER_THREAD).clamp(1, parts.max(1));
    (0..runs)
        .map(|run| parts * run / runs..parts * (run + 1) / runs)
        .collect()
}

/// Whether `key` has the bits `prefix` above `shift` (every key while
/// `shift` is 64).
fn within(key: u64, prefix: u64, shift: u32) -> bool {
    shift == 64 || key >> shift == prefix
}

/// The values of ranks `lower` and `upper` (`upper` is `lower` or
/// `lower + 1`, both below `count`) in total order, of the values of
/// `parts` parts.
fn ranked_pair<I: Iterator<Item = f64>>(
    (count, parts): (usize, usize),
    values: &(impl Fn(usize) -> I + Sync),
    lower: usize,
    upper: usize,
) -> (f64, f64) {
    // The candidates: keys whose bits above `shift` are `prefix` (all keys
    // while `shift` is 64), `before` keys below them.
    let (mut prefix, mut shift, mut before, mut candidates) = (0_u64, 64_u32, 0_usize, count);
    let collected = |shift: u32| {
        if shift == 64 {
            SELECTED_AT_ONCE
        } else {
            COLLECTED
        }
    };
    while candidates > collected(shift) && shift > 0 {
        let next = shift - DIGIT;
        // Each run of parts is counted into one table: a table a part
        // would be megabytes to clear and add up for 16 parts.
        let count_run = |run: Range<usize>| {
            let mut counts = vec![0_usize; 1 << DIGIT];
            for part in run {
                for key in values(part).map(order_key) {
                    if within(key, prefix, shift) {
                        counts[((key >> next) & 0xFFFF) as usize] += 1;
                    }
                }
            }
            counts
        };
        let mut runs_counts = run_parts(part_runs(parts), count_run).into_iter();
        let mut counts = runs_counts.next().expect("one part at least");
        for run in runs_counts {
            for (total, in_run) in counts.iter_mut().zip(run) {
                *total += in_run;
            }
        }
        let mut below = before;
        let mut lower_bin = None;
        let mut upper_bin = 0;
        for (bin, &in_bin) in counts.iter().enumerate() {
            if lower_bin.is_none() && lower < below + in_bin {
                lower_bin = Some((bin, below));
            }
            if upper < below + in_bin {
                upper_bin = bin;
                break;
            }
            below += in_bin;
        }
        let (lower_bin, below_lower) = lower_bin.expect("the values are as many as counted");
        let extend = |bin: usize| (prefix << DIGIT) | bin as u64;
        if lower_bin != upper_bin {
            // The two middle ranks are the last of one bin and the first
            // of a later one.
            let (lower_prefix, upper_prefix) = (extend(lower_bin), extend(upper_bin));
            let ends_of_part = |part: usize| {
                let (mut largest, mut smallest) = (0, u64::MAX);
                for key in values(part).map(order_key) {
                    if within(key, lower_prefix, next) {
                        largest = largest.max(key);
                    } else if within(key, upper_prefix, next) {
                        smallest = smallest.min(key);
                    }
                }
                (largest, smallest)
            };
            let (largest, smallest) = run_parts((0..parts).collect(), ends_of_part)
                .into_iter()
                .fold((0, u64::MAX), |(l, s), (pl, ps)| (l.max(pl), s.min(ps)));
            return (key_value(largest), key_value(smallest));
        }
        prefix = extend(lower_bin);
        shift = next;
        before = below_lower;
        candidates = counts[lower_bin];
    }
    if shift == 0 {
        // Every candidate has the same key.
        let value = key_value(prefix);
        return (value, value);
    }
    let kept_of_part = |part: usize| -> Vec<f64> {
        values(part)
            .filter(|&value| within(order_key(value), prefix, shift))
            .collect()
    };
    let mut kept: Vec<f64> = Vec::with_capacity(candidates);
    for part in run_parts((0..parts).collect(), kept_of_part) {
        kept.extend(part);
    }
    let (below, upper_value, _) = kept.select_nth_unstable_by(upper - before, f64::total_cmp);
    let upper_value = *upper_value;
    let lower_value = if lower == upper {
        upper_value
    } else {
        // Rank `upper − 1` is the largest of those below.
        below
            .iter()
            .copied()
            .max_by(f64::total_cmp)
            .expect("the lower middle rank is among the candidates")
    };
    (lower_value, upper_value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The median by sorting a copy.
    fn sorted_median(values: &[f64]) -> f64 {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        }
    }

    /// The median read in one part, and in 2, 3 and 7 parts of uneven
    /// sizes (one empty among 7 for a few values): the same bits.
    fn streamed_median(values: &[f64]) -> f64 {
        let whole = median_of(values.len(), || values.iter().copied());
        for parts in [2, 3, 7] {
            let at = |part: usize| values.len() * part * part / (parts * parts);
            let parted = median_of_parts(values.len(), parts, |part| {
                values[at(part)..at(part + 1)].iter().copied()
            });
            assert_eq!(parted.to_bits(), whole.to_bits(), "{parts} parts");
        }
        whole
    }

    #[test]
    fn keys_order_values_as_total_cmp() {
        let values = [
            f64::NEG_INFINITY,
            -3.5,
            -1e-300,
            -0.0,
            0.0,
            5e-324,
            1.0,
            2.0,
            f64::INFINITY,
        ];
        for pair in values.windows(2) {
            assert!(order_key(pair[0]) < order_key(pair[1]), "{pair:?}");
        }
        for value in values {
            assert_eq!(key_value(order_key(value)).to_bits(), value.to_bits());
        }
    }

    #[test]
    fn the_median_is_that_of_the_sorted_values_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for count in [
            1, 2, 3, 4, 7, 100, 4095, 4096, 4097, 10_000, 50_001, 65_536, 65_537, 200_000,
        ] {
            // Gaussian-like residuals, of both signs and many sizes.
            let values: Vec<f64> = (0..count)
                .map(|_| {
                    let u: f64 = rng.random_range(-1.0..1.0);
                    u * u * u * 1e-5
                })
                .collect();
            assert_eq!(
                streamed_median(&values).to_bits(),
                sorted_median(&values).to_bits(),
                "{count} values"
            );
        }
    }

    #[test]
    fn repeated_and_split_middle_values_are_found() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let rng_uniform = |rng: &mut ChaCha8Rng| rng.random_range(0.0..1.0);
        // One value a hundred thousand times (one key throughout).
        let same = vec![0.25; 100_000];
        assert_eq!(streamed_median(&same), 0.25);
        // Two values, the middle ranks on either side: neighbouring bins
        // at the first pass, then far apart.
        for (a, b) in [(1.0, 1.0 + f64::EPSILON), (-2.0, 7.0), (0.0, -0.0)] {
            let values: Vec<f64> = (0..70_000)
                .map(|i| if i % 2 == 0 { a } else { b })
                .collect();
            assert_eq!(
                streamed_median(&values).to_bits(),
                sorted_median(&values).to_bits(),
                "{a}, {b}"
            );
        }
        // Values that share their first 16 key bits, then their first 32:
        // the candidates are split by a second and a third pass.
        for width in [0.06, 1e-6] {
            for count in [100_000, 100_001] {
                let values: Vec<f64> = (0..count)
                    .map(|_| 1.0 + rng_uniform(&mut rng) * width)
                    .collect();
                assert_eq!(
                    streamed_median(&values).to_bits(),
                    sorted_median(&values).to_bits(),
                    "{count} values within {width}"
                );
            }
        }
        // Many exact zeros among noise (noise-free rows of a set).
        let values: Vec<f64> = (0..90_000)
            .map(|i| {
                if i % 3 == 0 {
                    rng.random_range(-1e-6..1e-6)
                } else {
                    0.0
                }
            })
            .collect();
        assert_eq!(streamed_median(&values), sorted_median(&values));
    }
}
