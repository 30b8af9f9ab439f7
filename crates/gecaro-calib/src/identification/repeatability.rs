//! The noise measured, not stated: repeated poses in the data.
//!
//! A datasheet's σ (a tracker's maximum permissible error, say) may be twice
//! the noise the cell shows; stated so, it hides a model error of about √3 σ
//! (an unmodelled compliance: "fits 1.13"). Repeated measurements of one
//! pose are the honest source of σ: their spread about their own mean is
//! the noise (the sensor's and the robot's repeatability), whatever the
//! model. So the observations of each set that measures one configuration
//! at a time (position, frame) are grouped by configuration — joint values
//! within [`SAME_POSE`] of each other, the encoders' jitter of a commanded
//! pose — and, with at least [`MIN_FREEDOM`] degrees of freedom among the
//! groups of two or more, the pure error
//!
//! `SS_pe = Σ_groups Σ_i ‖r_i − r̄_g‖²`, `ν_pe = Σ_groups rows·(n_g − 1)`
//!
//! of the residuals (scaled by the sensors' σ) measures the noise:
//! `σ_pe = √(SS_pe/ν_pe)` in units of the stated σ. The fit is then judged
//! against it by the lack-of-fit F test of regression: with the residuals'
//! `χ²` over `ν` degrees of freedom, `F = ((χ² − SS_pe)/(ν − ν_pe)) /
//! (SS_pe/ν_pe)`, which exceeds the F(ν − ν_pe, ν_pe) quantile at 1 − 1 %
//! when the model misses what the robot does, whatever σ was stated.
//!
//! Grouping sorts the configurations by their first joint and compares
//! each with those within [`SAME_POSE`] of it there (a handful: distinct
//! poses are far apart in every joint); studies of more than
//! [`MAX_CONFIGURATIONS`] configurations are not grouped.

use crate::observation::ObservationSystem;
use crate::study::Study;

/// Joint values (rad, or m) within this of each other are one pose.
pub const SAME_POSE: f64 = 1e-4;

/// Degrees of freedom of the pure error the noise is measured with, at
/// least.
pub const MIN_FREEDOM: usize = 10;

/// Configurations beyond which no repeated pose is looked for.
const MAX_CONFIGURATIONS: usize = 100_000;

/// Poses compared with each, at most: the next ones along the sorted joint.
const NEIGHBOURS: usize = 256;

/// The level of the lack-of-fit test.
const LEVEL: f64 = 0.01;

/// The noise the repeated poses measure, and the fit judged against it.
#[derive(Clone, Debug, PartialEq)]
pub struct Repeatability {
    /// Poses measured more than once.
    pub poses: usize,
    /// The observations of those poses.
    pub observations: usize,
    /// Degrees of freedom of the pure error, ν_pe.
    pub degrees_of_freedom: usize,
    /// σ_pe: the noise the repeats measure, in units of the stated σ
    /// (metres and radians for unweighted sets).
    pub sigma_ratio: f64,
    /// The lack-of-fit statistic F.
    pub lack_of_fit: f64,
    /// The F(ν − ν_pe, ν_pe) quantile at 1 − 1 %.
    pub critical: f64,
}

impl Repeatability {
    /// Whether the residuals fit the noise the repeats measure.
    pub fn passed(&self) -> bool {
        self.lack_of_fit <= self.critical
    }
}

/// Observations (numbered across a study's sets) grouped by the pose they
/// measure, the groups of more than one.
pub(super) type PoseGroups = Vec<Vec<usize>>;

/// The observations of `study` that measure one pose more than once, a
/// group for each pose (module docs): what only the data decide, found on
/// another core while the fit ends. None beyond [`MAX_CONFIGURATIONS`].
pub(super) fn repeated_poses(study: &Study) -> PoseGroups {
    let configurations: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    if configurations > MAX_CONFIGURATIONS {
        return Vec::new();
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut first = 0;
    for set in &study.sets {
        let grouped = set.method.grouped_observations(set.samples.as_slice());
        let count = grouped.as_ref().map_or(set.samples.len(), Vec::len);
        if grouped.is_none() {
            let poses: Vec<&[f64]> = set
                .samples
                .as_slice()
                .iter()
                .map(|sample| sample.motor_positions())
                .collect();
            groups.extend(
                same_poses(&poses)
                    .into_iter()
                    .map(|group| group.into_iter().map(|k| first + k).collect()),
            );
        }
        first += count;
    }
    groups.retain(|members| members.len() > 1);
    groups
}

/// The fit of `system` judged against the noise its repeated poses
/// measure (`groups`, from [`repeated_poses`]; module docs), from the
/// residuals' `chi_square` over `freedom` degrees of freedom; `None`
/// without [`MIN_FREEDOM`] among the repeats.
pub(super) fn repeatability(
    groups: &[Vec<usize>],
    system: &ObservationSystem,
    chi_square: f64,
    freedom: usize,
) -> Option<Repeatability> {
    if groups.is_empty() {
        return None;
    }
    // The scaled residuals of the repeated observations, in row order.
    let mut slot = vec![usize::MAX; system.observation_count()];
    for (index, observation) in groups.iter().flatten().enumerate() {
        slot[*observation] = index;
    }
    let mut residuals: Vec<Vec<f64>> = vec![Vec::new(); groups.iter().map(Vec::len).sum()];
    let observations = system.row_observations();
    for (row, scaled) in system.scaled_rows() {
        if let Some(held) = residuals.get_mut(slot[observations[row] as usize]) {
            held.push(scaled);
        }
    }
    let mut index = 0;
    let groups: Vec<Vec<usize>> = groups
        .iter()
        .map(|members| {
            let local = (index..index + members.len()).collect();
            index += members.len();
            local
        })
        .collect();
    let (mut poses, mut repeated, mut squares, mut pure_freedom) = (0, 0, 0.0, 0_usize);
    for members in &groups {
        let width = residuals[members[0]].len();
        if width == 0 || members.iter().any(|m| residuals[*m].len() != width) {
            continue;
        }
        let n = members.len() as f64;
        let mut mean = vec![0.0; width];
        for member in members {
            for (sum, value) in mean.iter_mut().zip(&residuals[*member]) {
                *sum += value / n;
            }
        }
        for member in members {
            squares += residuals[*member]
                .iter()
                .zip(&mean)
                .map(|(value, mean)| (value - mean).powi(2))
                .sum::<f64>();
        }
        pure_freedom += width * (members.len() - 1);
        poses += 1;
        repeated += members.len();
    }
    if pure_freedom < MIN_FREEDOM || freedom <= pure_freedom || squares <= 0.0 {
        return None;
    }
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    let lack_freedom = freedom - pure_freedom;
    let pure = squares / pure_freedom as f64;
    let lack_of_fit = ((chi_square - squares).max(0.0) / lack_freedom as f64) / pure;
    let critical = FisherSnedecor::new(lack_freedom as f64, pure_freedom as f64)
        .map(|f| f.inverse_cdf(1.0 - LEVEL))
        .ok()?;
    Some(Repeatability {
        poses,
        observations: repeated,
        degrees_of_freedom: pure_freedom,
        sigma_ratio: pure.sqrt(),
        lack_of_fit,
        critical,
    })
}

/// The groups of `poses` (motor values) within [`SAME_POSE`] of each other
/// in every joint, joined through common members (indices into `poses`,
/// each group in order); poses measured once are in none.
fn same_poses(poses: &[&[f64]]) -> Vec<Vec<usize>> {
    // Sorted along the joint the poses spread over most: few neighbours
    // within SAME_POSE there (at most NEIGHBOURS are compared).
    let joints = poses.first().map_or(0, |pose| pose.len());
    let spread = |j: usize| {
        let values = poses.iter().filter_map(|pose| pose.get(j).copied());
        let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
            (a.min(q), b.max(q))
        });
        high - low
    };
    let axis = (0..joints)
        .max_by(|a, b| spread(*a).total_cmp(&spread(*b)))
        .unwrap_or(0);
    let first = |k: usize| poses[k].get(axis).copied().unwrap_or(0.0);
    let mut keyed: Vec<(f64, usize)> = (0..poses.len()).map(|k| (first(k), k)).collect();
    keyed.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let order: Vec<usize> = keyed.iter().map(|(_, k)| *k).collect();
    // Union–find over the pairs within SAME_POSE in every joint.
    let mut parent: Vec<usize> = (0..poses.len()).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    for (position, &a) in order.iter().enumerate() {
        for &b in order[position + 1..]
            .iter()
            .take_while(|b| first(**b) - first(a) <= SAME_POSE)
            .take(NEIGHBOURS)
        {
            let close = poses[a].len() == poses[b].len()
                && poses[a]
                    .iter()
                    .zip(poses[b])
                    .all(|(x, y)| (x - y).abs() <= SAME_POSE);
            if close {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Only poses measured more than once form groups (most are not).
    let roots: Vec<usize> = (0..poses.len()).map(|k| root(&mut parent, k)).collect();
    let mut sizes = vec![0_u32; poses.len()];
    for r in &roots {
        sizes[*r] += 1;
    }
    let mut slots = vec![usize::MAX; poses.len()];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, r) in roots.iter().enumerate() {
        if sizes[*r] > 1 {
            if slots[*r] == usize::MAX {
                slots[*r] = groups.len();
                groups.push(Vec::new());
            }
            groups[slots[*r]].push(k);
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_within_a_tenth_of_a_milliradian_are_one() {
        let poses = [
            [0.1, 0.2, 0.3],
            [0.5, 0.5, 0.5],
            [0.1 + 5e-5, 0.2 - 5e-5, 0.3],
            [0.1 - 4e-5, 0.2, 0.3 + 9e-5],
            [0.1, 0.2 + 3e-4, 0.3],
        ];
        let references: Vec<&[f64]> = poses.iter().map(|p| &p[..]).collect();
        let mut groups = same_poses(&references);
        groups.sort();
        assert_eq!(groups, vec![vec![0, 2, 3]]);
    }
}
