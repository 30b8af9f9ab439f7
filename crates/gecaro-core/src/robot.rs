//! The robot model of paper §2: Khalil–Kleinfinger frames with Hayati β,
//! joint parameters (limits, offsets, gains) and the coupling matrices of eq. 4.
//!
//! A robot with n joints has n+2 frames j = 0..=n+1. Frame j is placed on
//! frame j−1 by (eq. 3)
//!
//! ```text
//! (j-1)T(j) = Rot(y, β_j) · Rot(x, α_j) · Trans(x, d_j) · Rot(z, θ_j) · Trans(z, r_j)
//! ```
//!
//! Frame 0 (the base, relative to the world frame −1) and frame n+1 (the
//! end-effector) are fixed (σ = 2); frames 1..=n are joints, revolute (σ = 0,
//! the joint variable q_j is added to θ_j) or prismatic (σ = 1, q_j is added to
//! r_j). Frame 0 carries only θ0 and r0: α0 = d0 = β0 = 0.
//!
//! Joint variables come from motor variables by eq. 4,
//! `q = Cj · diag(K) · Cm · qm + Offset`, and the joint limits `qmin ≤ q ≤ qmax`
//! apply to q (metres or radians, before θ_j / r_j are added).
//!
//! An elastic robot (issue 38) also has a compliance c_j per joint, which
//! adds `c_j·τ_j` to the joint variable under the gravity torque τ_j (see
//! [`crate::KinematicModel::forward_loaded`]); its parameter vector ends
//! with `c1 … cn` ([`ParameterSpace::elastic`]).
//!
//! A [`Robot`] is always valid: [`Robot::new`] checks every rule and names the
//! [`Field`] at fault.

use nalgebra::{DMatrix, DVector};

use crate::frame::{Frame, FrameType, Joint};
use crate::parameters::{ParameterId, ParameterKind, ParameterSpace};
use crate::priority::PriorityMatrix;
use crate::stated::{
    check_gain, check_magnitude, parameters_with, validate_compliances, validate_coupling,
    validate_frames, validate_joint,
};
use crate::{Error, Field};

/// How far beyond a joint limit (rad, or m) a joint value still counts as
/// within it ([`Robot::within_limits`], [`Robot::turned_into_limits`]): a
/// solver clamped to the limit may leave rounding's worth beyond it.
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// Whether `q` lies within the limits of `joint`, to [`LIMIT_TOLERANCE`].
fn within(joint: &Joint, q: f64) -> bool {
    (joint.qmin - LIMIT_TOLERANCE..=joint.qmax + LIMIT_TOLERANCE).contains(&q)
}

/// Everything needed to build a [`Robot`]; plain data, not yet validated.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotSpec {
    /// A human name, e.g. `Stanford`.
    pub name: String,
    /// Frames 0..=n+1.
    pub frames: Vec<Frame>,
    /// Joints 1..=n (element j−1 is joint j).
    pub joints: Vec<Joint>,
    /// Cm of eq. 4 (n×n); identity when `None`.
    pub motor_coupling: Option<DMatrix<f64>>,
    /// Cj of eq. 4 (n×n); identity when `None`.
    pub joint_coupling: Option<DMatrix<f64>>,
    /// A priority matrix overriding the defaults of paper §4.
    pub priority: Option<PriorityMatrix>,
    /// The compliance of every joint (rad/(N·m) or m/N) of an elastic
    /// robot; `None` for a rigid one.
    pub compliances: Option<Vec<f64>>,
}

impl RobotSpec {
    /// A rigid robot's statement: `frames` 0..=n+1 and `joints` 1..=n, no
    /// coupling (identity Cm and Cj), the paper's priorities, no compliance.
    pub fn rigid(name: impl Into<String>, frames: Vec<Frame>, joints: Vec<Joint>) -> RobotSpec {
        RobotSpec {
            name: name.into(),
            frames,
            joints,
            motor_coupling: None,
            joint_coupling: None,
            priority: None,
            compliances: None,
        }
    }
}

/// A valid serial robot (see the module docs for the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    name: String,
    frames: Vec<Frame>,
    joints: Vec<Joint>,
    motor_coupling: DMatrix<f64>,
    joint_coupling: DMatrix<f64>,
    priority_override: Option<PriorityMatrix>,
    compliances: Option<Vec<f64>>,
    /// tilt1, tilt2 (radians): how far gravity leans from the direction the
    /// mass model states ([`crate::MassModel::tilted`]); only an elastic
    /// robot's loads read them. Not part of a [`RobotSpec`]: an
    /// identification finds them and a front end folds them into the mass
    /// model's gravity before it writes the robot.
    gravity_tilt: [f64; 2],
    parameters: ParameterSpace,
    /// Cj · diag(K) · Cm, kept in step with the gains.
    motor_to_joint: DMatrix<f64>,
    /// Whether `motor_to_joint` is diagonal (no coupling): qm = (q − Offset)/K.
    /// Kept in step with it.
    motor_to_joint_diagonal: bool,
}

impl Robot {
    /// Validates a description and builds the robot.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the field at fault when: there are fewer than
    /// three frames; frame 0 or n+1 is not fixed (σ = 2), or a joint frame is;
    /// frame 0 has a non-zero α, d or β; a value is NaN or infinite; the joint
    /// count does not match; qmin > qmax; a gain is zero; a coupling matrix is
    /// not n×n or is singular; the priority matrix has the wrong shape or gives
    /// a priority to something that is not a parameter.
    pub fn new(spec: RobotSpec) -> Result<Self, Error> {
        let RobotSpec {
            name,
            frames,
            joints,
            motor_coupling,
            joint_coupling,
            priority,
            compliances,
        } = spec;
        validate_frames(&frames)?;
        let n = frames.len() - 2;
        if joints.len() != n {
            return Err(Error::invalid(
                Field::Frames,
                format!(
                    "{} joint frames need {} sets of joint parameters, got {}",
                    n,
                    n,
                    joints.len()
                ),
            ));
        }
        for (index, joint) in joints.iter().enumerate() {
            validate_joint(index + 1, joint)?;
        }
        let motor_coupling = validate_coupling("Cm", motor_coupling, n)?;
        let joint_coupling = validate_coupling("Cj", joint_coupling, n)?;
        let parameters = parameters_with(compliances.as_deref(), n)?;
        if let Some(priority) = &priority {
            priority.validate(&parameters)?;
        }
        let mut robot = Robot {
            name,
            frames,
            joints,
            motor_coupling,
            joint_coupling,
            priority_override: priority,
            compliances,
            gravity_tilt: [0.0; 2],
            parameters,
            motor_to_joint: DMatrix::zeros(n, n),
            motor_to_joint_diagonal: true,
        };
        robot.update_motor_to_joint();
        Ok(robot)
    }

    /// A template arm to start a new robot file from: joint types from the
    /// letters (`R` revolute, `P` prismatic, case-insensitive; e.g. `RRPRRR`),
    /// α alternating −π/2, +π/2 from joint 2 on so that the chain is not
    /// degenerate, the tool frame 0.1 m along the last z axis, default limits.
    ///
    /// # Errors
    /// [`Error::Invalid`] (at [`Field::Frames`]) for an empty string or a
    /// letter other than R or P.
    ///
    /// ```
    /// let robot = gecaro_core::Robot::template("scara", "RRPR")?;
    /// assert_eq!(robot.joint_letters(), "RRPR");
    /// assert_eq!(robot.frames().len(), 6);
    /// # Ok::<(), gecaro_core::Error>(())
    /// ```
    pub fn template(name: impl Into<String>, joint_letters: &str) -> Result<Self, Error> {
        if joint_letters.is_empty() {
            return Err(Error::invalid(
                Field::Frames,
                "no joints: give joint letters such as RRPRRR",
            ));
        }
        let mut frames = vec![Frame::new(FrameType::Fixed)];
        for (index, letter) in joint_letters.chars().enumerate() {
            let frame_type = match letter.to_ascii_uppercase() {
                'R' => FrameType::Revolute,
                'P' => FrameType::Prismatic,
                other => {
                    return Err(Error::invalid(
                        Field::Frames,
                        format!(
                            "joint {} is `{other}`: joints are R (revolute) or P (prismatic)",
                            index + 1
                        ),
                    ));
                }
            };
            let alpha = match index {
                0 => 0.0,
                odd if odd % 2 == 1 => -std::f64::consts::FRAC_PI_2,
                _ => std::f64::consts::FRAC_PI_2,
            };
            frames.push(Frame {
                alpha,
                ..Frame::new(frame_type)
            });
        }
        frames.push(Frame {
            r: 0.1,
            ..Frame::new(FrameType::Fixed)
        });
        let joints = frames[1..frames.len() - 1]
            .iter()
            .map(|frame| Joint::default_for(frame.frame_type))
            .collect();
        Robot::new(RobotSpec::rigid(name, frames, joints))
    }

    /// The description this robot was built from (to edit and rebuild).
    pub fn to_spec(&self) -> RobotSpec {
        RobotSpec {
            name: self.name.clone(),
            frames: self.frames.clone(),
            joints: self.joints.clone(),
            motor_coupling: Some(self.motor_coupling.clone()),
            joint_coupling: Some(self.joint_coupling.clone()),
            priority: self.priority_override.clone(),
            compliances: self.compliances.clone(),
        }
    }

    /// The compliances c_1..c_n of an elastic robot (rad/(N·m) for a
    /// revolute joint, m/N for a prismatic one); `None` for a rigid robot.
    pub fn compliances(&self) -> Option<&[f64]> {
        self.compliances.as_deref()
    }

    /// Makes the robot elastic with these compliances (`None`: rigid again).
    /// The parameter vector gains (or loses) `c1 … cn` at its end.
    ///
    /// # Errors
    /// When there are not n finite compliances, or the priority override
    /// gives a priority to a compliance the robot would no longer have.
    pub fn set_compliances(&mut self, compliances: Option<Vec<f64>>) -> Result<(), Error> {
        let n = self.joint_count();
        let parameters = parameters_with(compliances.as_deref(), n)?;
        if let Some(priority) = &self.priority_override {
            priority.validate(&parameters)?;
        }
        self.parameters = parameters;
        self.compliances = compliances;
        Ok(())
    }

    /// The gravity tilts tilt1, tilt2 (radians; see the field's docs), zero
    /// unless an identification moved them.
    pub fn gravity_tilt(&self) -> [f64; 2] {
        self.gravity_tilt
    }

    /// The same robot with its gravity tilts at zero: what remains once
    /// they are folded into the mass model ([`crate::MassModel::tilted`]).
    pub fn untilted(&self) -> Robot {
        Robot {
            gravity_tilt: [0.0; 2],
            ..self.clone()
        }
    }

    /// Whether the robot is elastic (has compliances, even all zero).
    pub fn is_elastic(&self) -> bool {
        self.compliances.is_some()
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Renames the robot.
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }

    /// Number of joints n.
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Frames 0..=n+1.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Joints 1..=n (element j−1 is joint j).
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The joint letters, e.g. `RRPRRR` for the Stanford arm.
    pub fn joint_letters(&self) -> String {
        self.frames[1..=self.joint_count()]
            .iter()
            .map(|frame| frame.frame_type.letter())
            .collect()
    }

    /// Cm of eq. 4.
    pub fn motor_coupling(&self) -> &DMatrix<f64> {
        &self.motor_coupling
    }

    /// Cj of eq. 4.
    pub fn joint_coupling(&self) -> &DMatrix<f64> {
        &self.joint_coupling
    }

    /// The parameter vocabulary of this robot.
    pub fn parameters(&self) -> &ParameterSpace {
        &self.parameters
    }

    /// The priority matrix in force: the user's override, or the defaults of paper §4.
    pub fn priority(&self) -> PriorityMatrix {
        self.priority_override
            .clone()
            .unwrap_or_else(|| PriorityMatrix::default_for(&self.frames))
    }

    /// The user's priority matrix, if the robot carries one.
    pub fn priority_override(&self) -> Option<&PriorityMatrix> {
        self.priority_override.as_ref()
    }

    /// Replaces (or, with `None`, removes) the priority override.
    ///
    /// # Errors
    /// When the matrix does not fit this robot.
    pub fn set_priority_override(&mut self, priority: Option<PriorityMatrix>) -> Result<(), Error> {
        if let Some(priority) = &priority {
            priority.validate(&self.parameters)?;
        }
        self.priority_override = priority;
        Ok(())
    }

    /// The value of one parameter.
    ///
    /// # Panics
    /// If `id` is not a parameter of this robot (see [`ParameterSpace::index_of`]).
    pub fn parameter(&self, id: ParameterId) -> f64 {
        assert!(
            self.parameters.contains(id),
            "{id} is not a parameter of this robot"
        );
        match (id.kind, &self.compliances) {
            (ParameterKind::Gain, _) => self.joints[id.frame - 1].gain,
            (ParameterKind::Compliance, Some(compliances)) => compliances[id.frame - 1],
            (ParameterKind::GravityTilt, _) => self.gravity_tilt[id.frame - 1],
            (kind, _) => self.frames[id.frame].get(kind),
        }
    }

    /// The parameter vector η in vocabulary order.
    pub fn parameter_values(&self) -> DVector<f64> {
        DVector::from_iterator(
            self.parameters.len(),
            self.parameters.ids().iter().map(|id| self.parameter(*id)),
        )
    }

    /// Sets one parameter.
    ///
    /// # Errors
    /// When `id` is not a parameter of this robot, the value is not finite, or
    /// a gain would become zero.
    pub fn set_parameter(&mut self, id: ParameterId, value: f64) -> Result<(), Error> {
        if self.assign(id, value)? {
            self.update_motor_to_joint();
        }
        Ok(())
    }

    /// Wraps every constant angle (α, θ, β of every frame) into (−π, π]:
    /// the geometry is unchanged (rotations are 2π-periodic; joint offsets
    /// and limits, which a turn would move, are left alone). An
    /// identification can leave θ or α several turns away on a nearly
    /// flat direction; a robot file states them within a turn.
    ///
    /// ```
    /// use gecaro_core::{ParameterId, ParameterKind, Robot};
    ///
    /// let mut robot = Robot::template("arm", "RR").unwrap();
    /// let theta = ParameterId::new(ParameterKind::Theta, 1);
    /// robot.set_parameter(theta, 0.5 + 4.0 * std::f64::consts::PI).unwrap();
    /// robot.wrap_angles();
    /// assert!((robot.parameter(theta) - 0.5).abs() < 1e-12);
    /// ```
    pub fn wrap_angles(&mut self) {
        let angles: Vec<ParameterId> = self
            .parameters
            .ids()
            .iter()
            .copied()
            .filter(|id| {
                matches!(
                    id.kind,
                    ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta
                )
            })
            .collect();
        for id in angles {
            let value = self.parameter(id);
            let wrapped = crate::kinematics::turn::wrapped(value);
            if wrapped != value {
                // An angle is never a gain: assigning it cannot fail.
                let _ = self.assign(id, wrapped);
            }
        }
    }

    /// Brings every angle (α, θ, β) within ±π of `reference`'s value of it
    /// by whole turns, the same robot: an identification's steps may take an
    /// angle the long way round (a joint zero 90° off written as 2250°).
    ///
    /// ```
    /// use gecaro_core::{ParameterId, ParameterKind, Robot};
    ///
    /// let nominal = Robot::template("arm", "RR").unwrap();
    /// let mut robot = nominal.clone();
    /// let theta = ParameterId::new(ParameterKind::Theta, 2);
    /// robot.set_parameter(theta, 1.5 + 6.0 * std::f64::consts::PI).unwrap();
    /// robot.wrap_angles_near(&nominal);
    /// assert!((robot.parameter(theta) - 1.5).abs() < 1e-12);
    /// ```
    pub fn wrap_angles_near(&mut self, reference: &Robot) {
        use std::f64::consts::{PI, TAU};
        let angles: Vec<ParameterId> = self
            .parameters
            .ids()
            .iter()
            .copied()
            .filter(|id| {
                matches!(
                    id.kind,
                    ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta
                ) && reference.parameters.contains(*id)
            })
            .collect();
        for id in angles {
            let (value, near) = (self.parameter(id), reference.parameter(id));
            let turns = ((value - near) / TAU).round();
            let wrapped = value - TAU * turns;
            if turns != 0.0 && (wrapped - near).abs() <= PI + 1e-12 {
                // An angle is never a gain: assigning it cannot fail.
                let _ = self.assign(id, wrapped);
            }
        }
    }

    /// Adds `deltas` (vocabulary order) to the parameters: η ← η + Δη.
    ///
    /// # Errors
    /// When `deltas` has the wrong length, or a result is invalid (see
    /// [`Robot::set_parameter`]).
    pub fn apply_deltas(&mut self, deltas: &[f64]) -> Result<(), Error> {
        if deltas.len() != self.parameters.len() {
            return Err(Error::invalid(
                Field::Frames,
                format!(
                    "a parameter update needs {} values, got {}",
                    self.parameters.len(),
                    deltas.len()
                ),
            ));
        }
        // Cj·diag(K)·Cm once for all the gains, even when a later value fails.
        let mut gains_changed = false;
        let outcome = deltas
            .iter()
            .enumerate()
            .filter(|(_, delta)| **delta != 0.0)
            .try_for_each(|(index, delta)| {
                let id = self.parameters.id(index);
                gains_changed |= self.assign(id, self.parameter(id) + delta)?;
                Ok(())
            });
        if gains_changed {
            self.update_motor_to_joint();
        }
        outcome
    }

    /// Validates and stores one parameter value; whether it was a gain (then
    /// the motor-to-joint map is out of date).
    fn assign(&mut self, id: ParameterId, value: f64) -> Result<bool, Error> {
        if !self.parameters.contains(id) {
            return Err(Error::UnknownParameter {
                name: id.to_string(),
                suggestion: None,
            });
        }
        let field = Field::Frame {
            index: id.frame,
            key: match id.kind {
                ParameterKind::Gain => "K",
                ParameterKind::Compliance => "compliance",
                kind => kind.symbol(),
            },
        };
        if !value.is_finite() {
            return Err(Error::invalid(
                field,
                format!("{value} is not a finite number"),
            ));
        }
        match id.kind {
            ParameterKind::Gain => {
                check_gain(field, value)?;
                self.joints[id.frame - 1].gain = value;
                Ok(true)
            }
            ParameterKind::Compliance => {
                check_magnitude(field, value)?;
                if let Some(compliances) = &mut self.compliances {
                    compliances[id.frame - 1] = value;
                }
                Ok(false)
            }
            ParameterKind::GravityTilt => {
                check_magnitude(field, value)?;
                self.gravity_tilt[id.frame - 1] = value;
                Ok(false)
            }
            kind => {
                if let Some(slot) = self.frames[id.frame].get_mut(kind) {
                    *slot = value;
                }
                Ok(false)
            }
        }
    }

    /// Joint variables from motor variables, eq. 4: `q = Cj·diag(K)·Cm·qm + Offset`.
    ///
    /// # Errors
    /// When `qm` does not hold n finite values.
    pub fn joint_positions(&self, motor_positions: &[f64]) -> Result<DVector<f64>, Error> {
        let mut q = DVector::zeros(self.joint_count());
        self.joint_positions_into(motor_positions, q.as_mut_slice())?;
        Ok(q)
    }

    /// [`joint_positions`](Self::joint_positions) written into
    /// `joint_positions` (n values), without allocating: a million
    /// configurations checked against their limits.
    ///
    /// # Errors
    /// As [`joint_positions`](Self::joint_positions); `joint_positions`
    /// must hold n values.
    pub fn joint_positions_into(
        &self,
        motor_positions: &[f64],
        joint_positions: &mut [f64],
    ) -> Result<(), Error> {
        self.check_conversion(motor_positions, joint_positions)?;
        // q = M·qm + Offset, each row summed in the order of nalgebra's
        // matrix–vector product (the same bits).
        for (row, (value, joint)) in joint_positions.iter_mut().zip(&self.joints).enumerate() {
            let product = motor_positions
                .iter()
                .enumerate()
                .map(|(column, qm)| self.motor_to_joint[(row, column)] * qm)
                .reduce(|sum, term| sum + term)
                .unwrap_or(0.0);
            *value = product + joint.offset;
        }
        Ok(())
    }

    /// Motor variables from joint variables, the inverse of eq. 4:
    /// `qm = (Cj·diag(K)·Cm)⁻¹ · (q − Offset)`.
    ///
    /// # Errors
    /// When `q` does not hold n finite values.
    pub fn motor_positions(&self, joint_positions: &[f64]) -> Result<DVector<f64>, Error> {
        let mut motor_positions = DVector::zeros(self.joint_count());
        self.motor_positions_into(joint_positions, motor_positions.as_mut_slice())?;
        Ok(motor_positions)
    }

    /// [`motor_positions`](Self::motor_positions) written into
    /// `motor_positions` (n values): without couplings, without allocating
    /// (an inverse solution's motor values, a million program targets).
    ///
    /// # Errors
    /// As [`motor_positions`](Self::motor_positions); `motor_positions`
    /// must hold n values.
    pub fn motor_positions_into(
        &self,
        joint_positions: &[f64],
        motor_positions: &mut [f64],
    ) -> Result<(), Error> {
        self.check_conversion(joint_positions, motor_positions)?;
        let shifted = joint_positions
            .iter()
            .zip(&self.joints)
            .map(|(q, joint)| q - joint.offset);
        // Without couplings the map is diagonal: qm = (q − Offset)/K, as LU
        // solves it.
        let map = &self.motor_to_joint;
        if self.motor_to_joint_diagonal {
            for (index, (value, shifted)) in motor_positions.iter_mut().zip(shifted).enumerate() {
                *value = shifted / map[(index, index)];
            }
            return Ok(());
        }
        // Validation guarantees the product is regular; LU keeps this exact to rounding.
        let shifted = DVector::from_iterator(self.joint_count(), shifted);
        let lu = self.motor_to_joint.clone().lu();
        let solved = lu.solve(&shifted).ok_or_else(|| {
            Error::invalid(
                Field::Coupling("Cj·diag(K)·Cm"),
                "the motor-to-joint map is singular",
            )
        })?;
        motor_positions.copy_from_slice(solved.as_slice());
        Ok(())
    }

    /// Checks a conversion of eq. 4 from `from` into `into`: n finite
    /// values, and room for n.
    fn check_conversion(&self, from: &[f64], into: &[f64]) -> Result<(), Error> {
        self.check_configuration(from)?;
        if into.len() != self.joint_count() {
            return Err(Error::ConfigurationLength {
                expected: self.joint_count(),
                found: into.len(),
            });
        }
        Ok(())
    }

    /// The product Cj · diag(K) · Cm, so that q = M · qm + Offset.
    pub fn motor_to_joint(&self) -> &DMatrix<f64> {
        &self.motor_to_joint
    }

    /// Whether each joint variable of `q` lies within its limits (with a
    /// tolerance of [`LIMIT_TOLERANCE`] for values pushed there by a solver).
    pub fn within_limits(&self, joint_positions: &[f64]) -> bool {
        joint_positions
            .iter()
            .zip(&self.joints)
            .all(|(q, joint)| within(joint, *q))
    }

    /// `joint_positions` with each revolute joint beyond its limits turned by
    /// whole turns (2π: the same pose) back within them, by the turn that
    /// brings it closest to its value in `reference` (joint positions of
    /// the same robot) where the range holds more than one. `None` when a
    /// joint cannot be brought within its limits: a prismatic one beyond
    /// them, or a revolute one whose range holds no whole turn of it.
    /// Joints within their limits are left as they are.
    ///
    /// A solver that follows a joint continuously cannot pass a limit, but
    /// a joint with a range of ±π reaches the pose of q = π + 0.1 at
    /// q = −π + 0.1 by turning the other way round.
    ///
    /// ```
    /// use gecaro_core::Robot;
    /// use std::f64::consts::PI;
    ///
    /// let robot = Robot::template("planar", "RP").unwrap(); // ±π, 0..1 m
    /// let turned = robot.turned_into_limits(&[PI + 0.1, 0.5], &[3.0, 0.5]);
    /// assert!((turned.unwrap()[0] - (0.1 - PI)).abs() < 1e-12);
    /// assert!(robot.turned_into_limits(&[0.3, 1.2], &[0.3, 0.5]).is_none());
    /// ```
    pub fn turned_into_limits(
        &self,
        joint_positions: &[f64],
        reference: &[f64],
    ) -> Option<Vec<f64>> {
        let turn = std::f64::consts::TAU;
        joint_positions
            .iter()
            .zip(reference)
            .zip(&self.joints)
            .zip(&self.frames[1..])
            .map(|(((q, near), joint), frame)| {
                if within(joint, *q) {
                    return Some(*q);
                }
                let (low, high) = (joint.qmin - LIMIT_TOLERANCE, joint.qmax + LIMIT_TOLERANCE);
                if frame.frame_type != FrameType::Revolute {
                    return None;
                }
                let (fewest, most) = (((low - q) / turn).ceil(), ((high - q) / turn).floor());
                (fewest <= most).then(|| q + turn * ((near - q) / turn).round().clamp(fewest, most))
            })
            .collect()
    }

    /// Whether `values`, configurations of n values one after another, all
    /// pass [`check_configuration`](Self::check_configuration): one pass
    /// over millions of them, which says only yes or no (the configuration
    /// at fault is found by checking them one by one).
    pub fn configurations_sound(&self, values: &[f64]) -> bool {
        // Every value read (no early exit: the loop is vectorised).
        values.len().is_multiple_of(self.joint_count())
            && values
                .iter()
                .fold(true, |all, value| all & value.is_finite())
    }

    /// Checks that a configuration has n finite values.
    ///
    /// # Errors
    /// [`Error::ConfigurationLength`] or [`Error::NonFiniteConfiguration`].
    pub fn check_configuration(&self, values: &[f64]) -> Result<(), Error> {
        if values.len() != self.joint_count() {
            return Err(Error::ConfigurationLength {
                expected: self.joint_count(),
                found: values.len(),
            });
        }
        if let Some((index, value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFiniteConfiguration {
                joint: index + 1,
                value: *value,
            });
        }
        Ok(())
    }

    /// Checks the robot against the rules a robot file is loaded by
    /// ([`Robot::new`]): values set one by one (`set_parameter`, an
    /// identification's steps) may leave them, e.g. a length beyond
    /// [`MAX_MAGNITUDE`](crate::MAX_MAGNITUDE). A front end checks before it writes or hands a
    /// robot on, so that every robot gecaro writes loads again.
    ///
    /// # Errors
    /// The first value that breaks a rule, with its field.
    pub fn check_stated(&self) -> Result<(), Error> {
        validate_frames(&self.frames)?;
        for (index, joint) in self.joints.iter().enumerate() {
            validate_joint(index + 1, joint)?;
        }
        if let Some(compliances) = &self.compliances {
            validate_compliances(compliances, self.joint_count())?;
        }
        Ok(())
    }

    fn update_motor_to_joint(&mut self) {
        let gains = DVector::from_iterator(self.joints.len(), self.joints.iter().map(|j| j.gain));
        self.motor_to_joint =
            &self.joint_coupling * DMatrix::from_diagonal(&gains) * &self.motor_coupling;
        let map = &self.motor_to_joint;
        self.motor_to_joint_diagonal = (0..map.ncols())
            .all(|column| (0..map.nrows()).all(|row| row == column || map[(row, column)] == 0.0));
    }
}

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};

    use super::*;

    /// Revolute joints beyond their limits are turned back by whole turns,
    /// to the turn closest to the reference where the range holds two;
    /// the pose does not change; prismatic joints are never turned.
    #[test]
    fn joints_beyond_their_limits_are_turned_back_by_whole_turns() {
        use std::f64::consts::TAU;
        let mut spec = Robot::template("three", "RRP").expect("template").to_spec();
        (spec.joints[1].qmin, spec.joints[1].qmax) = (-TAU, TAU);
        (spec.joints[0].qmin, spec.joints[0].qmax) = (-1.0, 1.0);
        let robot = Robot::new(spec).expect("valid");
        let within = [0.5, -3.0, 0.4];
        assert_eq!(
            robot.turned_into_limits(&within, &[0.0; 3]),
            Some(within.to_vec())
        );
        // Joint 2 (±2π) holds two turns of 7: 7 − 2π near 0.5, 7 − 4π near −5.
        let beyond = [0.5, 7.0, 0.4];
        let near_zero = robot.turned_into_limits(&beyond, &[0.0, 0.5, 0.0]);
        assert_eq!(near_zero, Some(vec![0.5, 7.0 - TAU, 0.4]));
        let near_minus_five = robot.turned_into_limits(&beyond, &[0.0, -5.0, 0.0]);
        assert_eq!(near_minus_five, Some(vec![0.5, 7.0 - 2.0 * TAU, 0.4]));
        let model = crate::KinematicModel::new(&robot);
        let pose = |q: &[f64]| {
            model
                .terminal_pose(q, &mut Default::default())
                .expect("pose")
        };
        let moved = pose(&beyond).inverse() * pose(&near_minus_five.expect("turned"));
        assert!(moved.translation.vector.norm() < 1e-12 && moved.rotation.angle() < 1e-12);
        // Joint 1 (±1 rad) holds no turn of 2; a prismatic joint is not turned.
        assert_eq!(robot.turned_into_limits(&[2.0, 0.0, 0.4], &[0.0; 3]), None);
        assert_eq!(robot.turned_into_limits(&[0.0, 0.0, 1.5], &[0.0; 3]), None);
    }

    /// Configurations checked at once pass exactly when each one passes
    /// `check_configuration`.
    #[test]
    fn configurations_checked_at_once_are_those_checked_one_by_one() {
        let robot = Robot::template("three", "RRP").expect("template");
        let sound: Vec<f64> = (0..30).map(|i| 0.1 * f64::from(i) - 1.0).collect();
        let one_by_one = |values: &[f64]| {
            values.len().is_multiple_of(3)
                && values
                    .chunks(3)
                    .all(|configuration| robot.check_configuration(configuration).is_ok())
        };
        let mut cases = vec![sound.clone(), Vec::new(), sound[..29].to_vec()];
        for (at, bad) in [(0, f64::NAN), (14, f64::INFINITY), (29, f64::NEG_INFINITY)] {
            let mut values = sound.clone();
            values[at] = bad;
            cases.push(values);
        }
        for values in &cases {
            assert_eq!(
                robot.configurations_sound(values),
                one_by_one(values),
                "{values:?}"
            );
        }
        assert!(robot.configurations_sound(&sound));
        assert!(!robot.configurations_sound(&sound[..29]));
    }
    use crate::test_robots::random_robot;

    /// `deltas` added one `set_parameter` at a time, up to the first error.
    fn one_by_one(robot: &Robot, deltas: &[f64]) -> (Robot, bool) {
        let mut robot = robot.clone();
        for (index, delta) in deltas.iter().enumerate() {
            let id = robot.parameters().id(index);
            if *delta != 0.0
                && robot
                    .set_parameter(id, robot.parameter(id) + delta)
                    .is_err()
            {
                return (robot, false);
            }
        }
        (robot, true)
    }

    /// Eq. 4 without allocating gives nalgebra's matrix–vector product to
    /// the bit, with couplings and gains, and refuses a buffer of the wrong
    /// length or a value that is not finite.
    #[test]
    fn joint_positions_into_is_the_matrix_product_of_eq_4() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut spec = random_robot(&mut rng, 4).to_spec();
        let coupling = |rng: &mut rand_chacha::ChaCha8Rng| {
            DMatrix::from_fn(4, 4, |i, j| {
                if i == j {
                    1.0
                } else {
                    rng.random_range(-0.3..0.3)
                }
            })
        };
        spec.motor_coupling = Some(coupling(&mut rng));
        spec.joint_coupling = Some(coupling(&mut rng));
        let robot = Robot::new(spec).expect("robot");
        let qm = [0.3, -1.2, 0.05, 2.5];
        let mut expected = robot.motor_to_joint() * DVector::from_column_slice(&qm);
        for (value, joint) in expected.iter_mut().zip(robot.joints()) {
            *value += joint.offset;
        }
        let mut q = [0.0; 4];
        robot.joint_positions_into(&qm, &mut q).expect("q");
        assert_eq!(q.as_slice(), expected.as_slice());
        assert!(matches!(
            robot.joint_positions_into(&qm, &mut [0.0; 3]),
            Err(Error::ConfigurationLength {
                expected: 4,
                found: 3
            })
        ));
        assert!(matches!(
            robot.joint_positions_into(&[0.0, f64::NAN, 0.0, 0.0], &mut q),
            Err(Error::NonFiniteConfiguration { joint: 2, .. })
        ));
    }

    /// `motor_positions` undoes eq. 4, with couplings (LU) and without
    /// (a division by the gains), offsets and gains away from 1; written
    /// into a buffer, it gives nalgebra's division by the diagonal or LU
    /// solve to the bit, and refuses a buffer of the wrong length.
    #[test]
    fn motor_positions_invert_eq_4() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
        let mut spec = random_robot(&mut rng, 4).to_spec();
        for (index, joint) in spec.joints.iter_mut().enumerate() {
            joint.gain = 1.0 + 0.01 * index as f64;
            joint.offset = 0.1 * index as f64 - 0.15;
        }
        // (A random robot has couplings.)
        spec.motor_coupling = None;
        spec.joint_coupling = None;
        let plain = Robot::new(spec.clone()).expect("robot");
        let map = plain.motor_to_joint();
        assert!((0..4).all(|i| (0..4).all(|j| i == j || map[(i, j)] == 0.0)));
        spec.joint_coupling = Some(DMatrix::from_fn(4, 4, |i, j| {
            if i == j {
                1.0
            } else {
                0.05 * (i + 2 * j) as f64
            }
        }));
        let coupled = Robot::new(spec).expect("robot");
        let qm = [0.3, -1.2, 0.05, 2.5];
        for (robot, diagonal) in [(plain, true), (coupled, false)] {
            let mut q = [0.0; 4];
            robot.joint_positions_into(&qm, &mut q).expect("q");
            let back = robot.motor_positions(&q).expect("qm");
            for (a, b) in back.iter().zip(qm) {
                assert!((a - b).abs() < 1e-14, "{a} vs {b}");
            }
            let shifted = DVector::from_iterator(
                4,
                q.iter()
                    .zip(robot.joints())
                    .map(|(q, joint)| q - joint.offset),
            );
            let map = robot.motor_to_joint();
            let expected = if diagonal {
                shifted.component_div(&map.diagonal())
            } else {
                map.clone().lu().solve(&shifted).expect("regular")
            };
            let mut written = [0.0; 4];
            robot.motor_positions_into(&q, &mut written).expect("qm");
            assert_eq!(written.as_slice(), expected.as_slice());
            assert_eq!(back.as_slice(), expected.as_slice());
            assert!(matches!(
                robot.motor_positions_into(&q, &mut [0.0; 5]),
                Err(Error::ConfigurationLength {
                    expected: 4,
                    found: 5
                })
            ));
        }
    }

    #[test]
    fn apply_deltas_keeps_the_motor_to_joint_map_in_step_with_the_gains() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let robot = random_robot(&mut rng, 5);
        let count = robot.parameters().len();
        let gains: Vec<usize> = (0..count)
            .filter(|i| robot.parameters().id(*i).kind == ParameterKind::Gain)
            .collect();
        assert_eq!(gains.len(), 5);
        let mut deltas: Vec<f64> = (0..count).map(|i| 1e-3 * (i as f64 + 1.0)).collect();
        let mut together = robot.clone();
        together.apply_deltas(&deltas).expect("valid");
        assert_eq!((together, true), one_by_one(&robot, &deltas));

        // The fourth gain driven to zero: an error, the earlier values kept,
        // and the map still that of the gains stored.
        let fourth = robot.parameters().id(gains[3]);
        deltas[gains[3]] = -robot.parameter(fourth);
        let mut failing = robot.clone();
        assert!(failing.apply_deltas(&deltas).is_err());
        assert_eq!((failing, false), one_by_one(&robot, &deltas));
    }
}
