//! The difference vector between two frames, Appendix I (eq. 21–25).
//!
//! For frames i and j given in the same reference frame,
//! `Δx = [Pⁱ − Pʲ; δ_{i,j}]` (eq. 21), where δ_{i,j} is the small rotation
//! (world axes, radians) that carries the orientation Aʲ onto Aⁱ:
//! `Aⁱ ≈ Rot(δ) · Aʲ`.

use nalgebra::{IsometryMatrix3, Rotation3, UnitQuaternion, Vector3, Vector6};

/// How δ_{i,j} is computed from the two orientations (Appendix I).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum OrientationDifference {
    /// Method 1, eq. 22: `δ = ½ (sʲ×sⁱ + nʲ×nⁱ + aʲ×aⁱ)`. It equals `u·sin α`,
    /// so it is exact only to first order.
    CrossProducts,
    /// Method 2, eq. 23–24: `Aⁱ·Aʲᵀ = Rot(u, α)` and `δ = u·α`, exact for
    /// α up to π. The paper found it converges better; it is the default.
    #[default]
    AxisAngle,
}

impl OrientationDifference {
    /// The names users give: `axis-angle` (method 2), `cross-products` (method 1).
    pub const NAMES: [&'static str; 2] = ["axis-angle", "cross-products"];

    /// The method of a name of [`NAMES`](Self::NAMES).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "axis-angle" => Some(OrientationDifference::AxisAngle),
            "cross-products" => Some(OrientationDifference::CrossProducts),
            _ => None,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            OrientationDifference::AxisAngle => "axis-angle",
            OrientationDifference::CrossProducts => "cross-products",
        }
    }
}

/// δ_{i,j}, the rotation vector from orientation `rotation_j` to `rotation_i`
/// (world axes, radians).
pub fn orientation_difference(
    rotation_i: &Rotation3<f64>,
    rotation_j: &Rotation3<f64>,
    method: OrientationDifference,
) -> Vector3<f64> {
    match method {
        OrientationDifference::CrossProducts => {
            let (a_i, a_j) = (rotation_i.matrix(), rotation_j.matrix());
            (0..3)
                .map(|axis| a_j.column(axis).cross(&a_i.column(axis)))
                .sum::<Vector3<f64>>()
                * 0.5
        }
        OrientationDifference::AxisAngle => {
            // Eq. 23; the quaternion route keeps u·α accurate near 0 and near π.
            let difference = rotation_i * rotation_j.inverse();
            UnitQuaternion::from_rotation_matrix(&difference).scaled_axis()
        }
    }
}

/// Δx of eq. 21 between frame i and frame j: `[Pⁱ − Pʲ; δ_{i,j}]`.
///
/// In calibration, i is the measured (or target) frame and j the frame the
/// model computes, so that `Δx ≈ J Δη` (eq. 7).
pub fn pose_difference(
    pose_i: &IsometryMatrix3<f64>,
    pose_j: &IsometryMatrix3<f64>,
    method: OrientationDifference,
) -> Vector6<f64> {
    let position = pose_i.translation.vector - pose_j.translation.vector;
    let orientation = orientation_difference(&pose_i.rotation, &pose_j.rotation, method);
    Vector6::new(
        position.x,
        position.y,
        position.z,
        orientation.x,
        orientation.y,
        orientation.z,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Unit;

    fn rotation(axis: [f64; 3], angle: f64) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::from(axis)), angle)
    }

    #[test]
    fn axis_angle_recovers_the_rotation_exactly() {
        let reference = rotation([0.2, -0.5, 0.7], 1.3);
        for angle in [1e-9, 0.01, 0.5, 2.0, 3.1] {
            let axis = Vector3::new(0.3, 0.4, -0.2).normalize();
            let moved = Rotation3::new(axis * angle) * reference;
            let delta =
                orientation_difference(&moved, &reference, OrientationDifference::AxisAngle);
            assert!(
                (delta - axis * angle).norm() < 1e-12 * angle.max(1.0),
                "angle {angle}"
            );
        }
    }

    #[test]
    fn cross_products_is_u_sin_alpha() {
        let reference = rotation([1.0, 2.0, 3.0], 0.4);
        let axis = Vector3::new(-0.6, 0.0, 0.8);
        for angle in [1e-6, 0.1, 1.0] {
            let moved = Rotation3::new(axis * angle) * reference;
            let delta =
                orientation_difference(&moved, &reference, OrientationDifference::CrossProducts);
            assert!((delta - axis * angle.sin()).norm() < 1e-14, "angle {angle}");
        }
    }

    #[test]
    fn sign_convention_matches_eq_25_corrected() {
        // NOTES.md: eq. 25's first component is A(3,2) − A(2,3) for Ad = Aⁱ Aʲᵀ.
        let a_j = rotation([0.0, 1.0, 1.0], 0.7);
        let a_i = Rotation3::new(Vector3::new(1e-6, -2e-6, 3e-6)) * a_j;
        let ad = (a_i * a_j.inverse()).into_inner();
        let eq_25 = 0.5
            * Vector3::new(
                ad[(2, 1)] - ad[(1, 2)],
                ad[(0, 2)] - ad[(2, 0)],
                ad[(1, 0)] - ad[(0, 1)],
            );
        let delta = orientation_difference(&a_i, &a_j, OrientationDifference::AxisAngle);
        assert!((delta - eq_25).norm() < 1e-17);
    }
}
