//! Serial chains given by their joint axes at the zero configuration (the
//! form of URDF, KDL and datasheet drawings), and the Khalil–Kleinfinger
//! frames of such a chain (paper §2.1, eq. 2–3).
//!
//! An [`AxisChain`] holds, at q = 0 and in the world frame −1: the frame of
//! every joint with the joint's axis in it, and the tool frame. Its direct
//! model is the URDF one: a revolute joint turns everything after it by q_j
//! about its axis (right hand), a prismatic joint moves it by q_j along the
//! axis.
//!
//! [`AxisChain::khalil_kleinfinger_frames`] writes the same chain as frames
//! 0..n+1 of eq. 3 **with the same joint variables**: z_j is the joint axis in
//! its given sense, and the zero of q_j is kept in θ_j (revolute) or r_j
//! (prismatic). The frames are placed by the rules of [`crate::placement`]
//! (those of `shared/realdata/tools`, so the real-data tables come out
//! unchanged):
//!
//! - z_0 is the world z axis and the origin of frame 0 lies on it (frame 0
//!   carries only θ0 and r0): "axis 0" is the world z axis. Facing a parallel
//!   axis 1, frame 0 sits at the height of the given base link.
//! - Frame j faces the next axis (axis j+1, or the tool's z axis for j = n):
//!   on their common normal, or — parallel or nearly so — with Hayati's β, its
//!   origin where the x axis of frame j−1 meets axis j (r_j = 0), or for the
//!   last joint at the given origin of joint n.
//! - The free sense of each x_j follows the x (else y) axis of the given joint
//!   frame, frame 0's that of the base link.
//! - Values within 1e-14 of zero, of a multiple of π/2 or of a number with ten
//!   decimals are written as such (the table of a URDF reads like its drawing).
//!
//! Frames are placed at the zero configuration, lengths in metres, angles in
//! radians. Errors: a chain without joints, a non-finite pose, or an axis that
//! is not of unit length.

use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Unit, Vector3};

use crate::frame::{Frame, FrameType};
use crate::kinematics::frame_transform;
use crate::placement::{
    Line, Placed, decompose, nearly_parallel, place_facing, tidy, tidy_angle, turned_x, z_axis_of,
};
use crate::{Error, Field};

/// One joint of an [`AxisChain`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ChainJoint {
    /// Revolute or prismatic ([`FrameType::Fixed`] is refused).
    pub frame_type: FrameType,
    /// The joint's frame at q = 0, in the world frame; its origin is on the axis.
    pub world_from_joint: IsometryMatrix3<f64>,
    /// The joint axis (positive sense of q) in the joint's frame.
    pub axis: Unit<Vector3<f64>>,
}

impl ChainJoint {
    /// The axis in the world frame.
    fn world_axis(&self) -> Unit<Vector3<f64>> {
        Unit::new_normalize(self.world_from_joint.rotation * self.axis.into_inner())
    }

    /// The joint's motion by `q`, in its own frame.
    fn motion(&self, q: f64) -> IsometryMatrix3<f64> {
        match self.frame_type {
            FrameType::Prismatic => IsometryMatrix3::from_parts(
                Translation3::from(self.axis.into_inner() * q),
                Rotation3::identity(),
            ),
            _ => IsometryMatrix3::from_parts(
                Translation3::identity(),
                Rotation3::from_axis_angle(&self.axis, q),
            ),
        }
    }
}

/// A serial chain given by its joints at q = 0 (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct AxisChain {
    /// The frame of the link that carries joint 1, in the world frame: it
    /// orients x_0 and, when the world z axis is parallel to axis 1, places
    /// frame 0 at its height. Identity when the world is that link.
    pub world_from_base_link: IsometryMatrix3<f64>,
    /// Joints 1..n in order.
    pub joints: Vec<ChainJoint>,
    /// The tool frame (frame n+1) at q = 0, in the world frame.
    pub world_from_tool: IsometryMatrix3<f64>,
}

impl AxisChain {
    /// The tool pose `world_from_tool` at joint variables `joint_positions`
    /// (the URDF direct model).
    ///
    /// # Errors
    /// [`Error::ConfigurationLength`] when the count does not match.
    pub fn forward(&self, joint_positions: &[f64]) -> Result<IsometryMatrix3<f64>, Error> {
        if joint_positions.len() != self.joints.len() {
            return Err(Error::ConfigurationLength {
                expected: self.joints.len(),
                found: joint_positions.len(),
            });
        }
        let mut pose = IsometryMatrix3::identity();
        let mut previous = IsometryMatrix3::identity();
        for (joint, q) in self.joints.iter().zip(joint_positions) {
            pose = pose * previous.inverse() * joint.world_from_joint * joint.motion(*q);
            previous = joint.world_from_joint;
        }
        Ok(pose * previous.inverse() * self.world_from_tool)
    }

    /// The Khalil–Kleinfinger frames 0..n+1 of this chain (see the module
    /// docs for the placement rules); q_j of the chain is q_j of the frames.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a chain without joints, a fixed joint, or a pose
    /// or axis that is not finite.
    ///
    /// # Example
    /// A planar two-link arm drawn URDF-style, axes along y:
    /// ```
    /// use gecaro_core::{AxisChain, ChainJoint, FrameType};
    /// use nalgebra::{IsometryMatrix3, Translation3, Vector3};
    /// let at = |x: f64| IsometryMatrix3::from_parts(
    ///     Translation3::new(x, 0.0, 0.5), nalgebra::Rotation3::identity());
    /// let joint = |x: f64| ChainJoint {
    ///     frame_type: FrameType::Revolute,
    ///     world_from_joint: at(x),
    ///     axis: Vector3::y_axis(),
    /// };
    /// let chain = AxisChain {
    ///     world_from_base_link: IsometryMatrix3::identity(),
    ///     joints: vec![joint(0.0), joint(0.4)],
    ///     world_from_tool: at(0.7),
    /// };
    /// let frames = chain.khalil_kleinfinger_frames()?;
    /// // The two parallel axes are 0.4 m apart: d2 = 0.4, β2 = 0.
    /// assert_eq!((frames[2].d, frames[2].beta), (0.4, 0.0));
    /// # Ok::<(), gecaro_core::Error>(())
    /// ```
    pub fn khalil_kleinfinger_frames(&self) -> Result<Vec<Frame>, Error> {
        self.check()?;
        let n = self.joints.len();
        let lines: Vec<Line> = self
            .joints
            .iter()
            .map(|joint| Line {
                point: joint.world_from_joint.translation.vector,
                direction: joint.world_axis(),
            })
            .chain(std::iter::once(Line {
                point: self.world_from_tool.translation.vector,
                direction: z_axis_of(&self.world_from_tool),
            }))
            .collect();
        let base = &self.world_from_base_link;
        // Frame 0 on the world z axis, facing axis 1; when they are parallel,
        // at the height of the base link.
        let mut placed = vec![place_facing(
            &Line {
                point: Vector3::zeros(),
                direction: Vector3::z_axis(),
            },
            &lines[0],
            || Vector3::z() * base.translation.vector.z,
            &[base.rotation * Vector3::x(), base.rotation * Vector3::y()],
        )];
        for (j, joint) in self.joints.iter().enumerate() {
            let previous = placed[j];
            let line = &lines[j];
            // Facing a (nearly) parallel axis, the last joint keeps its given
            // origin (the tool's r stays short); the others take r_j = 0: where
            // the (turned) x axis of frame j−1 meets axis j.
            let parallel_origin = || {
                if j + 1 == n {
                    line.point
                } else {
                    line.closest_point_to(&Line {
                        point: previous.origin,
                        direction: turned_x(&previous, &line.direction),
                    })
                }
            };
            let rotation = joint.world_from_joint.rotation;
            placed.push(place_facing(
                line,
                &lines[j + 1],
                parallel_origin,
                &[rotation * Vector3::x(), rotation * Vector3::y()],
            ));
        }
        let mut poses: Vec<IsometryMatrix3<f64>> = placed.iter().map(Placed::pose).collect();
        poses.push(self.world_from_tool);
        let x0 = placed[0].x;
        let mut frames = vec![Frame {
            theta: tidy_angle(x0.y.atan2(x0.x)),
            r: tidy(placed[0].origin.z),
            ..Frame::new(FrameType::Fixed)
        }];
        for j in 1..=n + 1 {
            let frame_type = self
                .joints
                .get(j - 1)
                .map_or(FrameType::Fixed, |joint| joint.frame_type);
            let hayati = nearly_parallel(&z_axis_of(&poses[j - 1]), &z_axis_of(&poses[j]));
            let relative = poses[j - 1].inverse() * poses[j];
            let frame = decompose(&relative, frame_type, hayati);
            let error = (frame_transform(&frame, 0.0).to_homogeneous() - relative.to_homogeneous())
                .abs()
                .max();
            if error.is_nan() || error >= 1e-9 {
                return Err(Error::invalid(
                    Field::Frame {
                        index: j,
                        key: "alpha",
                    },
                    format!(
                        "frame {j} could not be placed on frame {} (mismatch {error:.1e}); \
                         the chain is degenerate",
                        j - 1
                    ),
                ));
            }
            frames.push(frame);
        }
        Ok(frames)
    }

    fn check(&self) -> Result<(), Error> {
        if self.joints.is_empty() {
            return Err(Error::invalid(
                Field::Frames,
                "the chain has no revolute or prismatic joint",
            ));
        }
        let finite =
            |pose: &IsometryMatrix3<f64>| pose.to_homogeneous().iter().all(|v| v.is_finite());
        if !finite(&self.world_from_base_link) || !finite(&self.world_from_tool) {
            return Err(Error::invalid(
                Field::Frames,
                "the base or tool pose is not finite",
            ));
        }
        for (index, joint) in self.joints.iter().enumerate() {
            let field = |key| Field::Frame {
                index: index + 1,
                key,
            };
            if joint.frame_type == FrameType::Fixed {
                return Err(Error::invalid(
                    field("sigma"),
                    "a chain joint is revolute or prismatic, not fixed",
                ));
            }
            if !finite(&joint.world_from_joint) {
                return Err(Error::invalid(
                    field("theta"),
                    "the joint pose is not finite",
                ));
            }
            if !joint.axis.iter().all(|v| v.is_finite()) || (joint.axis.norm() - 1.0).abs() > 1e-9 {
                return Err(Error::invalid(
                    field("theta"),
                    "the joint axis is not a unit vector",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NEARLY_PARALLEL_DEGREES;
    use crate::frame::Joint;
    use crate::kinematics::{forward_kinematics, terminal_pose};
    use crate::robot::{Robot, RobotSpec};
    use crate::test_robots::stanford;
    use rand::{Rng, RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn unit(rng: &mut impl Rng) -> Unit<Vector3<f64>> {
        loop {
            let v = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            if let Some(unit) = Unit::try_new(v, 0.1) {
                return unit;
            }
        }
    }

    fn rotation(rng: &mut impl Rng) -> Rotation3<f64> {
        Rotation3::from_scaled_axis(unit(rng).into_inner() * rng.random_range(-3.0..3.0))
    }

    fn point(rng: &mut impl Rng) -> Vector3<f64> {
        Vector3::new(
            rng.random_range(-0.6..0.6),
            rng.random_range(-0.6..0.6),
            rng.random_range(-0.6..0.6),
        )
    }

    /// A world direction for the next axis: related to `previous` in one of
    /// the ways real chains are (parallel, nearly, perpendicular, antiparallel) or not.
    fn next_direction(rng: &mut impl Rng, previous: &Unit<Vector3<f64>>) -> Unit<Vector3<f64>> {
        let tilt = |rng: &mut ChaCha8Rng, angle: f64| {
            let axis = Unit::new_normalize(previous.cross(&unit(rng)));
            Rotation3::from_axis_angle(&axis, angle) * *previous
        };
        let mut rng = ChaCha8Rng::seed_from_u64(rng.random());
        match rng.random_range(0..6) {
            0 => *previous,
            1 => -*previous,
            2 => {
                let angle = 10f64.powf(rng.random_range(-9.0..-1.0));
                tilt(&mut rng, angle)
            }
            3 => tilt(&mut rng, std::f64::consts::FRAC_PI_2),
            _ => unit(&mut rng),
        }
    }

    /// A joint frame whose axis (in its own frame) is `world_axis`.
    fn joint_with_axis(
        rng: &mut impl Rng,
        frame_type: FrameType,
        origin: Vector3<f64>,
        world_axis: Unit<Vector3<f64>>,
    ) -> ChainJoint {
        let rotation = rotation(rng);
        ChainJoint {
            frame_type,
            world_from_joint: IsometryMatrix3::from_parts(Translation3::from(origin), rotation),
            axis: Unit::new_normalize(rotation.inverse() * world_axis.into_inner()),
        }
    }

    fn random_chain(rng: &mut ChaCha8Rng, n: usize) -> AxisChain {
        let mut joints = Vec::new();
        let mut direction = if rng.random_bool(0.4) {
            Vector3::z_axis()
        } else {
            unit(rng)
        };
        let mut origin = point(rng);
        for _ in 0..n {
            let frame_type = if rng.random_bool(0.2) {
                FrameType::Prismatic
            } else {
                FrameType::Revolute
            };
            joints.push(joint_with_axis(rng, frame_type, origin, direction));
            direction = next_direction(rng, &direction);
            origin = match rng.random_range(0..4) {
                0 => origin,                                // intersecting
                1 => origin + direction.into_inner() * 0.3, // same point further on
                _ => point(rng),
            };
        }
        let tool_rotation = if rng.random_bool(0.5) {
            // Tool z along (or nearly along) the last axis, as flanges and balls are.
            let z = next_direction(rng, &joints[n - 1].world_axis());
            Rotation3::rotation_between(&Vector3::z(), &z).unwrap_or_else(Rotation3::identity)
                * Rotation3::from_axis_angle(&Vector3::z_axis(), rng.random_range(-3.0..3.0))
        } else {
            rotation(rng)
        };
        AxisChain {
            world_from_base_link: if rng.random_bool(0.5) {
                IsometryMatrix3::identity()
            } else {
                IsometryMatrix3::from_parts(Translation3::from(point(rng)), rotation(rng))
            },
            joints,
            world_from_tool: IsometryMatrix3::from_parts(Translation3::from(origin), tool_rotation),
        }
    }

    fn robot_of(chain: &AxisChain) -> Robot {
        let frames = chain.khalil_kleinfinger_frames().expect("placeable");
        let joints = chain
            .joints
            .iter()
            .map(|joint| Joint {
                qmin: -4.0,
                qmax: 4.0,
                ..Joint::default_for(joint.frame_type)
            })
            .collect();
        Robot::new(RobotSpec::rigid("chain", frames, joints)).expect("valid")
    }

    fn distance(a: &IsometryMatrix3<f64>, b: &IsometryMatrix3<f64>) -> f64 {
        (a.to_homogeneous() - b.to_homogeneous()).abs().max()
    }

    #[test]
    fn the_frames_have_the_chain_s_direct_model_with_the_same_joint_variables() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for trial in 0..400 {
            let chain = random_chain(&mut rng, 1 + trial % 8);
            let robot = robot_of(&chain);
            for _ in 0..10 {
                let q: Vec<f64> = chain
                    .joints
                    .iter()
                    .map(|joint| match joint.frame_type {
                        FrameType::Prismatic => rng.random_range(-0.5..0.5),
                        _ => rng.random_range(-3.2..3.2),
                    })
                    .collect();
                let expected = chain.forward(&q).expect("n values");
                let got = terminal_pose(&robot, &q).expect("valid");
                assert!(
                    distance(&expected, &got) < 1e-12,
                    "trial {trial}: {}",
                    distance(&expected, &got)
                );
            }
        }
    }

    #[test]
    fn nearly_parallel_axes_take_beta_and_no_length_runs_away() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let sine = NEARLY_PARALLEL_DEGREES.to_radians().sin();
        for trial in 0..400 {
            let chain = random_chain(&mut rng, 1 + trial % 8);
            let frames = chain.khalil_kleinfinger_frames().expect("placeable");
            let poses = forward_kinematics(&robot_of(&chain), &vec![0.0; chain.joints.len()])
                .expect("valid")
                .poses()
                .to_vec();
            // Everything given lies within 1.1 m of the origin; a common normal
            // lies at most 1/sin(10°) times the distance between two axes away.
            let bound = 2.2 / sine + 2.2;
            for (j, frame) in frames.iter().enumerate().skip(1) {
                let parallel = poses[j - 1]
                    .rotation
                    .matrix()
                    .column(2)
                    .cross(&poses[j].rotation.matrix().column(2))
                    .norm()
                    < sine;
                if !parallel {
                    assert_eq!(frame.beta, 0.0, "trial {trial}, frame {j}: {frame:?}");
                }
                assert!(
                    frame.d.abs() < bound && frame.r.abs() < bound,
                    "trial {trial}, frame {j}: {frame:?}"
                );
                // Nearly parallel axes: d is of the order of the distance between them
                // (r_j is where the next common normal meets axis j).
                if parallel {
                    assert!(frame.d.abs() < 2.5, "trial {trial}, frame {j}: {frame:?}");
                }
            }
        }
    }

    #[test]
    fn the_stanford_arm_drawn_as_a_chain_gives_back_table_1() {
        let robot = stanford();
        let chain_poses = forward_kinematics(&robot, &[0.0; 6]).expect("valid");
        let poses = chain_poses.poses();
        let chain = AxisChain {
            world_from_base_link: poses[0],
            joints: (1..=6)
                .map(|j| ChainJoint {
                    frame_type: robot.frames()[j].frame_type,
                    world_from_joint: poses[j],
                    axis: Vector3::z_axis(),
                })
                .collect(),
            world_from_tool: poses[7],
        };
        let frames = chain.khalil_kleinfinger_frames().expect("placeable");
        for (j, (got, expected)) in frames.iter().zip(robot.frames()).enumerate() {
            for (name, a, b) in [
                ("alpha", got.alpha, expected.alpha),
                ("d", got.d, expected.d),
                ("theta", got.theta, expected.theta),
                ("r", got.r, expected.r),
                ("beta", got.beta, expected.beta),
            ] {
                assert!((a - b).abs() < 1e-12, "frame {j}, {name}: {a} against {b}");
            }
            assert_eq!(got.frame_type, expected.frame_type);
        }
    }

    #[test]
    fn exactly_parallel_axes_keep_beta_zero_and_tilted_ones_carry_it() {
        let at = |x: f64, axis: Unit<Vector3<f64>>| ChainJoint {
            frame_type: FrameType::Revolute,
            world_from_joint: IsometryMatrix3::from_parts(
                Translation3::new(x, 0.0, 0.4),
                Rotation3::identity(),
            ),
            axis,
        };
        let tilted = Unit::new_normalize(Vector3::new(1e-4, 1.0, 2e-4));
        for (second, beta_is_zero) in [(Vector3::y_axis(), true), (tilted, false)] {
            let chain = AxisChain {
                world_from_base_link: IsometryMatrix3::identity(),
                joints: vec![
                    at(0.0, Vector3::y_axis()),
                    at(0.6, second),
                    at(1.0, Vector3::z_axis()),
                ],
                world_from_tool: IsometryMatrix3::translation(1.0, 0.0, 0.6),
            };
            let frames = chain.khalil_kleinfinger_frames().expect("placeable");
            assert_eq!(frames[2].beta == 0.0, beta_is_zero, "{frames:?}");
            assert!((frames[2].d.abs() - 0.6).abs() < 1e-3, "{frames:?}");
            assert!(frames[2].r.abs() < 1e-3, "{frames:?}");
        }
    }

    #[test]
    fn degenerate_chains_are_errors() {
        let empty = AxisChain {
            world_from_base_link: IsometryMatrix3::identity(),
            joints: Vec::new(),
            world_from_tool: IsometryMatrix3::identity(),
        };
        assert!(empty.khalil_kleinfinger_frames().is_err());
        let mut chain = AxisChain {
            joints: vec![ChainJoint {
                frame_type: FrameType::Revolute,
                world_from_joint: IsometryMatrix3::identity(),
                axis: Unit::new_unchecked(Vector3::new(f64::NAN, 0.0, 1.0)),
            }],
            ..empty
        };
        assert!(chain.khalil_kleinfinger_frames().is_err());
        chain.joints[0].axis = Vector3::z_axis();
        chain.world_from_tool.translation.vector.x = f64::INFINITY;
        assert!(chain.khalil_kleinfinger_frames().is_err());
    }
}
