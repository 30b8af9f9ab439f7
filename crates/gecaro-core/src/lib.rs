//! # gecaro-core
//!
//! The robot model and the kinematic models of GECARO (Khalil et al.), on
//! which every calibration method of gecaro is built.
//!
//! - [`Robot`]: n joints, frames 0..=n+1 in Khalil–Kleinfinger parameters
//!   (σ, α, d, θ, r) with Hayati's β for parallel axes (eq. 2–3), joint limits,
//!   offsets, transmission gains K and the coupling matrices Cm, Cj of eq. 4.
//! - [`ParameterSpace`]: the parameter vector η and its names
//!   (`theta0 r0 alpha1 d1 theta1 r1 beta1 … K1 … Kn`).
//! - [`PriorityMatrix`]: the (n+2)×6 priority matrix and the default rules of §4.
//! - [`AxisChain`]: a chain given by its joint axes at q = 0 (URDF's form) and
//!   its Khalil–Kleinfinger frames, with Hayati's β for (nearly) parallel axes.
//! - Kinematics: [`forward_kinematics`] (eq. 1), [`pose_difference`]
//!   (Appendix I), [`parameter_jacobian`] (Appendix II) and the numerical
//!   [`inverse_kinematics`]; [`turn`], the sine and cosine of a frame's
//!   turn that every route of the direct model shares.
//!
//! Units: metres and radians throughout; gains are dimensionless. Every
//! vector is expressed in the world frame −1; 6-vectors are `[position; rotation]`.
//!
//! ## Example
//!
//! The Stanford arm of the paper's Table 1, its end-effector at one
//! configuration, and the 6×43 Jacobian of eq. 7:
//!
//! ```
//! use std::f64::consts::FRAC_PI_2;
//! use gecaro_core::{
//!     Frame, FrameType, Joint, Robot, RobotSpec, forward_kinematics, parameter_jacobian,
//! };
//!
//! let revolute = |alpha: f64, r: f64| Frame { alpha, r, ..Frame::new(FrameType::Revolute) };
//! let frames = vec![
//!     Frame { theta: FRAC_PI_2, r: 0.5, ..Frame::new(FrameType::Fixed) },
//!     revolute(0.1, 0.0),
//!     revolute(-FRAC_PI_2, 0.2),
//!     Frame { alpha: FRAC_PI_2, ..Frame::new(FrameType::Prismatic) },
//!     revolute(0.0, 0.0),
//!     revolute(-FRAC_PI_2, 0.0),
//!     revolute(FRAC_PI_2, 0.0),
//!     Frame { alpha: 1.3, d: 0.2, theta: FRAC_PI_2, r: 0.1, ..Frame::new(FrameType::Fixed) },
//! ];
//! let joints = frames[1..7].iter().map(|f| Joint::default_for(f.frame_type)).collect();
//! let stanford = Robot::new(RobotSpec::rigid("Stanford", frames, joints))?;
//!
//! let qm = [0.0, 0.0, 0.5, 0.0, 0.0, 0.0];
//! let tool = forward_kinematics(&stanford, &qm)?.world_from_tool().translation.vector;
//! assert!((tool - nalgebra::Vector3::new(-0.0505392, 0.2, 1.0344655)).norm() < 1e-6);
//!
//! let jacobian = parameter_jacobian(&stanford, &qm)?;
//! assert_eq!(jacobian.shape(), (6, 43));
//! # Ok::<(), gecaro_core::Error>(())
//! ```

#![warn(missing_docs)]

mod axis_chain;
pub mod delta;
mod error;
mod frame;
pub mod gough_stewart;
mod gravity;
mod kinematics;
pub mod parallel_model;
pub mod parallel_robot;
mod parameters;
mod placement;
mod priority;
mod rebase;
mod reframe;
mod region;
mod robot;
mod stated;

#[cfg(test)]
mod test_robots;

pub use axis_chain::{AxisChain, ChainJoint};
pub use error::{Compact, Error, Field};
pub use frame::{Frame, FrameType, Joint};
pub use gravity::{
    LinkMass, MAX_CENTRE_DISTANCE, MAX_GRAVITY, MAX_LINK_MASS, MassModel, STANDARD_GRAVITY,
    gravity_loads_in, gravity_torques, gravity_torques_in, upright_gravity,
};
pub use kinematics::turn;
pub use kinematics::{
    CONFIGURATION_LANES, ChainBuffer, FrameChain, InverseOptions, InverseSolution, InverseSolver,
    JacobianRows, KinematicModel, KnownMinima, LaneBuffer, OrientationDifference, SphericalWrist,
    Target, forward_kinematics, frame_transform, inverse_kinematics, joint_jacobian,
    orientation_difference, parameter_jacobian, parameter_jacobian_of_chain, pose_difference,
    terminal_pose,
};
pub use parameters::{ParameterId, ParameterKind, ParameterSpace};
pub use placement::NEARLY_PARALLEL_DEGREES;
pub use priority::PriorityMatrix;
pub use rebase::{SAME_FRAME_ANGLE, SAME_FRAME_DISTANCE};
pub use region::{JointRegion, MEASURED_MARGIN};
pub use robot::{LIMIT_TOLERANCE, Robot, RobotSpec};
pub use stated::{MAX_COMPLIANCE, MAX_JOINTS, MAX_MAGNITUDE, MIN_GAIN};

#[cfg(test)]
pub(crate) use test_robots::stanford as ready_robot_for_tests;
