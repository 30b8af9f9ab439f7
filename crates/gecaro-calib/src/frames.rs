//! Named tools and stations: extra frames identified together with the robot.
//!
//! A laser tracker measures one or several reflectors on the tool, sometimes
//! from several stations. A study's measurement set can then name its
//! **tool** (the pose of the measured point or frame in the robot's tool
//! frame n+1 — the robot file's last frame, a URDF's `tool0` — replacing
//! that frame's origin as the measured point for that set) and its
//! **station** (the pose of the measurement frame in the robot's world frame
//! −1: the set's data are poses in the station frame). Sets that name
//! neither measure the robot's own frame n+1 in the world frame, as a
//! single-method study does.
//!
//! One convention everywhere: a reflector stated as (40, 25, 90) mm is at
//! those coordinates in the frame the user knows as the flange or `tool0`
//! (`robot reframe --tool` moves the same frame), whatever Khalil–Kleinfinger
//! frame n the import chose.
//!
//! ## Unknowns
//!
//! Each named frame brings six unknowns, identified with η as a method's
//! auxiliary unknowns are (they come first among them):
//! `x, y, z` (metres) the frame's origin in its parent frame (tool frame
//! n+1 for a tool, world frame for a station), and `rx, ry, rz` (radians) a
//! rotation after the stated orientation `R₀`:
//! `R = R₀ · Rot(x, rx) · Rot(y, ry) · Rot(z, rz)`, so that the angles start
//! at 0 and stay far from the representation's singularity (ry = ±90°).
//! A point measure does not see a tool's orientation: those three columns
//! have no effect and Appendix III reports them so.
//!
//! ## Frame n+1 under a named tool
//!
//! Where every set of a study names a tool, nothing measures the robot's own
//! frame n+1 apart from the tools: its parameters would only duplicate the
//! tools' unknowns, so their columns are zero in the named tools' sets (no
//! effect; they keep their nominal values) and the tools are identified in
//! the nominal frame n+1. Where some set measures the robot's own frame n+1
//! (no tool named), that set determines frame n+1 and the tools ride on it:
//! their columns are the rigid-body ones below.
//!
//! ## The state of a set with a tool and a station
//!
//! With `P` the pose of the robot's frame n+1 in the world, the tool's pose
//! in the world is `X = P·T` and the measured pose `Y = S⁻¹·X` for a station
//! `S`. Their Jacobians follow from Appendix II's, column by column
//! (`d = X_p − P_p` in the world, `δ` the small rotation):
//!
//! | unknown | position rows (world) | rotation rows (world) |
//! |---|---|---|
//! | robot parameter k (frame n+1: 0 when every set names a tool) | `J_p,k − d × J_δ,k` | `J_δ,k` |
//! | tool x, y, z | `R_P e_i` | 0 |
//! | tool rx, ry, rz | 0 | `R_P R₀ (e_x, Rot(x, rx) e_y, Rot(x, rx) Rot(y, ry) e_z)` |
//!
//! then, in the station frame, every column is rotated by `R_Sᵀ`, and the
//! station's own columns are, with `y` the measured position in the station
//! frame and `ω_j = R₀,S (e_x, Rot(x, rx) e_y, Rot(x, rx) Rot(y, ry) e_z)_j`:
//! position `−R_Sᵀ e_i` (x, y, z) and `[y]× R_Sᵀ ω_j` (rotations); rotation
//! rows 0 and `−R_Sᵀ ω_j`. The tests check every column against finite
//! differences.
//!
//! A station measured by no set that names none has no reference: the world
//! frame is then that of the robot's nominal base, whose parameters the
//! stations absorb (Appendix III reports them without effect or regrouped).

use gecaro_core::Robot;
use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Translation3, Vector3};

use crate::states::TerminalState;

/// Unknowns of one named frame: x, y, z, rx, ry, rz.
pub const FRAME_UNKNOWNS: usize = 6;

/// The names of a frame's unknowns, in order.
pub const UNKNOWN_NAMES: [&str; FRAME_UNKNOWNS] = ["x", "y", "z", "rx", "ry", "rz"];

/// Whether a named frame carries the measured point (a tool) or measures
/// (a station).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum FrameRole {
    /// A reflector or tool frame, stated in the robot's tool frame n+1.
    Tool,
    /// A measurement frame (an instrument's), stated in the world frame.
    Station,
}

impl FrameRole {
    /// `tool` or `station`.
    pub fn as_str(self) -> &'static str {
        match self {
            FrameRole::Tool => "tool",
            FrameRole::Station => "station",
        }
    }
}

/// A tool or station of a study, with its stated (nominal) pose.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedFrame {
    /// Its name in the study.
    pub name: String,
    /// Tool or station.
    pub role: FrameRole,
    /// The stated pose: a tool's in the robot's tool frame n+1, a station's
    /// in the world frame (metres).
    pub pose: IsometryMatrix3<f64>,
}

impl NamedFrame {
    /// The initial values of its unknowns: the stated origin, no rotation.
    pub fn initial_values(&self) -> [f64; FRAME_UNKNOWNS] {
        let t = self.pose.translation.vector;
        [t.x, t.y, t.z, 0.0, 0.0, 0.0]
    }

    /// Its pose at `values` (x, y, z, rx, ry, rz; see the module docs).
    pub fn pose_at(&self, values: &[f64]) -> IsometryMatrix3<f64> {
        let rotation = self.pose.rotation
            * Rotation3::from_axis_angle(&Vector3::x_axis(), values[3])
            * Rotation3::from_axis_angle(&Vector3::y_axis(), values[4])
            * Rotation3::from_axis_angle(&Vector3::z_axis(), values[5]);
        IsometryMatrix3::from_parts(Translation3::new(values[0], values[1], values[2]), rotation)
    }

    /// The same frame, stated at the pose its unknowns `values` give (an
    /// identified frame, ready to be stated again).
    pub fn at(&self, values: &[f64]) -> NamedFrame {
        NamedFrame {
            pose: self.pose_at(values),
            ..self.clone()
        }
    }

    /// The axes `ω_j` (in the parent frame) of its three rotation unknowns
    /// at `values`: `R₀ e_x`, `R₀ Rot(x, rx) e_y`, `R₀ Rot(x, rx) Rot(y, ry) e_z`.
    fn rotation_axes(&self, values: &[f64]) -> [Vector3<f64>; 3] {
        let after_x =
            self.pose.rotation * Rotation3::from_axis_angle(&Vector3::x_axis(), values[3]);
        let after_y = after_x * Rotation3::from_axis_angle(&Vector3::y_axis(), values[4]);
        [
            self.pose.rotation * Vector3::x(),
            after_x * Vector3::y(),
            after_y * Vector3::z(),
        ]
    }
}

/// The robot whose frame n+1 in its world frame is the pose measured with
/// `tool` from `station` (either `None`: the robot's own): `robot`
/// re-framed ([`Robot::reframed`]). Data simulated on it are data of that
/// reflector measured from that station; the identification computes the
/// same poses by another route (`SetFrames`).
///
/// # Errors
/// As [`Robot::reframed`] (a one-joint robot with both a tool and a station).
pub fn measuring_robot(
    robot: &Robot,
    tool: Option<&NamedFrame>,
    station: Option<&NamedFrame>,
) -> Result<Robot, gecaro_core::Error> {
    let new_tool = tool.map_or(IsometryMatrix3::identity(), |tool| tool.pose);
    let new_world = station.map_or(IsometryMatrix3::identity(), |station| {
        station.pose.inverse()
    });
    robot.reframed(&new_world, &new_tool)
}

/// The tool and station a set measures with, and where their unknowns sit.
#[derive(Clone, Debug)]
pub(crate) struct SetFrames<'a> {
    /// The tool, its unknowns' values and the index of its first unknown.
    pub tool: Option<(&'a NamedFrame, &'a [f64], usize)>,
    /// The station, likewise.
    pub station: Option<(&'a NamedFrame, &'a [f64], usize)>,
    /// The vocabulary indices of the robot's frame n+1 parameters whose
    /// columns are held at zero under a named tool (none where another set
    /// measures frame n+1; see the module docs).
    pub held_tool_parameters: Vec<usize>,
    /// All unknowns of all named frames (the extra Jacobian columns).
    pub unknowns: usize,
}

impl<'a> SetFrames<'a> {
    /// The frames of a set measuring with `tool` and `station` (indices into
    /// `frames`, whose unknowns' values are `values`) on `robot`;
    /// `tool_frame_measured`: some set of the study measures the robot's own
    /// frame n+1 (names no tool).
    pub(crate) fn new(
        robot: &Robot,
        frames: &'a [NamedFrame],
        values: &'a [f64],
        tool: Option<usize>,
        station: Option<usize>,
        tool_frame_measured: bool,
    ) -> Self {
        let entry = |index: usize| {
            let first = index * FRAME_UNKNOWNS;
            (
                &frames[index],
                &values[first..first + FRAME_UNKNOWNS],
                first,
            )
        };
        let last = robot.frames().len() - 1;
        SetFrames {
            tool: tool.map(entry),
            station: station.map(entry),
            held_tool_parameters: if tool_frame_measured {
                Vec::new()
            } else {
                robot
                    .parameters()
                    .ids()
                    .iter()
                    .enumerate()
                    .filter(|(_, id)| id.frame == last)
                    .map(|(index, _)| index)
                    .collect()
            },
            unknowns: frames.len() * FRAME_UNKNOWNS,
        }
    }

    /// Replaces `state` (the robot's frame n+1, all six Jacobian rows) by
    /// the state of the measured pose, with `unknowns` more Jacobian columns
    /// (see the module docs), keeping `rows` rows.
    pub(crate) fn apply(&self, state: &mut TerminalState, rows: usize) {
        let parameters = state.parameter_count();
        let columns = parameters + self.unknowns;
        let own = state.pose;
        let world_pose = match self.tool {
            Some((frame, values, _)) => own * frame.pose_at(values),
            None => own,
        };
        // Columns in the world frame: 3 position rows, 3 rotation rows.
        let mut position = vec![Vector3::zeros(); columns];
        let mut rotation = vec![Vector3::zeros(); columns];
        let offset = world_pose.translation.vector - own.translation.vector;
        for k in 0..parameters {
            let j_p = Vector3::from_fn(|axis, _| state.jacobian_row(axis)[k]);
            let j_d = Vector3::from_fn(|axis, _| state.jacobian_row(axis + 3)[k]);
            position[k] = j_p - offset.cross(&j_d);
            rotation[k] = j_d;
        }
        if let Some((frame, values, first)) = self.tool {
            for k in &self.held_tool_parameters {
                position[*k] = Vector3::zeros();
                rotation[*k] = Vector3::zeros();
            }
            let to_world: Matrix3<f64> = *own.rotation.matrix();
            for axis in 0..3 {
                position[parameters + first + axis] = to_world.column(axis).into_owned();
            }
            for (axis, omega) in frame.rotation_axes(values).iter().enumerate() {
                rotation[parameters + first + 3 + axis] = to_world * omega;
            }
        }
        let pose = match self.station {
            Some((frame, values, first)) => {
                let station = frame.pose_at(values);
                let back = station.rotation.inverse();
                for k in 0..columns {
                    position[k] = back * position[k];
                    rotation[k] = back * rotation[k];
                }
                let measured = station.inverse() * world_pose;
                let y = measured.translation.vector;
                for axis in 0..3 {
                    position[parameters + first + axis] = -(back * Vector3::ith(axis, 1.0));
                }
                for (axis, omega) in frame.rotation_axes(values).iter().enumerate() {
                    let local = back * omega;
                    position[parameters + first + 3 + axis] = y.cross(&local);
                    rotation[parameters + first + 3 + axis] = -local;
                }
                measured
            }
            None => world_pose,
        };
        let mut jacobian = vec![0.0; rows * columns];
        for axis in 0..rows {
            let row = &mut jacobian[axis * columns..(axis + 1) * columns];
            for (k, value) in row.iter_mut().enumerate() {
                *value = if axis < 3 {
                    position[k][axis]
                } else {
                    rotation[k][axis - 3]
                };
            }
        }
        *state = TerminalState::from_parts(pose, jacobian, columns, rows);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;
    use crate::samples::Samples;
    use crate::simulation::Sampler;
    use crate::states::evaluate_states;
    use gecaro_core::{JacobianRows, OrientationDifference, ParameterId, pose_difference};

    fn frames() -> Vec<NamedFrame> {
        vec![
            NamedFrame {
                name: "smr".into(),
                role: FrameRole::Tool,
                pose: IsometryMatrix3::from_parts(
                    Translation3::new(0.04, 0.025, 0.09),
                    Rotation3::from_euler_angles(0.3, -0.2, 0.5),
                ),
            },
            NamedFrame {
                name: "tracker".into(),
                role: FrameRole::Station,
                pose: IsometryMatrix3::from_parts(
                    Translation3::new(2.3, 0.1, 0.4),
                    Rotation3::from_euler_angles(0.1, 0.05, 0.6),
                ),
            },
        ]
    }

    /// The measured pose and its Jacobian at (robot, values).
    fn measured(
        robot: &Robot,
        frames: &[NamedFrame],
        values: &[f64],
        q: &[f64],
        tool: Option<usize>,
        station: Option<usize>,
        tool_frame_measured: bool,
    ) -> TerminalState {
        let mut states = Vec::new();
        evaluate_states(
            robot,
            Samples::from([Sample::new(q.to_vec())].as_slice()).as_slice(),
            JacobianRows::Full,
            &mut states,
        )
        .expect("state");
        let mut state = states.pop().expect("one");
        SetFrames::new(robot, frames, values, tool, station, tool_frame_measured)
            .apply(&mut state, 6);
        state
    }

    /// Every column of the measured pose's Jacobian (robot parameters and
    /// frame unknowns) equals central finite differences of the pose, the
    /// tool riding on the robot's frame n+1; where no set measures that
    /// frame, its columns are held at zero under a named tool and the others
    /// are unchanged.
    #[test]
    fn jacobian_columns_match_finite_differences() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut robot = crate::simulation::perturbed_robot(&robot, 1.0, &mut Sampler::new(3))
            .expect("perturbed");
        // The robot's own tool off the flange, so that replacing it matters.
        let last = robot.frames().len() - 1;
        robot
            .set_parameter(ParameterId::new(gecaro_core::ParameterKind::R, last), 0.12)
            .expect("r");
        let frames = frames();
        let mut values: Vec<f64> = frames.iter().flat_map(|f| f.initial_values()).collect();
        values[3..6].copy_from_slice(&[0.02, -0.03, 0.01]);
        values[9..12].copy_from_slice(&[-0.01, 0.04, 0.02]);
        let q = Sampler::new(8).configuration(&robot);
        let step = 1e-6;
        for (tool, station) in [(Some(0), Some(1)), (Some(0), None), (None, Some(1))] {
            let state = measured(&robot, &frames, &values, &q, tool, station, true);
            let held = measured(&robot, &frames, &values, &q, tool, station, false);
            for column in 0..state.parameter_count() {
                let in_tool_frame = column < robot.parameters().len()
                    && robot.parameters().id(column).frame == last;
                for axis in 0..6 {
                    let expected = if in_tool_frame && tool.is_some() {
                        0.0
                    } else {
                        state.jacobian_row(axis)[column]
                    };
                    assert_eq!(held.jacobian_row(axis)[column], expected, "column {column}");
                }
            }
            let parameters = robot.parameters().len();
            let columns = parameters + values.len();
            assert_eq!(state.parameter_count(), columns);
            for column in 0..columns {
                let shifted = |sign: f64| {
                    let mut robot = robot.clone();
                    let mut values = values.clone();
                    if column < parameters {
                        let id = robot.parameters().id(column);
                        let value = robot.parameter(id);
                        robot.set_parameter(id, value + sign * step).expect("set");
                    } else {
                        values[column - parameters] += sign * step;
                    }
                    measured(&robot, &frames, &values, &q, tool, station, true).pose
                };
                let (plus, minus) = (shifted(1.0), shifted(-1.0));
                // dp, and δ with plus ≈ Rot(δ)·minus (Appendix I's difference).
                let difference = pose_difference(&plus, &minus, OrientationDifference::AxisAngle);
                for axis in 0..3 {
                    let position = difference[axis] / (2.0 * step);
                    let angle = difference[axis + 3] / (2.0 * step);
                    let name = if column < parameters {
                        robot.parameters().id(column).to_string()
                    } else {
                        format!("unknown {}", column - parameters)
                    };
                    assert!(
                        (state.jacobian_row(axis)[column] - position).abs() < 1e-6,
                        "{tool:?} {station:?} {name} position {axis}: {} vs {position}",
                        state.jacobian_row(axis)[column]
                    );
                    assert!(
                        (state.jacobian_row(axis + 3)[column] - angle).abs() < 1e-6,
                        "{tool:?} {station:?} {name} rotation {axis}: {} vs {angle}",
                        state.jacobian_row(axis + 3)[column]
                    );
                }
            }
        }
    }

    #[test]
    fn a_frame_at_its_initial_values_is_its_stated_pose() {
        for frame in frames() {
            let pose = frame.pose_at(&frame.initial_values());
            assert!((pose.to_homogeneous() - frame.pose.to_homogeneous()).norm() < 1e-15);
            let moved = frame.at(&[1.0, 2.0, 3.0, 0.1, 0.2, 0.3]);
            assert_eq!(moved.pose, frame.pose_at(&[1.0, 2.0, 3.0, 0.1, 0.2, 0.3]));
        }
    }
}
