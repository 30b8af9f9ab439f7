//! Seeded random configurations and configurations that reach a target, for
//! points generation and for the random observation matrices of
//! identifiability (paper §3.2, §4).
//!
//! Everything random in gecaro draws from one [`Sampler`], a ChaCha8 stream
//! seeded by the user: the same seed gives the same configurations, bit for
//! bit, on every platform.

use gecaro_core::{InverseOptions, InverseSolution, InverseSolver, Robot, Target};
use nalgebra::{Rotation3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::Error;
use crate::cell::Cell;

/// Start configurations tried before a target is declared out of reach.
const REACH_ATTEMPTS: usize = 30;

/// Two configurations are distinct when some joint differs by more than this
/// fraction of its range.
const DISTINCT_FRACTION: f64 = 0.02;

/// Random starts [`solve_from_starts`] tries after the middle of the joint ranges.
pub const RANDOM_STARTS: usize = 20;

/// The inverse geometric model without a start configuration: from the
/// middle of the joint ranges, then from [`RANDOM_STARTS`] random
/// configurations (seeded by `seed`).
///
/// # Errors
/// The error of the first start when none reaches the target.
pub fn solve_from_starts(
    robot: &Robot,
    target: &Target,
    options: &InverseOptions,
    seed: u64,
) -> Result<InverseSolution, gecaro_core::Error> {
    let middle: Vec<f64> = robot
        .joints()
        .iter()
        .map(|joint| 0.5 * (joint.qmin + joint.qmax))
        .collect();
    let first = robot.motor_positions(&middle)?;
    let solver = InverseSolver::new(robot);
    let first_error = match solver.solve(target, first.as_slice(), options) {
        Ok(solution) => return Ok(solution),
        Err(error) => error,
    };
    let mut sampler = Sampler::new(seed);
    for _ in 0..RANDOM_STARTS {
        let start = sampler.configuration(robot);
        if let Ok(solution) = solver.solve(target, &start, options) {
            return Ok(solution);
        }
    }
    Err(first_error)
}

/// Seed of [`spread_indices`]: a subsample is the same on every run.
const SPREAD_SEED: u64 = 0x5eed_5bb1;

/// Indices of at most `limit` of `len` items, in increasing order, for the
/// parts of an identification that read a bounded subsample of large data:
/// one index drawn at random in each of `limit` equal stretches (seeded, so
/// the same on every run). All `len` when `len <= limit`. Spread over the
/// whole data as evenly spaced indices are, but no cycle of the data aligns
/// with them: every 50th of 500 repeats of 50 poses is one pose 500 times,
/// and an identification that read those started from nowhere.
pub(crate) fn spread_indices(len: usize, limit: usize) -> Vec<usize> {
    if len <= limit {
        return (0..len).collect();
    }
    let mut rng = ChaCha8Rng::seed_from_u64(SPREAD_SEED);
    (0..limit)
        .map(|stretch| {
            let (start, end) = (stretch * len / limit, (stretch + 1) * len / limit);
            rng.random_range(start..end.max(start + 1))
        })
        .collect()
}

/// The items of [`spread_indices`]`(len, limit)` among the `len` that
/// `items` yields, picked as they go by: a million items are not listed
/// first.
pub(crate) fn spread_items<T>(
    items: impl Iterator<Item = T>,
    len: usize,
    limit: usize,
) -> impl Iterator<Item = T> {
    let mut picked = spread_indices(len, limit).into_iter().peekable();
    items
        .enumerate()
        .filter_map(move |(index, item)| picked.next_if_eq(&index).map(|_| item))
}

/// Draws of a configuration before one the cell admits is given up on.
pub const CELL_DRAWS: usize = 10_000;

/// The seed of every random draw when none is asked for (generation,
/// random configurations, planning pools, folds): the command line's
/// `--seed`, Python's `seed`, the page's Seed fields (sent by `/api/info`).
pub const DEFAULT_SEED: u64 = 1;

/// The source of randomness of points generation; see the module docs.
#[derive(Clone, Debug)]
pub struct Sampler {
    rng: ChaCha8Rng,
    cell: Cell,
    cell_misses: usize,
}

impl Sampler {
    /// A sampler seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Sampler {
            rng: ChaCha8Rng::seed_from_u64(seed),
            cell: Cell::default(),
            cell_misses: 0,
        }
    }

    /// The same sampler drawing only configurations that `cell` admits
    /// (in [`configuration`](Self::configuration) and [`reach`](Self::reach)).
    #[must_use]
    pub fn with_cell(mut self, cell: Cell) -> Self {
        self.cell = cell;
        self
    }

    /// How many times [`configuration`](Self::configuration) gave a
    /// configuration the cell does not admit: after [`CELL_DRAWS`] draws for
    /// the first, after one draw for the next (the work has failed then): a
    /// cell that leaves next to nothing to measure.
    pub fn cell_misses(&self) -> usize {
        self.cell_misses
    }

    /// A uniform number in `[low, high)`; `low` when the range is empty.
    /// Bounds whose difference overflows (±1e308) are mixed rather than
    /// subtracted, so that any two finite bounds give a finite number.
    pub fn uniform(&mut self, low: f64, high: f64) -> f64 {
        if high.partial_cmp(&low) != Some(std::cmp::Ordering::Greater) {
            low
        } else if (high - low).is_finite() {
            self.rng.random_range(low..high)
        } else {
            let fraction: f64 = self.rng.random();
            low * (1.0 - fraction) + high * fraction
        }
    }

    /// `amount` distinct indices below `length` (all when `amount` is
    /// larger), drawn uniformly, in random order.
    pub fn subset(&mut self, length: usize, amount: usize) -> Vec<usize> {
        rand::seq::index::sample(&mut self.rng, length, amount.min(length)).into_vec()
    }

    /// A Gaussian number of mean 0 and standard deviation `sigma` (0 draws nothing).
    pub fn gaussian(&mut self, sigma: f64) -> f64 {
        if sigma == 0.0 {
            return 0.0;
        }
        let unit: f64 = StandardNormal.sample(&mut self.rng);
        sigma * unit
    }

    /// A vector of three independent Gaussian numbers.
    pub fn gaussian_vector(&mut self, sigma: f64) -> Vector3<f64> {
        Vector3::new(
            self.gaussian(sigma),
            self.gaussian(sigma),
            self.gaussian(sigma),
        )
    }

    /// A small random rotation, each rotation-vector component of deviation `sigma`.
    pub fn gaussian_rotation(&mut self, sigma: f64) -> Rotation3<f64> {
        Rotation3::new(self.gaussian_vector(sigma))
    }

    /// Motor variables of a configuration drawn uniformly within the joint
    /// limits, and admitted by the sampler's cell (redrawn up to
    /// [`CELL_DRAWS`] times; see [`cell_misses`](Self::cell_misses)).
    ///
    /// # Panics
    /// Never for a valid robot (its coupling is invertible).
    pub fn configuration(&mut self, robot: &Robot) -> Vec<f64> {
        let mut candidate = self.draw(robot);
        // After one miss the work is known to fail (the front ends refuse
        // data with misses): count the others without searching, so that a
        // cell that admits nothing fails in one search, not one per
        // configuration (20,000 of them took 18 minutes).
        if self.cell.is_open() {
            return candidate;
        }
        if self.cell_misses > 0 {
            if !self.cell.admits(robot, &candidate) {
                self.cell_misses += 1;
            }
            return candidate;
        }
        for _ in 1..CELL_DRAWS {
            if self.cell.admits(robot, &candidate) {
                return candidate;
            }
            candidate = self.draw(robot);
        }
        if !self.cell.admits(robot, &candidate) {
            self.cell_misses += 1;
        }
        candidate
    }

    /// Motor variables of joint values drawn uniformly within the limits.
    fn draw(&mut self, robot: &Robot) -> Vec<f64> {
        let joint_positions: Vec<f64> = robot
            .joints()
            .iter()
            .map(|joint| self.uniform(joint.qmin, joint.qmax))
            .collect();
        robot
            .motor_positions(&joint_positions)
            .expect("a valid robot maps joint to motor variables")
            .as_slice()
            .to_vec()
    }

    /// Motor variables of a configuration reaching `target`, distinct from
    /// every configuration in `distinct_from`. Tries `start` first, then
    /// random starts within the joint limits.
    ///
    /// # Errors
    /// [`Error::Generation`] when no attempt succeeds.
    pub fn reach(
        &mut self,
        robot: &Robot,
        target: &Target,
        start: Option<&[f64]>,
        distinct_from: &[&[f64]],
    ) -> Result<Vec<f64>, Error> {
        let options = InverseOptions::default();
        let solver = InverseSolver::new(robot);
        for attempt in 0..REACH_ATTEMPTS {
            let start = match (attempt, start) {
                (0, Some(start)) => start.to_vec(),
                _ => self.configuration(robot),
            };
            let Ok(solution) = solver.solve(target, &start, &options) else {
                continue;
            };
            if !self.cell.admits(robot, &solution.motor_positions) {
                continue;
            }
            if distinct_from
                .iter()
                .all(|other| distinct(robot, &solution.motor_positions, other))
            {
                return Ok(solution.motor_positions);
            }
        }
        let what = match target {
            Target::Position(_) => "point",
            Target::Frame(_) => "frame",
            Target::Plane { .. } => "plane",
        };
        Err(Error::Generation {
            message: format!(
                "no configuration within the joint limits reached the {what} from {REACH_ATTEMPTS} \
                 start configurations{}",
                if distinct_from.is_empty() {
                    ""
                } else {
                    " (distinct from the others of its set)"
                }
            ),
        })
    }
}

/// Whether two motor configurations differ noticeably in joint space.
fn distinct(robot: &Robot, first: &[f64], second: &[f64]) -> bool {
    let (Ok(q1), Ok(q2)) = (robot.joint_positions(first), robot.joint_positions(second)) else {
        return true;
    };
    robot
        .joints()
        .iter()
        .zip(q1.iter().zip(q2.iter()))
        .any(|(joint, (a, b))| {
            (a - b).abs() > DISTINCT_FRACTION * (joint.qmax - joint.qmin).max(1e-9)
        })
}

#[cfg(test)]
mod tests {
    use super::{spread_indices, spread_items};

    #[test]
    fn spread_indices_cover_the_data_and_no_cycle_of_it() {
        assert_eq!(spread_indices(5, 10), vec![0, 1, 2, 3, 4]);
        // 500 repeats of 50 poses, 500 read: evenly spaced indices would all
        // be one pose.
        let (len, limit, period) = (25_000, 500, 50);
        let indices = spread_indices(len, limit);
        assert_eq!(indices.len(), limit);
        assert!(indices.windows(2).all(|pair| pair[0] < pair[1]));
        for (stretch, index) in indices.iter().enumerate() {
            assert!((stretch * len / limit..(stretch + 1) * len / limit).contains(index));
        }
        let mut poses: Vec<usize> = indices.iter().map(|index| index % period).collect();
        poses.sort_unstable();
        poses.dedup();
        assert_eq!(poses.len(), period, "every pose read");
        assert_eq!(indices, spread_indices(len, limit), "the same every run");
        let items: Vec<usize> = spread_items((0..len).map(|i| 10 * i), len, limit).collect();
        let expected: Vec<usize> = indices.iter().map(|i| 10 * i).collect();
        assert_eq!(items, expected, "the items at the spread indices");
    }
}
