//! A change of the cell during the measurement: outliers that come one
//! after another in a set's row order.
//!
//! A reflector re-seated in its nest, a tracker bumped or moved, a tool
//! knocked: from that moment every measurement of the set is off by the
//! change, and the rows that follow disagree with the rest as one block. A
//! robust loss or `--reject` hides exactly that: the rows weigh nothing, the
//! fit "fits the noise", and the calibrated robot is right for the cell as
//! it was, not as it is (11–16× the noise floor for the last 10 % of the
//! rows after a 0.5 mm re-seat). Gross errors of their own (a beam broken
//! and re-locked) come alone, scattered over the set.
//!
//! So the outliers of each set (beyond the outlier threshold, at the first
//! fit: before any rejection) are read in row order. With `K` outliers
//! among `n` observations, the rate under independence is `p = K/n`; a
//! segment from one outlier to another holding `k` of them over `m`
//! observations has, under independence, the binomial tail
//! `P(X ≥ k | m, p) ≤ exp(−m·KL(k/m ‖ p))` (Chernoff; KL the relative
//! entropy of two Bernoulli laws). The densest segment (at least
//! [`MIN_CHANGED`] outliers, at least half of its observations) is named a
//! change when that tail times the number of segments tried (Bonferroni)
//! is below [`CHANGE_LEVEL`]. Twelve consecutive outliers among 120
//! (p = 0.1) give 10⁻¹² · 66; four scattered ones among 80 give nothing.

use super::outliers::Outlier;
use crate::study::Study;

/// Outliers at least, in a segment named a change.
pub const MIN_CHANGED: usize = 3;

/// The chance, under independent outliers, below which a segment of them
/// is named a change (Bonferroni over the segments tried).
pub const CHANGE_LEVEL: f64 = 1e-3;

/// Outliers of a set beyond which only runs of consecutive outliers are
/// tried (the segments between every two of them are K²/2).
const MAX_SCANNED: usize = 2000;

/// A block of consecutive observations of one set that disagrees with the
/// rest: see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct CellChange {
    /// The measurement set (its index in the study).
    pub set: usize,
    /// Its label (usually its data file).
    pub label: String,
    /// The block's first and last observations (0-based, in the set).
    pub first: usize,
    /// See [`first`](Self::first).
    pub last: usize,
    /// The observations of the set.
    pub observations: usize,
    /// The block's first and last lines of the data file, when known.
    pub lines: Option<(usize, usize)>,
    /// Outliers in the block.
    pub outliers_inside: usize,
    /// Outliers of the set outside it.
    pub outliers_elsewhere: usize,
    /// The chance of so dense a block among independent outliers
    /// (Bonferroni over the blocks tried).
    pub chance: f64,
}

impl CellChange {
    /// Whether the block runs to the set's last observation: the cell
    /// changed and stayed so.
    pub fn to_end(&self) -> bool {
        self.last + 1 == self.observations
    }

    /// The block in words, for the verdict of a study's set.
    pub fn words(&self, threshold: f64) -> String {
        self.words_with(
            threshold,
            "state the change — split the set there, the later rows a set of their own with \
             their own tool or station — or leave those rows out",
        )
    }

    /// The block in words, ending with `remedy`: what to do about it.
    pub fn words_with(&self, threshold: f64, remedy: &str) -> String {
        let span = self.last - self.first + 1;
        let lines = self.lines.map_or_else(String::new, |(first, last)| {
            format!(" (lines {first}–{last})")
        });
        let from = match self.lines {
            Some((first, _)) => format!("line {first}"),
            None => format!("observation {}", self.first + 1),
        };
        let when = if self.to_end() {
            format!("from {from} on")
        } else {
            format!("from {from} for {span} observations")
        };
        format!(
            "{}: observations {}–{}{lines} disagree with the rest as one block ({} of these {span} \
             beyond {threshold} σ̂, {} of the other {}), which scattered gross errors are not: the \
             cell seems to have changed {when} (a reflector re-seated, the tracker moved or \
             bumped?); {remedy}",
            self.label,
            self.first + 1,
            self.last + 1,
            self.outliers_inside,
            self.outliers_elsewhere,
            self.observations - span,
        )
    }
}

/// The changes among `outliers` (located in `study`), one per set at
/// most: see the module docs.
pub(super) fn cell_changes(study: &Study, outliers: &[Outlier]) -> Vec<CellChange> {
    let mut changes = Vec::new();
    for (index, set) in study.sets.iter().enumerate() {
        let mut located: Vec<&Outlier> = outliers
            .iter()
            .filter(|outlier| outlier.location.set == index)
            .collect();
        if located.len() < MIN_CHANGED {
            continue;
        }
        located.sort_by_key(|outlier| outlier.location.observation);
        let observations = set
            .method
            .grouped_observations(set.samples.as_slice())
            .map_or(set.samples.len(), |groups| groups.len());
        let positions: Vec<usize> = located.iter().map(|o| o.location.observation).collect();
        let line = |k: usize, last: bool| {
            let lines = &located[k].location.lines;
            if last { lines.last() } else { lines.first() }.copied()
        };
        changes.extend(change_among(
            (index, &set.label),
            &positions,
            observations,
            line,
        ));
    }
    changes
}

/// The change among the outliers at the sorted observation `positions`
/// of set `(index, label)` of `observations` (module docs): `line(k,
/// last)` is the first (last) line of the `k`-th outlier's observation,
/// when known. For data outside a study too (a parallel robot's).
pub(crate) fn change_among(
    (set, label): (usize, &str),
    positions: &[usize],
    observations: usize,
    line: impl Fn(usize, bool) -> Option<usize>,
) -> Option<CellChange> {
    let (i, j, chance) = densest_block(positions, observations)?;
    Some(CellChange {
        set,
        label: label.to_owned(),
        first: positions[i],
        last: positions[j],
        observations,
        lines: line(i, false).zip(line(j, true)),
        outliers_inside: j - i + 1,
        outliers_elsewhere: positions.len() - (j - i + 1),
        chance,
    })
}

/// The densest block of the sorted outlier `positions` among `n`
/// observations, `(first, last, chance)` indices into `positions`, when it
/// is a change (module docs).
fn densest_block(positions: &[usize], n: usize) -> Option<(usize, usize, f64)> {
    let outliers = positions.len();
    let rate = outliers as f64 / n as f64;
    if outliers < MIN_CHANGED || rate >= 0.5 {
        return None;
    }
    let tries = (outliers * (outliers - 1) / 2) as f64;
    let log_tail = |k: usize, m: usize| -> Option<f64> {
        let density = k as f64 / m as f64;
        (k >= MIN_CHANGED && density >= 0.5 && density > rate)
            .then(|| -(m as f64) * relative_entropy(density, rate))
    };
    let mut best: Option<(usize, usize, f64)> = None;
    let mut consider = |i: usize, j: usize| {
        let m = positions[j] - positions[i] + 1;
        if let Some(log) = log_tail(j - i + 1, m)
            && best.is_none_or(|(_, _, b)| log < b)
        {
            best = Some((i, j, log));
        }
    };
    if outliers <= MAX_SCANNED {
        for i in 0..outliers {
            for j in i + MIN_CHANGED - 1..outliers {
                consider(i, j);
            }
        }
    } else {
        // Runs of consecutive outliers only.
        let mut start = 0;
        for j in 1..=outliers {
            if j == outliers || positions[j] != positions[j - 1] + 1 {
                if j - start >= MIN_CHANGED {
                    consider(start, j - 1);
                }
                start = j;
            }
        }
    }
    let (i, j, log) = best?;
    let chance = (log + tries.ln()).exp();
    (chance < CHANGE_LEVEL).then_some((i, j, chance))
}

/// KL(a ‖ p) of two Bernoulli laws (nats), `a` in (0, 1], `p` in (0, 1).
fn relative_entropy(a: f64, p: f64) -> f64 {
    let term = |x: f64, y: f64| if x > 0.0 { x * (x / y).ln() } else { 0.0 };
    term(a, p) + term(1.0 - a, 1.0 - p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_block_of_outliers_is_a_change_and_scattered_ones_are_not() {
        // The last 12 of 120, all outliers.
        let block: Vec<usize> = (108..120).collect();
        let (i, j, chance) = densest_block(&block, 120).expect("a change");
        assert_eq!((block[i], block[j]), (108, 119));
        assert!(chance < 1e-8, "{chance}");
        // Nine of the last twelve, and two gross errors elsewhere.
        let mut mixed = vec![5, 60];
        mixed.extend([108, 109, 111, 112, 113, 115, 116, 118, 119]);
        let (i, j, _) = densest_block(&mixed, 120).expect("a change");
        assert_eq!((mixed[i], mixed[j]), (108, 119));
        // Four scattered gross errors among 80, or three in a row among
        // 10⁴ with a hundred others: chance.
        assert!(densest_block(&[8, 26, 43, 67], 80).is_none());
        let mut many: Vec<usize> = (0..100).map(|k| k * 97 + 13).collect();
        many.extend([5000, 5001, 5002]);
        many.sort_unstable();
        assert!(densest_block(&many, 10_000).is_none());
        // Two in a row are no block; most of a set is no change of it.
        assert!(densest_block(&[40, 41], 120).is_none());
        assert!(densest_block(&(0..70).collect::<Vec<_>>(), 120).is_none());
    }

    #[test]
    fn many_outliers_are_scanned_by_their_runs() {
        // 3,000 scattered outliers among 10⁶ and a run of 20: the run.
        let mut positions: Vec<usize> = (0..3000).map(|k| k * 333 + 7).collect();
        positions.extend(500_100..500_120);
        positions.sort_unstable();
        positions.dedup();
        let (i, j, _) = densest_block(&positions, 1_000_000).expect("a change");
        assert_eq!((positions[i], positions[j]), (500_100, 500_119));
    }
}
