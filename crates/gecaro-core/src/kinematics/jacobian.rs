//! Jacobian of the end-effector frame n+1 with respect to the geometric
//! parameters and the gains, Appendix II (eq. 26–27).
//!
//! Columns are in the order of the [`ParameterSpace`](crate::ParameterSpace);
//! rows 0–2 are the position of the origin of frame n+1, rows 3–5 the small
//! rotation, all in the world frame. With `s, n, a` the x, y, z axes and `P`
//! the origin of a frame in the world, and `L(j, n+1) = P(n+1) − P(j)`:
//!
//! | parameter | position rows | rotation rows |
//! |---|---|---|
//! | α_j | `x'(j−1) × L(j−1, n+1)` | `x'(j−1)` |
//! | d_j | `x'(j−1)` | 0 |
//! | θ_j | `a(j) × L(j, n+1)` | `a(j)` |
//! | r_j | `a(j)` | 0 |
//! | β_j | `n(j−1) × L(j−1, n+1)` | `n(j−1)` |
//! | K_j | `Σ_i j_{q_i} · ∂q_i/∂K_j` | |
//!
//! where `x'(j−1) = cos β_j · s(j−1) − sin β_j · a(j−1)` is the x axis of frame
//! j−1 after the Hayati rotation Rot(y, β_j) of eq. 3. The paper prints
//! `s(j−1)`, which is right only while β_j = 0 (NOTES.md). `j_{q_i}` is the θ_i
//! column of a revolute joint or the r_i column of a prismatic one, and from
//! eq. 4, `∂q_i/∂K_j = Cj(i, j) · (Cm·qm)_j`. Frame −1 (the world) is the
//! identity, so θ0 and r0 act about and along the world z axis.

use nalgebra::{Matrix6xX, Vector3};

use super::direct::{FrameChain, forward_kinematics};
use crate::Error;
use crate::frame::FrameType;
use crate::parameters::{ParameterId, ParameterKind};
use crate::robot::Robot;

/// The 6×Np parameter Jacobian of eq. 7 at motor configuration `motor_positions`.
///
/// # Errors
/// When `motor_positions` does not hold n finite values.
pub fn parameter_jacobian(robot: &Robot, motor_positions: &[f64]) -> Result<Matrix6xX<f64>, Error> {
    let chain = forward_kinematics(robot, motor_positions)?;
    let mut jacobian = Matrix6xX::zeros(robot.parameters().len());
    parameter_jacobian_of_chain(robot, &chain, &mut jacobian);
    Ok(jacobian)
}

/// Fills `jacobian` (resized to 6×Np) with the parameter Jacobian at the
/// configuration of `chain`, which must come from [`forward_kinematics`] on
/// the same robot. This is the allocation-free form for tight loops.
pub fn parameter_jacobian_of_chain(
    robot: &Robot,
    chain: &FrameChain,
    jacobian: &mut Matrix6xX<f64>,
) {
    let parameters = robot.parameters();
    if jacobian.ncols() != parameters.len() {
        *jacobian = Matrix6xX::zeros(parameters.len());
    }
    let tool = chain.world_from_tool().translation.vector;
    let mut set =
        |kind: ParameterKind, frame: usize, position: Vector3<f64>, rotation: Vector3<f64>| {
            if let Some(index) = parameters.index_of(ParameterId::new(kind, frame)) {
                let mut column = jacobian.column_mut(index);
                column.fixed_rows_mut::<3>(0).copy_from(&position);
                column.fixed_rows_mut::<3>(3).copy_from(&rotation);
            }
        };
    let zero = Vector3::zeros();
    for (j, frame) in robot.frames().iter().enumerate() {
        let pose = chain.world_from_frame(j);
        let z_axis: Vector3<f64> = pose.rotation.matrix().column(2).into();
        let lever = tool - pose.translation.vector;
        set(ParameterKind::Theta, j, z_axis.cross(&lever), z_axis);
        set(ParameterKind::R, j, z_axis, zero);
        if j == 0 {
            continue;
        }
        let previous = chain.world_from_frame(j - 1);
        let axes = previous.rotation.matrix();
        let (x_previous, y_previous, z_previous): (Vector3<f64>, Vector3<f64>, Vector3<f64>) = (
            axes.column(0).into(),
            axes.column(1).into(),
            axes.column(2).into(),
        );
        let lever_previous = tool - previous.translation.vector;
        let (sin_beta, cos_beta) = frame.beta.sin_cos();
        let x_rotated = x_previous * cos_beta - z_previous * sin_beta;
        set(
            ParameterKind::Alpha,
            j,
            x_rotated.cross(&lever_previous),
            x_rotated,
        );
        set(ParameterKind::D, j, x_rotated, zero);
        set(
            ParameterKind::Beta,
            j,
            y_previous.cross(&lever_previous),
            y_previous,
        );
    }
    fill_gain_columns(robot, chain, jacobian);
}

/// The gain columns `j_{K_j} = Σ_i j_{q_i} Cj(i, j) (Cm·qm)_j`, from the joint columns already in place.
fn fill_gain_columns(robot: &Robot, chain: &FrameChain, jacobian: &mut Matrix6xX<f64>) {
    let parameters = robot.parameters();
    let n = robot.joint_count();
    let coupled = chain.coupled_motor_positions();
    let joint_columns: Vec<usize> = (1..=n).map(|i| joint_parameter_index(robot, i)).collect();
    for joint in 1..=n {
        let Some(gain_index) = parameters.index_of(ParameterId::new(ParameterKind::Gain, joint))
        else {
            continue;
        };
        let mut column = nalgebra::Vector6::zeros();
        for (i, &joint_column) in joint_columns.iter().enumerate() {
            let weight = robot.joint_coupling()[(i, joint - 1)] * coupled[joint - 1];
            if weight != 0.0 {
                column += jacobian.column(joint_column) * weight;
            }
        }
        jacobian.set_column(gain_index, &column);
    }
}

/// Index in η of the parameter the variable of joint `joint` adds to (θ or r).
fn joint_parameter_index(robot: &Robot, joint: usize) -> usize {
    let kind = match robot.frames()[joint].frame_type {
        FrameType::Prismatic => ParameterKind::R,
        _ => ParameterKind::Theta,
    };
    robot
        .parameters()
        .index_of(ParameterId::new(kind, joint))
        .expect("every joint frame has θ and r")
}

/// The 6×n Jacobian of frame n+1 with respect to the joint variables q
/// (not the motor variables): column i is `j_{q_i}`.
pub fn joint_jacobian(robot: &Robot, chain: &FrameChain) -> Matrix6xX<f64> {
    let n = robot.joint_count();
    let tool = chain.world_from_tool().translation.vector;
    let mut jacobian = Matrix6xX::zeros(n);
    for joint in 1..=n {
        let pose = chain.world_from_frame(joint);
        let z_axis: Vector3<f64> = pose.rotation.matrix().column(2).into();
        let mut column = jacobian.column_mut(joint - 1);
        match robot.frames()[joint].frame_type {
            FrameType::Prismatic => column.fixed_rows_mut::<3>(0).copy_from(&z_axis),
            _ => {
                let lever = tool - pose.translation.vector;
                column
                    .fixed_rows_mut::<3>(0)
                    .copy_from(&z_axis.cross(&lever));
                column.fixed_rows_mut::<3>(3).copy_from(&z_axis);
            }
        }
    }
    jacobian
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::{OrientationDifference, pose_difference, terminal_pose};
    use crate::test_robots::{random_configuration, random_robot};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Central difference of the terminal pose with respect to parameter `index`.
    fn finite_difference_column(
        robot: &Robot,
        qm: &[f64],
        index: usize,
        step: f64,
    ) -> nalgebra::Vector6<f64> {
        let id = robot.parameters().id(index);
        let value = robot.parameter(id);
        let mut plus = robot.clone();
        plus.set_parameter(id, value + step).expect("finite");
        let mut minus = robot.clone();
        minus.set_parameter(id, value - step).expect("finite");
        let pose_plus = terminal_pose(&plus, qm).expect("valid");
        let pose_minus = terminal_pose(&minus, qm).expect("valid");
        pose_difference(&pose_plus, &pose_minus, OrientationDifference::AxisAngle) / (2.0 * step)
    }

    #[test]
    fn every_column_matches_central_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for trial in 0..40 {
            let robot = random_robot(&mut rng, 2 + trial % 6);
            let qm = random_configuration(&robot, &mut rng);
            let jacobian = parameter_jacobian(&robot, &qm).expect("valid");
            for index in 0..robot.parameters().len() {
                let numeric = finite_difference_column(&robot, &qm, index, 1e-6);
                let analytic = jacobian.column(index);
                let error = (analytic - numeric).norm();
                assert!(
                    error < 1e-7 * (1.0 + numeric.norm()),
                    "trial {trial}, {} ({}): analytic {analytic:?} numeric {numeric:?}",
                    robot.parameters().id(index),
                    robot.joint_letters()
                );
            }
        }
    }

    #[test]
    fn small_parameter_change_is_a_small_rotation() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..20 {
            let robot = random_robot(&mut rng, 6);
            let qm = random_configuration(&robot, &mut rng);
            let jacobian = parameter_jacobian(&robot, &qm).expect("valid");
            let deltas: Vec<f64> = (0..robot.parameters().len())
                .map(|i| 1e-7 * ((i as f64 * 1.7).sin()))
                .collect();
            let mut moved = robot.clone();
            moved.apply_deltas(&deltas).expect("finite");
            let before = terminal_pose(&robot, &qm).expect("valid");
            let after = terminal_pose(&moved, &qm).expect("valid");
            let actual = pose_difference(&after, &before, OrientationDifference::AxisAngle);
            let predicted = &jacobian * nalgebra::DVector::from_vec(deltas);
            // First order: the remainder is O(|Δη|²) ≈ 1e-13.
            assert!(
                (actual - predicted).norm() < 1e-11,
                "{actual} vs {predicted}"
            );
        }
    }

    #[test]
    fn joint_jacobian_matches_the_parameter_columns_of_the_joints() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let robot = random_robot(&mut rng, 6);
        let qm = random_configuration(&robot, &mut rng);
        let chain = forward_kinematics(&robot, &qm).expect("valid");
        let joints = joint_jacobian(&robot, &chain);
        let parameters = parameter_jacobian(&robot, &qm).expect("valid");
        for joint in 1..=6 {
            let index = joint_parameter_index(&robot, joint);
            assert_eq!(joints.column(joint - 1), parameters.column(index));
        }
    }
}
