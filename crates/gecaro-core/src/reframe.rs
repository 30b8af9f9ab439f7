//! Re-expressing a robot in another world frame and with another tool frame.
//!
//! The world (measurement) frame and the tool frame are conventions of a
//! calibration setup: the same robot can be described in any of them. This
//! module rewrites frames 0 and 1 (for a new world) and frames n and n+1 (for
//! a new tool) so that the new robot's end-effector pose is
//! `new_world_from_old_world · (old world → old tool) · old_tool_from_new_tool`
//! at every configuration.
//!
//! Why: Khalil–Kleinfinger frames place x along common normals, and when the
//! world z axis is (nearly) parallel to axis 1 — or a tool's z axis to axis n —
//! that normal is ill-defined: the table puts it far away (r0, r1 of metres
//! with opposite signs) and, exactly parallel with d1 = 0, loses a degree of
//! freedom of the base. A known tilt of the world (tool) frame, applied to the
//! measurements as well, makes the tables generic and well conditioned without
//! losing information — the reason the paper's Stanford arm has α1 = 0.1.
//!
//! Both rewrites solve the same decomposition: a rigid transform `H` given in a
//! frame whose z axis is a joint axis is written
//! `H = Rot(z, θa)·Trans(z, ra)·Rot(x, α)·Trans(x, d)·Rot(z, θb)·Trans(z, rb)`,
//! the x axis of the middle frame on the common normal of the two z axes.

use nalgebra::{IsometryMatrix3, Vector3};

use crate::kinematics::frame_transform;
use crate::robot::{Frame, FrameType, Robot};
use crate::{Error, Field};

/// The six parameters of `H = Rz(θa)·Tz(ra)·Rx(α)·Tx(d)·Rz(θb)·Tz(rb)`.
#[derive(Copy, Clone, Debug, PartialEq)]
struct SixParameters {
    theta_a: f64,
    r_a: f64,
    alpha: f64,
    d: f64,
    theta_b: f64,
    r_b: f64,
}

/// Lines closer to parallel than this (sine of their angle) are treated as parallel.
const PARALLEL: f64 = 1e-12;

fn decompose(transform: &IsometryMatrix3<f64>) -> SixParameters {
    let z_axis = Vector3::z();
    let rotation = transform.rotation.matrix();
    let z_b: Vector3<f64> = rotation.column(2).into();
    let x_b: Vector3<f64> = rotation.column(0).into();
    let origin = transform.translation.vector;
    let cross = z_axis.cross(&z_b);
    let (foot_a, normal, distance) = if cross.norm() > PARALLEL {
        // Closest points of the z axis (through 0) and of the line origin + t·z_b.
        let b = z_axis.dot(&z_b);
        let denominator = 1.0 - b * b;
        let d = -z_axis.dot(&origin);
        let e = -z_b.dot(&origin);
        let s = (b * e - d) / denominator;
        let t = (e - b * d) / denominator;
        let foot_a = z_axis * s;
        let foot_b = origin + z_b * t;
        let between = foot_b - foot_a;
        let normal = if between.norm() > 1e-15 {
            between.normalize()
        } else {
            cross.normalize()
        };
        (s, normal, between.dot(&normal))
    } else {
        // Parallel axes: the normal through the new frame's origin.
        let radial = origin - z_axis * origin.z;
        if radial.norm() > 1e-15 {
            (origin.z, radial.normalize(), radial.norm())
        } else {
            let fallback = x_b - z_axis * x_b.z;
            (
                origin.z,
                if fallback.norm() > 1e-12 {
                    fallback.normalize()
                } else {
                    Vector3::x()
                },
                0.0,
            )
        }
    };
    let theta_a = normal.y.atan2(normal.x);
    let alpha = z_axis.cross(&z_b).dot(&normal).atan2(z_axis.dot(&z_b));
    let foot_b = z_axis * foot_a + normal * distance;
    let r_b = (origin - foot_b).dot(&z_b);
    let theta_b = normal.cross(&x_b).dot(&z_b).atan2(normal.dot(&x_b));
    SixParameters {
        theta_a,
        r_a: foot_a,
        alpha,
        d: distance,
        theta_b,
        r_b,
    }
}

impl Robot {
    /// The same robot in another world frame and with another tool frame (see
    /// the module docs): `new_world_from_old_world` maps old world coordinates
    /// to new ones, `old_tool_from_new_tool` is the new tool frame in the old one.
    /// Frames 0 and 1 (and the β of frame 1) change when the world changes,
    /// frames n and n+1 (the θ or r offset of joint n) when the tool changes.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a one-joint robot when both frames change (frame 1
    /// would have to serve both), or non-finite transforms.
    pub fn reframed(
        &self,
        new_world_from_old_world: &IsometryMatrix3<f64>,
        old_tool_from_new_tool: &IsometryMatrix3<f64>,
    ) -> Result<Robot, Error> {
        let identity = IsometryMatrix3::identity();
        let world_changes = *new_world_from_old_world != identity;
        let tool_changes = *old_tool_from_new_tool != identity;
        let finite =
            |pose: &IsometryMatrix3<f64>| pose.to_homogeneous().iter().all(|v| v.is_finite());
        if !finite(new_world_from_old_world) || !finite(old_tool_from_new_tool) {
            return Err(Error::invalid(
                Field::Frames,
                "a world or tool transform is not finite",
            ));
        }
        let n = self.joint_count();
        if n == 1 && world_changes && tool_changes {
            return Err(Error::invalid(
                Field::Frames,
                "a one-joint robot cannot change both its world and its tool frame at once (frame 1 carries both)",
            ));
        }
        let mut spec = self.to_spec();
        let frames = &mut spec.frames;
        if world_changes {
            // Frame 1 at q1 = 0 in the new world: Rz(θ0)Tz(r0)·Rx(α1)Tx(d1)Rz(θ1)Tz(r1).
            let pose = new_world_from_old_world
                * frame_transform(&frames[0], 0.0)
                * frame_transform(&frames[1], 0.0);
            let six = decompose(&pose);
            frames[0].theta = six.theta_a;
            frames[0].r = six.r_a;
            frames[1] = Frame {
                frame_type: frames[1].frame_type,
                alpha: six.alpha,
                d: six.d,
                theta: six.theta_b,
                r: six.r_b,
                beta: 0.0,
            };
        }
        if tool_changes {
            // The new tool seen from frame n without its θ and r offsets.
            let joint = frames[n];
            let offsets = frame_transform(
                &Frame {
                    frame_type: FrameType::Fixed,
                    alpha: 0.0,
                    d: 0.0,
                    theta: joint.theta,
                    r: joint.r,
                    beta: 0.0,
                },
                0.0,
            );
            let pose = offsets * frame_transform(&frames[n + 1], 0.0) * old_tool_from_new_tool;
            let six = decompose(&pose);
            frames[n].theta = six.theta_a;
            frames[n].r = six.r_a;
            frames[n + 1] = Frame {
                frame_type: FrameType::Fixed,
                alpha: six.alpha,
                d: six.d,
                theta: six.theta_b,
                r: six.r_b,
                beta: 0.0,
            };
        }
        // A user's priority matrix keeps its meaning cell by cell.
        Robot::new(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::terminal_pose;
    use crate::test_robots::{random_configuration, random_robot, stanford};
    use nalgebra::{Rotation3, Translation3};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_pose(rng: &mut ChaCha8Rng) -> IsometryMatrix3<f64> {
        IsometryMatrix3::from_parts(
            Translation3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ),
            Rotation3::new(Vector3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            )),
        )
    }

    #[test]
    fn reframed_robots_have_the_transformed_end_effector_pose() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let mut robots = vec![stanford()];
        robots.extend((0..12).map(|i| random_robot(&mut rng, 2 + i % 6)));
        for robot in robots {
            let world = random_pose(&mut rng);
            let tool = random_pose(&mut rng);
            for (world, tool) in [
                (world, IsometryMatrix3::identity()),
                (IsometryMatrix3::identity(), tool),
                (world, tool),
            ] {
                let reframed = robot.reframed(&world, &tool).expect("valid");
                for _ in 0..5 {
                    let qm = random_configuration(&robot, &mut rng);
                    let expected = world * terminal_pose(&robot, &qm).expect("valid") * tool;
                    let got = terminal_pose(&reframed, &qm).expect("valid");
                    assert!(
                        (expected.to_homogeneous() - got.to_homogeneous())
                            .abs()
                            .max()
                            < 1e-12
                    );
                }
            }
        }
    }

    #[test]
    fn parallel_and_intersecting_axes_are_handled() {
        let robot = stanford();
        // A world frame whose z axis is exactly axis 1 (α1 = d1 = 0), and one
        // merely shifted along it.
        let axis_one =
            frame_transform(&robot.frames()[0], 0.0) * frame_transform(&robot.frames()[1], 0.0);
        for world in [
            axis_one.inverse(),
            Translation3::new(0.0, 0.0, 0.3) * axis_one.inverse(),
        ] {
            let reframed = robot
                .reframed(&world, &IsometryMatrix3::identity())
                .expect("valid");
            assert!(
                reframed.frames()[1].alpha.abs() < 1e-12 && reframed.frames()[1].d.abs() < 1e-12
            );
            let qm = [0.3, -0.2, 0.5, 0.1, 0.4, -0.6];
            let expected = world * terminal_pose(&robot, &qm).expect("valid");
            let got = terminal_pose(&reframed, &qm).expect("valid");
            assert!(
                (expected.to_homogeneous() - got.to_homogeneous())
                    .abs()
                    .max()
                    < 1e-12
            );
        }
    }
}
