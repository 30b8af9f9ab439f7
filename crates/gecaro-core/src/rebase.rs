//! A robot calibrated in a measurement frame, re-expressed in its own base
//! frame.
//!
//! A calibration with a laser tracker identifies the robot in the tracker's
//! frame: frames 0 and 1 of the calibrated robot place joint 1 where the
//! tracker saw it. Programs, though, are taught in the robot's own frame,
//! the one its controller and its nominal robot file use. Splitting the
//! calibrated robot into the measurement frame's pose and the robot in its
//! own frame lets a program in robot coordinates be corrected, and a URDF be
//! exported in the robot's frame.
//!
//! ## The robot's own frame
//!
//! The base frame of a robot is where its first joint is: the robot's own
//! frame is the one in which the calibrated frame 1 (joint 1's axis, the
//! zero of joint 1, the origin on the axis) stands where the nominal robot
//! puts it. With `F₁(q₁)` the pose of frame 1 in the world, and since joint
//! 1 enters frame 1's transform last (`Rot(z, θ₁ + q₁)·Trans(z, r₁)`, or
//! `Trans(z, r₁ + q₁)` for a prismatic joint), `F₁(q₁) = F₁(0)·Rot(z, q₁)`:
//!
//! `B = F₁,nominal(0) · F₁,calibrated(0)⁻¹`
//!
//! maps measurement-frame coordinates to robot coordinates at every
//! configuration, and the calibrated robot seen from the robot's frame is the
//! calibrated robot with the nominal's frames 0 and 1 (every other frame,
//! the joints' gains, offsets and couplings stay calibrated). The errors of
//! the base that the calibration found are the measurement frame's pose:
//! they are where the robot stands, not how it moves. `B` is the pose of the
//! measurement frame in the robot's base frame.
//!
//! ```
//! use gecaro_core::{Robot, terminal_pose};
//! use nalgebra::{IsometryMatrix3, Translation3, UnitQuaternion};
//!
//! let nominal = Robot::template("arm", "RRPRRR").unwrap();
//! // The robot seen from a tracker 2.5 m away, turned 120°.
//! let tracker = IsometryMatrix3::from_parts(
//!     Translation3::new(2.5, 0.3, -0.4),
//!     UnitQuaternion::from_euler_angles(0.0, 0.0, 2.1).to_rotation_matrix(),
//! );
//! let in_tracker_frame = nominal.reframed(&tracker, &IsometryMatrix3::identity()).unwrap();
//! let (measurement_frame, own) = in_tracker_frame.rebased(&nominal).unwrap();
//! let q = [0.1, -0.2, 0.3, 0.4, -0.5, 0.6];
//! let difference = terminal_pose(&own, &q).unwrap().translation.vector
//!     - terminal_pose(&nominal, &q).unwrap().translation.vector;
//! assert!(difference.norm() < 1e-12);
//! assert!((measurement_frame.inverse().translation.vector - tracker.translation.vector).norm() < 1e-12);
//! ```

use nalgebra::IsometryMatrix3;

use crate::kinematics::frame_transform;
use crate::robot::Robot;
use crate::{Error, Field};

/// Two robots whose joint 1 stands farther apart than this (metres) are
/// not described in the same frame: no calibration moves a base that far.
pub const SAME_FRAME_DISTANCE: f64 = 0.1;

/// Likewise for the angle between their frames 1 (radians): 5°.
pub const SAME_FRAME_ANGLE: f64 = 5.0 * std::f64::consts::PI / 180.0;

impl Robot {
    /// The pose of frame 1 (joint 1's) in the world frame with joint 1 at
    /// its zero: where the robot stands.
    pub fn base_pose(&self) -> IsometryMatrix3<f64> {
        let frames = self.frames();
        frame_transform(&frames[0], 0.0) * frame_transform(&frames[1], 0.0)
    }

    /// Where this robot's world frame lies in `nominal`'s, this robot's
    /// base placed where `nominal` puts its own: `N₁·C₁⁻¹` with `C₁`, `N₁`
    /// their [`base_pose`](Self::base_pose)s. For a robot calibrated in a
    /// tracker's frame, the tracker's frame in the robot's own.
    pub fn measurement_frame_in(&self, nominal: &Robot) -> IsometryMatrix3<f64> {
        nominal.base_pose() * self.base_pose().inverse()
    }

    /// How far `other`'s joint 1 stands from this robot's: the distance
    /// (metres) and angle (radians) between their [`base_pose`](Self::base_pose)s.
    pub fn base_offset(&self, other: &Robot) -> (f64, f64) {
        let change = self.base_pose().inverse() * other.base_pose();
        (change.translation.vector.norm(), change.rotation.angle())
    }

    /// Whether `other` is described in the same frame as this robot: its
    /// joint 1 within [`SAME_FRAME_DISTANCE`] and [`SAME_FRAME_ANGLE`].
    pub fn same_frame_as(&self, other: &Robot) -> bool {
        let (distance, angle) = self.base_offset(other);
        distance <= SAME_FRAME_DISTANCE && angle <= SAME_FRAME_ANGLE
    }

    /// The first link between two joints (frames 2..n) whose parameter
    /// differs from `other`'s beyond what a calibration moves
    /// ([`SAME_FRAME_DISTANCE`] for d and r, 10° for α and β): its frame,
    /// the parameter's name and the difference as words. θ is not compared:
    /// a calibration regroups it with joint offsets and the tool's rotation
    /// (a position calibration turns θ6 by tens of degrees).
    fn link_difference(&self, other: &Robot) -> Option<(usize, &'static str, String)> {
        let angle = 10f64.to_radians();
        let wrapped = |a: f64, b: f64| {
            let d = (a - b).rem_euclid(std::f64::consts::TAU);
            d.min(std::f64::consts::TAU - d)
        };
        (2..=self.joint_count()).find_map(|j| {
            let (a, b) = (&self.frames()[j], &other.frames()[j]);
            [
                ("alpha", wrapped(a.alpha, b.alpha), true),
                ("beta", wrapped(a.beta, b.beta), true),
                ("d", (a.d - b.d).abs(), false),
                ("r", (a.r - b.r).abs(), false),
            ]
            .into_iter()
            .find(|(_, difference, is_angle)| {
                *difference
                    > if *is_angle {
                        angle
                    } else {
                        SAME_FRAME_DISTANCE
                    }
            })
            .map(|(name, difference, is_angle)| {
                let words = if is_angle {
                    format!("{:.1}°", difference.to_degrees())
                } else {
                    format!("{:.3} m", difference)
                };
                (j, name, words)
            })
        })
    }

    /// This robot (calibrated in a measurement frame) split into the pose of
    /// the measurement frame in the robot's own base frame and the robot
    /// seen from that frame, the base frame being `nominal`'s (see the
    /// module docs). `robot reframe --world` of the pose's inverse gives this
    /// robot back.
    ///
    /// # Errors
    /// [`Error::Invalid`] when `nominal` has other joints (count or type of
    /// joint 1) or the result breaks a rule of the model.
    pub fn rebased(&self, nominal: &Robot) -> Result<(IsometryMatrix3<f64>, Robot), Error> {
        if self.joint_letters() != nominal.joint_letters() {
            return Err(Error::invalid(
                Field::Frames,
                format!(
                    "the nominal robot has other joints ({}, this one {}): a robot is re-expressed \
                     in the base frame of its own nominal robot",
                    nominal.joint_letters(),
                    self.joint_letters()
                ),
            ));
        }
        // Another robot of the same joints (an industrial6 onto a puma560)
        // is no calibration of this one: its links differ by more than any
        // calibration moves them.
        if let Some((j, name, difference)) = self.link_difference(nominal) {
            return Err(Error::invalid(
                Field::Frames,
                format!(
                    "frame {j}'s {name} differs from {}'s by {difference}: not a calibration of \
                     it (a calibration moves a link by millimetres and tenths of a degree); \
                     re-express a robot in the base frame of its own nominal robot",
                    nominal.name()
                ),
            ));
        }
        let measurement_frame = self.measurement_frame_in(nominal);
        let mut spec = self.to_spec();
        spec.frames[0] = nominal.frames()[0];
        spec.frames[1] = nominal.frames()[1];
        Ok((measurement_frame, Robot::new(spec)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terminal_pose;
    use crate::test_robots::stanford;
    use nalgebra::{Rotation3, Translation3};

    fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> IsometryMatrix3<f64> {
        IsometryMatrix3::from_parts(
            Translation3::new(x, y, z),
            Rotation3::from_euler_angles(roll, pitch, yaw),
        )
    }

    /// A calibrated robot: every frame moved a little, joint 1's gain and
    /// offset too.
    fn calibrated(nominal: &Robot) -> Robot {
        let mut spec = nominal.to_spec();
        for (j, frame) in spec.frames.iter_mut().enumerate() {
            let shift = 1e-3 * (j as f64 + 1.0);
            if j > 0 {
                frame.alpha += shift;
                frame.d += shift;
            }
            frame.theta -= shift;
            frame.r += 0.5 * shift;
        }
        spec.joints[0].gain = 1.001;
        spec.joints[0].offset = 0.002;
        Robot::new(spec).expect("calibrated")
    }

    fn configurations() -> Vec<Vec<f64>> {
        (0..20)
            .map(|i| {
                let t = f64::from(i);
                vec![
                    (0.7 * t).sin() * 2.0,
                    (1.3 * t).cos(),
                    0.3 + 0.1 * (0.4 * t).sin(),
                    (0.9 * t).sin() * 2.0,
                    (0.5 * t).cos(),
                    (1.7 * t).sin() * 3.0,
                ]
            })
            .collect()
    }

    #[test]
    fn the_split_gives_back_the_robot_and_keeps_its_motion() {
        let nominal = stanford();
        let real = calibrated(&nominal);
        let tracker = pose(2.5, -0.4, 0.3, 0.02, -0.01, 2.3);
        let seen = real
            .reframed(&tracker, &IsometryMatrix3::identity())
            .expect("reframed");
        let (measurement_frame, own) = seen.rebased(&nominal).expect("rebased");
        // Frames 0 and 1 are the nominal's; the others and the joints are kept.
        assert_eq!(own.frames()[0], nominal.frames()[0]);
        assert_eq!(own.frames()[1], nominal.frames()[1]);
        assert_eq!(own.frames()[2..], seen.frames()[2..]);
        assert_eq!(own.joints(), seen.joints());
        for q in configurations() {
            // The robot in its frame moves as the measured one seen from there…
            let expected = measurement_frame * terminal_pose(&seen, &q).expect("pose");
            let got = terminal_pose(&own, &q).expect("pose");
            assert!(
                (expected.to_homogeneous() - got.to_homogeneous())
                    .abs()
                    .max()
                    < 1e-12,
                "{q:?}"
            );
        }
        // …and the split does not depend on the frame it was measured in.
        let (direct_frame, direct) = real.rebased(&nominal).expect("rebased");
        assert!(
            (direct_frame * tracker.inverse() * measurement_frame.inverse())
                .to_homogeneous()
                .relative_eq(&nalgebra::Matrix4::identity(), 1e-12, 1e-12)
        );
        for q in configurations() {
            let a = terminal_pose(&direct, &q).expect("pose");
            let b = terminal_pose(&own, &q).expect("pose");
            assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-12);
        }
        // Reframing by the inverse pose gives the measured robot's motion back.
        let back = own
            .reframed(&measurement_frame.inverse(), &IsometryMatrix3::identity())
            .expect("back");
        for q in configurations() {
            let a = terminal_pose(&back, &q).expect("pose");
            let b = terminal_pose(&seen, &q).expect("pose");
            assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-12);
        }
    }

    #[test]
    fn robots_far_apart_are_not_in_the_same_frame() {
        let nominal = stanford();
        let real = calibrated(&nominal);
        assert!(nominal.same_frame_as(&real));
        let seen = real
            .reframed(
                &pose(2.5, 0.0, 0.0, 0.0, 0.0, 0.0),
                &IsometryMatrix3::identity(),
            )
            .expect("reframed");
        assert!(!nominal.same_frame_as(&seen));
        let (distance, _) = nominal.base_offset(&seen);
        assert!((distance - 2.5).abs() < 0.05, "{distance}");
        let turned = real
            .reframed(
                &pose(0.0, 0.0, 0.0, 0.0, 0.0, 0.2),
                &IsometryMatrix3::identity(),
            )
            .expect("reframed");
        assert!(!nominal.same_frame_as(&turned));
        let other = Robot::template("other", "PRPRRR").expect("template");
        assert!(seen.rebased(&other).is_err());
    }

    /// Another robot of the same joints is refused as a nominal (issue 75:
    /// a robot was written rebased onto a PUMA), naming the link that
    /// differs; a calibration of the robot itself is not.
    #[test]
    fn a_robot_is_rebased_onto_its_own_nominal_only() {
        let nominal = stanford();
        let seen = calibrated(&nominal)
            .reframed(
                &pose(2.5, 0.3, 0.0, 0.0, 0.0, 1.0),
                &IsometryMatrix3::identity(),
            )
            .expect("reframed");
        assert!(seen.rebased(&nominal).is_ok());
        let mut spec = nominal.to_spec();
        spec.frames[4].r += 0.3;
        let other = Robot::new(spec).expect("other");
        let message = seen.rebased(&other).expect_err("another robot").to_string();
        assert!(message.contains("frame 4's r differs"), "{message}");
        let other = Robot::template("other", "RRRRRR").expect("template");
        assert!(seen.rebased(&other).is_err());
    }
}
