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

/// A rigid registration of named points and what the points say of it:
/// the transform, each point's residual, and its precision.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRegistration {
    /// `T` with `T x_i ≈ y_i` (the `to` points' frame from the `from`
    /// points' frame).
    pub transform: IsometryMatrix3<f64>,
    /// `‖T x_i − y_i‖` per point (the units of the points).
    pub residuals: Vec<f64>,
    /// The residuals' standard deviation per coordinate,
    /// `s = √(Σ‖r_i‖² / (3N − 6))`.
    pub sigma: f64,
    /// The standard deviation of the `from` frame's origin in the `to`
    /// frame (per axis, RMS of the three), from `s² (JᵀJ)⁻¹`.
    pub origin_sigma: f64,
    /// The standard deviation of the rotation (rad, per axis, RMS of the
    /// three), likewise.
    pub rotation_sigma: f64,
}

/// The rigid fit of `from` onto `to` ([`rigid_fit`]) with its residuals
/// and precision: the parameters `(δt, δφ)` of `y = (I + [δφ]×) R x + t + δt`
/// have the Jacobian rows `[I, −[R x_i]×]` per point, and the covariance
/// `s² (JᵀJ)⁻¹` with `s` of 3N − 6 degrees of freedom.
///
/// # Errors
/// Fewer than 3 pairs, or points on one line (the rotation about it is
/// free), as a sentence.
pub fn register_points(
    from: &[Vector3<f64>],
    to: &[Vector3<f64>],
) -> Result<PointRegistration, String> {
    let count = from.len().min(to.len());
    if count < 3 {
        return Err(format!(
            "{count} point(s): a frame is registered from at least 3 points not on one line"
        ));
    }
    let mean = from.iter().sum::<Vector3<f64>>() / count as f64;
    let spread: Matrix3<f64> = from
        .iter()
        .map(|x| (x - mean) * (x - mean).transpose())
        .sum();
    let mut extents = spread.symmetric_eigenvalues();
    extents.as_mut_slice().sort_by(|a, b| b.total_cmp(a));
    // The points' second-largest extent (m): a line has none.
    let width = extents[1].max(0.0).sqrt() / (count as f64).sqrt();
    let length = extents[0].max(0.0).sqrt() / (count as f64).sqrt();
    if width.is_nan() || width <= 1e-6 * length.max(1e-9) || width < 1e-9 {
        return Err(format!(
            "the {count} points lie on one line: the rotation about it is free; add a point \
             off that line"
        ));
    }
    let transform = rigid_fit(from, to);
    let residuals: Vec<f64> = from
        .iter()
        .zip(to)
        .map(|(x, y)| ((transform * nalgebra::Point3::from(*x)).coords - y).norm())
        .collect();
    let freedom = 3 * count - 6;
    let sigma = if freedom > 0 {
        (residuals.iter().map(|r| r * r).sum::<f64>() / freedom as f64).sqrt()
    } else {
        0.0
    };
    let mut normal = nalgebra::Matrix6::<f64>::zeros();
    for x in from {
        let r = transform.rotation * x;
        let mut rows = nalgebra::Matrix3x6::<f64>::zeros();
        rows.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        rows.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-r.cross_matrix()));
        normal += rows.transpose() * rows;
    }
    let (origin_sigma, rotation_sigma) = match normal.try_inverse() {
        Some(inverse) => {
            let diagonal = inverse.diagonal() * sigma * sigma;
            (
                (diagonal.rows(0, 3).sum() / 3.0).sqrt(),
                (diagonal.rows(3, 3).sum() / 3.0).sqrt(),
            )
        }
        None => (f64::INFINITY, f64::INFINITY),
    };
    Ok(PointRegistration {
        transform,
        residuals,
        sigma,
        origin_sigma,
        rotation_sigma,
    })
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

    /// Noisy points: the transform within its stated precision, the σ
    /// of the noise found, a line refused.
    #[test]
    fn a_registration_states_its_precision() {
        let truth = IsometryMatrix3::from_parts(
            Translation3::new(2.5, 0.4, -0.3),
            Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.1, 0.2, 1.0)), 2.2),
        );
        let from: Vec<Vector3<f64>> = cloud().iter().map(|x| x * 0.3).collect();
        let mut sampler = crate::simulation::Sampler::new(11);
        let sigma = 2e-5;
        let (mut origin_errors, mut rotation_errors, mut sigmas) = (0.0, 0.0, 0.0);
        let trials = 200;
        let mut stated = (0.0, 0.0);
        for _ in 0..trials {
            let to: Vec<Vector3<f64>> = from
                .iter()
                .map(|x| {
                    (truth * nalgebra::Point3::from(*x)).coords + sampler.gaussian_vector(sigma)
                })
                .collect();
            let found = register_points(&from, &to).expect("registered");
            let error = truth.inverse() * found.transform;
            origin_errors += found
                .transform
                .translation
                .vector
                .metric_distance(&truth.translation.vector)
                .powi(2);
            rotation_errors += error.rotation.scaled_axis().norm_squared();
            sigmas += found.sigma;
            stated = (found.origin_sigma, found.rotation_sigma);
        }
        // Per axis: the RMS over trials of the 3-D error, over √3.
        let origin = (origin_errors / trials as f64 / 3.0).sqrt();
        let rotation = (rotation_errors / trials as f64 / 3.0).sqrt();
        assert!(
            (sigmas / trials as f64 / sigma - 1.0).abs() < 0.1,
            "σ {}",
            sigmas / trials as f64
        );
        assert!(
            (origin / stated.0 - 1.0).abs() < 0.25,
            "origin {origin} vs {}",
            stated.0
        );
        assert!(
            (rotation / stated.1 - 1.0).abs() < 0.25,
            "rotation {rotation} vs {}",
            stated.1
        );
        let line: Vec<Vector3<f64>> = (0..5)
            .map(|i| Vector3::new(f64::from(i), 0.0, 0.0))
            .collect();
        assert!(
            register_points(&line, &line)
                .expect_err("a line")
                .contains("one line")
        );
        assert!(register_points(&from[..2], &from[..2]).is_err());
    }

    #[test]
    fn a_mirror_image_is_not_taken_for_a_rotation() {
        let from = cloud();
        let to: Vec<Vector3<f64>> = from.iter().map(|x| Vector3::new(-x.x, x.y, x.z)).collect();
        let found = rigid_fit(&from, &to);
        assert!((found.rotation.matrix().determinant() - 1.0).abs() < 1e-12);
    }
}
