//! Direct geometric model, eq. 1–3.
//!
//! `world_from_tool = (−1)T(0) · (0)T(1)(q1) · … · (n−1)T(n)(qn) · (n)T(n+1)`
//! with each factor given by eq. 3. Joint variables come from the motor
//! variables by eq. 4 ([`Robot::joint_positions`]).

use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Translation3, Vector3};

use super::turn;
use crate::Error;
use crate::frame::{Frame, FrameType};
use crate::robot::Robot;

/// The transform `(j−1)T(j)` of eq. 3 for a frame whose joint variable is `q`
/// (q is ignored for a fixed frame):
/// `Rot(y, β) · Rot(x, α) · Trans(x, d) · Rot(z, θ + q) · Trans(z, r)` for a
/// revolute frame, `… Rot(z, θ) · Trans(z, r + q)` for a prismatic one.
pub fn frame_transform(frame: &Frame, q: f64) -> IsometryMatrix3<f64> {
    let (theta, r) = match frame.frame_type {
        FrameType::Revolute => (frame.theta + q, frame.r),
        FrameType::Prismatic => (frame.theta, frame.r + q),
        FrameType::Fixed => (frame.theta, frame.r),
    };
    let (sin_alpha, cos_alpha) = frame.alpha.sin_cos();
    let (sin_theta, cos_theta) = turn::sin_cos(theta);
    // Rot(x, α) · Rot(z, θ), and Rot(x, α) · (d, 0, r) — eq. 2 in closed form.
    #[rustfmt::skip]
    let mut rotation = Matrix3::new(
        cos_theta,             -sin_theta,             0.0,
        cos_alpha * sin_theta, cos_alpha * cos_theta,  -sin_alpha,
        sin_alpha * sin_theta, sin_alpha * cos_theta,  cos_alpha,
    );
    let mut translation = Vector3::new(frame.d, -r * sin_alpha, r * cos_alpha);
    if frame.beta != 0.0 {
        let (sin_beta, cos_beta) = frame.beta.sin_cos();
        #[rustfmt::skip]
        let rot_y = Matrix3::new(
            cos_beta,  0.0, sin_beta,
            0.0,       1.0, 0.0,
            -sin_beta, 0.0, cos_beta,
        );
        rotation = rot_y * rotation;
        translation = rot_y * translation;
    }
    IsometryMatrix3::from_parts(
        Translation3::from(translation),
        Rotation3::from_matrix_unchecked(rotation),
    )
}

/// The world poses of all frames 0..=n+1 at one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameChain {
    world_from_frame: Vec<IsometryMatrix3<f64>>,
    joint_positions: Vec<f64>,
    /// Cm · qm, needed for the gain columns of the Jacobian.
    coupled_motor_positions: Vec<f64>,
}

impl FrameChain {
    /// `(−1)T(j)`, the pose of frame j (0..=n+1) in the world frame.
    pub fn world_from_frame(&self, frame: usize) -> &IsometryMatrix3<f64> {
        &self.world_from_frame[frame]
    }

    /// `(−1)T(n+1)`, the end-effector pose in the world frame (eq. 1).
    pub fn world_from_tool(&self) -> &IsometryMatrix3<f64> {
        self.world_from_frame
            .last()
            .expect("a frame chain always holds frames 0..=n+1")
    }

    /// All frame poses, frame 0 first.
    pub fn poses(&self) -> &[IsometryMatrix3<f64>] {
        &self.world_from_frame
    }

    /// The joint variables q of eq. 4 at this configuration.
    pub fn joint_positions(&self) -> &[f64] {
        &self.joint_positions
    }

    pub(crate) fn coupled_motor_positions(&self) -> &[f64] {
        &self.coupled_motor_positions
    }
}

/// Direct geometric model (eq. 1): the world poses of every frame at motor
/// configuration `motor_positions`.
///
/// # Errors
/// When `motor_positions` does not hold n finite values.
///
/// # Example
/// ```
/// use gecaro_core::{forward_kinematics, Frame, FrameType, Joint, Robot, RobotSpec};
/// // A one-joint arm: a revolute joint and a tool 0.5 m along x.
/// let tool = Frame { d: 0.5, ..Frame::new(FrameType::Fixed) };
/// let robot = Robot::new(RobotSpec::rigid(
///     "pendulum",
///     vec![Frame::new(FrameType::Fixed), Frame::new(FrameType::Revolute), tool],
///     vec![Joint::default_for(FrameType::Revolute)],
/// ))?;
/// let chain = forward_kinematics(&robot, &[std::f64::consts::FRAC_PI_2])?;
/// let tip = chain.world_from_tool().translation.vector;
/// assert!((tip - nalgebra::Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-15);
/// # Ok::<(), gecaro_core::Error>(())
/// ```
pub fn forward_kinematics(robot: &Robot, motor_positions: &[f64]) -> Result<FrameChain, Error> {
    let joint_positions = robot.joint_positions(motor_positions)?;
    let coupled = robot.motor_coupling() * nalgebra::DVector::from_column_slice(motor_positions);
    Ok(chain_at_joint_positions(
        robot,
        joint_positions.as_slice(),
        coupled.as_slice().to_vec(),
    ))
}

/// The frame chain at joint variables q (eq. 1–3 without eq. 4). The caller
/// guarantees n values; `coupled_motor_positions` is Cm·qm (for the gain columns).
pub(crate) fn chain_at_joint_positions(
    robot: &Robot,
    joint_positions: &[f64],
    coupled_motor_positions: Vec<f64>,
) -> FrameChain {
    let frames = robot.frames();
    let mut world_from_frame = Vec::with_capacity(frames.len());
    let mut pose = IsometryMatrix3::identity();
    for (j, frame) in frames.iter().enumerate() {
        let q = match frame.frame_type {
            FrameType::Fixed => 0.0,
            _ => joint_positions[j - 1],
        };
        pose *= frame_transform(frame, q);
        world_from_frame.push(pose);
    }
    FrameChain {
        world_from_frame,
        joint_positions: joint_positions.to_vec(),
        coupled_motor_positions,
    }
}

/// The end-effector pose `(−1)T(n+1)` at motor configuration `motor_positions` (eq. 1).
///
/// # Errors
/// When `motor_positions` does not hold n finite values.
pub fn terminal_pose(
    robot: &Robot,
    motor_positions: &[f64],
) -> Result<IsometryMatrix3<f64>, Error> {
    Ok(*forward_kinematics(robot, motor_positions)?.world_from_tool())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_robots::stanford;
    use nalgebra::{Matrix4, Vector3};

    fn rot_x(angle: f64) -> Matrix4<f64> {
        Rotation3::from_axis_angle(&Vector3::x_axis(), angle).to_homogeneous()
    }
    fn rot_y(angle: f64) -> Matrix4<f64> {
        Rotation3::from_axis_angle(&Vector3::y_axis(), angle).to_homogeneous()
    }
    fn rot_z(angle: f64) -> Matrix4<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), angle).to_homogeneous()
    }
    fn trans(x: f64, y: f64, z: f64) -> Matrix4<f64> {
        Translation3::new(x, y, z).to_homogeneous()
    }

    #[test]
    fn closed_form_equals_the_product_of_eq_3() {
        for frame_type in [FrameType::Revolute, FrameType::Prismatic, FrameType::Fixed] {
            let frame = Frame {
                frame_type,
                alpha: 0.3,
                d: 0.25,
                theta: -1.1,
                r: 0.4,
                beta: 0.07,
            };
            let q = 0.6;
            let (theta, r) = match frame_type {
                FrameType::Revolute => (frame.theta + q, frame.r),
                FrameType::Prismatic => (frame.theta, frame.r + q),
                FrameType::Fixed => (frame.theta, frame.r),
            };
            let product = rot_y(frame.beta)
                * rot_x(frame.alpha)
                * trans(frame.d, 0.0, 0.0)
                * rot_z(theta)
                * trans(0.0, 0.0, r);
            let closed = frame_transform(&frame, q).to_homogeneous();
            assert!((product - closed).abs().max() < 1e-15, "{frame_type:?}");
        }
    }

    #[test]
    fn stanford_reference_point() {
        // Hand-derived in the issue: qm = (0, 0, 0.5, 0, 0, 0).
        let pose = terminal_pose(&stanford(), &[0.0, 0.0, 0.5, 0.0, 0.0, 0.0]).expect("valid");
        let expected = Vector3::new(-0.0505392, 0.2, 1.0344655);
        assert!((pose.translation.vector - expected).norm() < 1e-6, "{pose}");
    }

    #[test]
    fn wrong_configurations_are_errors() {
        let robot = stanford();
        assert_eq!(
            terminal_pose(&robot, &[0.0; 5]),
            Err(Error::ConfigurationLength {
                expected: 6,
                found: 5
            })
        );
        assert!(matches!(
            terminal_pose(&robot, &[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]),
            Err(Error::NonFiniteConfiguration { joint: 2, .. })
        ));
    }
}
