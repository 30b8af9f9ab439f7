//! Sets and pairs of configurations: what the link and distance methods
//! share (grouping by id, size checks, mean-centring; see the parent module).

use std::collections::HashMap;

use crate::error::Error;
use crate::samples::SampleSlice;

/// Sample indices grouped by their `group` id, groups in order of first appearance.
///
/// Linear in the number of samples (a file of 10⁶ rows may hold 5·10⁵ pairs).
pub(crate) fn groups(samples: SampleSlice<'_>) -> Vec<Vec<usize>> {
    let mut position_of: HashMap<u64, usize> = HashMap::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (index, sample) in samples.iter().enumerate() {
        let id = sample.group().unwrap_or(0);
        let position = *position_of.entry(id).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[position].push(index);
    }
    members
}

/// Checks that every group has between `min` and `max` members.
pub(crate) fn check_group_sizes(
    samples: SampleSlice<'_>,
    min: usize,
    max: usize,
    what: &str,
) -> Result<(), Error> {
    for members in groups(samples) {
        if members.len() < min || members.len() > max {
            let first = &samples.get(members[0]);
            let expected = if min == max {
                format!("exactly {min}")
            } else {
                format!("at least {min}")
            };
            return Err(Error::InvalidData {
                line: first.line(),
                message: format!(
                    "{what} {} has {} configuration(s); it needs {expected}",
                    first.group().unwrap_or(0),
                    members.len()
                ),
            });
        }
    }
    Ok(())
}

/// Mean-centres, in place, the per-member blocks of one set: `buffer` holds
/// one equal block per member (values, or rows of coefficients), and each
/// entry of a block loses its mean over the members, weighted by `weights`
/// (one per member: the robust weights of their observations, all 1 in plain
/// least squares; the plain mean if they sum to 0). See the module docs.
pub(crate) fn centre(buffer: &mut [f64], weights: &[f64]) {
    let members = weights.len();
    let stride = buffer.len() / members.max(1);
    let total: f64 = weights.iter().sum();
    // Equal weights (least squares): the plain mean, as without weights.
    let uniform = total <= 0.0 || weights.iter().all(|w| *w == weights[0]);
    for offset in 0..stride {
        let values = (0..members).map(|m| (weights[m], buffer[m * stride + offset]));
        let mean = if uniform {
            values.map(|(_, value)| value).sum::<f64>() / members as f64
        } else {
            values.map(|(weight, value)| weight * value).sum::<f64>() / total
        };
        for m in 0..members {
            buffer[m * stride + offset] -= mean;
        }
    }
}

/// Sizes of the sets of generated link data: about `count` configurations
/// in sets of `size` (at least 2 each); the remainder is spread over the sets.
pub(crate) fn set_sizes(count: usize, size: usize) -> Vec<usize> {
    let count = count.max(2);
    let sets = (count / size.max(2)).max(1);
    let mut sizes = vec![count / sets; sets];
    for size in sizes.iter_mut().take(count % sets) {
        *size += 1;
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;
    use crate::samples::Samples;

    #[test]
    fn centring_removes_the_mean() {
        let mut values = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        centre(&mut values, &[1.0; 3]);
        assert_eq!(values, [-2.0, -2.0, 0.0, 0.0, 2.0, 2.0]);
        // Weighted: the first member does not count in the mean (3, 4 → 4, 5).
        let mut values = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        centre(&mut values, &[0.0, 1.0, 1.0]);
        assert_eq!(values, [-3.0, -3.0, -1.0, -1.0, 1.0, 1.0]);
    }

    #[test]
    fn groups_keep_the_order_of_first_appearance_at_any_size() {
        let with_group = |group: u64| Sample {
            group: Some(group),
            ..Sample::new(vec![0.0])
        };
        let small: Vec<Sample> = [7, 3, 7, 9, 3].into_iter().map(with_group).collect();
        assert_eq!(
            groups(Samples::from(small.as_slice()).as_slice()),
            [vec![0, 2], vec![1, 4], vec![3]]
        );
        // 10⁵ pairs, ids in descending order: one pass (this was quadratic).
        let pairs: Vec<Sample> = (0..200_000_u64)
            .map(|row| with_group(1_000_000 - row / 2))
            .collect();
        let grouped = groups(Samples::from(pairs.as_slice()).as_slice());
        assert_eq!(grouped.len(), 100_000);
        assert!(
            grouped
                .iter()
                .enumerate()
                .all(|(k, members)| members == &[2 * k, 2 * k + 1])
        );
    }

    #[test]
    fn set_sizes_cover_the_count() {
        assert_eq!(set_sizes(10, 4), [5, 5]);
        assert_eq!(set_sizes(3, 4), [3]);
        assert_eq!(set_sizes(8, 2).iter().sum::<usize>(), 8);
    }
}
