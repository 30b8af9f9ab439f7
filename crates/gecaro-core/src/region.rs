//! A region of the joint space: a range of every joint variable q_j
//! (radians for a revolute joint, metres for a prismatic one; joint
//! variables of eq. 4, not motor variables).
//!
//! Two regions matter to a calibration: the one its data covered (the
//! smallest box holding every measured configuration), where the calibrated
//! model is an interpolation, and the one it is used in (the joint limits,
//! or the work region a user states). Outside the measured region the
//! calibrated model is extrapolated, and parameters the data saw over a
//! narrow range only (a gain over ±15°) may be far off there.
//!
//! ```
//! use gecaro_core::{JointRegion, Robot};
//!
//! let robot = Robot::template("planar", "RR").unwrap(); // limits ±π
//! let measured = JointRegion::covering(2, [[0.1, -0.2], [0.3, 0.4]].iter().map(|q| &q[..]));
//! assert_eq!(measured.range(0), (0.1, 0.3));
//! assert!(measured.contains(&[0.2, 0.0]));
//! assert_eq!(measured.outside(&[0.5, 0.0]).collect::<Vec<_>>(), vec![0]);
//! let limits = JointRegion::of_limits(&robot);
//! assert!((measured.fraction_of(&limits, 1) - 0.6 / std::f64::consts::TAU).abs() < 1e-12);
//! ```

use crate::robot::Robot;

/// How far outside a measured region, in parts of each joint's measured
/// range, a pose is still taken as within it: the predicted error grows
/// smoothly away from the data, and a program's target at the edge of the
/// region moves a little when it is corrected.
pub const MEASURED_MARGIN: f64 = 0.1;

/// A range `[min, max]` of every joint variable (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct JointRegion {
    ranges: Vec<(f64, f64)>,
}

impl JointRegion {
    /// The region of the given ranges, one `(min, max)` per joint.
    ///
    /// # Errors
    /// A range that is not finite or whose minimum exceeds its maximum,
    /// with its joint (1-based) and why.
    pub fn new(ranges: Vec<(f64, f64)>) -> Result<Self, (usize, String)> {
        for (index, (min, max)) in ranges.iter().enumerate() {
            if !(min.is_finite() && max.is_finite()) {
                return Err((index + 1, format!("the range {min}..{max} is not finite")));
            }
            if min > max {
                return Err((
                    index + 1,
                    format!("the range starts at {min}, above its end {max}"),
                ));
            }
        }
        Ok(JointRegion { ranges })
    }

    /// The region of `robot`'s joint limits.
    pub fn of_limits(robot: &Robot) -> Self {
        JointRegion {
            ranges: robot
                .joints()
                .iter()
                .map(|joint| (joint.qmin, joint.qmax))
                .collect(),
        }
    }

    /// The smallest region holding every one of `joint_positions` (each of
    /// `joints` values); empty ranges (`min` +∞, `max` −∞) when there are
    /// none. Values that are not finite are skipped.
    pub fn covering<'a>(joints: usize, joint_positions: impl Iterator<Item = &'a [f64]>) -> Self {
        let mut region = JointRegion {
            ranges: vec![(f64::INFINITY, f64::NEG_INFINITY); joints],
        };
        for configuration in joint_positions {
            region.include(configuration);
        }
        region
    }

    /// Widens the ranges to hold `joint_positions` (values that are not
    /// finite are skipped).
    pub fn include(&mut self, joint_positions: &[f64]) {
        for ((min, max), q) in self.ranges.iter_mut().zip(joint_positions) {
            if q.is_finite() {
                *min = min.min(*q);
                *max = max.max(*q);
            }
        }
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.ranges.len()
    }

    /// The range of joint `index` (0-based).
    pub fn range(&self, index: usize) -> (f64, f64) {
        self.ranges[index]
    }

    /// Every joint's range, in joint order.
    pub fn ranges(&self) -> &[(f64, f64)] {
        &self.ranges
    }

    /// Whether every joint variable of `joint_positions` lies in its range
    /// (to [`LIMIT_TOLERANCE`](crate::LIMIT_TOLERANCE)).
    pub fn contains(&self, joint_positions: &[f64]) -> bool {
        self.outside(joint_positions).next().is_none()
    }

    /// The joints (0-based) of `joint_positions` outside their range.
    pub fn outside<'a>(&'a self, joint_positions: &'a [f64]) -> impl Iterator<Item = usize> + 'a {
        let tolerance = crate::LIMIT_TOLERANCE;
        self.ranges
            .iter()
            .zip(joint_positions)
            .enumerate()
            .filter(move |(_, ((min, max), q))| !(min - tolerance..=max + tolerance).contains(*q))
            .map(|(index, _)| index)
    }

    /// The part of `other`'s range of joint `index` that this region's
    /// covers (0 to 1; 1 when `other`'s range is empty).
    pub fn fraction_of(&self, other: &JointRegion, index: usize) -> f64 {
        let (min, max) = self.ranges[index];
        let (low, high) = other.ranges[index];
        if high <= low {
            return 1.0;
        }
        ((max.min(high) - min.max(low)) / (high - low)).clamp(0.0, 1.0)
    }

    /// The region with each range widened on both sides by `fraction` of
    /// its width: the poses a check takes as within a measured region
    /// ([`MEASURED_MARGIN`]).
    #[must_use]
    pub fn widened(&self, fraction: f64) -> JointRegion {
        JointRegion {
            ranges: self
                .ranges
                .iter()
                .map(|(min, max)| {
                    let margin = fraction * (max - min).max(0.0);
                    (min - margin, max + margin)
                })
                .collect(),
        }
    }

    /// This region and `other` together: each joint's range the one that
    /// holds both.
    #[must_use]
    pub fn union(&self, other: &JointRegion) -> JointRegion {
        JointRegion {
            ranges: self
                .ranges
                .iter()
                .zip(&other.ranges)
                .map(|((a, b), (c, d))| (a.min(*c), b.max(*d)))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_region_refuses_ranges_no_joint_has() {
        assert!(JointRegion::new(vec![(0.0, 1.0), (-1.0, -1.0)]).is_ok());
        let (joint, why) = JointRegion::new(vec![(0.0, 1.0), (2.0, 1.0)]).expect_err("refused");
        assert_eq!(joint, 2);
        assert!(why.contains("above its end"), "{why}");
        assert_eq!(
            JointRegion::new(vec![(f64::NAN, 1.0)])
                .expect_err("refused")
                .0,
            1
        );
    }

    #[test]
    fn covering_holds_every_configuration_and_no_more() {
        let configurations = [[0.5, -1.0], [-0.2, 2.0], [0.1, f64::NAN]];
        let region = JointRegion::covering(2, configurations.iter().map(|q| &q[..]));
        assert_eq!(region.ranges(), &[(-0.2, 0.5), (-1.0, 2.0)]);
        for q in &configurations[..2] {
            assert!(region.contains(q));
        }
        assert!(!region.contains(&[0.6, 0.0]));
        assert_eq!(region.outside(&[-0.3, 2.5]).collect::<Vec<_>>(), vec![0, 1]);
        let other = JointRegion::new(vec![(-1.0, 1.0), (0.0, 4.0)]).expect("a region");
        assert!((region.fraction_of(&other, 0) - 0.35).abs() < 1e-12);
        assert!((region.fraction_of(&other, 1) - 0.5).abs() < 1e-12);
        assert_eq!(region.union(&other).ranges(), &[(-1.0, 1.0), (-1.0, 4.0)]);
        let wider = region.widened(MEASURED_MARGIN);
        assert!((wider.range(0).0 + 0.27).abs() < 1e-12 && (wider.range(1).1 - 2.3).abs() < 1e-12);
        assert!(wider.contains(&[0.55, 2.2]) && !region.contains(&[0.55, 2.2]));
    }
}
