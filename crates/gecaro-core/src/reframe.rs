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
//! Both rewrites keep every other frame and place the rewritten ones by the
//! rules of [`crate::placement`]: frame 0 (on the new world z axis) and frame
//! n (on axis n) face the next axis on their common normal, or with Hayati's
//! β when it is parallel or nearly so — never with a common normal far away;
//! x points from the axis towards the next one (d ≥ 0).

use nalgebra::{IsometryMatrix3, Vector3};

use crate::frame::{Frame, FrameType};
use crate::kinematics::frame_transform;
use crate::placement::{Line, decompose, nearly_parallel, place_facing, z_axis_of};
use crate::robot::Robot;
use crate::{Error, Field};

/// The world poses of `frames` at q = 0.
fn poses_at_zero(frames: &[Frame]) -> Vec<IsometryMatrix3<f64>> {
    frames
        .iter()
        .scan(IsometryMatrix3::identity(), |pose, frame| {
            *pose *= frame_transform(frame, 0.0);
            Some(*pose)
        })
        .collect()
}

/// Preferred senses of the x axis of a frame on `line` facing `next`: from
/// `line` towards `next` (so that d ≥ 0), else along z × z_next, else (the
/// axes coincide) the frame's old x.
fn towards(line: &Line, next: &Line, old_x: Vector3<f64>) -> [Vector3<f64>; 3] {
    let between = if nearly_parallel(&line.direction, &next.direction) {
        let offset = next.point - line.point;
        offset - line.direction.into_inner() * line.direction.dot(&offset)
    } else {
        next.closest_point_to(line) - line.closest_point_to(next)
    };
    [between, line.direction.cross(&next.direction), old_x]
}

fn line_of(pose: &IsometryMatrix3<f64>) -> Line {
    Line {
        point: pose.translation.vector,
        direction: z_axis_of(pose),
    }
}

impl Robot {
    /// The same robot in another world frame and with another tool frame (see
    /// the module docs): `new_world_from_old_world` maps old world coordinates
    /// to new ones, `old_tool_from_new_tool` is the new tool frame in the old one.
    /// Frames 0 and 1 change when the world changes, frames n and n+1 (the θ
    /// and r of joint n) when the tool changes.
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
            let old = poses_at_zero(frames);
            let frame_one = new_world_from_old_world * old[1];
            let axis_one = line_of(&frame_one);
            let world_z = Line {
                point: Vector3::zeros(),
                direction: Vector3::z_axis(),
            };
            let frame_zero = place_facing(
                &world_z,
                &axis_one,
                || Vector3::z() * frame_one.translation.vector.z,
                &towards(
                    &world_z,
                    &axis_one,
                    new_world_from_old_world.rotation * (old[0].rotation * Vector3::x()),
                ),
            );
            frames[0] = Frame {
                theta: frame_zero.x.y.atan2(frame_zero.x.x),
                r: frame_zero.origin.z,
                ..Frame::new(FrameType::Fixed)
            };
            frames[1] = decompose(
                &(frame_zero.pose().inverse() * frame_one),
                frames[1].frame_type,
                nearly_parallel(&world_z.direction, &axis_one.direction),
            );
        }
        if tool_changes {
            let poses = poses_at_zero(frames);
            let (frame_n, tool) = (poses[n], poses[n + 1] * old_tool_from_new_tool);
            let axis_n = line_of(&frame_n);
            let old_x = frame_n.rotation * Vector3::x();
            let placed = place_facing(
                &axis_n,
                &line_of(&tool),
                || frame_n.translation.vector,
                &towards(&axis_n, &line_of(&tool), old_x),
            );
            // Frame n turns about and slides along its own z axis: only θ_n, r_n change.
            let turn = old_x
                .cross(&placed.x)
                .dot(&axis_n.direction)
                .atan2(old_x.dot(&placed.x));
            let theta = frames[n].theta + turn;
            frames[n].theta = theta.sin().atan2(theta.cos());
            frames[n].r += (placed.origin - axis_n.point).dot(&axis_n.direction);
            frames[n + 1] = decompose(
                &(placed.pose().inverse() * tool),
                FrameType::Fixed,
                nearly_parallel(&axis_n.direction, &z_axis_of(&tool)),
            );
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

    #[test]
    fn nearly_parallel_world_and_tool_frames_take_beta_not_a_far_normal() {
        let robot = stanford();
        let poses = poses_at_zero(robot.frames());
        // A world whose z axis is 1e-4 rad from axis 1, and a tool whose z is
        // 2e-4 rad from axis 6, both well off the axes.
        let tilt = |angle: f64| {
            IsometryMatrix3::from_parts(
                nalgebra::Translation3::new(0.2, -0.1, 0.05),
                nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), angle),
            )
        };
        let world = tilt(1e-4) * poses[1].inverse();
        let tool = poses[7].inverse() * poses[6] * tilt(2e-4);
        let reframed = robot.reframed(&world, &tool).expect("valid");
        for frame in reframed.frames() {
            assert!(frame.d.abs() < 1.0 && frame.r.abs() < 1.0, "{frame:?}");
        }
        assert!(reframed.frames()[1].beta != 0.0 && reframed.frames()[7].beta != 0.0);
        for qm in [
            [0.3, -0.2, 0.5, 0.1, 0.4, -0.6],
            [1.0, 0.5, 0.2, -2.0, 1.1, 0.7],
        ] {
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
