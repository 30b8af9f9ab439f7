//! The parameterisation of the identified robot nearest to the nominal one.
//!
//! Khalil–Kleinfinger parameters describe a robot in more than one way. A
//! half turn of frame j about its z axis commutes through the next frame's
//! transform (eq. 3) with the signs of its x and y axes changed:
//! `Rot(z, π)·Rot(y, β)·Rot(x, α)·Trans(x, d)·Rot(z, θ) =
//! Rot(y, −β)·Rot(x, −α)·Trans(x, −d)·Rot(z, θ + π)·Rot(z, π)`, so
//!
//! `(θ_j + π, β_{j+1}, α_{j+1}, d_{j+1}, θ_{j+1})` and
//! `(θ_j, −β_{j+1}, −α_{j+1}, −d_{j+1}, θ_{j+1} + π)`
//!
//! are the same robot, every pose and Jacobian alike. A fit that meets a
//! joint whose zero is a quarter turn off may land on either: "joint 2's
//! zero is −89.4°, joint 3's +180°, its links −0.075× their nominal
//! lengths" is the robot whose joint 2 is +90.6° off. After each pass, every
//! such half turn (j = 0..n) that brings the robot nearer to the nominal —
//! angles in radians, lengths in tenths of a metre — is taken, and the pass
//! ends at the same fit, written the way a person reads it.

use gecaro_core::{ParameterId, ParameterKind, Robot};

/// Lengths count against angles in this unit (metres per radian).
const LENGTH_UNIT: f64 = 0.1;

/// The robot of `robot`'s parameterisation nearest to `nominal` (module
/// docs), `None` when `robot` is it.
pub(super) fn nearest_branch(nominal: &Robot, robot: &Robot) -> Option<Robot> {
    let mut nearest = robot.clone();
    let mut changed = false;
    // A half turn at frame j changes frame j + 1: a second sweep sees what
    // the first made possible.
    for _ in 0..2 {
        let mut turned_any = false;
        for frame in 0..nominal.frames().len() - 1 {
            let turned = half_turned(&nearest, frame)?;
            if distance(nominal, &turned, frame) + 1e-12 < distance(nominal, &nearest, frame) {
                nearest = turned;
                turned_any = true;
            }
        }
        changed |= turned_any;
        if !turned_any {
            break;
        }
    }
    changed.then_some(nearest)
}

/// The parameters a half turn at frame `frame` changes.
fn members(frame: usize) -> [ParameterId; 5] {
    [
        ParameterId::new(ParameterKind::Theta, frame),
        ParameterId::new(ParameterKind::Beta, frame + 1),
        ParameterId::new(ParameterKind::Alpha, frame + 1),
        ParameterId::new(ParameterKind::D, frame + 1),
        ParameterId::new(ParameterKind::Theta, frame + 1),
    ]
}

/// `robot` with frame `frame` turned by a half turn about its z axis and
/// frame `frame + 1` written for it (module docs); `None` when a value
/// cannot be set.
fn half_turned(robot: &Robot, frame: usize) -> Option<Robot> {
    use std::f64::consts::PI;
    let mut turned = robot.clone();
    let [theta, beta, alpha, d, next] = members(frame);
    let turn = |value: f64| if value > 0.0 { value - PI } else { value + PI };
    turned
        .set_parameter(theta, turn(robot.parameter(theta)))
        .ok()?;
    if robot.parameters().contains(beta) {
        turned.set_parameter(beta, -robot.parameter(beta)).ok()?;
    }
    turned.set_parameter(alpha, -robot.parameter(alpha)).ok()?;
    turned.set_parameter(d, -robot.parameter(d)).ok()?;
    turned
        .set_parameter(next, turn(robot.parameter(next)))
        .ok()?;
    Some(turned)
}

/// How far the parameters a half turn at `frame` changes lie from the
/// nominal's: angles wrapped, in radians; lengths in [`LENGTH_UNIT`]. The
/// angles of the base (frame 0) and of the tool (frame n+1) count
/// [`FREE_WEIGHT`] as much: the measurement frame and a tool may be turned
/// any way, a joint's zero may not (a tool half a turn off about the
/// flange's axis is θ of frame n+1, not joint n's zero).
fn distance(nominal: &Robot, robot: &Robot, frame: usize) -> f64 {
    use std::f64::consts::TAU;
    let tool = nominal.frames().len() - 1;
    members(frame)
        .into_iter()
        .filter(|id| robot.parameters().contains(*id))
        .map(|id| {
            let difference = robot.parameter(id) - nominal.parameter(id);
            if id.kind == ParameterKind::D {
                (difference / LENGTH_UNIT).powi(2)
            } else {
                let weight = if id.frame == 0 || id.frame == tool {
                    FREE_WEIGHT
                } else {
                    1.0
                };
                weight * (difference - TAU * (difference / TAU).round()).powi(2)
            }
        })
        .sum()
}

/// What a turn of the base or the tool counts against a joint's.
const FREE_WEIGHT: f64 = 0.01;

#[cfg(test)]
mod tests {
    use super::*;
    use gecaro_core::terminal_pose;

    #[test]
    fn a_half_turn_is_the_same_robot_and_the_nearest_is_taken() {
        let nominal = gecaro_io::load_robot("industrial6").expect("ready").robot;
        let theta2 = ParameterId::new(ParameterKind::Theta, 2);
        let mut real = nominal.clone();
        real.set_parameter(theta2, 1.58).expect("θ2");
        // The other description of the same robot.
        let other = half_turned(&real, 2).expect("turned");
        for q in [
            [0.1, -0.4, 0.7, 0.2, -0.3, 0.9],
            [1.0, -1.2, 0.3, -2.0, 0.5, 0.1],
        ] {
            let (a, b) = (
                terminal_pose(&real, &q).expect("pose"),
                terminal_pose(&other, &q).expect("pose"),
            );
            assert!((a.translation.vector - b.translation.vector).norm() < 1e-12);
            assert!((a.rotation.matrix() - b.rotation.matrix()).norm() < 1e-12);
        }
        assert!(other.parameter(ParameterId::new(ParameterKind::D, 3)) < 0.0);
        let nearest = nearest_branch(&nominal, &other).expect("turned back");
        assert!((nearest.parameter(theta2) - 1.58).abs() < 1e-12);
        assert!(nearest_branch(&nominal, &real).is_none());
        assert!(nearest_branch(&nominal, &nominal).is_none());
    }
}
