//! The joint calibration file, `FILE.joint_calibration.yaml`: what a URDF
//! or a DH table cannot carry of eq. 4 (gains K, couplings), written beside
//! an export ([`joint_calibration`]) and read back on import
//! ([`apply_joint_calibration`]), so that an exported robot imports to the
//! same motion.
//!
//! The format's joint values are `q = M · qm` (offsets folded into the
//! file), `qm` the motor (encoder) values, `M = Cj·diag(K)·Cm`:
//!
//! ```yaml
//! joints: ["joint_a1", "joint_a2"]
//! matrix:
//!   - [1.001, 0.0]
//!   - [0.0, 0.998]
//! gains: [1.001, 0.998]
//! compliances: [0.0, 4.2e-6]   # an elastic robot's c_j, rad/(N·m) (m/N if prismatic)
//! ```
//!
//! An elastic robot writes the file even when its map is the identity:
//! the compliances are what the URDF or the table cannot carry.

use std::path::Path;

use gecaro_core::Robot;
use nalgebra::DMatrix;
use serde::Deserialize;

use crate::Error;
use crate::robot_file::RobotFile;

/// [`joint_calibration`] for a format whose joints are numbered (a DH
/// table, a SYMORO file: `joint 1`, …), with the note that says so pushed
/// to `notes` when there is one; `format` names the format in the note (`a
/// DH table`).
pub(crate) fn numbered_joint_calibration(
    robot: &Robot,
    (file_word, format): (&str, &str),
    notes: &mut Vec<String>,
) -> Option<String> {
    let joint_names: Vec<String> = (1..=robot.joint_count())
        .map(|j| format!("joint {j}"))
        .collect();
    let calibration = joint_calibration(robot, &joint_names, file_word);
    if calibration.is_some() {
        notes.push(format!(
            "gains K or couplings are not expressible in {format}: its joint values are \
             q = Cj·diag(K)·Cm·qm, a map written to the joint calibration file for the driver"
        ));
    }
    calibration
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
    if *map == DMatrix::identity(map.nrows(), map.ncols()) && !robot.is_elastic() {
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
    if let Some(compliances) = robot.compliances() {
        text.push_str(&format!(
            "compliances: {} # rad/(N·m), m/N for a prismatic joint (elastic joints)\n",
            list(compliances.iter().map(|c| format!("{c:?}")).collect())
        ));
    }
    Some(text)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCalibration {
    joints: Vec<String>,
    matrix: Vec<Vec<f64>>,
    gains: Vec<f64>,
    #[serde(default)]
    compliances: Option<Vec<f64>>,
}

/// Applies the joint calibration `text` (the file `path`) to an imported
/// robot: the gains, and where the map `M` is not diagonal, a joint
/// coupling `Cj = M·diag(K)⁻¹` (with `Cm` the identity), so that the robot's
/// `q = Cj·diag(K)·Cm·qm` is the file's `M·qm`. An imported URDF's joints
/// must be those the file names, in order.
///
/// # Errors
/// [`Error::Parse`] naming the file and the key at fault: malformed YAML,
/// another number of joints or other joint names, a map that is not n×n,
/// gains that are zero or not finite, compliances of another count or not
/// finite.
pub fn apply_joint_calibration(file: &mut RobotFile, text: &str, path: &Path) -> Result<(), Error> {
    let fail = |key: &str, message: String| Error::parse(path, 1, Some(key.to_owned()), message);
    let raw: RawCalibration = serde_yaml_ng::from_str(text).map_err(|error| {
        let line = error.location().map_or(1, |location| location.line());
        Error::parse(path, line, None, error.to_string())
    })?;
    let n = file.robot.joint_count();
    if raw.joints.len() != n {
        return Err(fail(
            "joints",
            format!("names {} joints, the robot has {n}", raw.joints.len()),
        ));
    }
    if let Some(names) = &file.urdf {
        for (j, (named, joint)) in raw.joints.iter().zip(&names.joints).enumerate() {
            if *named != joint.name {
                return Err(fail(
                    "joints",
                    format!(
                        "joint {} is `{named}`, the URDF's is `{}`: the file belongs to another robot",
                        j + 1,
                        joint.name
                    ),
                ));
            }
        }
    }
    if raw.matrix.len() != n || raw.matrix.iter().any(|row| row.len() != n) {
        return Err(fail(
            "matrix",
            format!("must be {n}×{n}, one row per joint"),
        ));
    }
    if raw.gains.len() != n {
        return Err(fail(
            "gains",
            format!("gives {} gains for {n} joints", raw.gains.len()),
        ));
    }
    if let Some(gain) = raw.gains.iter().find(|g| !g.is_finite() || **g == 0.0) {
        return Err(fail(
            "gains",
            format!("a gain must be finite and not zero, not {gain}"),
        ));
    }
    let map = DMatrix::from_fn(n, n, |i, j| raw.matrix[i][j]);
    if map.iter().any(|v| !v.is_finite()) {
        return Err(fail("matrix", "must hold finite numbers".into()));
    }
    let mut spec = file.robot.to_spec();
    for (joint, gain) in spec.joints.iter_mut().zip(&raw.gains) {
        joint.gain = *gain;
    }
    let diagonal = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&raw.gains));
    let coupling = map.clone()
        * diagonal
            .try_inverse()
            .ok_or_else(|| fail("gains", "must not be zero".into()))?;
    if (coupling.clone() - DMatrix::identity(n, n)).amax() > 1e-12 {
        spec.joint_coupling = Some(coupling);
    }
    if let Some(compliances) = &raw.compliances
        && compliances.len() != n
    {
        return Err(fail(
            "compliances",
            format!("gives {} compliances for {n} joints", compliances.len()),
        ));
    }
    spec.compliances = raw.compliances.clone();
    let robot = Robot::new(spec).map_err(|error| {
        let key = if error.to_string().contains("compliance") {
            "compliances"
        } else {
            "matrix"
        };
        fail(key, error.to_string())
    })?;
    if (robot.motor_to_joint() - &map).amax() > 1e-9 * map.amax().max(1.0) {
        return Err(fail(
            "gains",
            "do not agree with the matrix: its diagonal holds the gains times the couplings".into(),
        ));
    }
    file.robot = robot;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_calibration_reads_back_to_the_same_map() {
        let mut spec = Robot::template("arm", "RRR").expect("template").to_spec();
        spec.joints[0].gain = 1.002;
        spec.joints[2].gain = 0.997;
        let mut coupling = DMatrix::identity(3, 3);
        coupling[(2, 1)] = 0.5;
        spec.joint_coupling = Some(coupling);
        let robot = Robot::new(spec).expect("robot");
        let names: Vec<String> = ["a", "b", "c"].map(str::to_owned).to_vec();
        let text = joint_calibration(&robot, &names, "URDF").expect("not the identity");
        let mut file = RobotFile::of(Robot::template("arm", "RRR").expect("template"));
        apply_joint_calibration(&mut file, &text, Path::new("x.yaml")).expect("read");
        assert!((file.robot.motor_to_joint() - robot.motor_to_joint()).amax() < 1e-15);
        let bad = text.replace("gains: [", "gains: [0.0, ");
        let error =
            apply_joint_calibration(&mut file, &bad, Path::new("x.yaml")).expect_err("four gains");
        assert!(error.to_string().contains("x.yaml"), "{error}");
        assert!(
            error.to_string().contains("4 gains for 3 joints"),
            "{error}"
        );
    }

    /// An elastic robot's compliances go to the file, even with the identity
    /// map, and come back.
    #[test]
    fn compliances_are_written_and_read_back() {
        let mut robot = Robot::template("arm", "RRP").expect("template");
        robot
            .set_compliances(Some(vec![0.0, 4.2e-6, 3e-7]))
            .expect("elastic");
        let names: Vec<String> = ["a", "b", "c"].map(str::to_owned).to_vec();
        let text = joint_calibration(&robot, &names, "URDF").expect("elastic");
        assert!(text.contains("compliances: [0.0, 4.2e-6, 3e-7]"), "{text}");
        let mut file = RobotFile::of(Robot::template("arm", "RRP").expect("template"));
        apply_joint_calibration(&mut file, &text, Path::new("x.yaml")).expect("read");
        assert_eq!(file.robot.compliances(), robot.compliances());
        let bad = text.replace("compliances: [", "compliances: [1.0, ");
        let error = apply_joint_calibration(&mut file, &bad, Path::new("x.yaml"))
            .expect_err("four compliances");
        assert!(error.to_string().contains("compliances"), "{error}");
        // A rigid robot with the identity map writes none.
        let rigid = Robot::template("arm", "RRP").expect("template");
        assert!(joint_calibration(&rigid, &names, "URDF").is_none());
    }
}
