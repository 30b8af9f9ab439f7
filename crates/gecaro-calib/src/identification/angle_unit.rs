//! Joint values in degrees read as radians, named before any fitting.
//!
//! Read as radians, joint angles written in degrees are 57.3× too large:
//! most of them lie beyond the joint limits, and the identification fails
//! to converge far from any solution ("522 joint values outside the joint
//! limits … try Levenberg–Marquardt", which does not help). Read as
//! degrees, the same values lie within the limits. So each set's revolute
//! joint values (eq. 4's joint variables, at most [`CHECKED`] configurations
//! spread over the set) are held against the limits both ways: more than
//! [`OUTSIDE_AS_READ`] of them outside as read, more than
//! [`BEYOND_A_TURN`] beyond a full turn (which joints in radians seldom
//! are: ±350° wrists only), and at most [`OUTSIDE_AS_DEGREES`] outside as
//! degrees, is named as the unit. Data that only leave the limits a little
//! (a joint pushed past its limit, a limit stated too tight) are left to the
//! limit check.

use gecaro_core::{FrameType, LIMIT_TOLERANCE, Robot};

use crate::Error;
use crate::sampler::spread_indices;
use crate::study::Study;

/// Configurations of a set checked at most.
const CHECKED: usize = 500;

/// The part of a set's revolute joint values outside the limits as read
/// above which the unit is questioned.
const OUTSIDE_AS_READ: f64 = 0.25;

/// The part of a set's revolute joint values beyond a full turn above
/// which the unit is questioned.
const BEYOND_A_TURN: f64 = 0.1;

/// The part outside the limits read as degrees at most for the unit to be
/// named degrees.
const OUTSIDE_AS_DEGREES: f64 = 0.01;

/// Refuses a set whose revolute joint values are degrees read as radians
/// (module docs).
///
/// # Errors
/// [`Error::WrongUnit`] naming the set and the joint values both ways; a
/// configuration that does not fit the robot.
pub(super) fn check_angle_unit(robot: &Robot, study: &Study) -> Result<(), Error> {
    let revolute: Vec<usize> = (0..robot.joint_count())
        .filter(|j| robot.frames()[j + 1].frame_type == FrameType::Revolute)
        .collect();
    if revolute.is_empty() {
        return Ok(());
    }
    let mut joints = vec![0.0; robot.joint_count()];
    for set in &study.sets {
        let (mut values, mut outside, mut outside_as_degrees) = (0_usize, 0_usize, 0_usize);
        let mut beyond_a_turn = 0_usize;
        let mut largest = 0.0_f64;
        for index in spread_indices(set.samples.len(), CHECKED) {
            robot.joint_positions_into(set.samples.get(index).motor_positions(), &mut joints)?;
            for &j in &revolute {
                let limits = &robot.joints()[j];
                let within = |q: f64| {
                    (limits.qmin - LIMIT_TOLERANCE..=limits.qmax + LIMIT_TOLERANCE).contains(&q)
                };
                values += 1;
                outside += usize::from(!within(joints[j]));
                outside_as_degrees += usize::from(!within(joints[j].to_radians()));
                largest = largest.max(joints[j].abs());
                beyond_a_turn += usize::from(joints[j].abs() > std::f64::consts::TAU);
            }
        }
        if values == 0 {
            continue;
        }
        let part = |count: usize| count as f64 / values as f64;
        if part(outside) > OUTSIDE_AS_READ
            && part(beyond_a_turn) > BEYOND_A_TURN
            && part(outside_as_degrees) <= OUTSIDE_AS_DEGREES
        {
            return Err(Error::WrongUnit {
                quantity: "angle",
                unit: "deg",
                message: format!(
                    "{}: the joint angles look like degrees read as radians: {:.0} % of the \
                     revolute joint values lie outside the joint limits as read (up to {:.1} \
                     rad), and {} read as degrees",
                    set.label,
                    100.0 * part(outside),
                    largest,
                    if outside_as_degrees == 0 {
                        "all lie within them".to_owned()
                    } else {
                        format!("{:.1} % outside them", 100.0 * part(outside_as_degrees))
                    }
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::{MethodOptions, method};
    use crate::sample::Sample;
    use crate::simulation::Sampler;

    fn study(robot: &Robot, scale: f64) -> Study {
        let mut sampler = Sampler::new(4);
        let samples: Vec<Sample> = (0..60)
            .map(|_| {
                let motors: Vec<f64> = sampler
                    .configuration(robot)
                    .iter()
                    .map(|q| q * scale)
                    .collect();
                Sample::new(motors)
            })
            .collect();
        let position = method("position", &MethodOptions::default()).expect("method");
        Study::single(position, samples, "log.csv")
    }

    #[test]
    fn degrees_read_as_radians_are_named_and_radians_pass() {
        for name in ["industrial6", "puma560", "panda", "ur10e"] {
            let robot = gecaro_io::load_robot(name).expect("ready").robot;
            check_angle_unit(&robot, &study(&robot, 1.0)).expect("radians");
            let error = check_angle_unit(&robot, &study(&robot, 180.0 / std::f64::consts::PI))
                .expect_err("degrees");
            let text = error.to_string();
            assert!(
                text.contains("log.csv") && text.contains("degrees read as radians"),
                "{text}"
            );
            assert!(matches!(error, Error::WrongUnit { unit: "deg", .. }));
        }
        // Values a little outside (a limit stated too tight) are no unit.
        let robot = gecaro_io::load_robot("industrial6").expect("ready").robot;
        check_angle_unit(&robot, &study(&robot, 1.3)).expect("not degrees");
    }
}
