//! Rigid transforms as files write them: URDF's `xyz` + `rpy`, and gecaro's
//! seven numbers `x, y, z, qw, qx, qy, qz`.
//!
//! `rpy` is URDF's convention: fixed axes roll about x, then pitch about y,
//! then yaw about z, i.e. `R = Rz(yaw)·Ry(pitch)·Rx(roll)` (radians).

use nalgebra::{IsometryMatrix3, Quaternion, Rotation3, Translation3, UnitQuaternion, Vector3};

/// The transform of URDF's `<origin xyz rpy>`.
pub(crate) fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// Roll, pitch, yaw of a rotation, accurate everywhere: the pitch from
/// `atan2` (an `asin` loses half the digits next to ±π/2), and at the
/// singularity (cos pitch = 0) the whole turn about z in the yaw.
pub(crate) fn rpy(rotation: &Rotation3<f64>) -> [f64; 3] {
    let m = rotation.matrix();
    let cos_pitch = m[(0, 0)].hypot(m[(1, 0)]);
    let pitch = (-m[(2, 0)]).atan2(cos_pitch);
    if cos_pitch > 1e-12 {
        [
            m[(2, 1)].atan2(m[(2, 2)]),
            pitch,
            m[(1, 0)].atan2(m[(0, 0)]),
        ]
    } else {
        [0.0, pitch, (-m[(0, 1)]).atan2(m[(1, 1)])]
    }
}

/// A tool's pose in frame n+1 as a person writes it (issue 74): `x,y,z`,
/// each a length with its unit or bare metres (no bare number beside a
/// unit), optionally followed by `qw,qx,qy,qz`; no rotation when omitted.
/// Or the 16 numbers of its 4×4 homogeneous matrix, row by row
/// ([`pose_from_matrix`]; the translation's three may carry their unit).
///
/// ```
/// let tool = gecaro_io::parse_tool_pose("0,0,120mm").unwrap();
/// assert!((tool.translation.vector.z - 0.12).abs() < 1e-15);
/// assert!(gecaro_io::parse_tool_pose("10,0,120mm").is_err());
/// let turned = gecaro_io::parse_tool_pose("0,0,0.1,0,1,0,0").unwrap();
/// assert!((turned.rotation.matrix()[(1, 1)] + 1.0).abs() < 1e-15);
/// ```
///
/// # Errors
/// A sentence naming what is wrong: the count, a unit, a mix of units, a
/// quaternion that is not a unit one.
pub fn parse_tool_pose(text: &str) -> Result<IsometryMatrix3<f64>, String> {
    parse_pose(text, "tool", "frame n+1")
}

/// A point as a person writes it, `x,y,z` each with its unit (`250mm,-100mm,0`;
/// bare numbers metres, a bare number beside one with a unit refused but 0):
/// the mount of a measuring leg's socket. `what` names it in messages.
///
/// ```
/// let point = gecaro_io::parse_point("250mm,-100mm,0", "the leg's base").unwrap();
/// assert_eq!(point, nalgebra::Vector3::new(0.25, -0.1, 0.0));
/// let error = gecaro_io::parse_point("250,-100mm,0", "the leg's base").unwrap_err();
/// assert!(error.contains("mixes units"), "{error}");
/// ```
///
/// # Errors
/// Not three coordinates, a coordinate that is no length, mixed units.
pub fn parse_point(text: &str, what: &str) -> Result<nalgebra::Vector3<f64>, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y, z] = parts.as_slice() else {
        return Err(format!(
            "{what} is three coordinates x,y,z, each with its unit (250mm,-100mm,0), not '{text}'"
        ));
    };
    let [x, y, z] = crate::written_lengths::point(&[*x, *y, *z], what)?;
    Ok(nalgebra::Vector3::new(x, y, z))
}

/// A pose as a person writes it, as [`parse_tool_pose`] reads a tool's: of
/// the `what` (a tool, the measurement frame) in its `parent` frame, named
/// so in messages.
///
/// ```
/// let error = gecaro_io::parse_pose("3,0,0.4mm", "frame", "the base frame").unwrap_err();
/// assert!(error.contains("the frame's position"), "{error}");
/// ```
///
/// # Errors
/// As [`parse_tool_pose`].
pub fn parse_pose(text: &str, what: &str, parent: &str) -> Result<IsometryMatrix3<f64>, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() == 16 {
        let [x, y, z] = crate::written_lengths::point(
            &[parts[3], parts[7], parts[11]],
            &format!("the {what}'s position"),
        )?;
        let mut values = [0.0; 16];
        for (index, (value, text)) in values.iter_mut().zip(&parts).enumerate() {
            *value = match index {
                3 => x,
                7 => y,
                11 => z,
                _ => text
                    .parse()
                    .map_err(|_| format!("the {what}'s matrix holds '{text}', not a number"))?,
            };
        }
        return pose_from_matrix(&values)
            .map_err(|message| format!("the {what}'s matrix {message}"));
    }
    let (position, quaternion) = match parts.as_slice() {
        [x, y, z] => ([*x, *y, *z], None),
        [x, y, z, rest @ ..] if rest.len() == 4 => ([*x, *y, *z], Some(rest)),
        _ => {
            return Err(format!(
                "'{text}' is not a {what} pose: give its position in {parent} with units, and \
                 optionally its quaternion: 0,0,120mm or 0,0,120mm,1,0,0,0; or the 16 numbers \
                 of its 4×4 matrix, row by row"
            ));
        }
    };
    let [x, y, z] = crate::written_lengths::point(&position, &format!("the {what}'s position"))?;
    let rotation = match quaternion {
        None => Rotation3::identity(),
        Some(values) => {
            let mut q = [0.0; 4];
            for (value, text) in q.iter_mut().zip(values) {
                *value = text
                    .parse()
                    .map_err(|_| format!("the {what}'s quaternion holds '{text}', not a number"))?;
            }
            unit_quaternion(q[0], q[1], q[2], q[3])
                .map_err(|message| format!("the {what}'s quaternion: {message}"))?
                .to_rotation_matrix()
        }
    };
    Ok(IsometryMatrix3::from_parts(
        Translation3::new(x, y, z),
        rotation,
    ))
}

/// `[x, y, z, qw, qx, qy, qz]` of a transform (the quaternion with qw ≥ 0).
pub(crate) fn to_seven(pose: &IsometryMatrix3<f64>) -> [f64; 7] {
    let t = pose.translation.vector;
    let mut q = UnitQuaternion::from_rotation_matrix(&pose.rotation);
    if q.w < 0.0 {
        q = UnitQuaternion::new_unchecked(-q.into_inner());
    }
    [t.x, t.y, t.z, q.w, q.i, q.j, q.k]
}

/// The orientation of a unit quaternion `(qw, qx, qy, qz)`, or why not: a
/// norm further than `NORMALISED_TOLERANCE` from 1 is refused (it is not an
/// orientation, or its components are mixed up); within that, it is
/// normalised (see `quaternion_deviation` to tell the user).
///
/// # Errors
/// The message says what is wrong (non-finite values, the norm).
pub fn unit_quaternion(w: f64, x: f64, y: f64, z: f64) -> Result<UnitQuaternion<f64>, String> {
    let quaternion = Quaternion::new(w, x, y, z);
    let norm = quaternion.norm();
    if !norm.is_finite() {
        return Err("(qw, qx, qy, qz) holds a value that is not a finite number".into());
    }
    if (norm - 1.0).abs() > NORMALISED_TOLERANCE {
        return Err(format!(
            "(qw, qx, qy, qz) has norm {norm:.6}, not 1: it is not a unit quaternion"
        ));
    }
    Ok(UnitQuaternion::from_quaternion(quaternion))
}

/// How far from 1 the norm of a quaternion may be and still be taken as a
/// unit quaternion written with few digits (normalised, with a note):
/// four decimals leave norms within ~2·10⁻⁴ of 1.
pub(crate) const NORMALISED_TOLERANCE: f64 = 1e-3;

/// Below this, a norm's distance from 1 is rounding, normalised silently.
pub(crate) const SILENT_TOLERANCE: f64 = 1e-6;

/// How far the norm of `(qw, qx, qy, qz)` is from 1 when it is worth a note
/// (above [`SILENT_TOLERANCE`]), `None` otherwise.
pub(crate) fn quaternion_deviation(w: f64, x: f64, y: f64, z: f64) -> Option<f64> {
    let deviation = (Quaternion::new(w, x, y, z).norm() - 1.0).abs();
    (deviation > SILENT_TOLERANCE).then_some(deviation)
}

/// `translation` (m) when no coordinate is beyond
/// [`gecaro_core::MAX_MAGNITUDE`] (a frame kilometres away is a typo or a
/// length in another unit; issue 75: 1e300 gave "frame 0 theta NaN").
fn bounded(translation: Vector3<f64>) -> Result<Translation3<f64>, String> {
    match translation
        .iter()
        .find(|v| v.abs() > gecaro_core::MAX_MAGNITUDE)
    {
        Some(v) => Err(format!(
            "puts the frame {v:.3e} m away: beyond ±{} m, no robot cell is that large",
            gecaro_core::MAX_MAGNITUDE
        )),
        None => Ok(Translation3::from(translation)),
    }
}

/// The transform of `[x, y, z, qw, qx, qy, qz]` (metres, then a unit
/// quaternion), or why not.
///
/// # Errors
/// The message says what is wrong (count, non-finite values, the norm).
pub fn pose_from_seven(values: &[f64]) -> Result<IsometryMatrix3<f64>, String> {
    let [x, y, z, w, i, j, k] = values[..] else {
        return Err(format!(
            "needs seven numbers [x, y, z, qw, qx, qy, qz], got {}",
            values.len()
        ));
    };
    if !values.iter().all(|v| v.is_finite()) {
        return Err("holds a value that is not a finite number".into());
    }
    Ok(IsometryMatrix3::from_parts(
        bounded(Vector3::new(x, y, z))?,
        unit_quaternion(w, i, j, k)?.to_rotation_matrix(),
    ))
}

/// The transform of a 4×4 homogeneous matrix, its 16 numbers row by row
/// (the translation in metres), or why not: the last row must be `0, 0,
/// 0, 1` and the upper-left block a rotation (`‖RᵀR − I‖ ≤ 1e-6`, a
/// positive determinant; a matrix of 6 decimals, as instruments write
/// them, is made exactly orthonormal).
///
/// ```
/// let pose = gecaro_io::pose_from_matrix(&[
///     0.0, -1.0, 0.0, 0.1, 1.0, 0.0, 0.0, 0.2, 0.0, 0.0, 1.0, 0.3, 0.0, 0.0, 0.0, 1.0,
/// ])
/// .unwrap();
/// assert!((pose.translation.vector.y - 0.2).abs() < 1e-15);
/// assert!(gecaro_io::pose_from_matrix(&[2.0; 16]).is_err());
/// ```
///
/// # Errors
/// The message says what is wrong (count, non-finite values, the last
/// row, a block that is no rotation).
pub fn pose_from_matrix(values: &[f64]) -> Result<IsometryMatrix3<f64>, String> {
    let [
        r11,
        r12,
        r13,
        x,
        r21,
        r22,
        r23,
        y,
        r31,
        r32,
        r33,
        z,
        last @ ..,
    ] = values
    else {
        return Err(format!(
            "needs the 16 numbers of a 4×4 homogeneous matrix, row by row, got {}",
            values.len()
        ));
    };
    if !values.iter().all(|v| v.is_finite()) {
        return Err("holds a value that is not a finite number".into());
    }
    if last
        .iter()
        .zip([0.0, 0.0, 0.0, 1.0])
        .any(|(a, b)| (a - b).abs() > 1e-12)
    {
        return Err("the last row of a homogeneous matrix must be 0, 0, 0, 1".into());
    }
    let rotation = nalgebra::Matrix3::new(*r11, *r12, *r13, *r21, *r22, *r23, *r31, *r32, *r33);
    let error = (rotation.transpose() * rotation - nalgebra::Matrix3::identity())
        .abs()
        .max();
    if error > 1e-6 || rotation.determinant() < 0.0 {
        return Err(format!(
            "the upper-left 3×3 block is not a rotation (‖RᵀR − I‖ = {error:.1e}, det = {:.3})",
            rotation.determinant()
        ));
    }
    let rotation = if error <= 1e-12 {
        Rotation3::from_matrix_unchecked(rotation)
    } else {
        Rotation3::from_matrix(&rotation)
    };
    Ok(IsometryMatrix3::from_parts(
        bounded(Vector3::new(*x, *y, *z))?,
        rotation,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tool as a 4×4 matrix (the translation with its unit) is the tool
    /// of its position and quaternion; a reflection, a skewed block or a
    /// bare number beside a unit are refused.
    #[test]
    fn a_tool_is_read_from_its_matrix() {
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let by_quaternion =
            parse_tool_pose(&format!("10mm,20mm,120mm,{half},0,0,{half}")).expect("pose");
        let by_matrix =
            parse_tool_pose("0,-1,0,10mm, 1,0,0,20mm, 0,0,1,120mm, 0,0,0,1").expect("matrix");
        assert!((by_matrix.to_homogeneous() - by_quaternion.to_homogeneous()).norm() < 1e-12);
        // Six decimals, as instruments write them: made orthonormal.
        let rounded =
            parse_tool_pose("0.707107,-0.707107,0,0, 0.707107,0.707107,0,0, 0,0,1,0.1, 0,0,0,1")
                .expect("rounded");
        let r = rounded.rotation.matrix();
        assert!((r.transpose() * r - nalgebra::Matrix3::identity()).norm() < 1e-14);
        for (text, words) in [
            ("-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1", "not a rotation"),
            ("1,0.1,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1", "not a rotation"),
            ("1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1", "last row"),
            ("1,0,0,10, 0,1,0,0, 0,0,1,120mm, 0,0,0,1", "unit"),
        ] {
            let message = parse_tool_pose(text).expect_err(text);
            assert!(message.contains(words), "{text}: {message}");
        }
    }

    #[test]
    fn rpy_is_urdf_s_convention_and_round_trips_next_to_the_singularity() {
        let (roll, pitch, yaw) = (0.3, -0.7, 2.1);
        let product = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), pitch)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), roll);
        let pose = from_xyz_rpy([0.0; 3], [roll, pitch, yaw]);
        assert!((pose.rotation.matrix() - product.matrix()).abs().max() < 1e-15);
        for pitch in [
            std::f64::consts::FRAC_PI_2,
            std::f64::consts::FRAC_PI_2 - 4.9e-12,
            -std::f64::consts::FRAC_PI_2 + 1e-9,
            1.2,
            -3.0,
        ] {
            let rotation = Rotation3::from_euler_angles(0.4, pitch, -1.1);
            let [r, p, y] = rpy(&rotation);
            let again = Rotation3::from_euler_angles(r, p, y);
            assert!(
                (again.matrix() - rotation.matrix()).abs().max() < 1e-15,
                "pitch {pitch}"
            );
        }
    }

    #[test]
    fn seven_numbers_round_trip_and_refuse_what_is_not_a_pose() {
        let pose = from_xyz_rpy([0.1, -0.2, 0.3], [0.5, 0.6, -2.9]);
        let again = pose_from_seven(&to_seven(&pose)).expect("valid");
        assert!((again.to_homogeneous() - pose.to_homogeneous()).abs().max() < 1e-15);
        assert!(pose_from_seven(&[0.0; 6]).is_err());
        assert!(pose_from_seven(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0]).is_err());
        assert!(pose_from_seven(&[f64::NAN, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]).is_err());
    }
}
