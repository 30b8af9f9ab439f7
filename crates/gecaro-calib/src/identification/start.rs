//! A start that converges from anywhere: a closed-form guess of the
//! measurement frame and of the tool point before the iterations.
//!
//! The identification linearises around the nominal robot (eq. 6). A laser
//! tracker stands wherever it was put, and a robot file rarely says where:
//! 2 m away and turned 90°, the nominal is far outside the linearisation,
//! and Gauss–Newton stops in a wrong minimum. So, for the sets that measure
//! points in the world frame (position and frame measure), with the nominal
//! flange poses `(R_i, t_i)` and the measured points `P_i`, the model
//! `P_i = R_b (R_i p + t_i) + t_b` is fitted for the measurement frame
//! `(R_b, t_b)` and the tool point `p` (in the nominal frame n+1) by
//! alternating two exact steps: Horn/Kabsch for `(R_b, t_b)` given `p` (the
//! SVD of the 3×3 cross-covariance of the centred points), then least squares
//! for `p` given `(R_b, t_b)`, which is the mean of `R_iᵀ R_bᵀ (P_i − R_b t_i
//! − t_b)` since the `R_b R_i` are rotations. The robot re-framed by them
//! ([`Robot::reframed`]: frames 0, 1, n and n+1) is the start when the
//! nominal misplaces the measurement frame or the tool point by more than
//! 10 cm or 10° and the start at least halves the nominal's RMS error on
//! these points; otherwise the nominal is (a near nominal converges as the
//! paper's scheme does, to the same numbers as before). Sets that name a
//! tool or a station ([`crate::frames`]) take no part: their frames start
//! from the poses the study states. At most [`MAXIMUM_POINTS`] points,
//! evenly spread over the data, take part. Where the sets measure
//! orientations (frame measure), the tool's rotation `R_t` is fitted too:
//! the rotation closest to every `(R_b R_i)ᵀ Q_i` (`Q_i` the measured
//! orientation; the SVD projection of their sum), so that a tool stated
//! half a turn off about the flange's axis starts where it is rather than
//! drifting into an implausible θ of frame n+1; the start is then also
//! taken when it halves the RMS orientation error. The priority matrix is
//! honoured: a base (frames 0 and 1) or a tool (frame n+1) whose every
//! parameter it holds at priority 0 stays where the robot file states it,
//! and only the other is fitted.

use gecaro_core::{ChainBuffer, KinematicModel, PriorityMatrix, Robot};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};

use super::subsample::spread_points;
use crate::Error;
use crate::registration::rigid_fit;
use crate::sampler::spread_indices;
use crate::study::Study;

/// Alternations at most.
const ROUNDS: usize = 30;
/// The start must at least divide the nominal's RMS error by this.
const IMPROVEMENT: f64 = 2.0;
/// The start is for a measurement frame or tool point that the nominal
/// misplaces by more than this (metres)…
const FAR_LENGTH: f64 = 0.1;
/// …or turns by more than this (radians, 10°); nearer ones are within the
/// paper's linearisation, and start from the nominal as before.
const FAR_ANGLE: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Points needed (three non-collinear ones fix a rigid transform).
const MINIMUM_POINTS: usize = 4;
/// Points used at most, evenly spread over the data: a start needs no more
/// (the iterations then fit every point), and the forward models of 5,000
/// configurations and the alternations over them were a tenth of a whole
/// identification at m = 5000.
const MAXIMUM_POINTS: usize = 500;

/// The re-framed robot to start from, or `None` when the nominal is as
/// good (see the module docs).
///
/// # Errors
/// A configuration that does not fit the robot.
pub(super) fn closed_form_start(
    robot: &Robot,
    study: &Study,
    priority: &PriorityMatrix,
) -> Result<Option<Robot>, Error> {
    // What the priority matrix lets be identified: the base (frames 0
    // and 1) and the tool (frame n+1); what it holds stays as stated.
    let free = |frames: &[usize]| {
        robot
            .parameters()
            .ids()
            .iter()
            .any(|id| frames.contains(&id.frame) && priority.get(*id) > 0)
    };
    let tool_frame = robot.frames().len() - 1;
    let (fit_base, fit_tool) = (free(&[0, 1]), free(&[tool_frame]));
    if !(fit_base || fit_tool) {
        return Ok(None);
    }
    // Sets with a named tool or station measure another point or in another
    // frame; their frames start from their stated poses.
    let slices: Vec<_> = study
        .sets
        .iter()
        .filter(|set| !set.uses_named_frames())
        .map(|set| set.samples.as_slice())
        .collect();
    let picked = spread_points(&slices, MAXIMUM_POINTS);
    if picked.len() < MINIMUM_POINTS {
        return Ok(None);
    }
    let mut flanges = Vec::new();
    let mut measured = Vec::new();
    let model = KinematicModel::new(robot);
    let mut chain = ChainBuffer::default();
    for (motors, point) in picked {
        flanges.push(model.terminal_pose(motors, &mut chain)?);
        measured.push(point);
    }
    // The measured orientations of frame n+1, where the sets hold them.
    let mut oriented = Vec::new();
    for slice in &slices {
        for index in spread_indices(slice.len(), MAXIMUM_POINTS) {
            let sample = slice.get(index);
            if let Some(orientation) = sample.orientation() {
                let flange = model.terminal_pose(sample.motor_positions(), &mut chain)?;
                oriented.push((flange.rotation, orientation.to_rotation_matrix()));
            }
        }
    }
    let nominal_rms = rms(
        &flanges,
        &measured,
        &IsometryMatrix3::identity(),
        &Vector3::zeros(),
    );
    let mut tool = Vector3::zeros();
    let mut base = IsometryMatrix3::identity();
    for _ in 0..ROUNDS {
        let model: Vec<Vector3<f64>> = flanges
            .iter()
            .map(|flange| flange.rotation * tool + flange.translation.vector)
            .collect();
        if fit_base {
            base = rigid_fit(&model, &measured);
        }
        if !fit_tool {
            break;
        }
        let next = flanges
            .iter()
            .zip(&measured)
            .map(|(flange, point)| {
                flange.rotation.inverse()
                    * (base.rotation.inverse() * (point - base.translation.vector)
                        - flange.translation.vector)
            })
            .sum::<Vector3<f64>>()
            / measured.len() as f64;
        let moved = (next - tool).norm();
        tool = next;
        if moved < 1e-12 {
            break;
        }
    }
    let start_rms = rms(&flanges, &measured, &base, &tool);
    // The tool's rotation, where orientations are measured: the rotation
    // R_t closest to every (R_b R_i)ᵀ Q_i (its chordal mean).
    let tool_rotation = mean_rotation(
        oriented
            .iter()
            .map(|(flange, measured)| (base.rotation * flange).inverse() * measured),
    )
    .filter(|_| fit_tool);
    let angles = |tool: &Rotation3<f64>, base: &Rotation3<f64>| {
        let squares: f64 = oriented
            .iter()
            .map(|(flange, measured)| {
                let predicted = base * flange * tool;
                (predicted.inverse() * measured).angle().powi(2)
            })
            .sum();
        (squares / oriented.len().max(1) as f64).sqrt()
    };
    let (nominal_angles, start_angles) = match tool_rotation {
        Some(rotation) => (
            angles(&Rotation3::identity(), &Rotation3::identity()),
            angles(&rotation, &base.rotation),
        ),
        None => (0.0, 0.0),
    };
    let tool_rotation = tool_rotation.unwrap_or_else(Rotation3::identity);
    let far = base.translation.vector.norm() > FAR_LENGTH
        || base.rotation.angle() > FAR_ANGLE
        || tool.norm() > FAR_LENGTH
        || tool_rotation.angle() > FAR_ANGLE;
    let better = (start_rms.is_finite() && start_rms * IMPROVEMENT <= nominal_rms)
        || (!oriented.is_empty()
            && start_angles.is_finite()
            && start_angles * IMPROVEMENT <= nominal_angles);
    if !(far && better) {
        return Ok(None);
    }
    let new_tool = IsometryMatrix3::from_parts(Translation3::from(tool), tool_rotation);
    Ok(robot.reframed(&base, &new_tool).ok())
}

/// The rotation closest to `rotations` in the chordal sense (the SVD
/// projection of their sum onto SO(3)); `None` without any.
fn mean_rotation(rotations: impl Iterator<Item = Rotation3<f64>>) -> Option<Rotation3<f64>> {
    let mut sum = nalgebra::Matrix3::<f64>::zeros();
    let mut count = 0;
    for rotation in rotations {
        sum += rotation.matrix();
        count += 1;
    }
    if count == 0 {
        return None;
    }
    let svd = sum.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut correction = nalgebra::Matrix3::<f64>::identity();
    correction[(2, 2)] = (u * v_t).determinant().signum();
    Some(Rotation3::from_matrix_unchecked(u * correction * v_t))
}

/// RMS distance between the measured points and the model's.
fn rms(
    flanges: &[IsometryMatrix3<f64>],
    measured: &[Vector3<f64>],
    base: &IsometryMatrix3<f64>,
    tool: &Vector3<f64>,
) -> f64 {
    let squares: f64 = flanges
        .iter()
        .zip(measured)
        .map(|(flange, point)| (base * (flange * nalgebra::Point3::from(*tool))).coords - point)
        .map(|error| error.norm_squared())
        .sum();
    (squares / measured.len() as f64).sqrt()
}

/// A measured point of a set with named frames: its station and tool
/// (indices into the study's frames), the nominal pose of the tool frame
/// n+1, and the point measured (in the station's frame).
type FramedPoint = (
    Option<usize>,
    Option<usize>,
    IsometryMatrix3<f64>,
    Vector3<f64>,
);

/// What the closed-form registration of a study's named frames found: the
/// study with its stations and tools re-stated there, and, when the data's
/// world frame stands far from the nominal robot's base, the robot's base in
/// it (`new_world_from_old_world` of [`Robot::reframed`]).
pub(super) struct Registered {
    /// The study, its named frames at the fitted poses.
    pub(super) study: Study,
    /// Where the robot stands in the world frame of the data, when the
    /// nominal's base is far from it.
    pub(super) base: Option<IsometryMatrix3<f64>>,
}

/// The study with its named stations and tools stated where a closed-form
/// fit puts them, and the robot's base in the data's world frame, or `None`
/// when all are stated near enough (see the module docs for the
/// conditions) or no frame is named.
///
/// A set that names a station measures points `Y_i = S⁻¹ F_i p` in the
/// station's frame, `F_i` the nominal pose of the tool frame n+1, `p` the
/// measured point in that frame (the set's tool, or its origin); a set
/// without one measures in the world frame, `Y_i = W⁻¹ F_i p`, `W` the world
/// frame (the reference tracker) seen from the robot's nominal base — one
/// more station. By alternation, as for the world frame above: Horn/Kabsch
/// for every station `S⁻¹` (and `W⁻¹`) given the points, then least
/// squares for every tool's point given the stations (the mean of
/// `R_Fᵢᵀ (S Y_i − t_Fᵢ)` over its samples). The robot then stands at
/// `W⁻¹` in the world frame and the stations at `W⁻¹ S`. The stated
/// orientations of the tools are kept (a point measure does not see them).
///
/// # Errors
/// A configuration that does not fit the robot.
pub(super) fn registered_frames(robot: &Robot, study: &Study) -> Result<Option<Registered>, Error> {
    use crate::frames::FrameRole;
    if !study.sets.iter().any(|set| set.uses_named_frames()) {
        return Ok(None);
    }
    // The world frame is station `world`, after the named frames.
    let world = study.frames.len();
    // (station, tool, tool_frame pose, measured point) of every point, spread
    // up to MAXIMUM_POINTS per set.
    let mut points: Vec<FramedPoint> = Vec::new();
    let model = KinematicModel::new(robot);
    let mut chain = ChainBuffer::default();
    for set in &study.sets {
        for (motors, point) in spread_points(&[set.samples.as_slice()], MAXIMUM_POINTS) {
            let tool_frame = model.terminal_pose(motors, &mut chain)?;
            points.push((
                Some(set.station.unwrap_or(world)),
                set.tool,
                tool_frame,
                point,
            ));
        }
    }
    if points.len() < MINIMUM_POINTS {
        return Ok(None);
    }
    let stated = |index: Option<usize>| index.map(|i| study.frames[i].pose);
    let mut stations: Vec<IsometryMatrix3<f64>> = study.frames.iter().map(|f| f.pose).collect();
    stations.push(IsometryMatrix3::identity());
    let mut tools: Vec<Vector3<f64>> = study
        .frames
        .iter()
        .map(|f| f.pose.translation.vector)
        .collect();
    let point_of =
        |tools: &[Vector3<f64>], tool: Option<usize>| tool.map_or(Vector3::zeros(), |t| tools[t]);
    let rms = |stations: &[IsometryMatrix3<f64>], tools: &[Vector3<f64>]| {
        let squares: f64 = points
            .iter()
            .map(|(station, tool, tool_frame, measured)| {
                let world = tool_frame * nalgebra::Point3::from(point_of(tools, *tool));
                let seen = station.map_or(world, |s| stations[s].inverse() * world);
                (seen.coords - measured).norm_squared()
            })
            .sum();
        (squares / points.len() as f64).sqrt()
    };
    let before = rms(&stations, &tools);
    let is_station =
        |index: usize| index == world || study.frames[index].role == FrameRole::Station;
    for _ in 0..ROUNDS {
        // How far this round moved a frame (metres, radians).
        let mut moved: f64 = 0.0;
        // Every station's pose (the world's too), given the tools' points.
        for index in (0..=world).filter(|index| is_station(*index)) {
            let (seen_from, seen): (Vec<Vector3<f64>>, Vec<Vector3<f64>>) = points
                .iter()
                .filter(|(station, ..)| *station == Some(index))
                .map(|(_, tool, tool_frame, measured)| {
                    (
                        (tool_frame * nalgebra::Point3::from(point_of(&tools, *tool))).coords,
                        *measured,
                    )
                })
                .unzip();
            if seen_from.len() >= MINIMUM_POINTS {
                let next = rigid_fit(&seen_from, &seen).inverse();
                let change = stations[index].inverse() * next;
                moved = moved
                    .max(change.translation.vector.norm())
                    .max(change.rotation.angle());
                stations[index] = next;
            }
        }
        // Every tool's point, given the stations.
        for (index, frame) in study.frames.iter().enumerate() {
            if frame.role != FrameRole::Tool {
                continue;
            }
            let estimates: Vec<Vector3<f64>> = points
                .iter()
                .filter(|(_, tool, ..)| *tool == Some(index))
                .map(|(station, _, tool_frame, measured)| {
                    let seen_from = station.map_or(*measured, |s| {
                        (stations[s] * nalgebra::Point3::from(*measured)).coords
                    });
                    tool_frame.rotation.inverse() * (seen_from - tool_frame.translation.vector)
                })
                .collect();
            if !estimates.is_empty() {
                let next = estimates.iter().sum::<Vector3<f64>>() / estimates.len() as f64;
                moved = moved.max((next - tools[index]).norm());
                tools[index] = next;
            }
        }
        if moved < 1e-12 {
            break;
        }
    }
    let after = rms(&stations, &tools);
    // The world frame seen from the robot's base; the robot seen from it.
    let world_pose = stations[world];
    let world_far = world_pose.translation.vector.norm() > FAR_LENGTH
        || world_pose.rotation.angle() > FAR_ANGLE;
    let far = world_far
        || study.frames.iter().enumerate().any(|(index, frame)| {
            let (stated_pose, fitted) = match frame.role {
                FrameRole::Station => (stated(Some(index)), world_pose.inverse() * stations[index]),
                FrameRole::Tool => (
                    stated(Some(index)),
                    IsometryMatrix3::from_parts(
                        Translation3::from(tools[index]),
                        frame.pose.rotation,
                    ),
                ),
            };
            stated_pose.is_some_and(|pose| {
                let change = pose.inverse() * fitted;
                change.translation.vector.norm() > FAR_LENGTH || change.rotation.angle() > FAR_ANGLE
            })
        });
    if !(far && after.is_finite() && after * IMPROVEMENT <= before) {
        return Ok(None);
    }
    let frames = study
        .frames
        .iter()
        .enumerate()
        .map(|(index, frame)| {
            let pose = match frame.role {
                FrameRole::Station => world_pose.inverse() * stations[index],
                FrameRole::Tool => IsometryMatrix3::from_parts(
                    Translation3::from(tools[index]),
                    frame.pose.rotation,
                ),
            };
            crate::frames::NamedFrame {
                pose,
                ..frame.clone()
            }
        })
        .collect();
    Ok(Some(Registered {
        study: study.with_frames(frames),
        base: world_far.then(|| world_pose.inverse()),
    }))
}
