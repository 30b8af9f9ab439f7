//! Orientations as instruments write them (issue 74): a unit quaternion
//! `qw, qx, qy, qz` (gecaro's own), or three numbers `rx, ry, rz` in the
//! file's angle unit — Euler angles of a stated sequence, or a rotation
//! vector. A 6-D probe's export is read as it is: `--rotation euler-xyz
//! --angle-unit deg`.
//!
//! | name | `rx, ry, rz` = `(a, b, c)` | rotation |
//! |---|---|---|
//! | `quaternion` (default) | – (`qw, qx, qy, qz`) | the unit quaternion |
//! | `rpy` (alias `euler-zyx`) | roll, pitch, yaw about the fixed x, y, z axes (URDF's) | `Rz(c)·Ry(b)·Rx(a)` |
//! | `euler-xyz` | about x, then the new y, then the new z (intrinsic) | `Rx(a)·Ry(b)·Rz(c)` |
//! | `euler-zyz` | about z, then the new y, then the new z | `Rz(a)·Ry(b)·Rz(c)` |
//! | `rotation-vector` | the axis times the angle | `exp([r]×)` |
//!
//! gecaro writes quaternions: a file read in another form reads back as
//! the same orientations from what gecaro writes.

use nalgebra::{Rotation3, UnitQuaternion, Vector3};

/// How a file writes orientations (see the module docs).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum RotationFormat {
    /// `qw, qx, qy, qz`.
    #[default]
    Quaternion,
    /// Roll, pitch, yaw about the fixed x, y, z axes.
    Rpy,
    /// Intrinsic x, y', z''.
    EulerXyz,
    /// Intrinsic z, y', z''.
    EulerZyz,
    /// A rotation vector (axis × angle).
    RotationVector,
}

impl RotationFormat {
    /// The names users give.
    pub const NAMES: [&'static str; 6] = [
        "quaternion",
        "rpy",
        "euler-zyx",
        "euler-xyz",
        "euler-zyz",
        "rotation-vector",
    ];

    /// The format of a name of [`NAMES`](Self::NAMES).
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "quaternion" => Some(RotationFormat::Quaternion),
            "rpy" | "euler-zyx" => Some(RotationFormat::Rpy),
            "euler-xyz" => Some(RotationFormat::EulerXyz),
            "euler-zyz" => Some(RotationFormat::EulerZyz),
            "rotation-vector" => Some(RotationFormat::RotationVector),
            _ => None,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            RotationFormat::Quaternion => "quaternion",
            RotationFormat::Rpy => "rpy",
            RotationFormat::EulerXyz => "euler-xyz",
            RotationFormat::EulerZyz => "euler-zyz",
            RotationFormat::RotationVector => "rotation-vector",
        }
    }

    /// gecaro's names of its columns.
    pub fn columns(self) -> &'static [&'static str] {
        match self {
            RotationFormat::Quaternion => &["qw", "qx", "qy", "qz"],
            _ => &["rx", "ry", "rz"],
        }
    }

    /// The orientation of three values `(a, b, c)` in radians (see the
    /// module docs); the identity for [`RotationFormat::Quaternion`], which
    /// has four.
    pub fn orientation(self, [a, b, c]: [f64; 3]) -> UnitQuaternion<f64> {
        let about = |axis: &nalgebra::Unit<Vector3<f64>>, angle: f64| {
            Rotation3::from_axis_angle(axis, angle)
        };
        let (x, y, z) = (Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis());
        let rotation = match self {
            RotationFormat::Quaternion => Rotation3::identity(),
            RotationFormat::Rpy => about(&z, c) * about(&y, b) * about(&x, a),
            RotationFormat::EulerXyz => about(&x, a) * about(&y, b) * about(&z, c),
            RotationFormat::EulerZyz => about(&z, a) * about(&y, b) * about(&z, c),
            RotationFormat::RotationVector => Rotation3::new(Vector3::new(a, b, c)),
        };
        UnitQuaternion::from_rotation_matrix(&rotation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each sequence against nalgebra's own constructions.
    #[test]
    fn every_sequence_is_the_rotation_it_names() {
        let (a, b, c) = (0.3, -0.7, 1.9);
        let rpy = UnitQuaternion::from_euler_angles(a, b, c);
        assert!(RotationFormat::Rpy.orientation([a, b, c]).angle_to(&rpy) < 1e-14);
        let xyz = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), a)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), b)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), c);
        assert!(
            RotationFormat::EulerXyz
                .orientation([a, b, c])
                .angle_to(&xyz)
                < 1e-14
        );
        let vector = Vector3::new(a, b, c);
        let rotated = RotationFormat::RotationVector.orientation([a, b, c]);
        assert!((rotated.scaled_axis() - vector).norm() < 1e-14);
        for name in RotationFormat::NAMES {
            let format = RotationFormat::from_name(name).expect(name);
            assert!(name == "euler-zyx" || format.name() == name);
        }
    }
}
