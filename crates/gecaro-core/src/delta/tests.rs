use nalgebra::{Isometry3, Vector3};

use super::*;
use crate::parallel_model::moved;

/// A pick-and-place Delta: motors on a circle of 0.2 m, plate joints on
/// one of 0.05 m, upper arms 0.3 m, forearms 0.8 m, ranges −40°..+80°.
fn delta() -> Delta {
    let arms = (0..3)
        .map(|i| {
            let azimuth = f64::from(i) * 120f64.to_radians();
            let h = Vector3::new(azimuth.cos(), azimuth.sin(), 0.0);
            Arm {
                base: 0.2 * h,
                azimuth,
                offset: 0.0,
                gain: 1.0,
                upper_arm: 0.3,
                forearm: 0.8,
                platform: 0.05 * h,
                min: -40f64.to_radians(),
                max: 80f64.to_radians(),
            }
        })
        .collect();
    Delta::new("delta", arms, Vector3::new(0.0, 0.0, -0.05)).expect("delta")
}

#[test]
fn home_is_below_the_base_with_every_arm_mid_range() {
    let delta = delta();
    let home = delta.home();
    assert!(home.translation.z < -0.5, "{home}");
    for value in delta.actuator_values(&home).expect("values") {
        assert!((value - 20f64.to_radians()).abs() < 1e-9, "{value}");
    }
}

#[test]
fn direct_model_inverts_an_independent_closure() {
    let delta = delta();
    let home = delta.home().translation.vector;
    for offset in [
        Vector3::new(0.1, -0.05, 0.05),
        Vector3::new(-0.15, 0.1, -0.1),
        Vector3::zeros(),
    ] {
        let target = home + offset;
        let actuators = delta
            .actuator_values(&Isometry3::translation(target.x, target.y, target.z))
            .expect("reached");
        // Each forearm's length, written out here from the module docs.
        for (i, arm) in delta.arms().iter().enumerate() {
            let h = Vector3::new(arm.azimuth.cos(), arm.azimuth.sin(), 0.0);
            let angle = arm.offset + arm.gain * actuators[i];
            let elbow = arm.base + arm.upper_arm * (angle.cos() * h - angle.sin() * Vector3::z());
            let length = (target + arm.platform - elbow).norm();
            assert!((length - arm.forearm).abs() < 1e-12, "arm {i}: {length}");
            // The working mode: the elbow out of the motor circle.
            assert!(elbow.dot(&h) > arm.base.dot(&h) - 1e-9 || angle.cos() > 0.0);
        }
        let found = delta.direct(&actuators, &delta.home()).expect("solved");
        assert!((found.translation.vector - target).norm() < 1e-9, "{found}");
        assert!(found.rotation.angle() < 1e-15);
    }
}

#[test]
fn jacobians_match_finite_differences() {
    let delta = delta();
    let at = Isometry3::translation(0.05, 0.02, delta.home().translation.z + 0.03);
    let actuators = delta.actuator_values(&at).expect("reached");
    let analytic = delta.pose_jacobian(&at, &actuators);
    let h = 1e-7;
    for column in 0..3 {
        let mut step = [0.0; 3];
        step[column] = h;
        let plus = delta.closure(&moved(&at, &step), &actuators);
        let minus = delta.closure(&moved(&at, &step.map(|v| -v)), &actuators);
        for row in 0..3 {
            let numeric = (plus[row] - minus[row]) / (2.0 * h);
            assert!(
                (numeric - analytic[(row, column)]).abs() < 1e-7,
                "pose ({row}, {column})"
            );
        }
    }
    let values = delta.parameters();
    let analytic = delta.parameter_jacobian(&at, &actuators);
    for column in 0..PARAMETER_COUNT {
        let closure = |delta_value: f64| {
            let mut changed = values.clone();
            changed[column] += delta_value;
            delta
                .with_parameters(&changed)
                .expect("delta")
                .closure(&at, &actuators)
        };
        let numeric = (closure(h) - closure(-h)) / (2.0 * h);
        for row in 0..3 {
            assert!(
                (numeric[row] - analytic[(row, column)]).abs() < 1e-7,
                "{} row {row}: {} against {}",
                delta.parameter_names()[column],
                numeric[row],
                analytic[(row, column)]
            );
        }
    }
}

#[test]
fn a_pose_out_of_reach_and_a_mistaken_arm_are_named() {
    let delta = delta();
    let far = Isometry3::translation(0.0, 0.0, -3.0);
    assert!(matches!(
        delta.actuator_values(&far),
        Err(Error::Unreachable { .. })
    ));
    let mut arms = delta.arms().to_vec();
    arms[2].forearm = -0.8;
    let error = Delta::new("bad", arms, Vector3::zeros()).expect_err("refused");
    assert_eq!(
        error.to_string(),
        "arm 3, `forearm`: -0.8 is not the length of an arm"
    );
}

/// The equations visited on the stack are the matrices' rows.
#[test]
fn visited_equations_are_the_linearised_rows() {
    let delta = delta();
    let pose = moved(&delta.home(), &[0.03, -0.02, 0.05]);
    let actuators = [0.1, -0.2, 0.3];
    crate::parallel_model::assert_visits_match_linearised(&delta, &pose, &actuators);
}
