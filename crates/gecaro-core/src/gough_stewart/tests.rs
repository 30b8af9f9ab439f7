use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::*;
use crate::parallel_model::moved;

/// A hexapod of base radius 0.5 m and platform radius 0.3 m, joints paired
/// 30° apart, legs of 0.6 m at actuator zero, ranges ±0.1 m.
fn hexapod() -> GoughStewart {
    let on = |radius: f64, degrees: f64| {
        let angle = degrees.to_radians();
        Vector3::new(radius * angle.cos(), radius * angle.sin(), 0.0)
    };
    let legs = (0..6)
        .map(|i| {
            let pair = (i / 2) as f64 * 120.0;
            let side = if i % 2 == 0 { -15.0 } else { 15.0 };
            Leg::new(on(0.5, pair + side), on(0.3, pair + 3.0 * side), 0.6)
        })
        .collect();
    GoughStewart::new("hexapod", legs, Vector3::new(0.01, 0.02, 0.05)).expect("hexapod")
}

fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

#[test]
fn home_is_level_and_every_leg_mid_range() {
    let hexapod = hexapod();
    let home = hexapod.home();
    assert!(home.rotation.angle() < 1e-15);
    // A symmetric platform: every leg the same length, at mid-range (0).
    for value in hexapod.actuator_values(&home).expect("values") {
        assert!(value.abs() < 1e-12, "{value}");
    }
    assert!(home.translation.z > 0.0);
}

#[test]
fn direct_model_inverts_an_independent_inverse_model() {
    let hexapod = hexapod();
    let home = hexapod.home().translation.vector;
    for (i, target) in [
        pose(0.02, -0.03, home.z + 0.04, 0.05, -0.08, 0.1),
        pose(-0.05, 0.05, home.z - 0.03, -0.1, 0.02, -0.2),
        pose(0.0, 0.0, home.z, 0.0, 0.0, 0.3),
    ]
    .iter()
    .enumerate()
    {
        // Leg lengths written out here, independently of the model's code.
        let lengths: Vec<f64> = hexapod
            .legs()
            .iter()
            .map(|leg| {
                let world = target.rotation * leg.platform + target.translation.vector;
                (world - leg.base).norm()
            })
            .collect();
        let actuators: Vec<f64> = lengths.iter().map(|length| length - 0.6).collect();
        let found = hexapod.direct(&actuators, &hexapod.home()).expect("solved");
        let position = (found.translation.vector - target.translation.vector).norm();
        let angle = (found.rotation.inverse() * target.rotation).angle();
        assert!(
            position < 1e-9 && angle < 1e-9,
            "pose {i}: {position} m, {angle} rad"
        );
    }
}

#[test]
fn pose_jacobian_matches_finite_differences() {
    let hexapod = hexapod();
    let at = pose(
        0.01,
        0.02,
        hexapod.home().translation.z + 0.02,
        0.1,
        -0.05,
        0.2,
    );
    let jacobian = hexapod.inverse_kinematic_jacobian(&at);
    let h = 1e-6;
    for column in 0..6 {
        let mut step = [0.0; 6];
        step[column] = h;
        let shifted = |sign: f64| {
            let s = step.map(|v| v * sign);
            let moved = moved(&at, &s);
            hexapod.leg_lengths(&moved)
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        for row in 0..6 {
            let numeric = (plus[row] - minus[row]) / (2.0 * h);
            assert!(
                (numeric - jacobian[(row, column)]).abs() < 1e-8,
                "({row}, {column}): {numeric} against {}",
                jacobian[(row, column)]
            );
        }
    }
}

#[test]
fn parameter_rows_match_finite_differences() {
    let hexapod = hexapod();
    let at = pose(
        -0.02,
        0.01,
        hexapod.home().translation.z - 0.01,
        -0.05,
        0.1,
        -0.1,
    );
    let actuators = [0.01, -0.02, 0.03, 0.0, 0.05, -0.04];
    let rows = hexapod.leg_parameter_rows(&at, &actuators);
    let values = hexapod.parameters();
    let h = 1e-7;
    for parameter in 0..LEGS * PARAMETERS_PER_LEG {
        let residuals = |delta: f64| {
            let mut changed = values.clone();
            changed[parameter] += delta;
            hexapod
                .with_parameters(&changed)
                .expect("platform")
                .leg_residuals(&at, &actuators)
        };
        let numeric = (residuals(h) - residuals(-h)) / (2.0 * h);
        let (leg, within) = (
            parameter / PARAMETERS_PER_LEG,
            parameter % PARAMETERS_PER_LEG,
        );
        for row in 0..LEGS {
            let analytic = if row == leg { rows[row][within] } else { 0.0 };
            assert!(
                (numeric[row] - analytic).abs() < 1e-7,
                "{}: leg {row}: {} against {analytic}",
                hexapod.parameter_names()[parameter],
                numeric[row]
            );
        }
    }
}

#[test]
fn parameters_round_trip_with_their_names() {
    let hexapod = hexapod();
    let values = hexapod.parameters();
    assert_eq!(values.len(), PARAMETER_COUNT);
    assert_eq!(hexapod.parameter_names().len(), PARAMETER_COUNT);
    assert_eq!(hexapod.parameter_names()[7], "K1");
    assert_eq!(hexapod.parameter_names()[50], "tz");
    assert_eq!(hexapod.with_parameters(&values).expect("same"), hexapod);
}

#[test]
fn a_platform_no_one_builds_is_refused_naming_the_leg() {
    let mut legs = hexapod().legs().to_vec();
    legs[3].gain = 0.0;
    let error = GoughStewart::new("bad", legs.clone(), Vector3::zeros()).expect_err("refused");
    assert_eq!(
        error.to_string(),
        "leg 4, `gain`: a gain of zero moves nothing"
    );
    legs[3].gain = 1.0;
    legs[1].base.y = f64::NAN;
    let error = GoughStewart::new("bad", legs.clone(), Vector3::zeros()).expect_err("refused");
    assert!(error.to_string().starts_with("leg 2, `base`"), "{error}");
    legs.pop();
    let error = GoughStewart::new("bad", legs, Vector3::zeros()).expect_err("refused");
    assert!(
        error.to_string().contains("has 6 legs, 5 are given"),
        "{error}"
    );
}

#[test]
fn actuator_values_no_platform_takes_are_refused() {
    let hexapod = hexapod();
    let error = hexapod
        .direct(&[5.0, -0.5, 0.0, 0.0, 0.0, 0.0], &hexapod.home())
        .expect_err("refused");
    assert!(matches!(error, Error::NoAssembly { .. }), "{error}");
    let error = hexapod
        .direct(&[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0], &hexapod.home())
        .expect_err("refused");
    assert!(matches!(
        error,
        Error::NonFiniteConfiguration { joint: 2, .. }
    ));
}

#[test]
fn a_program_keeps_its_assembly_mode_target_after_target() {
    let hexapod = hexapod();
    let height = hexapod.home().translation.z;
    let mut previous = hexapod.home();
    for step in 0..200 {
        let t = f64::from(step) * 0.05;
        let target = pose(
            0.06 * t.cos(),
            0.06 * t.sin(),
            height + 0.03 * (2.0 * t).sin(),
            0.12 * t.sin(),
            -0.1 * t.cos(),
            0.25 * (0.5 * t).sin(),
        );
        let found = hexapod
            .direct(
                &hexapod.actuator_values(&target).expect("values"),
                &previous,
            )
            .expect("solved");
        let position = (found.translation.vector - target.translation.vector).norm();
        let angle = (found.rotation.inverse() * target.rotation).angle();
        assert!(
            position < 1e-9 && angle < 1e-9,
            "target {step}: {position} m, {angle} rad"
        );
        previous = found;
    }
}

#[test]
fn linearised_at_once_is_the_three_derivatives_apart() {
    let hexapod = hexapod();
    let at = pose(
        0.01,
        -0.02,
        hexapod.home().translation.z + 0.01,
        0.05,
        0.02,
        -0.1,
    );
    let actuators = [0.01, -0.02, 0.03, 0.0, 0.05, -0.04];
    let at_once = hexapod.linearised(&at, &actuators);
    assert!((at_once.closure - hexapod.closure(&at, &actuators)).amax() < 1e-15);
    assert!((at_once.by_pose - hexapod.pose_jacobian(&at, &actuators)).amax() < 1e-15);
    assert!((at_once.by_parameter - hexapod.parameter_jacobian(&at, &actuators)).amax() < 1e-15);
    let rows = hexapod.parameter_jacobian(&at, &actuators);
    for leg in 0..LEGS {
        let own = hexapod.equation_parameters(leg);
        for column in (0..PARAMETER_COUNT).filter(|c| !own.contains(c)) {
            assert_eq!(rows[(leg, column)], 0.0);
        }
    }
}

/// The equations visited on the stack are the matrices' rows.
#[test]
fn visited_equations_are_the_linearised_rows() {
    let platform = hexapod();
    let at = pose(0.01, -0.02, 0.55, 0.05, -0.03, 0.1);
    let actuators = [0.01, -0.02, 0.03, 0.0, 0.02, -0.01];
    crate::parallel_model::assert_visits_match_linearised(&platform, &at, &actuators);
}
