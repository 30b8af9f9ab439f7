//! The observation matrix W of a platform's measurements and its weighted
//! residuals (the module docs of [`super`] state the equations).

use faer::Mat;
use gecaro_core::gough_stewart::{GoughStewart, LEGS, PARAMETER_COUNT, PARAMETERS_PER_LEG};
use gecaro_data::sample::Sample;
use nalgebra::{Isometry3, Matrix3, Matrix6, SMatrix};

use super::measure::{PlatformMeasure, PlatformNoise};
use crate::Error;

/// The weighted system `W·Δξ ≈ r` of every measured configuration: each row
/// and its residual divided by the row's σ (1 m when no σ is stated), the
/// columns the [`PARAMETER_COUNT`] parameters.
pub(super) struct PlatformRows {
    /// W, rows × [`PARAMETER_COUNT`].
    pub(super) matrix: Mat<f64>,
    /// r: measured minus predicted (a point), or −Fᵢ (a leg), weighted.
    pub(super) residuals: Vec<f64>,
}

impl PlatformRows {
    /// The weighted cost `Σ r²`.
    pub(super) fn cost(&self) -> f64 {
        self.residuals.iter().map(|r| r * r).sum()
    }
}

/// The rows of `samples` at `platform`'s parameters. `poses` holds each
/// sample's last solved pose (the start of its next direct model: the
/// assembly mode kept, and few Newton steps); it is filled on the first
/// call.
///
/// # Errors
/// A sample without the measure's columns, or actuator values with no
/// pose ([`gecaro_core::Error::NoAssembly`], naming the sample's line).
pub(super) fn platform_rows(
    platform: &GoughStewart,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    poses: &mut Vec<Isometry3<f64>>,
) -> Result<PlatformRows, Error> {
    let per_sample = measure.rows_per_sample();
    let rows = samples.len() * per_sample;
    let mut matrix = Mat::<f64>::zeros(rows, PARAMETER_COUNT);
    let mut residuals = vec![0.0; rows];
    if poses.len() != samples.len() {
        *poses = vec![platform.home(); samples.len()];
    }
    for (index, (sample, start)) in samples.iter().zip(poses.iter_mut()).enumerate() {
        let actuators = actuator_values(sample)?;
        let measured = measure.measured(sample)?;
        let first = index * per_sample;
        match measure {
            PlatformMeasure::Pose => {
                let parameter_rows = platform.leg_parameter_rows(&measured, &actuators);
                let legs = platform.leg_residuals(&measured, &actuators);
                let vectors = platform.leg_vectors(&measured);
                for leg in 0..LEGS {
                    let sigma = noise.map_or(1.0, |noise| {
                        let arm = measured.rotation * platform.legs()[leg].platform;
                        noise.leg_variance(&arm, &vectors[leg].normalize()).sqrt()
                    });
                    let row = first + leg;
                    for (k, value) in parameter_rows[leg].iter().enumerate() {
                        matrix[(row, leg * PARAMETERS_PER_LEG + k)] = value / sigma;
                    }
                    residuals[row] = -legs[leg] / sigma;
                }
            }
            PlatformMeasure::Point => {
                let pose = platform
                    .direct(&actuators, start)
                    .map_err(|cause| located(sample, &cause))?;
                *start = pose;
                let sigma = noise.map_or(1.0, |noise| noise.length);
                let point = platform.tool_point(&pose);
                let derivative = point_derivative(platform, &pose, &actuators)
                    .ok_or_else(|| located(sample, &"the platform is singular there"))?;
                for axis in 0..3 {
                    let row = first + axis;
                    for column in 0..PARAMETER_COUNT {
                        matrix[(row, column)] = derivative[(axis, column)] / sigma;
                    }
                    residuals[row] = (measured.translation.vector[axis] - point[axis]) / sigma;
                }
            }
        }
    }
    Ok(PlatformRows { matrix, residuals })
}

/// A sample's six actuator values.
fn actuator_values(sample: &Sample) -> Result<[f64; LEGS], Error> {
    let values = sample.motor_positions.as_slice();
    <[f64; LEGS]>::try_from(values).map_err(|_| Error::InvalidData {
        line: sample.line,
        message: format!(
            "a Gough–Stewart platform has {LEGS} actuator values qm1…qm6, the sample has {}",
            values.len()
        ),
    })
}

/// A problem at a sample, with its line.
fn located(sample: &Sample, cause: &dyn std::fmt::Display) -> Error {
    Error::InvalidData {
        line: sample.line,
        message: format!("{cause}"),
    }
}

/// ∂y/∂ξ of the tool point y = p + R·t at the pose the actuators give:
/// `[I, −[R·t]×]·∂x/∂ξ` with `∂x/∂ξ = −J_x⁻¹·∂F/∂ξ`, plus R in the tool's
/// columns. `None` at a singular pose.
fn point_derivative(
    platform: &GoughStewart,
    pose: &Isometry3<f64>,
    actuators: &[f64; LEGS],
) -> Option<SMatrix<f64, 3, PARAMETER_COUNT>> {
    let inverse: Matrix6<f64> = platform.pose_jacobian(pose).try_inverse()?;
    let arm = pose.rotation * platform.tool();
    let mut to_point = SMatrix::<f64, 3, 6>::zeros();
    to_point
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&Matrix3::identity());
    to_point
        .fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-arm.cross_matrix()));
    // [I, −[R·t]×]·J_x⁻¹: the point's motion per unit of each leg's residual.
    let per_leg = to_point * inverse;
    let rows = platform.leg_parameter_rows(pose, actuators);
    let mut derivative = SMatrix::<f64, 3, PARAMETER_COUNT>::zeros();
    for leg in 0..LEGS {
        for (k, value) in rows[leg].iter().enumerate() {
            let column = leg * PARAMETERS_PER_LEG + k;
            for axis in 0..3 {
                derivative[(axis, column)] = -per_leg[(axis, leg)] * value;
            }
        }
    }
    derivative
        .fixed_view_mut::<3, 3>(0, LEGS * PARAMETERS_PER_LEG)
        .copy_from(pose.rotation.to_rotation_matrix().matrix());
    Some(derivative)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parallel_robots::{PlatformWorkspace, random_platform_poses, simulate_platform};
    use crate::simulation::Sampler;

    /// W of the point measure against central differences of the direct
    /// model's tool point.
    #[test]
    fn point_rows_match_finite_differences_of_the_direct_model() {
        let platform = gecaro_io::load_parallel_robot("hexapod")
            .expect("the ready hexapod")
            .platform;
        let mut sampler = Sampler::new(3);
        let poses =
            random_platform_poses(&platform, 4, PlatformWorkspace::of(&platform), &mut sampler)
                .expect("poses");
        let noise = PlatformNoise {
            length: 0.0,
            angle: 0.0,
        };
        let samples = simulate_platform(
            &platform,
            PlatformMeasure::Point,
            &poses,
            noise,
            &mut sampler,
        );
        let rows = platform_rows(
            &platform,
            &samples,
            PlatformMeasure::Point,
            None,
            &mut Vec::new(),
        )
        .expect("rows");
        let values = platform.parameters();
        let h = 1e-7;
        for column in 0..PARAMETER_COUNT {
            let points = |delta: f64| {
                let mut changed = values.clone();
                changed[column] += delta;
                let changed = platform.with_parameters(&changed).expect("platform");
                samples
                    .iter()
                    .flat_map(|sample| {
                        let actuators = actuator_values(sample).expect("six");
                        let pose = changed.direct(&actuators, &platform.home()).expect("pose");
                        changed
                            .tool_point(&pose)
                            .iter()
                            .copied()
                            .collect::<Vec<_>>()
                    })
                    .collect::<Vec<_>>()
            };
            let (plus, minus) = (points(h), points(-h));
            for row in 0..plus.len() {
                let numeric = (plus[row] - minus[row]) / (2.0 * h);
                let analytic = rows.matrix[(row, column)];
                assert!(
                    (numeric - analytic).abs() < 1e-6,
                    "row {row}, {}: {numeric} against {analytic}",
                    GoughStewart::parameter_names()[column]
                );
            }
        }
    }
}
