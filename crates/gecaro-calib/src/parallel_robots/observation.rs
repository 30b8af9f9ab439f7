//! The observation matrix W of a parallel robot's measurements and its
//! weighted residuals (the module docs of [`super`] state the equations).

use faer::{Mat, MatRef};
use gecaro_core::parallel_model::{
    Linearised, ParallelModel, SolvedPose, linearised_at, padded_inverse, solve_direct,
};
use gecaro_data::parallel::run_parts;
use gecaro_data::sample::Sample;
use nalgebra::{DMatrix, DVector, Isometry3, Matrix3, SMatrix};

use super::auxiliary::Auxiliary;
use super::leg::{LEG_UNKNOWNS, leg_reading};
use super::measure::{PlatformMeasure, PlatformNoise, check_pairs};
use super::stations::{STATION_UNKNOWNS, point_columns, pose_columns};
use crate::Error;
use crate::linalg::add_normal_sums;

/// The weighted observation matrix W of every measured configuration: each
/// row divided by its σ (1 m when no σ is stated), the columns the model's
/// parameters.
pub(super) struct PlatformRows {
    /// W, rows × parameters.
    pub(super) matrix: Mat<f64>,
}

/// The rows of `samples` at `model`'s parameters, held (for the rank
/// analysis of a few thousand configurations), with the columns of the
/// `auxiliary` unknowns after the parameters (stations' corrections, a
/// measuring leg: [`super::auxiliary`]).
/// `poses` holds each sample's last solved pose (the start of its next
/// direct model: the assembly mode kept, and few Newton steps); it is
/// filled on the first call.
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
    auxiliary: &Auxiliary,
    poses: &mut Vec<Isometry3<f64>>,
) -> Result<PlatformRows, Error> {
    check_samples(model, samples, measure)?;
    let per_observation = measure.rows_per_observation(model);
    let taken = measure.samples_per_observation();
    let columns = model.parameter_count() + auxiliary.count();
    let rows = measure.rows_for(model, samples.len());
    let mut matrix = Mat::<f64>::zeros(rows, columns);
    if poses.len() != samples.len() {
        *poses = starting_poses(model, samples, measure);
    }
    for (index, (observation, starts)) in samples
        .chunks_exact(taken)
        .zip(poses.chunks_exact_mut(taken))
        .enumerate()
    {
        let first = index * taken;
        let (block, _) = observation_rows(
            model,
            observation,
            measure,
            noise,
            (auxiliary, first),
            starts,
        )?;
        for row in 0..per_observation {
            for column in 0..columns {
                matrix[(index * per_observation + row, column)] = block[(row, column)];
            }
        }
    }
    Ok(PlatformRows { matrix })
}

/// The normal equations `WᵀW·Δξ = Wᵀr` of the weighted system and its cost
/// `Σ r²`, summed over the samples without holding W (10⁵ measured poses
/// are 6·10⁵ rows): on all cores, each row added on its non-zero columns
/// only (a leg's equation touches its own eight).
pub(super) struct NormalSystem {
    /// WᵀW (parameters × parameters).
    pub(super) gram: DMatrix<f64>,
    /// Wᵀr.
    pub(super) projected: DVector<f64>,
    /// Σ w r² (the rows weighted by their σ and their observation's
    /// robust weight w), and a prior's pseudo-observations' when it has
    /// them ([`prior_cost`](Self::prior_cost)).
    pub(super) cost: f64,
    /// The part of `cost` a prior's pseudo-observations make (0 without).
    pub(super) prior_cost: f64,
    /// Rows of W.
    pub(super) rows: usize,
    /// Each observation's residual: the RMS of its rows (in units of their
    /// σ; of 1 m without σ; not of its robust weight), in order — how far
    /// it stands out.
    pub(super) errors: Vec<f64>,
    /// Every row's residual, in the same units (not of its robust weight),
    /// in order: what a robust σ̂ is the spread of.
    pub(super) residuals: Vec<f64>,
}

/// Samples a part of the normal equations' sum takes: enough for its set-up
/// to be nothing, few enough for two cores to share evenly; even, so that
/// no pair of a distance is cut.
const PART_SAMPLES: usize = 2048;

/// Dense rows added to the normal equations at once.
const BATCH_ROWS: usize = 256;

/// See [`NormalSystem`]; `auxiliary` and `poses` as for [`platform_rows`];
/// `weights`, when given, each observation's robust weight w (its rows
/// multiplied by √w, iteratively reweighted least squares).
///
/// # Errors
/// As [`platform_rows`].
pub(super) fn normal_system<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    weights: Option<&[f64]>,
    auxiliary: &Auxiliary,
    poses: &mut Vec<Isometry3<f64>>,
) -> Result<NormalSystem, Error> {
    check_samples(model, samples, measure)?;
    let parameters = model.parameter_count();
    let columns = parameters + auxiliary.count();
    let stations = &auxiliary.stations;
    let taken = measure.samples_per_observation();
    if poses.len() != samples.len() {
        *poses = starting_poses(model, samples, measure);
    }
    let observations = samples.len() / taken;
    if let Some(weights) = weights
        && weights.len() != observations
    {
        return Err(Error::Numerical {
            message: format!(
                "{} robust weights for {observations} observations",
                weights.len()
            ),
        });
    }
    let parts: Vec<_> = samples
        .chunks(PART_SAMPLES)
        .zip(poses.chunks_mut(PART_SAMPLES))
        .enumerate()
        .map(|(part, (samples, starts))| {
            let first = part * PART_SAMPLES / taken;
            let own = weights.map(|weights| &weights[first..first + samples.len() / taken]);
            (part * PART_SAMPLES, samples, starts, own)
        })
        .collect();
    let sums = run_parts(parts, |(offset, samples, starts, weights)| {
        // √w of the part's observation `index`.
        let root = |index: usize| weights.map_or(1.0, |weights| weights[index].sqrt());
        let mut gram = DMatrix::<f64>::zeros(columns, columns);
        let mut projected = DVector::<f64>::zeros(columns);
        let mut cost = 0.0;
        // A point's rows wait in a batch (row-major), added as one product
        // `BᵀB` into the lower triangle of its own sums.
        let mut batch = vec![0.0; BATCH_ROWS * columns];
        let mut batch_right = vec![0.0; BATCH_ROWS];
        let mut lower = Mat::<f64>::zeros(columns, columns);
        let mut lower_right = Mat::<f64>::zeros(columns, 1);
        let mut filled = 0;
        // Each closure equation's own block of the normal equations, summed
        // apart (a leg's 8 × 8, with its station's correction 14 × 14) for
        // each station, and added into WᵀW once the part is done.
        let mut blocks: Vec<Vec<Vec<f64>>> = Vec::new();
        let mut block_rights: Vec<Vec<Vec<f64>>> = Vec::new();
        let mut extended: Vec<f64> = Vec::new();
        let mut errors: Vec<f64> = Vec::with_capacity(samples.len() / taken);
        let mut residuals: Vec<f64> = Vec::with_capacity(samples.len() / taken);
        let flush = |batch: &[f64],
                     right: &[f64],
                     filled: usize,
                     lower: &mut Mat<f64>,
                     lower_right: &mut Mat<f64>| {
            add_normal_sums(
                lower,
                lower_right,
                MatRef::from_row_major_slice(&batch[..filled * columns], filled, columns),
                MatRef::from_column_major_slice(&right[..filled], filled, 1),
            );
        };
        for (index, (observation, starts)) in samples
            .chunks_exact(taken)
            .zip(starts.chunks_exact_mut(taken))
            .enumerate()
        {
            let root = root(index);
            let first = offset + index * taken;
            // A closure equation is added on its own columns (a leg's
            // eight, and its station's correction), as the model visits it:
            // no matrix formed.
            if measure == PlatformMeasure::Pose {
                let sample = &observation[0];
                let actuators = actuator_values(model, sample)?;
                let measured = stations.corrected_measurement(first, &measure.measured(sample)?);
                let station = stations.station_of(first);
                if blocks.len() <= station {
                    blocks.resize_with(station + 1, Vec::new);
                    block_rights.resize_with(station + 1, Vec::new);
                }
                let (blocks, block_rights) = (&mut blocks[station], &mut block_rights[station]);
                let (mut squares, mut equations) = (0.0, 0usize);
                model.visit_equations(
                    &measured,
                    actuators,
                    &mut |equation, closure, by_pose, own| {
                        let sigma = noise.map_or(1.0, |noise| {
                            noise.closure_variance(by_pose.iter().copied()).sqrt()
                        });
                        squares += (closure / sigma).powi(2);
                        residuals.push(-closure / sigma);
                        let right = -closure * root / sigma;
                        cost += right * right;
                        equations += 1;
                        let own = if station == 0 {
                            own
                        } else {
                            extended.clear();
                            extended.extend_from_slice(own);
                            extended.extend(pose_columns(by_pose, &measured.translation.vector));
                            extended.as_slice()
                        };
                        let width = own.len();
                        if blocks.len() <= equation {
                            blocks.resize_with(equation + 1, Vec::new);
                            block_rights.resize_with(equation + 1, Vec::new);
                        }
                        let (block, block_right) =
                            (&mut blocks[equation], &mut block_rights[equation]);
                        if block.len() != width * width {
                            *block = vec![0.0; width * width];
                            *block_right = vec![0.0; width];
                        }
                        // w = own·√w/σ: the block += w·wᵀ and its right side
                        // += w·r, row by row on slices (vectorised).
                        let weight = root / sigma;
                        for ((row, value), projected) in block
                            .chunks_exact_mut(width)
                            .zip(own)
                            .zip(block_right.iter_mut())
                        {
                            let scaled = value * weight * weight;
                            *projected += value * weight * right;
                            for (entry, other) in row.iter_mut().zip(own) {
                                *entry += scaled * other;
                            }
                        }
                    },
                );
                errors.push((squares / equations.max(1) as f64).sqrt());
                continue;
            }
            // A point's coordinates involve every parameter, and wait in
            // the batch.
            let (block, right) = observation_rows(
                model,
                observation,
                measure,
                noise,
                (auxiliary, first),
                starts,
            )?;
            errors.push((right.norm_squared() / right.len().max(1) as f64).sqrt());
            residuals.extend(right.iter());
            for row in 0..block.nrows() {
                let weighted = right[row] * root;
                cost += weighted * weighted;
                for (entry, value) in batch[filled * columns..(filled + 1) * columns]
                    .iter_mut()
                    .zip(block.row(row).iter())
                {
                    *entry = *value * root;
                }
                batch_right[filled] = weighted;
                filled += 1;
                if filled == BATCH_ROWS {
                    flush(&batch, &batch_right, filled, &mut lower, &mut lower_right);
                    filled = 0;
                }
            }
        }
        if filled > 0 {
            flush(&batch, &batch_right, filled, &mut lower, &mut lower_right);
        }
        for i in 0..columns {
            projected[i] += lower_right[(i, 0)];
            for j in 0..=i {
                gram[(i, j)] += lower[(i, j)];
                if i != j {
                    gram[(j, i)] += lower[(i, j)];
                }
            }
        }
        for (station, (blocks, block_rights)) in blocks.iter().zip(&block_rights).enumerate() {
            let correction = match station {
                0 => 0..0,
                _ => {
                    let start = parameters + STATION_UNKNOWNS * (station - 1);
                    start..start + STATION_UNKNOWNS
                }
            };
            for (equation, (block, block_right)) in blocks.iter().zip(block_rights).enumerate() {
                let width = block_right.len();
                let own: Vec<usize> = model
                    .equation_parameters(equation)
                    .take(width - correction.len())
                    .chain(correction.clone())
                    .collect();
                for (a, i) in own.iter().enumerate() {
                    projected[*i] += block_right[a];
                    for (b, j) in own.iter().enumerate() {
                        gram[(*i, *j)] += block[a * width + b];
                    }
                }
            }
        }
        Ok::<_, Error>((gram, projected, cost, errors, residuals))
    });
    let mut system = NormalSystem {
        gram: DMatrix::zeros(columns, columns),
        projected: DVector::zeros(columns),
        cost: 0.0,
        prior_cost: 0.0,
        rows: measure.rows_for(model, samples.len()),
        errors: Vec::with_capacity(samples.len() / taken),
        residuals: Vec::with_capacity(measure.rows_for(model, samples.len())),
    };
    for part in sums {
        let (gram, projected, cost, errors, residuals) = part?;
        system.gram += gram;
        system.projected += projected;
        system.cost += cost;
        system.errors.extend(errors);
        system.residuals.extend(residuals);
    }
    Ok(system)
}

/// Where each sample's direct model starts when no pose was solved for it
/// yet: the home pose's orientation at the measured point (less the tool),
/// within a platform's error of the pose for a measured point (a few Newton
/// steps fewer than from home), else home itself.
fn starting_poses<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Vec<Isometry3<f64>> {
    let home = model.home();
    let arm = home.rotation * model.tool();
    samples
        .iter()
        .map(|sample| match (measure, sample.position) {
            (PlatformMeasure::Point, Some(point)) => {
                Isometry3::from_parts(nalgebra::Translation3::from(point - arm), home.rotation)
            }
            _ => home,
        })
        .collect()
}

/// What every job checks of `samples` before forming rows: a measure the
/// structure takes, and a distance's pairs whole.
fn check_samples(
    model: &impl ParallelModel,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<(), Error> {
    measure.check_for(model)?;
    if measure == PlatformMeasure::Distance {
        check_pairs(samples)?;
    }
    Ok(())
}

/// One observation's weighted rows of W and their residuals
/// ([`PlatformMeasure::samples_per_observation`] samples, the first the
/// data's sample `first`, with the `auxiliary` unknowns, `starts` their
/// last solved poses): see [`sample_rows`]; for a distance, the one
/// equation `u·(∂y_j/∂ξ − ∂y_i/∂ξ)·Δξ = D_measured − D` with `d = y_j − y_i`,
/// `D = ‖d‖`, `u = d/D` (eq. 19–20 of the serial robots, divided by 2D).
pub(super) fn observation_rows<M: ParallelModel>(
    model: &M,
    observation: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    (auxiliary, first): (&Auxiliary, usize),
    starts: &mut [Isometry3<f64>],
) -> Result<(DMatrix<f64>, DVector<f64>), Error> {
    if measure != PlatformMeasure::Distance {
        return sample_rows(
            model,
            &observation[0],
            measure,
            noise,
            (auxiliary, first),
            &mut starts[0],
        );
    }
    let mut points = [nalgebra::Vector3::zeros(); 2];
    let mut derivatives = Vec::with_capacity(2);
    for ((sample, start), point) in observation.iter().zip(starts.iter_mut()).zip(&mut points) {
        let (pose, derivative) = solved_point(model, sample, start)?;
        *point = model.tool_point(&pose);
        derivatives.push(derivative);
    }
    let difference = points[1] - points[0];
    let length = difference.norm();
    if length <= f64::EPSILON {
        return Err(located(
            &observation[1],
            &"the pair's two configurations put the tool point at one place: a distance of \
              zero says nothing of the parameters",
        ));
    }
    let direction = (difference / length).transpose();
    let sigma = noise.map_or(1.0, |noise| noise.length);
    // A distance has no frame: no correction's columns, zero.
    let mut rows = DMatrix::zeros(1, derivatives[0].ncols() + auxiliary.count());
    rows.columns_mut(0, derivatives[0].ncols())
        .copy_from(&(direction * (&derivatives[1] - &derivatives[0]) / sigma));
    let measured = observation[0].distance.unwrap_or(f64::NAN);
    Ok((rows, DVector::from_element(1, (measured - length) / sigma)))
}

/// One sample's weighted rows of W and their residuals: the closure
/// equations at its measured pose (each divided by the σ a measured pose's
/// noise gives it), or its tool point's coordinates through the direct
/// model from `start` (which is moved to the pose found); the measurement
/// corrected by its station's correction, whose columns follow the
/// parameters' (the data's sample `index`, the `auxiliary` unknowns); or a
/// measuring leg's equation ([`leg_rows`]).
fn sample_rows<M: ParallelModel>(
    model: &M,
    sample: &Sample,
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    (auxiliary, index): (&Auxiliary, usize),
    start: &mut Isometry3<f64>,
) -> Result<(DMatrix<f64>, DVector<f64>), Error> {
    let stations = &auxiliary.stations;
    let parameters = model.parameter_count();
    let correction = stations.first_column(index, parameters);
    // A measurement in the base frame, by its station's correction.
    let measured = || -> Result<Isometry3<f64>, Error> {
        Ok(stations.corrected_measurement(index, &measure.measured(sample)?))
    };
    match measure {
        PlatformMeasure::Leg => leg_rows(model, sample, noise, auxiliary, start),
        PlatformMeasure::Pose => {
            let actuators = actuator_values(model, sample)?;
            let measured = measured()?;
            let Linearised {
                closure,
                by_pose,
                by_parameter,
            } = model.linearised(&measured, actuators);
            let mut rows = with_columns(by_parameter, parameters + auxiliary.count());
            if let Some(column) = correction {
                for equation in 0..rows.nrows() {
                    let row: Vec<f64> = by_pose.row(equation).iter().copied().collect();
                    let coefficients = pose_columns(&row, &measured.translation.vector);
                    for (offset, value) in coefficients.into_iter().enumerate() {
                        rows[(equation, column + offset)] = value;
                    }
                }
            }
            let mut right = -closure;
            for equation in 0..rows.nrows() {
                let sigma = noise.map_or(1.0, |noise| {
                    noise
                        .closure_variance(by_pose.row(equation).iter().copied())
                        .sqrt()
                });
                rows.row_mut(equation).unscale_mut(sigma);
                right[equation] /= sigma;
            }
            Ok((rows, right))
        }
        PlatformMeasure::Point | PlatformMeasure::Distance => {
            let measured = measured()?;
            let (pose, derivative) = solved_point(model, sample, start)?;
            let sigma = noise.map_or(1.0, |noise| noise.length);
            let point = model.tool_point(&pose);
            let mut rows = with_columns(derivative, parameters + auxiliary.count());
            if let Some(column) = correction {
                rows.fixed_view_mut::<3, STATION_UNKNOWNS>(0, column)
                    .copy_from(&point_columns(&measured.translation.vector));
            }
            rows.unscale_mut(sigma);
            let right = DVector::from_fn(3, |axis, _| {
                (measured.translation.vector[axis] - point[axis]) / sigma
            });
            Ok((rows, right))
        }
    }
}

/// `rows` widened to `columns` with zeros (the auxiliary unknowns'), as
/// they are when there are none: no copy on the fit's common path.
fn with_columns(rows: DMatrix<f64>, columns: usize) -> DMatrix<f64> {
    if rows.ncols() == columns {
        rows
    } else {
        rows.resize_horizontally(columns, 0.0)
    }
}

/// The pose a sample's actuator values put the platform at, by the direct
/// model from `start` (moved to it), and the tool point's derivative there.
///
/// # Errors
/// Actuator values with no pose or a singular one, naming the line.
fn solved_point<M: ParallelModel>(
    model: &M,
    sample: &Sample,
    start: &mut Isometry3<f64>,
) -> Result<(Isometry3<f64>, DMatrix<f64>), Error> {
    let actuators = actuator_values(model, sample)?;
    let solved = solve_direct(model, actuators, start).map_err(|cause| located(sample, &cause))?;
    *start = solved.pose;
    let derivative = point_derivative_of(model, &solved)
        .ok_or_else(|| located(sample, &"the platform is singular there"))?;
    Ok((solved.pose, derivative))
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
/// with `∂x/∂ξ = −J_x⁻¹·∂F/∂ξ`, plus R in the tool's columns. Each
/// equation's own coefficients are visited ([`ParallelModel::visit_equations`]):
/// its columns are `−[I, −[R·t]×]·J_x⁻¹[:, e]` times them, and J_x is
/// inverted on the stack ([`padded_inverse`]). `None` at a singular pose.
pub(super) fn point_derivative<M: ParallelModel>(
    model: &M,
    pose: &Isometry3<f64>,
    actuators: &[f64],
) -> Option<DMatrix<f64>> {
    point_derivative_of(model, &linearised_at(model, pose, actuators).1)
}

/// [`point_derivative`] from a pose the direct model solved, with the
/// linearisation of its last visit ([`solve_direct`]): no visit more.
fn point_derivative_of<M: ParallelModel>(model: &M, solved: &SolvedPose) -> Option<DMatrix<f64>> {
    let mut to_point = SMatrix::<f64, 3, 6>::zeros();
    to_point
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&Matrix3::identity());
    if model.pose_freedom() == 6 {
        let arm = solved.pose.rotation * model.tool();
        to_point
            .fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-arm.cross_matrix()));
    }
    let mut derivative = through_pose(model, solved, &to_point)?;
    let tool = model.tool_parameters();
    derivative
        .view_mut((0, tool.start), (3, 3))
        .copy_from(solved.pose.rotation.to_rotation_matrix().matrix());
    Some(derivative)
}

/// `by_pose·∂x/∂ξ` of quantities whose derivative with respect to the
/// pose is `by_pose` (rows × `[δp; ω]`), at a pose the direct model solved:
/// `∂x/∂ξ = −J_x⁻¹·∂F/∂ξ` (the implicit function theorem), each equation's
/// own coefficients visited once and `J_x` inverted on the stack
/// ([`padded_inverse`]). `None` at a singular pose.
fn through_pose<M: ParallelModel, const R: usize>(
    model: &M,
    solved: &SolvedPose,
    by_pose: &SMatrix<f64, R, 6>,
) -> Option<DMatrix<f64>> {
    let SolvedPose {
        jacobian,
        coefficients,
        ends,
        ..
    } = solved;
    let inverse = padded_inverse(jacobian, model.pose_freedom())?;
    // Column e: the quantities' move per unit of equation e's residual.
    let along = -(by_pose * inverse);
    let mut derivative = DMatrix::<f64>::zeros(R, model.parameter_count());
    let mut start = 0;
    for (equation, end) in ends.iter().take(model.actuator_count()).enumerate() {
        let direction = along.column(equation);
        for (value, column) in coefficients[start..*end]
            .iter()
            .zip(model.equation_parameters(equation))
        {
            for row in 0..R {
                derivative[(row, column)] += direction[row] * value;
            }
        }
        start = *end;
    }
    Some(derivative)
}

/// A measuring leg's weighted row and residual at a sample (its reading in
/// `distance`): the platform's pose by the direct model from `start`
/// (moved to it), then `G` of [`super::leg`] linearised through it, the
/// leg's own columns after the stations' corrections.
///
/// # Errors
/// No leg stated, a sample without its reading, actuator values with no
/// pose or a singular one (naming the line).
fn leg_rows<M: ParallelModel>(
    model: &M,
    sample: &Sample,
    noise: Option<PlatformNoise>,
    auxiliary: &Auxiliary,
    start: &mut Isometry3<f64>,
) -> Result<(DMatrix<f64>, DVector<f64>), Error> {
    let leg = auxiliary.leg.ok_or_else(|| Error::InvalidOption {
        setting: crate::Setting::Method,
        message: "the leg measure needs the measuring leg's mount".into(),
    })?;
    let reading = leg_reading(sample)?;
    let actuators = actuator_values(model, sample)?;
    let solved = solve_direct(model, actuators, start).map_err(|cause| located(sample, &cause))?;
    *start = solved.pose;
    let (closure, by_pose, own) = leg.equation(&solved.pose, reading, model.pose_freedom());
    let derivative = through_pose(
        model,
        &solved,
        &SMatrix::<f64, 1, 6>::from_row_slice(&by_pose),
    )
    .ok_or_else(|| located(sample, &"the platform is singular there"))?;
    let parameters = model.parameter_count();
    let mut rows = derivative.resize_horizontally(parameters + auxiliary.count(), 0.0);
    let column = auxiliary.leg_column(parameters);
    for (offset, value) in own.into_iter().enumerate().take(LEG_UNKNOWNS) {
        rows[(0, column + offset)] = value;
    }
    let sigma = noise.map_or(1.0, |noise| noise.length);
    rows.unscale_mut(sigma);
    Ok((rows, DVector::from_element(1, -closure / sigma)))
}

#[cfg(test)]
mod tests {
    use gecaro_core::parallel_robot::ParallelRobot;

    use super::*;
    use crate::parallel_robots::stations::StationFrames;
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
                &Auxiliary::none(),
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

    /// The columns of a second station's correction against central
    /// differences of the residuals: `W·Δ = r` with `W = −∂r/∂δ`, for
    /// measured poses and points (unweighted: a pose's row σ moves with
    /// the pose, which Gauss–Newton's rows leave out).
    #[test]
    fn station_columns_match_finite_differences() {
        let model: ParallelRobot = gecaro_io::load_parallel_robot("hexapod")
            .expect("a ready parallel robot")
            .robot;
        let mut sampler = Sampler::new(5);
        let poses = random_platform_poses(&model, 3, PlatformWorkspace::of(&model), &mut sampler)
            .expect("poses");
        let noise = PlatformNoise {
            length: 2e-5,
            angle: 3e-5,
        };
        for measure in [PlatformMeasure::Pose, PlatformMeasure::Point] {
            let samples =
                simulate_platform(&model, measure, &poses, noise, &mut sampler).expect("samples");
            let stations = Auxiliary {
                stations: StationFrames::new(vec![0, 1, 1]),
                leg: None,
            };
            let parameters = model.parameter_count();
            let rows = platform_rows(&model, &samples, measure, None, &stations, &mut Vec::new())
                .expect("rows");
            let residuals = |correction: &[f64]| -> Vec<f64> {
                let moved = stations.at(correction);
                let mut starts = vec![model.home(); samples.len()];
                (0..samples.len())
                    .flat_map(|index| {
                        observation_rows(
                            &model,
                            &samples[index..=index],
                            measure,
                            None,
                            (&moved, index),
                            &mut starts[index..=index],
                        )
                        .expect("rows")
                        .1
                        .iter()
                        .copied()
                        .collect::<Vec<_>>()
                    })
                    .collect()
            };
            let h = 1e-7;
            for unknown in 0..STATION_UNKNOWNS {
                let mut plus = [0.0; STATION_UNKNOWNS];
                plus[unknown] = h;
                let mut minus = [0.0; STATION_UNKNOWNS];
                minus[unknown] = -h;
                let (up, down) = (residuals(&plus), residuals(&minus));
                for row in 0..up.len() {
                    let numeric = -(up[row] - down[row]) / (2.0 * h);
                    let analytic = rows.matrix[(row, parameters + unknown)];
                    let tolerance = 1e-5 * (1.0 + numeric.abs());
                    assert!(
                        (numeric - analytic).abs() < tolerance,
                        "{measure:?} row {row}, unknown {unknown}: {numeric} against {analytic}"
                    );
                }
            }
            // The first station's rows have no correction.
            let first_rows = measure.rows_per_observation(&model);
            for row in 0..first_rows {
                for unknown in 0..STATION_UNKNOWNS {
                    assert_eq!(rows.matrix[(row, parameters + unknown)], 0.0);
                }
            }
        }
    }

    /// A measuring leg's row against central differences of its residual:
    /// on the platform's parameters (through the direct model) and on the
    /// leg's own `a, b, l`.
    #[test]
    fn leg_rows_match_finite_differences() {
        use crate::parallel_robots::MeasuringLeg;
        let model: ParallelRobot = gecaro_io::load_parallel_robot("hexapod")
            .expect("a ready parallel robot")
            .robot;
        let leg = MeasuringLeg {
            base: nalgebra::Vector3::new(0.25, -0.1, 0.0),
            platform: nalgebra::Vector3::new(-0.12, 0.08, 0.0),
            length: 0.6,
            gain: 1.0,
        };
        let mut sampler = Sampler::new(7);
        let poses = random_platform_poses(&model, 3, PlatformWorkspace::of(&model), &mut sampler)
            .expect("poses");
        let exact = PlatformNoise {
            length: 0.0,
            angle: 0.0,
        };
        let samples =
            crate::parallel_robots::simulate_leg(&model, &leg, &poses, exact, &mut sampler)
                .expect("readings");
        let auxiliary = Auxiliary {
            stations: crate::parallel_robots::stations::StationFrames::single(),
            leg: Some(leg),
        };
        let rows = platform_rows(
            &model,
            &samples,
            PlatformMeasure::Leg,
            None,
            &auxiliary,
            &mut Vec::new(),
        )
        .expect("rows");
        let parameters = model.parameter_count();
        let mut values = model.parameters();
        values.extend(auxiliary.start());
        let residuals = |values: &[f64]| -> Vec<f64> {
            let robot = model.with_parameters(&values[..parameters]).expect("model");
            let moved = auxiliary.at(&values[parameters..]);
            let mut starts = vec![model.home(); samples.len()];
            (0..samples.len())
                .map(|index| {
                    observation_rows(
                        &robot,
                        &samples[index..=index],
                        PlatformMeasure::Leg,
                        None,
                        (&moved, index),
                        &mut starts[index..=index],
                    )
                    .expect("rows")
                    .1[0]
                })
                .collect()
        };
        let h = 1e-7;
        for column in 0..values.len() {
            let step = |delta: f64| {
                let mut changed = values.clone();
                changed[column] += delta;
                residuals(&changed)
            };
            let (up, down) = (step(h), step(-h));
            for row in 0..up.len() {
                let numeric = -(up[row] - down[row]) / (2.0 * h);
                let analytic = rows.matrix[(row, column)];
                assert!(
                    (numeric - analytic).abs() < 1e-6 * (1.0 + numeric.abs()),
                    "row {row}, column {column}: {numeric} against {analytic}"
                );
            }
        }
    }
}
