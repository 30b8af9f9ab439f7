//! Elastic joints (issue 38): the gravity loads every configuration puts on
//! the joints, and the deflection they cause.
//!
//! An elastic robot's joint j yields to the gravity torque τ_j it carries,
//! `q_j = K_j·qm_j + offset_j + c_j·τ_j` (eq. 4 with the compliance c_j; see
//! [`gecaro_core::KinematicModel::forward_loaded`]). The torques come from
//! the links' masses ([`MassModel`]) and the payload a sample states
//! ([`Sample::payload`](crate::sample::Sample::payload), its centre in frame n+1), by
//! [`gecaro_core::gravity_torques`].
//!
//! Two evaluations, for two uses:
//! - [`load_samples`] takes τ at the commanded configuration. Identification
//!   and evaluation use it, as a controller's gravity compensation does: the
//!   deflection turns the arm by c·τ ≈ 1e-3 rad, which changes τ by about
//!   that fraction, a micrometre at the flange.
//! - [`settled_torques`] solves the fixed point τ = τ(q + c∘τ), the arm at
//!   rest where it settles. Simulated robots use it, so that the "real"
//!   robot is not the identification's own approximation.

use gecaro_core::{
    ChainBuffer, FrameType, KinematicModel, LinkMass, MassModel, Robot, gravity_loads_in,
    gravity_torques,
};
use nalgebra::Vector3;

use crate::error::Error;
use crate::parallel::run_parts;
use crate::samples::{SampleSlice, Samples};
use crate::states::part_size;
use crate::study::Study;

/// A load change smaller than this fraction of the noise leaves the loads
/// where they are ([`reweighed`]).
const LOAD_TOLERANCE: f64 = 0.1;

/// Most fixed-point iterations of [`settled_torques`]: each one shrinks the
/// error by c·∂τ/∂q, ≈ 1e-3 for an industrial arm (three reach rounding),
/// 0.05 for an arm a hundred times softer.
const SETTLING_ITERATIONS: usize = 50;

/// Fills every sample's [`torques`](crate::sample::SampleLoads::torques)
/// with the gravity torques at its commanded configuration (see the module
/// docs), from `masses` and the sample's payload, and its
/// [`tilt_torques`](crate::sample::SampleLoads::tilt_torques) with their
/// derivatives with respect to gravity's tilts.
///
/// # Errors
/// A configuration that does not fit the robot, masses of another robot,
/// an invalid payload; the sample's line is named.
pub fn load_samples(robot: &Robot, masses: &MassModel, samples: &mut Samples) -> Result<(), Error> {
    let loads = loads_of(
        &KinematicModel::new(robot),
        robot,
        masses,
        samples.as_slice(),
    )?;
    carry(samples, loads);
    Ok(())
}

/// `samples` carrying `loads`, one per sample.
fn carry(samples: &mut Samples, loads: Vec<Load>) {
    for (sample, load) in samples.loads_mut().iter_mut().zip(loads) {
        let loads = sample.get_or_insert_with(Box::default);
        loads.torques = Some(load.torques);
        loads.tilt_torques = Some(load.tilt_torques);
    }
}

/// One sample's loads ([`loads_of`]).
struct Load {
    torques: Vec<f64>,
    tilt_torques: Vec<f64>,
    /// How far they move the tool point from the sample's own, squared (m²).
    moved: f64,
}

/// The loads of `samples` at `robot` (over the cores), each with how far
/// they move `robot`'s tool point from where the sample's own loads (none:
/// zero) put it, squared (m²), to first order: `Σ_j c_j·Δτ_j·∂p/∂q_j`
/// (τ with the share of `robot`'s gravity tilts),
/// with `∂p/∂q_j = z_j × (p − o_j)` for a revolute joint and `z_j` for a
/// prismatic one (the joints turn by c·τ ≈ 1e-3 rad, the loads change by a
/// few per cent of that).
fn loads_of(
    model: &KinematicModel,
    robot: &Robot,
    masses: &MassModel,
    samples: SampleSlice<'_>,
) -> Result<Vec<Load>, Error> {
    let joints = robot.joint_count();
    let compliances = robot.compliances().unwrap_or_default();
    let tilt = robot.gravity_tilt();
    // The torque joint j carries under `torques` and their tilts' share.
    let carried = |torques: &[f64], tilts: Option<&[f64]>, joint: usize| {
        torques.get(joint).copied().unwrap_or(0.0)
            + tilts.map_or(0.0, |tilts| {
                tilt[0] * tilts[joint] + tilt[1] * tilts[joints + joint]
            })
    };
    let frames = robot.frames();
    let parts = samples.chunks(part_size(samples.len())).collect();
    let loads = run_parts(parts, |part: SampleSlice<'_>| {
        let mut chain = ChainBuffer::default();
        part.iter()
            .map(|sample| {
                let failed = |error: gecaro_core::Error| Error::InvalidData {
                    line: sample.line(),
                    message: format!("the gravity torques of this configuration: {error}"),
                };
                model
                    .forward(sample.motor_positions(), &mut chain)
                    .map_err(failed)?;
                let mut torques = vec![0.0; joints];
                let mut tilt_torques = vec![0.0; 2 * joints];
                gravity_loads_in(
                    robot,
                    masses,
                    sample.payload(),
                    |frame| chain.world_from_frame(frame),
                    &mut torques,
                    Some(&mut tilt_torques),
                )
                .map_err(failed)?;
                let tool = chain.world_from_tool().translation.vector;
                let mut moved = Vector3::zeros();
                let own = sample.torques().unwrap_or_default();
                let own_tilts = sample
                    .tilt_torques()
                    .filter(|tilts| tilts.len() == 2 * joints);
                for (joint, compliance) in compliances.iter().enumerate() {
                    let turned = compliance
                        * (carried(&torques, Some(&tilt_torques), joint)
                            - carried(own, own_tilts, joint));
                    let pose = chain.world_from_frame(joint + 1);
                    let axis = pose.rotation * Vector3::z();
                    moved += turned
                        * match frames[joint + 1].frame_type {
                            FrameType::Prismatic => axis,
                            _ => axis.cross(&(tool - pose.translation.vector)),
                        };
                }
                Ok(Load {
                    torques,
                    tilt_torques,
                    moved: moved.norm_squared(),
                })
            })
            .collect::<Result<Vec<_>, Error>>()
    });
    let mut all = Vec::with_capacity(samples.len());
    for part in loads {
        all.extend(part?);
    }
    Ok(all)
}

/// Loads of every sample of a study: per set, per sample.
type StudyLoads = Vec<Vec<Load>>;

/// Every set's loads at `robot` ([`loads_of`]) and how far they move the
/// model: the RMS over the samples of the tool point's move (m).
fn study_loads(
    study: &Study,
    robot: &Robot,
    masses: &MassModel,
) -> Result<(StudyLoads, f64), Error> {
    let model = KinematicModel::new(robot);
    let (mut sum, mut count) = (0.0, 0usize);
    let mut loads = Vec::with_capacity(study.sets.len());
    for set in &study.sets {
        let set_loads = loads_of(&model, robot, masses, set.samples.as_slice())?;
        sum += set_loads.iter().map(|load| load.moved).sum::<f64>();
        count += set_loads.len();
        loads.push(set_loads);
    }
    Ok((loads, (sum / count.max(1) as f64).sqrt()))
}

/// `study` carrying `loads` (one list per set, one per sample).
fn carrying(study: &Study, loads: StudyLoads) -> Study {
    let mut weighed = study.clone();
    for (set, loads) in weighed.sets.iter_mut().zip(loads) {
        carry(&mut set.samples, loads);
    }
    weighed
}

/// `study` with every sample's loads evaluated at `robot` ([`load_samples`]),
/// and how far that moves the model: the RMS over the samples of how far
/// the tool point of `robot` moves between the old loads and the new (m).
///
/// # Errors
/// As [`load_samples`].
pub fn weighed_at(study: &Study, robot: &Robot, masses: &MassModel) -> Result<(Study, f64), Error> {
    let (loads, moved) = study_loads(study, robot, masses)?;
    Ok((carrying(study, loads), moved))
}

/// `study` with its loads at `robot` ([`weighed_at`]) when they move the
/// model by more than a tenth of the sets' smallest σ, or of 0.1 mm when
/// that is smaller or no set states one (RMS over the samples, which
/// changes σ̂ by half a per cent); `None` when they do not. An
/// identification follows the loads so
/// ([`crate::identification::IdentificationOptions::masses`]): the nominal
/// geometry is off by centimetres, which moves the torques by a few per
/// cent, tens of micrometres of deflection at the flange.
///
/// # Errors
/// As [`load_samples`].
pub fn reweighed(study: &Study, robot: &Robot, masses: &MassModel) -> Result<Option<Study>, Error> {
    let (loads, moved) = study_loads(study, robot, masses)?;
    let noise = study
        .sets
        .iter()
        .filter_map(|set| set.sigma)
        .fold(f64::INFINITY, f64::min)
        .min(1e-4);
    Ok((moved > LOAD_TOLERANCE * noise).then(|| carrying(study, loads)))
}

/// The gravity torques of `robot` at rest at `motor_positions` with its
/// joints deflected by them: the fixed point τ = τ(q + c∘τ) (module docs).
/// A rigid robot's are [`gravity_torques`]'s.
///
/// # Errors
/// As [`gravity_torques`].
pub fn settled_torques(
    robot: &Robot,
    masses: &MassModel,
    payload: Option<&LinkMass>,
    motor_positions: &[f64],
) -> Result<Vec<f64>, Error> {
    let mut torques = gravity_torques(robot, masses, payload, motor_positions)?;
    let Some(compliances) = robot.compliances() else {
        return Ok(torques.as_slice().to_vec());
    };
    let commanded = robot.joint_positions(motor_positions)?;
    for _ in 0..SETTLING_ITERATIONS {
        let previous = torques.clone();
        let deflected: Vec<f64> = commanded
            .iter()
            .zip(compliances)
            .zip(torques.iter())
            .map(|((q, c), tau)| q + c * tau)
            .collect();
        let motors = robot.motor_positions(&deflected)?;
        torques = gravity_torques(robot, masses, payload, motors.as_slice())?;
        if (&torques - &previous).amax() <= 1e-13 * previous.amax().max(1.0) {
            break;
        }
    }
    Ok(torques.as_slice().to_vec())
}

/// The motor values to command so that `robot`, yielding to gravity, comes
/// to rest at `settled` (motor values of the pose wanted): the joints
/// `q_c = q* − c∘τ(q*)`, with τ the torques at the pose wanted. Exact: at
/// rest at q* the arm carries τ(q*), and q_c + c∘τ(q*) = q*. What
/// compensation sends an elastic robot for the payload it will carry. A
/// rigid robot's are `settled`.
///
/// # Errors
/// As [`gravity_torques`].
pub fn commanded_under_load(
    robot: &Robot,
    masses: &MassModel,
    payload: Option<&LinkMass>,
    settled: &[f64],
) -> Result<Vec<f64>, Error> {
    let Some(compliances) = robot.compliances() else {
        return Ok(settled.to_vec());
    };
    let torques = gravity_torques(robot, masses, payload, settled)?;
    let wanted = robot.joint_positions(settled)?;
    let commanded: Vec<f64> = wanted
        .iter()
        .zip(compliances)
        .zip(torques.iter())
        .map(|((q, c), tau)| q - c * tau)
        .collect();
    Ok(robot.motor_positions(&commanded)?.as_slice().to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;

    /// A planar arm of two 1 m links held out level, a 10 kg mass at its
    /// tip: the shoulder carries 98 N·m and droops by c·τ; settled, the
    /// torque is m·g·cos(droop) of the drooped arm.
    fn level_arm() -> (Robot, MassModel) {
        use gecaro_core::{Frame, FrameType, Joint, RobotSpec};
        let revolute = |d: f64| Frame {
            d,
            ..Frame::new(FrameType::Revolute)
        };
        // Joint axes along y of the world (α1 = −90°), so gravity (−z) bends them.
        let robot = Robot::new(RobotSpec {
            name: "level arm".into(),
            frames: vec![
                Frame::new(FrameType::Fixed),
                Frame {
                    alpha: -std::f64::consts::FRAC_PI_2,
                    ..revolute(0.0)
                },
                revolute(1.0),
                Frame {
                    d: 1.0,
                    ..Frame::new(FrameType::Fixed)
                },
            ],
            joints: vec![Joint::default_for(FrameType::Revolute); 2],
            motor_coupling: None,
            joint_coupling: None,
            priority: None,
            compliances: Some(vec![1e-3, 0.0]),
        })
        .expect("robot");
        let mut masses = MassModel::new(4);
        masses
            .set_link(
                3,
                LinkMass {
                    mass: 10.0,
                    com: Vector3::zeros(),
                },
            )
            .expect("mass");
        (robot, masses)
    }

    #[test]
    fn torques_settle_at_the_drooped_pose() {
        let (robot, masses) = level_arm();
        let qm = [0.0, 0.0];
        let commanded = gravity_torques(&robot, &masses, None, &qm).expect("τ");
        let weight = 10.0 * gecaro_core::STANDARD_GRAVITY;
        // Stretched out level: the shoulder holds the weight at 2 m.
        assert!(
            (commanded[0].abs() - 2.0 * weight).abs() < 1e-9,
            "{commanded}"
        );
        let settled = settled_torques(&robot, &masses, None, &qm).expect("τ");
        // The arm droops by φ = c·τ and the lever shrinks to 2·cos φ: the
        // fixed point of τ = 2·m·g·cos(c·τ), by bisection on its own.
        let c = 1e-3;
        let (mut low, mut high) = (0.0, 2.0 * weight);
        for _ in 0..200 {
            let mid = 0.5 * (low + high);
            if mid < 2.0 * weight * (c * mid).cos() {
                low = mid;
            } else {
                high = mid;
            }
        }
        assert!(
            (settled[0].abs() - low).abs() < 1e-9,
            "{} vs {low}",
            settled[0]
        );
        assert!(settled[0].abs() < commanded[0].abs());
        // And the settled pose is the model's under those torques: the tip
        // 2·sin φ below the level line.
        let mut chain = ChainBuffer::default();
        KinematicModel::new(&robot)
            .forward_loaded(&qm, Some(&settled), &mut chain)
            .expect("pose");
        let drop = chain.world_from_tool().translation.vector.z;
        assert!((drop.abs() - 2.0 * (c * low).sin()).abs() < 1e-12, "{drop}");
        assert!(drop < 0.0, "the arm droops under gravity: {drop}");
    }

    /// Commanded where it says, the arm settles at the pose wanted.
    #[test]
    fn the_commanded_joints_settle_at_the_pose_wanted() {
        let (robot, masses) = level_arm();
        let payload = LinkMass {
            mass: 3.0,
            com: Vector3::new(0.1, 0.0, 0.05),
        };
        let wanted = [0.3, -0.4];
        let commanded =
            commanded_under_load(&robot, &masses, Some(&payload), &wanted).expect("commanded");
        assert!(
            (commanded[0] - wanted[0]).abs() > 1e-3,
            "the shoulder is loaded"
        );
        let settled = settled_torques(&robot, &masses, Some(&payload), &commanded).expect("τ");
        let mut chain = ChainBuffer::default();
        let model = KinematicModel::new(&robot);
        model
            .forward_loaded(&commanded, Some(&settled), &mut chain)
            .expect("pose");
        let reached = *chain.world_from_tool();
        model.forward(&wanted, &mut chain).expect("pose");
        let difference =
            (reached.translation.vector - chain.world_from_tool().translation.vector).norm();
        assert!(difference < 1e-12, "{difference:e} m");
    }

    #[test]
    fn samples_are_loaded_with_their_payload_and_lines_are_named() {
        let (robot, masses) = level_arm();
        let mut samples = vec![Sample::new(vec![0.0, 0.0]), Sample::new(vec![0.0, 0.0])];
        samples[1].set_payload(Some(LinkMass {
            mass: 5.0,
            com: Vector3::zeros(),
        }));
        let mut loaded = Samples::from(samples.clone());
        load_samples(&robot, &masses, &mut loaded).expect("loads");
        let first = loaded.get(0).torques().expect("τ").to_vec();
        let second = loaded.get(1).torques().expect("τ").to_vec();
        let weight = 5.0 * gecaro_core::STANDARD_GRAVITY;
        assert!((second[0].abs() - first[0].abs() - 2.0 * weight).abs() < 1e-9);
        samples[0].motor_positions = [f64::NAN, 0.0].as_slice().into();
        samples[0].line = Some(12);
        match load_samples(&robot, &masses, &mut Samples::from(samples)) {
            Err(Error::InvalidData { line, .. }) => assert_eq!(line, Some(12)),
            other => panic!("unexpected {other:?}"),
        }
    }

    /// The move [`weighed_at`] reports is the RMS over the samples of the
    /// tool point's move between the old loads and the new, to first order:
    /// the exact move (the deflected forward model twice) agrees to a few
    /// parts in a thousand, and loads that do not change move nothing.
    #[test]
    fn the_loads_move_the_tool_point_as_the_model_does() {
        let (robot, masses) = level_arm();
        let position =
            crate::methods::method("position", &crate::methods::MethodOptions::default())
                .expect("position");
        let samples: Vec<Sample> = [[0.3, -0.4], [1.2, 0.5], [-0.7, 2.0]]
            .iter()
            .map(|q| {
                let mut sample = Sample::new(q.to_vec());
                // Loads a few per cent off (a geometry centimetres off).
                sample.loads_mut().torques = Some(
                    gravity_torques(&robot, &masses, None, q)
                        .expect("τ")
                        .iter()
                        .map(|tau| 0.97 * tau + 1.5)
                        .collect(),
                );
                sample
            })
            .collect();
        let study = Study::single(position, samples, "arm");
        let (weighed, moved) = weighed_at(&study, &robot, &masses).expect("weighed");
        let model = KinematicModel::new(&robot);
        let (mut old, mut new) = (ChainBuffer::default(), ChainBuffer::default());
        let mut sum = 0.0;
        for (before, after) in study.sets[0]
            .samples
            .iter()
            .zip(weighed.sets[0].samples.iter())
        {
            let q = &before.motor_positions();
            model
                .forward_loaded(q, before.torques(), &mut old)
                .expect("pose");
            model
                .forward_loaded(q, after.torques(), &mut new)
                .expect("pose");
            sum += (new.world_from_tool().translation.vector
                - old.world_from_tool().translation.vector)
                .norm_squared();
        }
        let exact = (sum / 3.0).sqrt();
        assert!(exact > 1e-4, "the loads move the arm: {exact:e} m");
        assert!(
            (moved - exact).abs() < 5e-3 * exact,
            "{moved:e} vs {exact:e}"
        );
        let (_, again) = weighed_at(&weighed, &robot, &masses).expect("weighed");
        assert_eq!(again, 0.0);
        // Moved by more than a tenth of σ: followed; not moved: left.
        let mut measured = study.clone();
        measured.sets[0].sigma = Some(2e-5);
        assert!(reweighed(&measured, &robot, &masses).expect("w").is_some());
        measured.sets[0].samples = weighed.sets[0].samples.clone();
        assert!(reweighed(&measured, &robot, &masses).expect("w").is_none());
    }
}
