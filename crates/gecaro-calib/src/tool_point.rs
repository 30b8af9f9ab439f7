//! A tool's point taught by pivoting (issue 74), and a user frame from
//! three points: the frames a robot's owner works in.
//!
//! **Pivoting.** The tool's tip is held on one fixed point `P` (a cone, a
//! dimple) while the robot takes `N ≥ 4` orientations; at each, the pose
//! `(R_i, p_i)` of frame n+1 (tool0) comes from the robot's model. The tip
//! `t` in frame n+1 and the fixed point `P` in the world frame satisfy
//! `R_i t + p_i = P`, i.e. the linear system `[R_i  −I] [t; P] = −p_i` of
//! 3N equations in 6 unknowns, solved by least squares (an SVD of the
//! 3N × 6 matrix `A`). Its residuals say how well the tip stayed on the
//! point and the model agrees; `s² = ‖r‖² / (3N − 6)` and `s² (AᵀA)⁻¹`
//! give the precision of `t` and `P`. The orientations must turn about two
//! axes at least: about one axis only, the tip's position along it is not
//! determined. Their spread — `√λ_min` of `Σ (R_i − R̄)ᵀ(R_i − R̄) / N`,
//! the smallest RMS turn about any axis (rad) — is reported, and the
//! system refused when it is degenerate.
//!
//! **Three points.** A user frame (a fixture, a table) from its origin, a
//! point on its +x axis and a point in its xy plane (+y side): `x̂` along
//! origin → x, `ẑ = x̂ × (xy − origin)` normalised, `ŷ = ẑ × x̂`.

use nalgebra::{DMatrix, DVector, IsometryMatrix3, Matrix3, Rotation3, Translation3, Vector3};

/// The least spread of orientations (rad) below which a pivot is refused:
/// 1°, where a tip 0.1 m long moves by under 2 mm.
pub const LEAST_SPREAD: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// A tool point taught by pivoting (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct PivotFit {
    /// The tip in frame n+1 (m).
    pub tool: Vector3<f64>,
    /// The fixed point in the world frame (m).
    pub fixed: Vector3<f64>,
    /// `‖R_i t + p_i − P‖` per orientation (m).
    pub residuals: Vec<f64>,
    /// The residuals' σ per coordinate, 3N − 6 degrees of freedom (m).
    pub sigma: f64,
    /// The σ of the tip's coordinates (m, per axis, RMS of the three).
    pub tool_sigma: f64,
    /// The σ of the fixed point's coordinates (m, likewise).
    pub fixed_sigma: f64,
    /// The orientations' spread: the smallest RMS turn about any axis (rad).
    pub spread: f64,
}

/// The tool point of the frame n+1 poses `poses`, all with the tip on one
/// point (see the module docs).
///
/// # Errors
/// Fewer than 4 poses, or orientations that turn about one axis only (or
/// less than [`LEAST_SPREAD`]), as a sentence.
pub fn pivot(poses: &[IsometryMatrix3<f64>]) -> Result<PivotFit, String> {
    let count = poses.len();
    if count < 4 {
        return Err(format!(
            "{count} orientation(s): a tool point is taught from at least 4, turned about two \
             axes"
        ));
    }
    let mean: Matrix3<f64> = poses
        .iter()
        .map(|pose| *pose.rotation.matrix())
        .sum::<Matrix3<f64>>()
        / count as f64;
    let scatter: Matrix3<f64> = poses
        .iter()
        .map(|pose| {
            let d = pose.rotation.matrix() - mean;
            d.transpose() * d
        })
        .sum::<Matrix3<f64>>()
        / count as f64;
    let spread = scatter.symmetric_eigenvalues().min().max(0.0).sqrt();
    if spread.is_nan() || spread < LEAST_SPREAD {
        return Err(format!(
            "the {count} orientations turn by {:.2}° at most about some axis: the tip's \
             position along it is not determined; tilt the tool by 20° or more about two axes",
            spread.to_degrees()
        ));
    }
    let mut a = DMatrix::<f64>::zeros(3 * count, 6);
    let mut b = DVector::<f64>::zeros(3 * count);
    for (i, pose) in poses.iter().enumerate() {
        a.view_mut((3 * i, 0), (3, 3))
            .copy_from(pose.rotation.matrix());
        a.view_mut((3 * i, 3), (3, 3))
            .copy_from(&(-Matrix3::identity()));
        b.rows_mut(3 * i, 3).copy_from(&(-pose.translation.vector));
    }
    let svd = a.svd(true, true);
    let solution = svd
        .solve(&b, 1e-12)
        .map_err(|message| format!("the pivot's least squares failed: {message}"))?;
    let tool = Vector3::new(solution[0], solution[1], solution[2]);
    let fixed = Vector3::new(solution[3], solution[4], solution[5]);
    let residuals: Vec<f64> = poses
        .iter()
        .map(|pose| (pose.rotation * tool + pose.translation.vector - fixed).norm())
        .collect();
    let freedom = 3 * count - 6;
    let sigma = (residuals.iter().map(|r| r * r).sum::<f64>() / freedom as f64).sqrt();
    // (AᵀA)⁻¹ = V S⁻² Vᵀ from the SVD already made: its diagonal.
    let v_t = svd
        .v_t
        .as_ref()
        .ok_or_else(|| "the pivot's SVD has no V".to_owned())?;
    let diagonal = DVector::from_fn(6, |k, _| {
        (0..6)
            .map(|i| (v_t[(i, k)] / svd.singular_values[i]).powi(2))
            .sum::<f64>()
            * sigma
            * sigma
    });
    Ok(PivotFit {
        tool,
        fixed,
        residuals,
        sigma,
        tool_sigma: (diagonal.rows(0, 3).sum() / 3.0).sqrt(),
        fixed_sigma: (diagonal.rows(3, 3).sum() / 3.0).sqrt(),
        spread,
    })
}

/// The closest distance (m) between points for [`frame_from_three`]: a
/// millimetre.
const LEAST_SEPARATION: f64 = 1e-3;

/// The frame of `origin`, a point `on_x` on its +x axis and a point `in_xy`
/// in its xy plane on the +y side (see the module docs): its pose in the
/// points' frame.
///
/// # Errors
/// Points closer than a millimetre, or `in_xy` on the x axis.
pub fn frame_from_three(
    origin: &Vector3<f64>,
    on_x: &Vector3<f64>,
    in_xy: &Vector3<f64>,
) -> Result<IsometryMatrix3<f64>, String> {
    let along = on_x - origin;
    if along.norm() < LEAST_SEPARATION {
        return Err("the +x point is on the origin: give a point along the frame's x axis".into());
    }
    let x = along.normalize();
    let normal = x.cross(&(in_xy - origin));
    if normal.norm() < LEAST_SEPARATION {
        return Err(
            "the xy-plane point is on the x axis: give a point of the plane off that axis".into(),
        );
    }
    let z = normal.normalize();
    let y = z.cross(&x);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    Ok(IsometryMatrix3::from_parts(
        Translation3::from(*origin),
        rotation,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::Sampler;

    /// Poses of frame n+1 whose tip `tool` sits on `fixed`, turned by up to
    /// `tilt` about random axes.
    fn pivoting(
        tool: Vector3<f64>,
        fixed: Vector3<f64>,
        tilt: f64,
        count: usize,
        sampler: &mut Sampler,
    ) -> Vec<IsometryMatrix3<f64>> {
        (0..count)
            .map(|_| {
                let axis = nalgebra::Unit::new_normalize(sampler.gaussian_vector(1.0));
                let rotation = Rotation3::from_axis_angle(&axis, sampler.uniform(-tilt, tilt))
                    * Rotation3::from_euler_angles(std::f64::consts::PI, 0.0, 0.3);
                IsometryMatrix3::from_parts(Translation3::from(fixed - rotation * tool), rotation)
            })
            .collect()
    }

    #[test]
    fn an_exact_pivot_gives_the_tip_to_a_micrometre_and_noise_its_sigma() {
        let (tool, fixed) = (
            Vector3::new(0.012, -0.03, 0.215),
            Vector3::new(0.9, 0.2, 0.35),
        );
        let mut sampler = Sampler::new(4);
        let exact = pivot(&pivoting(tool, fixed, 0.6, 8, &mut sampler)).expect("pivot");
        assert!((exact.tool - tool).norm() < 1e-9 && (exact.fixed - fixed).norm() < 1e-9);
        // σ = 20 µm on each pose's position: the tip within its stated σ,
        // over many trials.
        let (mut squared, mut stated, trials) = (0.0, 0.0, 300);
        for _ in 0..trials {
            let mut poses = pivoting(tool, fixed, 0.6, 8, &mut sampler);
            for pose in &mut poses {
                pose.translation.vector += sampler.gaussian_vector(2e-5);
            }
            let fit = pivot(&poses).expect("pivot");
            squared += (fit.tool - tool).norm_squared() / 3.0;
            stated += fit.tool_sigma * fit.tool_sigma;
        }
        let ratio = (squared / stated).sqrt();
        assert!((ratio - 1.0).abs() < 0.2, "tip error / stated σ = {ratio}");
    }

    #[test]
    fn too_few_or_too_alike_orientations_are_refused() {
        let mut sampler = Sampler::new(5);
        let (tool, fixed) = (Vector3::new(0.0, 0.0, 0.2), Vector3::new(1.0, 0.0, 0.3));
        let message = pivot(&pivoting(tool, fixed, 0.5, 3, &mut sampler)).expect_err("3");
        assert!(message.contains("at least 4"), "{message}");
        // Turned about the tool's own axis only.
        let about_z: Vec<IsometryMatrix3<f64>> = (0..6)
            .map(|i| {
                let rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), f64::from(i));
                IsometryMatrix3::from_parts(Translation3::from(fixed - rotation * tool), rotation)
            })
            .collect();
        let message = pivot(&about_z).expect_err("one axis");
        assert!(message.contains("not determined"), "{message}");
    }

    #[test]
    fn three_points_make_a_right_handed_frame() {
        let frame = frame_from_three(
            &Vector3::new(1.0, 2.0, 0.5),
            &Vector3::new(1.0, 2.5, 0.5),
            &Vector3::new(0.2, 2.1, 0.5),
        )
        .expect("frame");
        let m = frame.rotation.matrix();
        assert!((m.column(0) - Vector3::y()).norm() < 1e-12);
        assert!((m.column(1) + Vector3::x()).norm() < 1e-12);
        assert!((m.column(2) - Vector3::z()).norm() < 1e-12);
        assert!(frame_from_three(&Vector3::zeros(), &Vector3::x(), &(2.0 * Vector3::x())).is_err());
    }
}
