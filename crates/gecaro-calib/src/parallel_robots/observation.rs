//! The observation matrix W of a parallel robot's measurements and its
//! weighted residuals (the module docs of [`super`] state the equations).

use faer::Mat;
use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;
use nalgebra::{DMatrix, Isometry3, Matrix3};

use super::measure::{PlatformMeasure, PlatformNoise};
use crate::Error;

/// The weighted system `W·Δξ ≈ r` of every measured configuration: each row
/// and its residual divided by the row's σ (1 m when no σ is stated), the
/// columns the model's parameters.
pub(super) struct PlatformRows {
    /// W, rows × parameters.
    pub(super) matrix: Mat<f64>,
    /// r: measured minus predicted (a point), or −Fᵢ (a closure equation),
    /// weighted.
    pub(super) residuals: Vec<f64>,
}

impl PlatformRows {
    /// The weighted cost `Σ r²`.
    pub(super) fn cost(&self) -> f64 {
        self.residuals.iter().map(|r| r * r).sum()
    }
}

/// The rows of `samples` at `model`'s parameters. `poses` holds each
/// sample's last solved pose (the start of its next direct model: the
/// assembly mode kept, and few Newton steps); it is filled on the first
/// call.
///
/// # Errors
/// A measure the structure cannot take, a sample without the measure's
/// columns or with another number of actuator values, or actuator values
/// with no pose (naming the sample's line).
pub(super) fn platform_rows<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    poses: &mut Vec<Isometry3<f64>>,
) -> Result<PlatformRows, Error> {
    measure.check_for(model)?;
    let per_sample = measure.rows_per_sample(model);
    let columns = model.parameters().len();
    let rows = samples.len() * per_sample;
    let mut matrix = Mat::<f64>::zeros(rows, columns);
    let mut residuals = vec![0.0; rows];
    if poses.len() != samples.len() {
        *poses = vec![model.home(); samples.len()];
    }
    for (index, (sample, start)) in samples.iter().zip(poses.iter_mut()).enumerate() {
        let actuators = actuator_values(model, sample)?;
        let measured = measure.measured(sample)?;
        let first = index * per_sample;
        match measure {
            PlatformMeasure::Pose => {
                let closure = model.closure(&measured, actuators);
                let by_pose = model.pose_jacobian(&measured, actuators);
                let by_parameter = model.parameter_jacobian(&measured, actuators);
                for equation in 0..per_sample {
                    let sigma = noise.map_or(1.0, |noise| {
                        let row: Vec<f64> = by_pose.row(equation).iter().copied().collect();
                        noise.closure_variance(&row).sqrt()
                    });
                    for column in 0..columns {
                        matrix[(first + equation, column)] =
                            by_parameter[(equation, column)] / sigma;
                    }
                    residuals[first + equation] = -closure[equation] / sigma;
                }
            }
            PlatformMeasure::Point => {
                let pose = model
                    .direct(actuators, start)
                    .map_err(|cause| located(sample, &cause))?;
                *start = pose;
                let sigma = noise.map_or(1.0, |noise| noise.length);
                let point = model.tool_point(&pose);
                let derivative = point_derivative(model, &pose, actuators)
                    .ok_or_else(|| located(sample, &"the platform is singular there"))?;
                for axis in 0..3 {
                    for column in 0..columns {
                        matrix[(first + axis, column)] = derivative[(axis, column)] / sigma;
                    }
                    residuals[first + axis] =
                        (measured.translation.vector[axis] - point[axis]) / sigma;
                }
            }
        }
    }
    Ok(PlatformRows { matrix, residuals })
}

/// A sample's actuator values, as many as the model has.
pub(super) fn actuator_values<'a>(
    model: &impl ParallelModel,
    sample: &'a Sample,
) -> Result<&'a [f64], Error> {
    let values = sample.motor_positions.as_slice();
    if values.len() == model.actuator_count() {
        Ok(values)
    } else {
        Err(Error::InvalidData {
            line: sample.line,
            message: format!(
                "{} has {} actuator values qm1…qm{}, the sample has {}",
                model.name(),
                model.actuator_count(),
                model.actuator_count(),
                values.len()
            ),
        })
    }
}

/// A problem at a sample, with its line.
fn located(sample: &Sample, cause: &dyn std::fmt::Display) -> Error {
    Error::InvalidData {
        line: sample.line,
        message: format!("{cause}"),
    }
}

/// ∂y/∂ξ of the tool point y = p + R·t at the pose the actuators give:
/// `[I, −[R·t]×]·∂x/∂ξ` (`I` alone for a platform that only translates)
/// with `∂x/∂ξ = −J_x⁻¹·∂F/∂ξ`, plus R in the tool's columns. `None` at a
/// singular pose.
fn point_derivative<M: ParallelModel>(
    model: &M,
    pose: &Isometry3<f64>,
    actuators: &[f64],
) -> Option<DMatrix<f64>> {
    let freedom = model.pose_freedom();
    let inverse = model.pose_jacobian(pose, actuators).try_inverse()?;
    let by_pose = -(inverse * model.parameter_jacobian(pose, actuators));
    let mut to_point = DMatrix::<f64>::zeros(3, freedom);
    to_point
        .view_mut((0, 0), (3, 3))
        .copy_from(&Matrix3::identity());
    if freedom == 6 {
        let arm = pose.rotation * model.tool();
        to_point
            .view_mut((0, 3), (3, 3))
            .copy_from(&(-arm.cross_matrix()));
    }
    let mut derivative = to_point * by_pose;
    let tool = model.tool_parameters();
    derivative
        .view_mut((0, tool.start), (3, 3))
        .copy_from(pose.rotation.to_rotation_matrix().matrix());
    Some(derivative)
}

#[cfg(test)]
mod tests {
    use gecaro_core::parallel_robot::ParallelRobot;

    use super::*;
    use crate::parallel_robots::{PlatformWorkspace, random_platform_poses, simulate_platform};
    use crate::simulation::Sampler;

    /// W of the point measure against central differences of the direct
    /// model's tool point, for both structures.
    #[test]
    fn point_rows_match_finite_differences_of_the_direct_model() {
        for name in ["hexapod", "delta"] {
            let model: ParallelRobot = gecaro_io::load_parallel_robot(name)
                .expect("a ready parallel robot")
                .robot;
            let mut sampler = Sampler::new(3);
            let poses =
                random_platform_poses(&model, 4, PlatformWorkspace::of(&model), &mut sampler)
                    .expect("poses");
            let exact = PlatformNoise {
                length: 0.0,
                angle: 0.0,
            };
            let samples =
                simulate_platform(&model, PlatformMeasure::Point, &poses, exact, &mut sampler)
                    .expect("samples");
            let rows = platform_rows(
                &model,
                &samples,
                PlatformMeasure::Point,
                None,
                &mut Vec::new(),
            )
            .expect("rows");
            let values = model.parameters();
            let h = 1e-7;
            for column in 0..values.len() {
                let points = |delta: f64| {
                    let mut changed = values.clone();
                    changed[column] += delta;
                    let changed = model.with_parameters(&changed).expect("model");
                    samples
                        .iter()
                        .flat_map(|sample| {
                            let actuators = actuator_values(&model, sample).expect("values");
                            let pose = changed.direct(actuators, &model.home()).expect("pose");
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
                        "{name} row {row}, {}: {numeric} against {analytic}",
                        model.parameter_names()[column]
                    );
                }
            }
        }
    }
}
