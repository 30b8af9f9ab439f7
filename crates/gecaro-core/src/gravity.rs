//! Gravity loads on the joints: the masses a robot carries (its links'
//! own, where known, and a payload) and the torque gravity exerts about
//! each joint axis at a configuration — the loads under which elastic joints
//! deflect (the paper's closing "next step": joints of non-negligible
//! elasticity).
//!
//! # Conventions
//! - A link's mass is stated in the frame that moves with it: frame j
//!   (1..=n) carries link j, the body joint j moves; frame 0 the base (which
//!   no joint moves, so it loads none); frame n+1 the tool, which moves with
//!   link n. Its centre of mass is in that frame's coordinates (metres).
//! - A payload's centre of mass is in the tool frame n+1.
//! - Gravity is an acceleration vector in the world frame (frame 0's
//!   reference, the measurement frame of a robot file), `(0, 0, −9.80665)`
//!   m/s² by default: the robot standing upright on a level floor.
//! - The torque of joint j is the generalised force gravity exerts on it,
//!   `τ_j = Σ_k m_k gᵀ ∂p_k/∂q_j = −∂V/∂q_j` with the potential energy
//!   `V(q) = −Σ_k m_k gᵀ p_k(q)` over every mass k that joint j moves (those
//!   of frames j..n+1 and the payload): for a revolute joint
//!   `m gᵀ (z_j × (p − o_j))` (N·m), for a prismatic one `m gᵀ z_j` (N), with
//!   `z_j` and `o_j` the joint's axis and frame origin. A joint yields in the
//!   direction of this torque; its motor holds `−τ_j`.
//! - Gravity may lean from the direction stated (a measurement frame that is
//!   not levelled) by two small angles, the elastic robot's parameters
//!   `tilt1`, `tilt2` ([`crate::Robot::gravity_tilt`]): about the axes
//!   `u₁, u₂` perpendicular to it ([`MassModel::tilt_axes`]; the world's x
//!   and y for gravity along −z), `g(a) = g + a₁ u₁ × g + a₂ u₂ × g` — the
//!   rotation to first order, exact as a model (its length grows by
//!   `√(1 + a²)`, 1.5·10⁻⁴ at 1°). Torques are linear in g, so
//!   `τ(a) = τ + a₁ ∂τ/∂a₁ + a₂ ∂τ/∂a₂` with `∂τ_j/∂a_k = (u_k × g)ᵀ v_j`,
//!   `v_j` the vector gravity is dotted with above
//!   ([`gravity_loads_in`] computes both).
//!
//! # Example
//! A pendulum: 2 kg, 0.5 m out along x of its link, its axis horizontal
//! (α = 90°), under standard gravity along −z. At q = 0 the arm is level and
//! the mass pulls with m·g·L:
//!
//! ```
//! use gecaro_core::{Frame, FrameType, Joint, LinkMass, MassModel, Robot, RobotSpec, gravity_torques};
//! use nalgebra::Vector3;
//!
//! let horizontal_axis = Frame { alpha: std::f64::consts::FRAC_PI_2, ..Frame::new(FrameType::Revolute) };
//! let robot = Robot::new(RobotSpec::rigid(
//!     "pendulum",
//!     vec![Frame::new(FrameType::Fixed), horizontal_axis, Frame::new(FrameType::Fixed)],
//!     vec![Joint::default_for(FrameType::Revolute)],
//! ))?;
//! let mut masses = MassModel::new(robot.frames().len());
//! masses.set_link(1, LinkMass { mass: 2.0, com: Vector3::new(0.5, 0.0, 0.0) })?;
//! let torques = gravity_torques(&robot, &masses, None, &[0.0])?;
//! assert!((torques[0].abs() - 2.0 * 9.80665 * 0.5).abs() < 1e-12);
//! # Ok::<(), gecaro_core::Error>(())
//! ```

use nalgebra::{DVector, IsometryMatrix3, Point3, Vector3};

use crate::error::{Error, Field};
use crate::frame::FrameType;
use crate::kinematics::forward_kinematics;
use crate::robot::Robot;

/// Standard gravity (m/s²).
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// Gravity when none is stated: standard gravity along −z of the world
/// frame (a robot upright on a level floor).
pub fn upright_gravity() -> Vector3<f64> {
    Vector3::new(0.0, 0.0, -STANDARD_GRAVITY)
}

/// A mass and its centre, in the coordinates of the frame it moves with.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LinkMass {
    /// Mass (kg), ≥ 0.
    pub mass: f64,
    /// Centre of mass in the frame's coordinates (m).
    pub com: Vector3<f64>,
}

/// The heaviest link a robot file may state (kg): 10 t, beyond the arm of
/// the largest industrial robot (issue 75: 1e300 kg was read).
pub const MAX_LINK_MASS: f64 = 1e4;

/// The farthest a link's centre of mass may sit from its frame (m).
pub const MAX_CENTRE_DISTANCE: f64 = 100.0;

/// The largest gravity a robot file may state (m/s²): 10 g.
pub const MAX_GRAVITY: f64 = 100.0;

impl LinkMass {
    fn check(&self, field: Field) -> Result<(), Error> {
        if !(self.mass.is_finite() && (0.0..=MAX_LINK_MASS).contains(&self.mass)) {
            return Err(Error::Invalid {
                field,
                message: format!(
                    "mass {} is not a link's mass in kg (0 to {MAX_LINK_MASS})",
                    self.mass
                ),
            });
        }
        if !self.com.iter().all(|v| v.is_finite()) {
            return Err(Error::Invalid {
                field,
                message: "the centre of mass holds a value that is not finite".into(),
            });
        }
        if self.com.norm() > MAX_CENTRE_DISTANCE {
            return Err(Error::Invalid {
                field,
                message: format!(
                    "the centre of mass is {:.3e} m from its frame: beyond {MAX_CENTRE_DISTANCE} \
                     m, no link's (a length in mm?)",
                    self.com.norm()
                ),
            });
        }
        Ok(())
    }
}

/// What a robot's links weigh and where gravity points (see the module
/// docs): one optional mass per frame 0..=n+1.
#[derive(Clone, Debug, PartialEq)]
pub struct MassModel {
    links: Vec<Option<LinkMass>>,
    gravity: Vector3<f64>,
}

impl MassModel {
    /// No mass on any of `frames` frames, standard gravity along −z.
    pub fn new(frames: usize) -> Self {
        MassModel {
            links: vec![None; frames],
            gravity: upright_gravity(),
        }
    }

    /// States the mass carried by frame `frame`.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a frame beyond the model's, a negative or
    /// non-finite mass, or a centre that is not finite.
    pub fn set_link(&mut self, frame: usize, link: LinkMass) -> Result<(), Error> {
        let field = Field::Frame {
            index: frame,
            key: "mass",
        };
        link.check(field.clone())?;
        let slot = self.links.get_mut(frame).ok_or_else(|| Error::Invalid {
            field,
            message: "there is no such frame".into(),
        })?;
        *slot = Some(link);
        Ok(())
    }

    /// The mass carried by frame `frame`, if stated.
    pub fn link(&self, frame: usize) -> Option<&LinkMass> {
        self.links.get(frame).and_then(Option::as_ref)
    }

    /// Gravity in the world frame (m/s²).
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// States gravity in the world frame (a base frame that is not
    /// levelled, or another planet).
    ///
    /// # Errors
    /// [`Error::Invalid`] for a vector that is not finite.
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<(), Error> {
        if !gravity.iter().all(|v| v.is_finite()) {
            return Err(Error::Invalid {
                field: Field::Key("gravity"),
                message: "gravity holds a value that is not finite".into(),
            });
        }
        if gravity.norm() > MAX_GRAVITY {
            return Err(Error::Invalid {
                field: Field::Key("gravity"),
                message: format!(
                    "gravity of {:.3e} m/s²: beyond {MAX_GRAVITY} m/s² (10 g), no cell's",
                    gravity.norm()
                ),
            });
        }
        self.gravity = gravity;
        Ok(())
    }

    /// The axes `u₁, u₂` gravity's tilts turn it about (module docs): unit,
    /// perpendicular to gravity and to each other, `(u₁, u₂, −ĝ)`
    /// right-handed. `u₁` is the world's x made perpendicular to gravity
    /// (its y when gravity lies within 45° of x): for gravity along −z,
    /// x and y.
    pub fn tilt_axes(&self) -> [Vector3<f64>; 2] {
        let down = self.gravity.try_normalize(0.0).unwrap_or(-Vector3::z());
        let reference = if down.x.abs() > std::f64::consts::FRAC_1_SQRT_2 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let first = (reference - reference.dot(&down) * down).normalize();
        [first, first.cross(&down)]
    }

    /// The same masses under gravity tilted by `tilt` (tilt1, tilt2 in
    /// radians; module docs): `g + a₁ u₁ × g + a₂ u₂ × g`. Folds an
    /// identified tilt into the gravity a robot file states.
    pub fn tilted(&self, tilt: [f64; 2]) -> MassModel {
        let [first, second] = self.tilt_axes();
        let gravity = self.gravity
            + tilt[0] * first.cross(&self.gravity)
            + tilt[1] * second.cross(&self.gravity);
        MassModel {
            gravity,
            ..self.clone()
        }
    }

    /// Whether any mass is stated.
    pub fn is_empty(&self) -> bool {
        self.links.iter().all(Option::is_none)
    }

    /// The mass the joints carry (kg): every stated mass but the base's
    /// (frame 0), which no joint moves.
    pub fn moving_mass(&self) -> f64 {
        self.links
            .iter()
            .skip(1)
            .flatten()
            .map(|link| link.mass)
            .sum()
    }

    /// The same masses stated for `new`, the robot `old` re-framed
    /// ([`Robot::reframed`] with `new_world_from_old_world`): a link keeps its
    /// body, so each centre is moved into its frame's new coordinates (the
    /// frames of one link keep their relative pose at every configuration;
    /// it is taken at zero), and gravity into the new world's.
    ///
    /// # Errors
    /// Robots of another number of frames than the masses'.
    pub fn reframed(
        &self,
        old: &Robot,
        new: &Robot,
        new_world_from_old_world: &nalgebra::IsometryMatrix3<f64>,
    ) -> Result<MassModel, Error> {
        let frames = self.links.len();
        if old.frames().len() != frames || new.frames().len() != frames {
            return Err(Error::Invalid {
                field: Field::Key("mass"),
                message: format!("the masses are stated for {frames} frames"),
            });
        }
        let zero = vec![0.0; old.joint_count()];
        let (before, after) = (
            forward_kinematics(old, &zero)?,
            forward_kinematics(new, &zero)?,
        );
        let links = self
            .links
            .iter()
            .enumerate()
            .map(|(frame, link)| {
                link.map(|link| {
                    let new_from_old = after.world_from_frame(frame).inverse()
                        * new_world_from_old_world
                        * before.world_from_frame(frame);
                    LinkMass {
                        com: (new_from_old * Point3::from(link.com)).coords,
                        ..link
                    }
                })
            })
            .collect();
        Ok(MassModel {
            links,
            gravity: new_world_from_old_world.rotation * self.gravity,
        })
    }
}

/// The torque (N·m; N for a prismatic joint) gravity exerts about each
/// joint at motor configuration `motor_positions`, from the links' masses
/// and an optional `payload` (its centre in frame n+1); see the module docs
/// for the conventions.
///
/// # Errors
/// A configuration that is not n finite values; a mass model of another
/// number of frames than `robot`'s; an invalid payload.
pub fn gravity_torques(
    robot: &Robot,
    masses: &MassModel,
    payload: Option<&LinkMass>,
    motor_positions: &[f64],
) -> Result<DVector<f64>, Error> {
    let chain = forward_kinematics(robot, motor_positions)?;
    let mut torques = DVector::zeros(robot.joint_count());
    gravity_torques_in(
        robot,
        masses,
        payload,
        |frame| chain.world_from_frame(frame),
        torques.as_mut_slice(),
    )?;
    Ok(torques)
}

/// [`gravity_torques`] of the configuration whose frames are where
/// `world_from_frame` puts them (frame 0..=n+1 in the world; a
/// [`crate::ChainBuffer`] or [`crate::FrameChain`] of the rigid robot at the
/// configuration), written to `torques` (n values) without allocating.
/// Joint j carries the masses of frames j..=n+1 and the payload: with M
/// their total and C their first moment `Σ m p`, `τ_j = gᵀ(z_j × (C − M o_j))`
/// for a revolute joint, `M gᵀ z_j` for a prismatic one, summed from the
/// tool inwards.
///
/// # Errors
/// A mass model of another number of frames than `robot`'s, an invalid
/// payload, `torques` of another length than n.
pub fn gravity_torques_in<'c>(
    robot: &Robot,
    masses: &MassModel,
    payload: Option<&LinkMass>,
    world_from_frame: impl Fn(usize) -> &'c IsometryMatrix3<f64>,
    torques: &mut [f64],
) -> Result<(), Error> {
    gravity_loads_in(robot, masses, payload, world_from_frame, torques, None)
}

/// [`gravity_torques_in`], and when `tilt_torques` is given (2n values)
/// the torques' derivatives with respect to gravity's tilts (module docs):
/// `∂τ_j/∂tilt1` for j = 1..n, then `∂τ_j/∂tilt2`.
///
/// # Errors
/// As [`gravity_torques_in`]; `tilt_torques` of another length than 2n.
pub fn gravity_loads_in<'c>(
    robot: &Robot,
    masses: &MassModel,
    payload: Option<&LinkMass>,
    world_from_frame: impl Fn(usize) -> &'c IsometryMatrix3<f64>,
    torques: &mut [f64],
    mut tilt_torques: Option<&mut [f64]>,
) -> Result<(), Error> {
    let frames = robot.frames();
    if masses.links.len() != frames.len() {
        return Err(Error::Invalid {
            field: Field::Key("mass"),
            message: format!(
                "the masses are stated for {} frames, the robot has {}",
                masses.links.len(),
                frames.len()
            ),
        });
    }
    if let Some(payload) = payload {
        payload.check(Field::Key("payload"))?;
    }
    let joints = robot.joint_count();
    let lengths = [
        (torques.len(), joints),
        (
            tilt_torques.as_ref().map_or(2 * joints, |t| t.len()),
            2 * joints,
        ),
    ];
    if let Some((found, expected)) = lengths
        .into_iter()
        .find(|(found, expected)| found != expected)
    {
        return Err(Error::ConfigurationLength { expected, found });
    }
    let gravity = masses.gravity;
    let [first, second] = masses.tilt_axes();
    let leaning = [first.cross(&gravity), second.cross(&gravity)];
    let tool = frames.len() - 1;
    // The total mass and first moment of frames k..=n+1 and the payload.
    let mut total = 0.0;
    let mut moment = Vector3::zeros();
    for frame in (1..=tool).rev() {
        let carried = masses.links[frame]
            .iter()
            .chain(payload.filter(|_| frame == tool));
        for link in carried {
            let point = world_from_frame(frame) * Point3::from(link.com);
            total += link.mass;
            moment += link.mass * point.coords;
        }
        if frame <= joints {
            let pose = world_from_frame(frame);
            let axis = pose.rotation * Vector3::z();
            let velocity = match frames[frame].frame_type {
                FrameType::Prismatic => total * axis,
                _ => axis.cross(&(moment - total * pose.translation.vector)),
            };
            torques[frame - 1] = gravity.dot(&velocity);
            if let Some(tilt_torques) = tilt_torques.as_deref_mut() {
                tilt_torques[frame - 1] = leaning[0].dot(&velocity);
                tilt_torques[joints + frame - 1] = leaning[1].dot(&velocity);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ready_robot_for_tests;

    /// Potential energy `V = −Σ m gᵀ p` at joint variables `q` (the test
    /// robot's gains are 1 and its couplings identity, so motor = joint).
    fn potential(robot: &Robot, masses: &MassModel, payload: &LinkMass, q: &[f64]) -> f64 {
        let chain = forward_kinematics(robot, q).expect("configuration");
        let tool = robot.frames().len() - 1;
        let mut energy = 0.0;
        for frame in 0..robot.frames().len() {
            if let Some(link) = masses.link(frame) {
                let point = chain.world_from_frame(frame) * nalgebra::Point3::from(link.com);
                energy -= link.mass * masses.gravity().dot(&point.coords);
            }
        }
        let point = chain.world_from_frame(tool) * nalgebra::Point3::from(payload.com);
        energy - payload.mass * masses.gravity().dot(&point.coords)
    }

    /// The Stanford arm (RRPRRR) with a mass on every moving frame, a
    /// payload and a tilted gravity.
    fn loaded() -> (Robot, MassModel, LinkMass) {
        let robot = ready_robot_for_tests();
        let mut masses = MassModel::new(robot.frames().len());
        for frame in 0..robot.frames().len() {
            let k = frame as f64;
            masses
                .set_link(
                    frame,
                    LinkMass {
                        mass: 1.0 + k,
                        com: Vector3::new(0.03 * k, -0.02 * k, 0.05),
                    },
                )
                .expect("mass");
        }
        masses
            .set_gravity(Vector3::new(0.4, -0.3, -9.8))
            .expect("gravity");
        let payload = LinkMass {
            mass: 12.0,
            com: Vector3::new(0.0, 0.01, 0.12),
        };
        (robot, masses, payload)
    }

    #[test]
    fn torques_are_minus_the_gradient_of_the_potential_energy() {
        // An independent route: central differences of V(q).
        let (robot, masses, payload) = loaded();
        for q in [
            [0.3, -0.7, 0.4, 1.1, -0.5, 2.0],
            [-2.0, 0.9, 0.25, -0.3, 1.4, -1.0],
        ] {
            let torques = gravity_torques(&robot, &masses, Some(&payload), &q).expect("torques");
            for j in 0..q.len() {
                let h = 1e-6;
                let (mut up, mut down) = (q, q);
                up[j] += h;
                down[j] -= h;
                let gradient = (potential(&robot, &masses, &payload, &up)
                    - potential(&robot, &masses, &payload, &down))
                    / (2.0 * h);
                assert!(
                    (torques[j] + gradient).abs() < 1e-6 * (1.0 + gradient.abs()),
                    "joint {}: {} vs −∂V/∂q = {}",
                    j + 1,
                    torques[j],
                    -gradient
                );
            }
        }
    }

    /// The tilts' torques are the derivatives of the torques under the
    /// tilted gravity (central differences), and the axes are those stated.
    #[test]
    fn tilt_torques_are_the_derivatives_of_the_torques_under_tilted_gravity() {
        let (robot, masses, payload) = loaded();
        let upright = MassModel {
            gravity: upright_gravity(),
            ..masses.clone()
        };
        let [x, y] = upright.tilt_axes();
        assert!((x - Vector3::x()).norm() < 1e-15 && (y - Vector3::y()).norm() < 1e-15);
        // A tilt about x leans gravity towards +y (right-handed about x).
        assert!(upright.tilted([0.01, 0.0]).gravity().y > 0.0);
        let q = [0.3, -0.7, 0.4, 1.1, -0.5, 2.0];
        let chain = forward_kinematics(&robot, &q).expect("chain");
        for model in [&masses, &upright] {
            let [u, v] = model.tilt_axes();
            let down = model.gravity().normalize();
            assert!(u.dot(&down).abs() < 1e-15 && v.dot(&down).abs() < 1e-15);
            assert!((u.cross(&v) + down).norm() < 1e-15, "right-handed");
            let mut torques = [0.0; 6];
            let mut tilts = [0.0; 12];
            gravity_loads_in(
                &robot,
                model,
                Some(&payload),
                |frame| chain.world_from_frame(frame),
                &mut torques,
                Some(&mut tilts),
            )
            .expect("loads");
            for axis in 0..2 {
                let h = 1e-5;
                let mut tilt = [0.0; 2];
                tilt[axis] = h;
                let up = gravity_torques(&robot, &model.tilted(tilt), Some(&payload), &q)
                    .expect("torques");
                tilt[axis] = -h;
                let down = gravity_torques(&robot, &model.tilted(tilt), Some(&payload), &q)
                    .expect("torques");
                for joint in 0..6 {
                    let derivative = (up[joint] - down[joint]) / (2.0 * h);
                    let analytic = tilts[axis * 6 + joint];
                    assert!(
                        (analytic - derivative).abs() < 1e-8 * (1.0 + derivative.abs()),
                        "tilt{} joint {}: {analytic} vs {derivative}",
                        axis + 1,
                        joint + 1
                    );
                }
            }
        }
        let mut short = [0.0; 11];
        let mut torques = [0.0; 6];
        assert!(
            gravity_loads_in(
                &robot,
                &masses,
                None,
                |frame| chain.world_from_frame(frame),
                &mut torques,
                Some(&mut short),
            )
            .is_err()
        );
    }

    #[test]
    fn the_base_loads_no_joint_and_gravity_along_an_axis_loads_it_not() {
        let (robot, _, _) = loaded();
        let mut base_only = MassModel::new(robot.frames().len());
        base_only
            .set_link(
                0,
                LinkMass {
                    mass: 100.0,
                    com: Vector3::new(0.2, 0.0, 0.1),
                },
            )
            .expect("mass");
        let q = [0.3, -0.7, 0.4, 1.1, -0.5, 2.0];
        let torques = gravity_torques(&robot, &base_only, None, &q).expect("torques");
        assert!(torques.iter().all(|t| *t == 0.0), "{torques}");
        // Gravity along joint 1's axis (fixed in the world): joint 1 carries
        // nothing, whatever the arm holds; the shoulder carries the arm.
        let axis = forward_kinematics(&robot, &q)
            .expect("chain")
            .world_from_frame(1)
            .rotation
            * Vector3::z();
        let (_, mut upright, payload) = loaded();
        upright
            .set_gravity(-STANDARD_GRAVITY * axis)
            .expect("gravity");
        let torques = gravity_torques(&robot, &upright, Some(&payload), &q).expect("torques");
        assert!(torques[0].abs() < 1e-12, "{torques}");
        assert!(
            torques[1].abs() > 1.0,
            "the shoulder carries the arm: {torques}"
        );
    }

    #[test]
    fn a_payload_at_the_tool_adds_its_moment_linearly() {
        let (robot, masses, payload) = loaded();
        let q = [0.3, -0.7, 0.4, 1.1, -0.5, 2.0];
        let without = gravity_torques(&robot, &masses, None, &q).expect("torques");
        let with = gravity_torques(&robot, &masses, Some(&payload), &q).expect("torques");
        let doubled = LinkMass {
            mass: 2.0 * payload.mass,
            ..payload
        };
        let twice = gravity_torques(&robot, &masses, Some(&doubled), &q).expect("torques");
        let difference = (&twice - &with) - (&with - &without);
        assert!(difference.norm() < 1e-9, "{difference}");
    }

    #[test]
    fn a_reframed_robot_carries_the_same_loads() {
        // The same arm in a world 1 m away and turned, with a new tool: every
        // joint carries the same torque at every configuration.
        let (robot, masses, payload) = loaded();
        let world = nalgebra::IsometryMatrix3::new(
            Vector3::new(1.0, -0.4, 0.2),
            Vector3::new(0.1, -0.2, 0.7),
        );
        let tool = nalgebra::IsometryMatrix3::new(
            Vector3::new(0.02, 0.0, 0.15),
            Vector3::new(0.0, 0.3, 0.0),
        );
        let reframed = robot.reframed(&world, &tool).expect("reframed");
        let moved = masses.reframed(&robot, &reframed, &world).expect("masses");
        // The payload's centre is stated in the tool frame, which moved.
        let payload_after = LinkMass {
            com: (tool.inverse() * Point3::from(payload.com)).coords,
            ..payload
        };
        for q in [
            [0.3, -0.7, 0.4, 1.1, -0.5, 2.0],
            [-2.0, 0.9, 0.25, -0.3, 1.4, -1.0],
        ] {
            let before = gravity_torques(&robot, &masses, Some(&payload), &q).expect("before");
            let after =
                gravity_torques(&reframed, &moved, Some(&payload_after), &q).expect("after");
            assert!(
                (&before - &after).norm() < 1e-9 * before.norm(),
                "{before} vs {after}"
            );
        }
    }

    #[test]
    fn bad_masses_name_their_frame() {
        let robot = ready_robot_for_tests();
        let mut masses = MassModel::new(robot.frames().len());
        let negative = LinkMass {
            mass: -1.0,
            com: Vector3::zeros(),
        };
        let error = masses.set_link(2, negative).expect_err("negative");
        assert!(error.to_string().contains("frame 2"), "{error}");
        assert!(
            masses
                .set_link(
                    99,
                    LinkMass {
                        mass: 1.0,
                        com: Vector3::zeros()
                    }
                )
                .is_err()
        );
        let short = MassModel::new(3);
        assert!(gravity_torques(&robot, &short, None, &[0.0; 6]).is_err());
        let payload = LinkMass {
            mass: f64::NAN,
            com: Vector3::zeros(),
        };
        assert!(gravity_torques(&robot, &masses, Some(&payload), &[0.0; 6]).is_err());
    }
}
