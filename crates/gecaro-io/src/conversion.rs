//! What a conversion between gecaro's robot files and another format gives:
//! the robot with notes ([`Imported`]), or the other format's text with the
//! joint calibration it cannot carry ([`Exported`]). Shared by every format
//! ([`crate::interchange`] dispatches to them).

use gecaro_core::Robot;
use nalgebra::DMatrix;

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

/// The joint calibration of a robot whose map `M = Cj·diag(K)·Cm` (eq. 4)
/// is not the identity, for a format whose joint values are `M·qm` (offsets
/// folded into the file): YAML naming the file's joints.
pub(crate) fn joint_calibration(
    robot: &Robot,
    joint_names: &[String],
    format: &str,
) -> Option<String> {
    let map: &DMatrix<f64> = robot.motor_to_joint();
    if *map == DMatrix::identity(map.nrows(), map.ncols()) {
        return None;
    }
    let list = |values: Vec<String>| format!("[{}]", values.join(", "));
    let mut text = format!(
        "# gecaro joint calibration of `{}` (GECARO eq. 4, offsets folded into the {format}):\n\
         # the {format}'s joint values are q = M · qm, qm the motor (encoder) values, M = Cj·diag(K)·Cm.\n\
         # A driver applies this map before publishing joint states.\n",
        robot.name()
    );
    text.push_str(&format!(
        "joints: {}\nmatrix:\n",
        list(
            joint_names
                .iter()
                .map(|name| format!("\"{}\"", name.replace('"', "\\\"")))
                .collect()
        )
    ));
    for row in map.row_iter() {
        text.push_str(&format!(
            "  - {}\n",
            list(row.iter().map(|v| format!("{v:?}")).collect())
        ));
    }
    text.push_str(&format!(
        "gains: {}\n",
        list(
            robot
                .joints()
                .iter()
                .map(|joint| format!("{:?}", joint.gain))
                .collect()
        )
    ));
    Some(text)
}
