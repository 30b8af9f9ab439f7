//! A robot compiled for fast, allocation-free kinematics in tight loops.
//!
//! The direct model (eq. 1–3) and the parameter Jacobian (Appendix II) of a
//! [`Robot`] are evaluated for thousands of configurations per identification
//! iteration. Everything that does not depend on the configuration — the sines
//! and cosines of α_j and β_j, whole transforms of fixed frames, the motor to
//! joint map of eq. 4, the column of each parameter, sin/cos θ_j of
//! prismatic joints — is computed once here; per configuration only
//! sin/cos(θ_j + q_j) of revolute joints remain, taken four at a time in
//! SIMD lanes ([`turn`], the one sine of every route). The
//! poses agree with [`forward_kinematics`](super::forward_kinematics) bit for
//! bit where no frame has a Hayati β (the same products), to rounding where
//! one has (its turn about y is applied in another order), and the Jacobian
//! with [`parameter_jacobian`](super::parameter_jacobian) to rounding (tested).
//! A model may compute only the Jacobian columns a caller reads, in the
//! caller's order ([`KinematicModel::selecting`]): the identification's
//! linearisations read the columns of the parameters they estimate. The
//! poses and the Jacobian are written once, generic over the scalar
//! ([`Lane`]): one configuration's `f64` here, four configurations' lanes in
//! [`lanes`](super::lanes), each lane bit for bit its configuration alone.
//!
//! ## Elastic joints (issue 38)
//!
//! An elastic robot's joint j yields to the gravity torque τ_j it carries:
//! `q_j = (Cj·diag(K)·Cm·qm)_j + offset_j + c_j·τ_j`. The torques of a
//! configuration are given with it ([`KinematicModel::forward_loaded`]);
//! gecaro evaluates them once, at the commanded configuration
//! (`gecaro_core::gravity_torques`), and holds them fixed: the deflection
//! moves the arm by c·τ ≈ 1e-3 rad, which changes τ by about that fraction,
//! so the model is exact to ~1e-3 of the deflection (micrometres). The
//! Jacobian column of c_j is the joint variable's column times τ_j (the
//! joint variable enters θ_j or r_j), and no other column changes.
//!
//! Gravity's tilts (`tilt1`, `tilt2`; [`crate::MassModel::tilted`]) load
//! the joints through the torques' derivatives given with them
//! ([`KinematicModel::forward_tilted`]): the joints carry
//! `τ_j + Σ_k tilt_k ∂τ_j/∂tilt_k`, and the column of tilt_k is
//! `Σ_j c_j ∂τ_j/∂tilt_k` times joint j's column. It is zero while every
//! compliance is: the tilts are seen only through the joints' yielding.

use nalgebra::{
    IsometryMatrix3, Matrix3, Matrix6xX, Rotation3, Scalar, SimdBool, SimdRealField, Translation3,
    Vector3, Vector6,
};

use super::direct::frame_transform;
use super::turn;
use crate::Error;
use crate::frame::FrameType;
use crate::parameters::{ParameterId, ParameterKind};
use crate::robot::Robot;

/// Per-frame constants of eq. 3.
#[derive(Clone, Debug)]
struct CompiledFrame {
    frame_type: FrameType,
    /// Rot(y, β)·Rot(x, α), the part before the joint.
    tilt: Matrix3<f64>,
    /// The whole transform of a fixed frame.
    fixed: IsometryMatrix3<f64>,
    d: f64,
    theta: f64,
    /// sin θ, cos θ: a prismatic frame's turn, the same for every configuration.
    sin_theta: f64,
    cos_theta: f64,
    r: f64,
    /// cos β, sin β for the rotated x axis of the α/d columns.
    cos_beta: f64,
    sin_beta: f64,
    /// Columns of θ, r, α, d, β of this frame in η (when they exist).
    columns: [Option<usize>; 5],
}

/// A [`Robot`] compiled for repeated kinematics; see the module docs.
#[derive(Clone, Debug)]
pub struct KinematicModel {
    frames: Vec<CompiledFrame>,
    /// Cj·diag(K)·Cm, row-major n×n, and the offsets of eq. 4.
    pub(super) motor_to_joint: Vec<f64>,
    /// Whether Cm and Cj are the identity (then q_j = K_j·qm_j + offset_j).
    pub(super) uncoupled: bool,
    pub(super) offsets: Vec<f64>,
    /// Cm (row-major), for the gain columns.
    pub(super) motor_coupling: Vec<f64>,
    /// Per joint j, the non-zero entries `(i, Cj(i, j))` of Cj's column j:
    /// the terms of K_j's column (one, the diagonal, without couplings).
    pub(super) gain_terms: Vec<Vec<(usize, f64)>>,
    /// Column of K_j in η, and of the joint variable's parameter (θ or r).
    pub(super) gain_columns: Vec<Option<usize>>,
    pub(super) joint_columns: Vec<usize>,
    /// c_j of an elastic robot (empty for a rigid one) and its column in η.
    pub(super) compliances: Vec<f64>,
    pub(super) compliance_columns: Vec<Option<usize>>,
    /// tilt1, tilt2 of an elastic robot and their columns in η.
    pub(super) gravity_tilt: [f64; 2],
    pub(super) tilt_columns: [Option<usize>; 2],
    pub(super) parameter_count: usize,
    /// Whether the Jacobian writes every column (then a buffer of the right
    /// size needs no zeroing first).
    pub(super) writes_every_column: bool,
    /// What the model was compiled from ([`fingerprint`]): the robot it is
    /// bound to ([`KinematicModel::is_of`]).
    source: Vec<f64>,
}

/// Every number of `robot` a compiled model holds: its parameters (the
/// frames', gains, compliances, gravity's tilt), the joint offsets and both
/// couplings of eq. 4.
fn fingerprint(robot: &Robot) -> Vec<f64> {
    let mut source: Vec<f64> = robot.parameter_values().iter().copied().collect();
    source.extend(robot.joints().iter().map(|joint| joint.offset));
    source.extend(robot.motor_coupling().iter().copied());
    source.extend(robot.joint_coupling().iter().copied());
    source
}

/// Which rows of the parameter Jacobian to compute.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum JacobianRows {
    /// Rows 0–2, the position of the terminal point: enough for every
    /// method that measures no orientation.
    Position,
    /// All six rows: position, then orientation.
    #[default]
    Full,
}

impl JacobianRows {
    /// Number of rows: 3 or 6.
    pub fn count(self) -> usize {
        match self {
            JacobianRows::Position => 3,
            JacobianRows::Full => 6,
        }
    }
}

/// Frame poses of one configuration, filled by [`KinematicModel::forward`].
#[derive(Clone, Debug, Default)]
pub struct ChainBuffer {
    pub(super) world_from_frame: Vec<IsometryMatrix3<f64>>,
    pub(super) joint_positions: Vec<f64>,
    /// sin/cos(θ_j + q_j) of the revolute joints, in order.
    pub(super) turns: Vec<(f64, f64)>,
    pub(super) coupled_motor_positions: Vec<f64>,
    /// The gravity torque of every joint (zeros when none was given), with
    /// the tilts' share.
    pub(super) torques: Vec<f64>,
    /// The torques' derivatives with respect to the tilts (2n values, or
    /// none when none were given).
    pub(super) tilt_torques: Vec<f64>,
}

impl ChainBuffer {
    /// `(−1)T(n+1)`, the end-effector pose.
    pub fn world_from_tool(&self) -> &IsometryMatrix3<f64> {
        self.world_from_frame
            .last()
            .expect("filled by KinematicModel::forward")
    }

    /// `(−1)T(j)`.
    pub fn world_from_frame(&self, frame: usize) -> &IsometryMatrix3<f64> {
        &self.world_from_frame[frame]
    }
}

impl KinematicModel {
    /// Compiles `robot`.
    pub fn new(robot: &Robot) -> Self {
        let parameters = robot.parameters();
        let column = |kind, frame| parameters.index_of(ParameterId::new(kind, frame));
        let frames: Vec<CompiledFrame> = robot
            .frames()
            .iter()
            .enumerate()
            .map(|(j, frame)| {
                let (sin_alpha, cos_alpha) = frame.alpha.sin_cos();
                let (sin_beta, cos_beta) = frame.beta.sin_cos();
                let (sin_theta, cos_theta) = turn::sin_cos(frame.theta);
                let rot_x = Matrix3::new(
                    1.0, 0.0, 0.0, 0.0, cos_alpha, -sin_alpha, 0.0, sin_alpha, cos_alpha,
                );
                let rot_y = Matrix3::new(
                    cos_beta, 0.0, sin_beta, 0.0, 1.0, 0.0, -sin_beta, 0.0, cos_beta,
                );
                CompiledFrame {
                    frame_type: frame.frame_type,
                    tilt: rot_y * rot_x,
                    fixed: frame_transform(frame, 0.0),
                    d: frame.d,
                    theta: frame.theta,
                    sin_theta,
                    cos_theta,
                    r: frame.r,
                    cos_beta,
                    sin_beta,
                    columns: [
                        column(ParameterKind::Theta, j),
                        column(ParameterKind::R, j),
                        column(ParameterKind::Alpha, j),
                        column(ParameterKind::D, j),
                        column(ParameterKind::Beta, j),
                    ],
                }
            })
            .collect();
        let n = robot.joint_count();
        let row_major = |matrix: &nalgebra::DMatrix<f64>| -> Vec<f64> {
            (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|(i, j)| matrix[(i, j)])
                .collect()
        };
        let joint_columns = (1..=n)
            .map(|joint| {
                let kind = match robot.frames()[joint].frame_type {
                    FrameType::Prismatic => ParameterKind::R,
                    _ => ParameterKind::Theta,
                };
                column(kind, joint).expect("joint frames have θ and r")
            })
            .collect();
        let identity = nalgebra::DMatrix::<f64>::identity(n, n);
        let gain_columns: Vec<Option<usize>> = (1..=n)
            .map(|joint| column(ParameterKind::Gain, joint))
            .collect();
        let compliance_columns: Vec<Option<usize>> = (1..=n)
            .map(|joint| column(ParameterKind::Compliance, joint))
            .collect();
        let tilt_columns = [1, 2].map(|axis| column(ParameterKind::GravityTilt, axis));
        let mut written = vec![false; parameters.len()];
        for index in frames
            .iter()
            .flat_map(|frame| frame.columns)
            .chain(gain_columns.iter().copied())
            .chain(compliance_columns.iter().copied())
            .chain(tilt_columns)
            .flatten()
        {
            written[index] = true;
        }
        KinematicModel {
            writes_every_column: written.iter().all(|w| *w),
            source: fingerprint(robot),
            frames,
            uncoupled: *robot.motor_coupling() == identity && *robot.joint_coupling() == identity,
            motor_to_joint: row_major(robot.motor_to_joint()),
            offsets: robot.joints().iter().map(|joint| joint.offset).collect(),
            motor_coupling: row_major(robot.motor_coupling()),
            gain_terms: robot
                .joint_coupling()
                .column_iter()
                .map(|column| {
                    column
                        .iter()
                        .enumerate()
                        .filter(|(_, coupling)| **coupling != 0.0)
                        .map(|(i, coupling)| (i, *coupling))
                        .collect()
                })
                .collect(),
            gain_columns,
            joint_columns,
            compliances: robot.compliances().map(<[f64]>::to_vec).unwrap_or_default(),
            compliance_columns,
            gravity_tilt: robot.gravity_tilt(),
            tilt_columns,
            parameter_count: parameters.len(),
        }
    }

    /// Number of joints n.
    pub fn joint_count(&self) -> usize {
        self.offsets.len()
    }

    /// Whether the Jacobian writes every column (a buffer of the right
    /// size then needs no zeroing first).
    pub(super) fn writes_every_column(&self) -> bool {
        self.writes_every_column
    }

    /// Whether this model was compiled from `robot` as it is now (its
    /// parameters, offsets and couplings, to the bit): a model and a robot
    /// passed side by side are checked with it, as pinocchio's model and
    /// data are.
    pub fn is_of(&self, robot: &Robot) -> bool {
        self.source == fingerprint(robot)
    }

    /// Number of columns of the Jacobian: Np, or for a model
    /// [`selecting`](Self::selecting) some, the columns it computes.
    pub fn parameter_count(&self) -> usize {
        self.parameter_count
    }

    /// This model computing only the Jacobian columns of the parameters
    /// `kept` (vocabulary indices, each once), in that order: column `k` of
    /// its Jacobian is the parameter `kept[k]`'s. The columns of parameters
    /// not kept are not computed, except a joint variable's (θ_j or r_j)
    /// that a kept gain, compliance or tilt column reads: such columns
    /// follow the kept ones, so [`parameter_count`](Self::parameter_count)
    /// may exceed `kept.len()`. Every value is computed as this model
    /// computes it, bit for bit, and the poses are the same.
    ///
    /// The identification's linearisations read only the columns of the
    /// parameters they estimate (fewer than Np: 31 of Stanford's 46 for
    /// position data); computing those alone, in the order of the columns
    /// of W, saves the rest and lets each row be copied whole.
    ///
    /// ```
    /// use gecaro_core::{ChainBuffer, JacobianRows, KinematicModel, Robot};
    ///
    /// let robot = Robot::template("arm", "RRPRRR")?;
    /// let model = KinematicModel::new(&robot);
    /// // K2 reads θ2's column, which is not kept: it follows the kept ones.
    /// let names = ["d3", "K2", "alpha1"];
    /// let kept = names.map(|name| robot.parameters().index_of_name(name).unwrap());
    /// let selected = model.selecting(&kept);
    /// assert_eq!(selected.parameter_count(), 4);
    /// let mut chain = ChainBuffer::default();
    /// model.forward(&[0.1, 0.2, 0.3, 0.4, 0.5, 0.6], &mut chain)?;
    /// let (mut all, mut some) = (Vec::new(), Vec::new());
    /// model.jacobian_rows(&chain, &mut all, JacobianRows::Full);
    /// selected.jacobian_rows(&chain, &mut some, JacobianRows::Full);
    /// let (np, width) = (model.parameter_count(), selected.parameter_count());
    /// for axis in 0..6 {
    ///     for (k, index) in kept.iter().enumerate() {
    ///         assert_eq!(some[axis * width + k], all[axis * np + index]);
    ///     }
    /// }
    /// # Ok::<(), gecaro_core::Error>(())
    /// ```
    ///
    /// # Panics
    /// When an index of `kept` is not below Np or is given twice.
    #[must_use]
    pub fn selecting(&self, kept: &[usize]) -> KinematicModel {
        let mut position = vec![None; self.parameter_count];
        for (k, index) in kept.iter().enumerate() {
            assert!(
                position[*index].replace(k).is_none(),
                "parameter {index} kept twice"
            );
        }
        // The joint columns that kept derived columns read (fill_jacobian),
        // after the kept ones.
        let is_kept =
            |column: Option<usize>| column.is_some_and(|column| position[column].is_some());
        let mut read = vec![false; self.joint_count()];
        for (joint, column) in self.gain_columns.iter().enumerate() {
            if is_kept(*column) {
                for (i, _) in &self.gain_terms[joint] {
                    read[*i] = true;
                }
            }
        }
        for (joint, column) in self.compliance_columns.iter().enumerate() {
            read[joint] |= is_kept(*column);
        }
        if self.tilt_columns.iter().any(|column| is_kept(*column)) {
            read.fill(true);
        }
        let mut width = kept.len();
        for (joint, column) in self.joint_columns.iter().enumerate() {
            if read[joint] && position[*column].is_none() {
                position[*column] = Some(width);
                width += 1;
            }
        }
        let moved = |column: Option<usize>| column.and_then(|column| position[column]);
        let mut selected = self.clone();
        for frame in &mut selected.frames {
            frame.columns = frame.columns.map(moved);
        }
        for column in selected
            .gain_columns
            .iter_mut()
            .chain(&mut selected.compliance_columns)
            .chain(&mut selected.tilt_columns)
        {
            *column = moved(*column);
        }
        // A joint column that no kept column reads is never read: its
        // index is kept only as a place (its values are not written).
        for joint in &mut selected.joint_columns {
            *joint = position[*joint].unwrap_or(usize::MAX);
        }
        selected.writes_every_column = self.writes_every_column;
        selected.parameter_count = width;
        selected
    }

    /// Direct model (eq. 1) at motor variables `motor_positions`, into `chain`
    /// (no load: an elastic robot's joints are not deflected).
    ///
    /// # Errors
    /// When `motor_positions` does not hold n finite values.
    pub fn forward(&self, motor_positions: &[f64], chain: &mut ChainBuffer) -> Result<(), Error> {
        self.forward_loaded(motor_positions, None, chain)
    }

    /// The frames' poses at the joint variables q (eq. 1–3 without eq. 4:
    /// no gains, couplings, offsets or loads), into `chain`; its Jacobians
    /// are then not those of any motor configuration. The caller
    /// guarantees n finite values (the inverse model's iterates).
    pub fn forward_joints(&self, joint_positions: &[f64], chain: &mut ChainBuffer) {
        debug_assert_eq!(joint_positions.len(), self.joint_count());
        chain.joint_positions.clear();
        chain.joint_positions.extend_from_slice(joint_positions);
        chain.coupled_motor_positions.clear();
        chain.torques.clear();
        chain.tilt_torques.clear();
        self.chain_of_joints(chain);
    }

    /// Fills `chain.turns` (the revolute joints' sin/cos(θ_j + q_j), four
    /// at a time) from `chain.joint_positions`.
    fn turns_of_joints(&self, chain: &mut ChainBuffer) {
        chain.turns.clear();
        let mut angles = self.turn_angles(&chain.joint_positions).peekable();
        while angles.peek().is_some() {
            let mut lanes = [0.0; turn::LANES];
            let mut filled = 0;
            for (lane, angle) in lanes.iter_mut().zip(angles.by_ref()) {
                *lane = angle;
                filled += 1;
            }
            let (sines, cosines) = turn::sin_cos_lanes(lanes);
            chain
                .turns
                .extend((0..filled).map(|lane| (sines[lane], cosines[lane])));
        }
    }

    /// The angles θ_j + q_j of the revolute joints' turns, in order, at
    /// the joint variables `joint_positions`.
    #[inline(always)]
    pub(super) fn turn_angles<'a>(
        &'a self,
        joint_positions: &'a [f64],
    ) -> impl Iterator<Item = f64> + 'a {
        self.frames
            .iter()
            .enumerate()
            .filter(|(_, frame)| frame.frame_type == FrameType::Revolute)
            .map(|(j, frame)| frame.theta + joint_positions[j - 1])
    }

    /// Fills `chain.world_from_frame` from `chain.joint_positions`.
    pub(super) fn chain_of_joints(&self, chain: &mut ChainBuffer) {
        self.turns_of_joints(chain);
        self.poses(
            &chain.joint_positions,
            &chain.turns,
            &mut chain.world_from_frame,
        );
    }

    /// The frames' poses `(−1)T(j)`, j = 0..n+1 (eq. 1), into `poses`, from
    /// the joint variables and the revolute joints' turns (sin, cos), in
    /// one configuration's values or in lanes of several ([`Lane`]): the
    /// same products either way, so each lane's poses are bit for bit
    /// those of its configuration alone.
    #[inline(always)]
    pub(super) fn poses<T: Lane>(
        &self,
        joint_positions: &[T],
        turns: &[(T, T)],
        poses: &mut Vec<IsometryMatrix3<T>>,
    ) {
        poses.clear();
        let mut pose = IsometryMatrix3::identity();
        let mut turns = turns.iter();
        for (j, frame) in self.frames.iter().enumerate() {
            let local = match frame.frame_type {
                FrameType::Fixed => splat_pose(&frame.fixed),
                FrameType::Revolute => frame.moving(
                    turns.next().copied().expect("a turn per revolute joint"),
                    T::splat(frame.r),
                ),
                FrameType::Prismatic => frame.moving(
                    (T::splat(frame.sin_theta), T::splat(frame.cos_theta)),
                    T::splat(frame.r) + joint_positions[j - 1],
                ),
            };
            pose *= local;
            poses.push(pose);
        }
    }

    /// The 6×n joint Jacobian of the configuration in `chain`: column j the
    /// velocity of frame n+1's origin (rows 0–2) and its angular velocity
    /// (rows 3–5) for a unit rate of joint j, `z_j × (p − o_j)` and `z_j`
    /// for a revolute joint, `z_j` and 0 for a prismatic one (z_j, o_j the
    /// axis and origin of frame j, which joint j moves), into `jacobian`.
    pub fn joint_jacobian(&self, chain: &ChainBuffer, jacobian: &mut Matrix6xX<f64>) {
        let n = self.joint_count();
        if jacobian.ncols() != n {
            *jacobian = Matrix6xX::zeros(n);
        }
        let tip = chain.world_from_tool().translation.vector;
        for (j, frame) in self.frames.iter().enumerate().skip(1) {
            if frame.frame_type == FrameType::Fixed || j > n {
                continue;
            }
            let pose = &chain.world_from_frame[j];
            let axis: Vector3<f64> = pose.rotation.matrix().column(2).into();
            let (linear, angular) = match frame.frame_type {
                FrameType::Revolute => (axis.cross(&(tip - pose.translation.vector)), axis),
                _ => (axis, Vector3::zeros()),
            };
            for row in 0..3 {
                jacobian[(row, j - 1)] = linear[row];
                jacobian[(row + 3, j - 1)] = angular[row];
            }
        }
    }

    /// The end-effector pose `(−1)T(n+1)` at `motor_positions` (the direct
    /// model into `chain`, then its last frame).
    ///
    /// # Errors
    /// As [`forward`](Self::forward).
    pub fn terminal_pose(
        &self,
        motor_positions: &[f64],
        chain: &mut ChainBuffer,
    ) -> Result<IsometryMatrix3<f64>, Error> {
        self.forward(motor_positions, chain)?;
        Ok(*chain.world_from_tool())
    }

    /// The 6×Np parameter Jacobian (Appendix II) of the configuration in
    /// `chain` (filled by [`forward`](Self::forward)), into `jacobian`.
    pub fn jacobian(&self, chain: &ChainBuffer, jacobian: &mut Matrix6xX<f64>) {
        if jacobian.ncols() != self.parameter_count {
            *jacobian = Matrix6xX::zeros(self.parameter_count);
        }
        self.fill_jacobian(&chain.view(), jacobian);
    }

    /// The same Jacobian, row-major: `rows[axis * Np + column]` (rows 0–2
    /// position, 3–5 rotation), so that each row is a contiguous slice; only
    /// the position rows when `which` says so (`rows` then holds 3·Np values).
    pub fn jacobian_rows(&self, chain: &ChainBuffer, rows: &mut Vec<f64>, which: JacobianRows) {
        let size = which.count() * self.parameter_count;
        if rows.len() != size || !self.writes_every_column {
            rows.clear();
            rows.resize(size, 0.0);
        }
        self.fill_jacobian(
            &chain.view(),
            &mut RowMajor {
                rows,
                parameters: self.parameter_count,
                rotation: which == JacobianRows::Full,
            },
        );
    }

    /// The parameter Jacobian (Appendix II) of the configuration(s) in
    /// `chain`, column by column into `jacobian`: in one configuration's
    /// values or in lanes of several ([`Lane`]), the same operations either
    /// way.
    #[inline(always)]
    pub(super) fn fill_jacobian<T: Lane>(
        &self,
        chain: &ChainView<'_, T>,
        jacobian: &mut impl JacobianStore<T>,
    ) {
        let tool = chain
            .poses
            .last()
            .expect("filled by KinematicModel::forward")
            .translation
            .vector;
        let zero = Vector3::zeros();
        let mut previous = IsometryMatrix3::identity();
        for (j, frame) in self.frames.iter().enumerate() {
            let pose = chain.poses[j];
            let z_axis: Vector3<T> = pose.rotation.matrix().column(2).into();
            let [theta, r, alpha, d, beta] = frame.columns;
            if theta.is_some() {
                jacobian.set(
                    theta,
                    z_axis.cross(&(tool - pose.translation.vector)),
                    z_axis,
                );
            }
            jacobian.set(r, z_axis, zero);
            if j > 0 && (alpha.is_some() || d.is_some() || beta.is_some()) {
                let axes = previous.rotation.matrix();
                let x_previous: Vector3<T> = axes.column(0).into();
                let y_previous: Vector3<T> = axes.column(1).into();
                let z_previous: Vector3<T> = axes.column(2).into();
                let lever = tool - previous.translation.vector;
                let x_rotated =
                    x_previous * T::splat(frame.cos_beta) - z_previous * T::splat(frame.sin_beta);
                if alpha.is_some() {
                    jacobian.set(alpha, x_rotated.cross(&lever), x_rotated);
                }
                jacobian.set(d, x_rotated, zero);
                if beta.is_some() {
                    jacobian.set(beta, y_previous.cross(&lever), y_previous);
                }
            }
            previous = pose;
        }
        // K_j: Σ_i j_{q_i} Cj(i, j) (Cm·qm)_j, from the joint columns (eq. 4).
        for (joint, gain_column) in self.gain_columns.iter().enumerate() {
            let Some(gain_column) = *gain_column else {
                continue;
            };
            let mut column = Vector6::zeros();
            for &(i, coupling) in &self.gain_terms[joint] {
                let weight = T::splat(coupling) * chain.coupled_motor_positions[joint];
                if any_non_zero(weight) {
                    column += jacobian.column(self.joint_columns[i]) * weight;
                }
            }
            jacobian.set(
                Some(gain_column),
                column.fixed_rows::<3>(0).into_owned(),
                column.fixed_rows::<3>(3).into_owned(),
            );
        }
        // c_j: the joint variable's column times τ_j (module docs).
        for (joint, compliance_column) in self.compliance_columns.iter().enumerate() {
            let Some(compliance_column) = *compliance_column else {
                continue;
            };
            let column = jacobian.column(self.joint_columns[joint]) * chain.torques[joint];
            jacobian.set(
                Some(compliance_column),
                column.fixed_rows::<3>(0).into_owned(),
                column.fixed_rows::<3>(3).into_owned(),
            );
        }
        // tilt_k: Σ_j c_j ∂τ_j/∂tilt_k times joint j's column (module docs).
        let n = self.joint_count();
        for (axis, tilt_column) in self.tilt_columns.iter().enumerate() {
            let Some(tilt_column) = *tilt_column else {
                continue;
            };
            let mut column = Vector6::zeros();
            if !chain.tilt_torques.is_empty() {
                for (joint, compliance) in self.compliances.iter().enumerate() {
                    let weight = T::splat(*compliance) * chain.tilt_torques[axis * n + joint];
                    if any_non_zero(weight) {
                        column += jacobian.column(self.joint_columns[joint]) * weight;
                    }
                }
            }
            jacobian.set(
                Some(tilt_column),
                column.fixed_rows::<3>(0).into_owned(),
                column.fixed_rows::<3>(3).into_owned(),
            );
        }
    }
}

/// The scalar of the kinematics: one configuration's `f64`, or the values
/// of several configurations in SIMD lanes (`simba`'s `WideF64x4`, four),
/// each lane computed with the operations, and so to the bits, of its
/// configuration alone (no operation mixes lanes).
pub(super) trait Lane: SimdRealField<Element = f64> + Copy {}

impl<T: SimdRealField<Element = f64> + Copy> Lane for T {}

/// Whether some lane of `value` is not zero: a derived column skips the
/// terms whose weight is zero in every lane (adding `0·x` to a sum begun at
/// +0 changes none of its bits, so a lane with a zero weight among others
/// that are not has the bits it has alone).
#[inline(always)]
fn any_non_zero<T: Lane>(value: T) -> bool {
    !value.simd_eq(T::zero()).all()
}

/// `pose` with each value in every lane.
#[inline(always)]
fn splat_pose<T: Lane>(pose: &IsometryMatrix3<f64>) -> IsometryMatrix3<T> {
    IsometryMatrix3::from_parts(
        Translation3::from(pose.translation.vector.map(T::splat)),
        Rotation3::from_matrix_unchecked(pose.rotation.matrix().map(T::splat)),
    )
}

/// What the parameter Jacobian reads of the configuration(s) evaluated:
/// the frames' poses and, for the gain, compliance and tilt columns, the
/// coupled motor variables and the loads.
pub(super) struct ChainView<'c, T: Scalar> {
    pub(super) poses: &'c [IsometryMatrix3<T>],
    pub(super) coupled_motor_positions: &'c [T],
    pub(super) torques: &'c [T],
    pub(super) tilt_torques: &'c [T],
}

impl ChainBuffer {
    fn view(&self) -> ChainView<'_, f64> {
        ChainView {
            poses: &self.world_from_frame,
            coupled_motor_positions: &self.coupled_motor_positions,
            torques: &self.torques,
            tilt_torques: &self.tilt_torques,
        }
    }

    /// The joint variables q of the configuration evaluated (eq. 4).
    pub(super) fn joint_positions(&self) -> &[f64] {
        &self.joint_positions
    }

    /// Its coupled motor variables Cm·qm, its loads τ and their tilt
    /// derivatives (empty when none).
    pub(super) fn loads(&self) -> (&[f64], &[f64], &[f64]) {
        (
            &self.coupled_motor_positions,
            &self.torques,
            &self.tilt_torques,
        )
    }
}

/// Where a Jacobian is written: column by column.
pub(super) trait JacobianStore<T: Scalar> {
    fn set(&mut self, column: Option<usize>, position: Vector3<T>, rotation: Vector3<T>);
    fn column(&self, column: usize) -> Vector6<T>;
}

impl JacobianStore<f64> for Matrix6xX<f64> {
    fn set(&mut self, column: Option<usize>, position: Vector3<f64>, rotation: Vector3<f64>) {
        if let Some(column) = column {
            let mut target = self.column_mut(column);
            target.fixed_rows_mut::<3>(0).copy_from(&position);
            target.fixed_rows_mut::<3>(3).copy_from(&rotation);
        }
    }

    fn column(&self, column: usize) -> Vector6<f64> {
        Matrix6xX::column(self, column).into_owned()
    }
}

/// A row-major 6×Np (or 3×Np, position rows only) buffer, of one
/// configuration's values or of several's in lanes.
pub(super) struct RowMajor<'a, T> {
    pub(super) rows: &'a mut [T],
    pub(super) parameters: usize,
    /// Whether the rotation rows 3–5 are kept.
    pub(super) rotation: bool,
}

impl<T: Lane> JacobianStore<T> for RowMajor<'_, T> {
    #[inline(always)]
    fn set(&mut self, column: Option<usize>, position: Vector3<T>, rotation: Vector3<T>) {
        if let Some(column) = column {
            for axis in 0..3 {
                self.rows[axis * self.parameters + column] = position[axis];
            }
            if self.rotation {
                for axis in 0..3 {
                    self.rows[(axis + 3) * self.parameters + column] = rotation[axis];
                }
            }
        }
    }

    #[inline(always)]
    fn column(&self, column: usize) -> Vector6<T> {
        let kept = if self.rotation { 6 } else { 3 };
        Vector6::from_fn(|axis, _| {
            if axis < kept {
                self.rows[axis * self.parameters + column]
            } else {
                T::zero()
            }
        })
    }
}

impl CompiledFrame {
    /// Eq. 3 with the configuration-dependent θ (its sine and cosine) and
    /// r: `tilt · (Trans(x,d)·Rot(z,θ)·Trans(z,r))`.
    #[inline(always)]
    fn moving<T: Lane>(&self, (sin_theta, cos_theta): (T, T), r: T) -> IsometryMatrix3<T> {
        let x_axis: Vector3<T> = self.tilt.column(0).map(T::splat);
        let y_axis: Vector3<T> = self.tilt.column(1).map(T::splat);
        let z_axis: Vector3<T> = self.tilt.column(2).map(T::splat);
        // tilt · Rot(z, θ): its columns are those of tilt turned about z.
        let rotation = Matrix3::from_columns(&[
            x_axis * cos_theta + y_axis * sin_theta,
            y_axis * cos_theta - x_axis * sin_theta,
            z_axis,
        ]);
        IsometryMatrix3::from_parts(
            Translation3::from(x_axis * T::splat(self.d) + z_axis * r),
            Rotation3::from_matrix_unchecked(rotation),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::{forward_kinematics, parameter_jacobian};
    use crate::test_robots::{elastic_stanford, random_configuration, random_robot, stanford};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The joints' turns, taken four at a time, are [`turn::sin_cos`] of
    /// each joint's angle bit for bit, for any number of revolute joints (a
    /// lane group part-filled) and joints turned many times round.
    #[test]
    fn turns_in_lanes_are_the_one_sine_of_every_route() {
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        for joints in 1..=9 {
            let robot = Robot::template("arm", &"R".repeat(joints)).expect("template");
            let model = KinematicModel::new(&robot);
            let mut chain = ChainBuffer::default();
            for _ in 0..50 {
                let q: Vec<f64> = (0..joints)
                    .map(|_| rand::RngExt::random_range(&mut rng, -100.0..100.0))
                    .collect();
                model.forward_joints(&q, &mut chain);
                assert_eq!(chain.turns.len(), joints);
                for (&(sin, cos), (j, frame)) in chain
                    .turns
                    .iter()
                    .zip(model.frames.iter().enumerate().skip(1))
                {
                    let (expected_sin, expected_cos) = turn::sin_cos(frame.theta + q[j - 1]);
                    assert_eq!(sin.to_bits(), expected_sin.to_bits(), "{}", q[j - 1]);
                    assert_eq!(cos.to_bits(), expected_cos.to_bits(), "{}", q[j - 1]);
                }
            }
        }
    }

    #[test]
    fn compiled_model_equals_the_reference_implementation() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut robots = vec![stanford()];
        robots.extend((0..10).map(|i| random_robot(&mut rng, 2 + i % 6)));
        let mut rows = Vec::new();
        let mut without_beta_seen = false;
        for robot in robots {
            let model = KinematicModel::new(&robot);
            let mut chain = ChainBuffer::default();
            let mut jacobian = Matrix6xX::zeros(0);
            for _ in 0..5 {
                let qm = random_configuration(&robot, &mut rng);
                model.forward(&qm, &mut chain).expect("valid");
                model.jacobian(&chain, &mut jacobian);
                let reference = forward_kinematics(&robot, &qm).expect("valid");
                // Bit for bit without a Hayati β (the same products and sines).
                let without_beta = robot.frames().iter().all(|frame| frame.beta == 0.0);
                for (a, b) in reference.poses().iter().zip(&chain.world_from_frame) {
                    assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-14);
                    if without_beta {
                        assert_eq!(a, b);
                    }
                }
                without_beta_seen |= without_beta;
                let expected = parameter_jacobian(&robot, &qm).expect("valid");
                assert!((&expected - &jacobian).abs().max() < 1e-13);
                // Row-major, all rows then position rows only, into a buffer
                // reused across configurations and robots (stale values must not survive).
                let np = expected.ncols();
                for which in [JacobianRows::Full, JacobianRows::Position] {
                    rows.iter_mut().for_each(|value| *value = f64::NAN);
                    model.jacobian_rows(&chain, &mut rows, which);
                    assert_eq!(rows.len(), which.count() * np);
                    for axis in 0..which.count() {
                        for column in 0..np {
                            assert_eq!(rows[axis * np + column], jacobian[(axis, column)]);
                        }
                    }
                }
            }
        }
        assert!(without_beta_seen, "a robot without β was compared");
    }

    /// A model selecting some columns computes each of them as the whole
    /// model does, bit for bit, in the order asked, for coupled chains,
    /// elastic ones with gravity's tilts, both sets of rows and buffers
    /// reused; the joint columns a kept gain, compliance or tilt reads
    /// follow the kept columns, and only then.
    #[test]
    fn a_selecting_model_computes_its_columns_as_the_whole_model() {
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let mut robots = vec![stanford(), elastic_stanford(1, 0.02)];
        robots.extend((0..8).map(|i| random_robot(&mut rng, 2 + i % 6)));
        let (mut all, mut some) = (Vec::new(), Vec::new());
        let mut chain = ChainBuffer::default();
        let mut hidden_seen = false;
        for robot in &robots {
            let model = KinematicModel::new(robot);
            let np = model.parameter_count();
            let n = robot.joint_count();
            for _ in 0..6 {
                // A random subset of the parameters, in a random order.
                let mut kept: Vec<usize> = (0..np)
                    .filter(|_| rand::RngExt::random_bool(&mut rng, 0.6))
                    .collect();
                for i in (1..kept.len()).rev() {
                    kept.swap(i, rand::RngExt::random_range(&mut rng, 0..=i));
                }
                let selected = model.selecting(&kept);
                let derived = model
                    .gain_columns
                    .iter()
                    .chain(&model.compliance_columns)
                    .chain(&model.tilt_columns)
                    .flatten()
                    .any(|column| kept.contains(column));
                let missing = model
                    .joint_columns
                    .iter()
                    .filter(|joint| !kept.contains(joint))
                    .count();
                // Joint columns follow the kept ones only when read.
                let width = selected.parameter_count();
                assert!(width >= kept.len() && width <= kept.len() + missing);
                if !derived {
                    assert_eq!(width, kept.len());
                }
                hidden_seen |= width > kept.len();
                let qm = random_configuration(robot, &mut rng);
                let torques: Vec<f64> = (0..n)
                    .map(|_| rand::RngExt::random_range(&mut rng, -20.0..20.0))
                    .collect();
                let tilts: Vec<f64> = (0..2 * n)
                    .map(|_| rand::RngExt::random_range(&mut rng, -5.0..5.0))
                    .collect();
                model
                    .forward_tilted(&qm, Some(&torques), Some(&tilts), &mut chain)
                    .expect("valid");
                for which in [JacobianRows::Full, JacobianRows::Position] {
                    some.iter_mut().for_each(|value| *value = f64::NAN);
                    model.jacobian_rows(&chain, &mut all, which);
                    selected.jacobian_rows(&chain, &mut some, which);
                    assert_eq!(some.len(), which.count() * width);
                    for axis in 0..which.count() {
                        for (k, index) in kept.iter().enumerate() {
                            assert_eq!(
                                some[axis * width + k].to_bits(),
                                all[axis * np + index].to_bits(),
                                "{} row {axis}, parameter {index}",
                                robot.name()
                            );
                        }
                    }
                }
            }
        }
        assert!(hidden_seen, "a kept gain read a joint column not kept");
    }

    /// An elastic robot under load: the pose is the rigid model's at the
    /// deflected joints (motor positions moved by M⁻¹·c∘τ), and each
    /// compliance column equals central differences of that pose in c_j.
    #[test]
    fn a_loaded_elastic_robot_deflects_and_its_compliance_columns_are_derivatives() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut robot = stanford();
        let compliances = vec![2e-3, 5e-3, 1e-4, 3e-3, 4e-3, 6e-3];
        robot
            .set_compliances(Some(compliances.clone()))
            .expect("elastic");
        let model = KinematicModel::new(&robot);
        let qm = random_configuration(&robot, &mut rng);
        let torques = [1.5, -20.0, 3.0, 0.7, -2.5, 0.4];
        let mut chain = ChainBuffer::default();
        model
            .forward_loaded(&qm, Some(&torques), &mut chain)
            .expect("valid");
        let deflection: Vec<f64> = compliances
            .iter()
            .zip(&torques)
            .map(|(c, t)| c * t)
            .collect();
        let joint = robot.joint_positions(&qm).expect("q");
        let deflected: Vec<f64> = joint.iter().zip(&deflection).map(|(q, d)| q + d).collect();
        let moved = robot.motor_positions(&deflected).expect("qm");
        let reference = forward_kinematics(&robot, moved.as_slice()).expect("valid");
        let difference =
            reference.world_from_tool().to_homogeneous() - chain.world_from_tool().to_homogeneous();
        assert!(difference.abs().max() < 1e-12, "{difference}");
        // Without torques the elastic robot is the rigid one.
        model.forward(&qm, &mut chain).expect("valid");
        let rigid = forward_kinematics(&robot, &qm).expect("valid");
        assert_eq!(rigid.world_from_tool(), chain.world_from_tool());

        model
            .forward_loaded(&qm, Some(&torques), &mut chain)
            .expect("valid");
        let mut jacobian = Matrix6xX::zeros(0);
        model.jacobian(&chain, &mut jacobian);
        assert_eq!(jacobian.ncols(), 51);
        // Steps of ~1e-4 rad: smaller ones lose the rotation's digits in
        // the axis-angle of a nearly identity rotation.
        let step = 1e-4;
        for joint in 1..=6 {
            let id = ParameterId::new(ParameterKind::Compliance, joint);
            let column = robot.parameters().index_of(id).expect("c_j");
            let pose_at = |delta: f64| {
                let mut moved = robot.clone();
                moved
                    .set_parameter(id, compliances[joint - 1] + delta)
                    .expect("set");
                let mut chain = ChainBuffer::default();
                KinematicModel::new(&moved)
                    .forward_loaded(&qm, Some(&torques), &mut chain)
                    .expect("valid");
                *chain.world_from_tool()
            };
            let (plus, minus) = (pose_at(step), pose_at(-step));
            let position = (plus.translation.vector - minus.translation.vector) / (2.0 * step);
            let rotation = (plus.rotation * minus.rotation.inverse()).scaled_axis() / (2.0 * step);
            let analytic = jacobian.column(column);
            let scale = analytic.norm().max(1.0);
            assert!(
                (analytic.fixed_rows::<3>(0) - position).norm() < 1e-6 * scale,
                "c{joint}"
            );
            assert!(
                (analytic.fixed_rows::<3>(3) - rotation).norm() < 1e-6 * scale,
                "c{joint}"
            );
        }
    }

    /// Gravity's tilts: the joints carry τ + Σ tilt_k ∂τ/∂tilt_k, and the
    /// tilts' and compliances' columns equal central differences of the
    /// pose; without the derivatives the tilts change nothing, and while
    /// every compliance is zero their columns are.
    #[test]
    fn the_gravity_tilts_load_the_joints_and_their_columns_are_derivatives() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut robot = stanford();
        let compliances = vec![2e-3, 5e-3, 1e-4, 3e-3, 4e-3, 6e-3];
        robot
            .set_compliances(Some(compliances.clone()))
            .expect("elastic");
        let tilt = [
            ParameterId::new(ParameterKind::GravityTilt, 1),
            ParameterId::new(ParameterKind::GravityTilt, 2),
        ];
        robot.set_parameter(tilt[0], 0.02).expect("tilt");
        robot.set_parameter(tilt[1], -0.03).expect("tilt");
        let qm = random_configuration(&robot, &mut rng);
        let torques = [1.5, -20.0, 3.0, 0.7, -2.5, 0.4];
        let tilt_torques = [
            4.0, -3.0, 0.5, 1.0, -0.2, 0.3, -2.0, 6.0, -1.0, 0.4, 0.9, -0.6,
        ];
        let pose_of = |robot: &Robot, tilts: Option<&[f64]>| {
            let mut chain = ChainBuffer::default();
            KinematicModel::new(robot)
                .forward_tilted(&qm, Some(&torques), tilts, &mut chain)
                .expect("valid");
            *chain.world_from_tool()
        };
        let carried: Vec<f64> = (0..6)
            .map(|j| torques[j] + 0.02 * tilt_torques[j] - 0.03 * tilt_torques[6 + j])
            .collect();
        let mut chain = ChainBuffer::default();
        let model = KinematicModel::new(&robot);
        model
            .forward_loaded(&qm, Some(&carried), &mut chain)
            .expect("valid");
        let expected = *chain.world_from_tool();
        let tilted = pose_of(&robot, Some(&tilt_torques));
        assert!(
            (expected.to_homogeneous() - tilted.to_homogeneous())
                .abs()
                .max()
                < 1e-14
        );
        model
            .forward_loaded(&qm, Some(&torques), &mut chain)
            .expect("valid");
        assert_eq!(pose_of(&robot, None), *chain.world_from_tool());

        model
            .forward_tilted(&qm, Some(&torques), Some(&tilt_torques), &mut chain)
            .expect("valid");
        let mut jacobian = Matrix6xX::zeros(0);
        model.jacobian(&chain, &mut jacobian);
        let step = 1e-4;
        let ids = tilt
            .into_iter()
            .chain((1..=6).map(|j| ParameterId::new(ParameterKind::Compliance, j)));
        for id in ids {
            let column = robot.parameters().index_of(id).expect("parameter");
            let pose_at = |delta: f64| {
                let mut moved = robot.clone();
                moved
                    .set_parameter(id, robot.parameter(id) + delta)
                    .expect("set");
                pose_of(&moved, Some(&tilt_torques))
            };
            let (plus, minus) = (pose_at(step), pose_at(-step));
            let position = (plus.translation.vector - minus.translation.vector) / (2.0 * step);
            let rotation = (plus.rotation * minus.rotation.inverse()).scaled_axis() / (2.0 * step);
            let analytic = jacobian.column(column);
            assert!(analytic.norm() > 1e-4, "{id} has an effect");
            let scale = analytic.norm().max(1.0);
            assert!(
                (analytic.fixed_rows::<3>(0) - position).norm() < 1e-6 * scale,
                "{id}"
            );
            assert!(
                (analytic.fixed_rows::<3>(3) - rotation).norm() < 1e-6 * scale,
                "{id}"
            );
        }
        // A robot whose joints do not yield: the tilts' columns are zero.
        robot.set_compliances(Some(vec![0.0; 6])).expect("elastic");
        let model = KinematicModel::new(&robot);
        model
            .forward_tilted(&qm, Some(&torques), Some(&tilt_torques), &mut chain)
            .expect("valid");
        model.jacobian(&chain, &mut jacobian);
        for id in tilt {
            let column = robot.parameters().index_of(id).expect("tilt");
            assert_eq!(jacobian.column(column).norm(), 0.0, "{id}");
        }
    }
}
