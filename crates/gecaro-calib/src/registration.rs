//! Registration of one point set onto another: the rigid transform (Horn,
//! Kabsch) or the similarity (Umeyama) that best maps points `x_i` onto
//! points `y_i` in the least-squares sense.
//!
//! With the centred points `x̃_i = x_i − x̄`, `ỹ_i = y_i − ȳ` and the SVD of
//! their cross-covariance `H = Σ x̃_i ỹ_iᵀ = U S Vᵀ`, the rotation is
//! `R = V C Uᵀ` with `C = diag(1, 1, det(V Uᵀ))` (a proper rotation, never a
//! reflection), the similarity's scale `s = tr(S C) / Σ‖x̃_i‖²` (1 for the
//! rigid fit) and the translation `t = ȳ − s R x̄`. Units are the points'.
//!
//! Used by the closed-form start of an identification (measurement frame and
//! tool point) and by the judge of a simulated calibration, which compares a
//! calibrated robot with the real one on held-out positions whatever the
//! base frame, which link and plane methods do not observe.

use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Translation3, Vector3};

/// A similarity transform `y = s R x + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// The scale `s` (1 for a rigid fit).
    pub scale: f64,
    /// The rotation and translation.
    pub isometry: IsometryMatrix3<f64>,
}

impl Similarity {
    /// The image of `point`.
    pub fn apply(&self, point: &Vector3<f64>) -> Vector3<f64> {
        self.scale * (self.isometry.rotation * point) + self.isometry.translation.vector
    }
}

/// The rigid transform `T` minimising `Σ ‖T x_i − y_i‖²` (Horn/Kabsch); the
/// identity for fewer than one pair or a degenerate covariance.
pub fn rigid_fit(from: &[Vector3<f64>], to: &[Vector3<f64>]) -> IsometryMatrix3<f64> {
    fit(from, to, false).isometry
}

/// The similarity minimising `Σ ‖s R x_i + t − y_i‖²` (Umeyama); the
/// identity for fewer than one pair or a degenerate covariance.
pub fn similarity_fit(from: &[Vector3<f64>], to: &[Vector3<f64>]) -> Similarity {
    fit(from, to, true)
}

fn fit(from: &[Vector3<f64>], to: &[Vector3<f64>], scaled: bool) -> Similarity {
    let identity = Similarity {
        scale: 1.0,
        isometry: IsometryMatrix3::identity(),
    };
    let count = from.len().min(to.len());
    if count == 0 {
        return identity;
    }
    let (from, to) = (&from[..count], &to[..count]);
    let from_mean = from.iter().sum::<Vector3<f64>>() / count as f64;
    let to_mean = to.iter().sum::<Vector3<f64>>() / count as f64;
    let covariance: Matrix3<f64> = from
        .iter()
        .zip(to)
        .map(|(x, y)| (x - from_mean) * (y - to_mean).transpose())
        .sum();
    let svd = covariance.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return identity;
    };
    let v = v_t.transpose();
    let mut correction = Matrix3::identity();
    correction[(2, 2)] = (v * u.transpose()).determinant().signum();
    let rotation = Rotation3::from_matrix_unchecked(v * correction * u.transpose());
    let spread: f64 = from.iter().map(|x| (x - from_mean).norm_squared()).sum();
    let scale = if scaled && spread > 0.0 {
        (svd.singular_values.component_mul(&correction.diagonal())).sum() / spread
    } else {
        1.0
    };
    let translation = to_mean - scale * (rotation * from_mean);
    Similarity {
        scale,
        isometry: IsometryMatrix3::from_parts(Translation3::from(translation), rotation),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Unit;

    fn cloud() -> Vec<Vector3<f64>> {
        (0..20)
            .map(|i| {
                let t = f64::from(i);
                Vector3::new((0.7 * t).sin(), (1.3 * t).cos(), 0.05 * t - 0.4)
            })
            .collect()
    }

    #[test]
    fn a_known_similarity_is_recovered() {
        let rotation =
            Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.3, -0.5, 0.8)), 2.1);
        let truth = Similarity {
            scale: 0.863,
            isometry: IsometryMatrix3::from_parts(Translation3::new(1.5, -2.0, 0.25), rotation),
        };
        let from = cloud();
        let to: Vec<Vector3<f64>> = from.iter().map(|x| truth.apply(x)).collect();
        let found = similarity_fit(&from, &to);
        assert!((found.scale - truth.scale).abs() < 1e-12, "{}", found.scale);
        assert!((found.isometry.rotation.matrix() - rotation.matrix()).norm() < 1e-12);
        for (x, y) in from.iter().zip(&to) {
            assert!((found.apply(x) - y).norm() < 1e-12);
        }
        // The rigid fit of the same points keeps the scale at 1 and leaves
        // exactly the residual that the scale explains.
        let rigid = rigid_fit(&from, &to);
        let residual: f64 = from
            .iter()
            .zip(&to)
            .map(|(x, y)| (rigid * nalgebra::Point3::from(*x)).coords - y)
            .map(|e| e.norm_squared())
            .sum();
        assert!(residual > 1e-3);
    }

    #[test]
    fn a_mirror_image_is_not_taken_for_a_rotation() {
        let from = cloud();
        let to: Vec<Vector3<f64>> = from.iter().map(|x| Vector3::new(-x.x, x.y, x.z)).collect();
        let found = rigid_fit(&from, &to);
        assert!((found.rotation.matrix().determinant() - 1.0).abs() < 1e-12);
    }
}
