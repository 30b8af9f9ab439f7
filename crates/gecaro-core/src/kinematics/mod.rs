//! Kinematic models of a [`Robot`](crate::Robot): direct geometric model
//! (eq. 1–3), pose difference (Appendix I), Jacobian with respect to the
//! geometric parameters and gains (Appendix II), and a numerical inverse
//! geometric model.
//!
//! Conventions: all vectors are expressed in the world (measurement) frame −1;
//! a 6-vector is `[position (m); orientation (rad)]`; configurations are motor
//! variables qm (eq. 4) unless a name says joint positions.

mod direct;
mod inverse;
mod jacobian;
mod joint_step;
mod known_minima;
mod lanes;
mod loaded;
mod model;
mod pose_difference;
mod solver;
mod spherical_wrist;
pub mod turn;

pub use direct::{FrameChain, forward_kinematics, frame_transform, terminal_pose};
pub use inverse::{InverseOptions, InverseSolution, Target, inverse_kinematics};
pub use jacobian::{joint_jacobian, parameter_jacobian, parameter_jacobian_of_chain};
pub use known_minima::KnownMinima;
pub use lanes::{CONFIGURATION_LANES, LaneBuffer};
pub use model::{ChainBuffer, JacobianRows, KinematicModel};
pub use pose_difference::{OrientationDifference, orientation_difference, pose_difference};
pub use solver::InverseSolver;
pub use spherical_wrist::SphericalWrist;
