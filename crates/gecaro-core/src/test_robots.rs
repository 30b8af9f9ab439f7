//! Robots for unit tests: the paper's Stanford arm and seeded random robots.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::DMatrix;
use rand::{Rng, RngExt};

use crate::{Frame, FrameType, Joint, ParameterId, ParameterKind, Robot, RobotSpec};

/// The Stanford arm of Table 1.
pub(crate) fn stanford() -> Robot {
    let revolute = |alpha: f64, r: f64| Frame {
        alpha,
        r,
        ..Frame::new(FrameType::Revolute)
    };
    let frames = vec![
        Frame {
            theta: FRAC_PI_2,
            r: 0.5,
            ..Frame::new(FrameType::Fixed)
        },
        revolute(0.1, 0.0),
        revolute(-FRAC_PI_2, 0.2),
        Frame {
            alpha: FRAC_PI_2,
            ..Frame::new(FrameType::Prismatic)
        },
        revolute(0.0, 0.0),
        revolute(-FRAC_PI_2, 0.0),
        revolute(FRAC_PI_2, 0.0),
        Frame {
            alpha: 1.3,
            d: 0.2,
            theta: FRAC_PI_2,
            r: 0.1,
            ..Frame::new(FrameType::Fixed)
        },
    ];
    let joints = frames[1..7]
        .iter()
        .map(|frame| Joint::default_for(frame.frame_type))
        .collect();
    Robot::new(RobotSpec::rigid("Stanford", frames, joints)).expect("Table 1 is a valid robot")
}

/// A random robot with n joints, non-zero β everywhere, gains ≠ 1, offsets and
/// non-trivial coupling matrices: the hardest case for the Jacobian.
pub(crate) fn random_robot(rng: &mut impl Rng, n: usize) -> Robot {
    let mut frames = Vec::with_capacity(n + 2);
    frames.push(Frame {
        theta: rng.random_range(-PI..PI),
        r: rng.random_range(-0.5..0.5),
        ..Frame::new(FrameType::Fixed)
    });
    for j in 0..=n {
        let frame_type = if j == n {
            FrameType::Fixed
        } else if rng.random_bool(0.25) {
            FrameType::Prismatic
        } else {
            FrameType::Revolute
        };
        frames.push(Frame {
            frame_type,
            alpha: rng.random_range(-PI..PI),
            d: rng.random_range(-0.5..0.5),
            theta: rng.random_range(-PI..PI),
            r: rng.random_range(-0.5..0.5),
            beta: rng.random_range(-0.2..0.2),
        });
    }
    let joints = frames[1..=n]
        .iter()
        .map(|frame| Joint {
            offset: rng.random_range(-0.1..0.1),
            gain: rng.random_range(0.8..1.2),
            ..Joint::default_for(frame.frame_type)
        })
        .collect();
    let mut coupling = || {
        DMatrix::from_fn(n, n, |i, j| {
            f64::from(u8::from(i == j)) + rng.random_range(-0.1..0.1)
        })
    };
    let motor_coupling = Some(coupling());
    let joint_coupling = Some(coupling());
    Robot::new(RobotSpec {
        name: "random".into(),
        frames,
        joints,
        motor_coupling,
        joint_coupling,
        priority: None,
        compliances: None,
    })
    .expect("random robots are valid")
}

/// The Stanford arm with elastic joints and gravity's tilt `tilt` (rad)
/// about measurement axis `axis` (1 or 2): every kind of Jacobian column.
pub(crate) fn elastic_stanford(axis: usize, tilt: f64) -> Robot {
    let mut robot = stanford();
    robot
        .set_compliances(Some(vec![2e-3, 5e-3, 1e-4, 3e-3, 4e-3, 6e-3]))
        .expect("elastic");
    robot
        .set_parameter(ParameterId::new(ParameterKind::GravityTilt, axis), tilt)
        .expect("tilt");
    robot
}

/// Motor variables of a random configuration within the joint limits.
pub(crate) fn random_configuration(robot: &Robot, rng: &mut impl Rng) -> Vec<f64> {
    let q: Vec<f64> = robot
        .joints()
        .iter()
        .map(|joint| rng.random_range(joint.qmin..joint.qmax))
        .collect();
    robot
        .motor_positions(&q)
        .expect("valid robot")
        .as_slice()
        .to_vec()
}
