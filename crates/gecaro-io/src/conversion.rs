//! What a conversion between gecaro's robot files and another format gives:
//! the robot with notes ([`Imported`]), or the other format's text with the
//! joint calibration it cannot carry ([`Exported`]). Shared by every format
//! ([`crate::interchange`] dispatches to them).

use crate::robot_file::RobotFile;

/// Which chain to take from a URDF, and what to call the robot.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChainEnds {
    /// The base link (default: the root link).
    pub base: Option<String>,
    /// The tip link (default: the leaf with the most moving joints).
    pub tip: Option<String>,
    /// The robot's name (default: the file's).
    pub name: Option<String>,
}

/// A robot read from another format.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The robot, ready to be written as a robot file.
    pub file: RobotFile,
    /// What the conversion did that a user should know (folded joints,
    /// couplings, default limits).
    pub notes: Vec<String>,
}

/// A robot written in another format.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The text of the file.
    pub text: String,
    /// What a driver must apply to the motor values to get the file's joint
    /// values, when gains or couplings are not expressible in the format
    /// (YAML text, for `FILE.joint_calibration.yaml`).
    pub joint_calibration: Option<String>,
    /// What the conversion changed or moved elsewhere, for the user.
    pub notes: Vec<String>,
}
