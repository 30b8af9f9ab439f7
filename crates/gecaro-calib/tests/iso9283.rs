//! ISO 9283's test planned on the ready robots and evaluated on a simulated
//! "real" robot of known repeatability.

use gecaro_calib::cell::Cell;
use gecaro_calib::iso9283::{
    Approaches, CubeChoice, Registration, TestCube, TestOptions, TestPlan, Visit, evaluate_test,
    plan_test,
};
use gecaro_calib::simulation::{Sampler, perturbed_robot};
use gecaro_core::{Robot, forward_kinematics, terminal_pose};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};

fn ready(name: &str) -> Robot {
    gecaro_io::load_robot(name).expect("a ready robot").robot
}

/// The cube the search finds on `robot`, shrunk to `side` (m) at most.
fn cube_of(robot: &Robot, side: f64) -> TestCube {
    let found = plan_test(robot, CubeChoice::Largest, &TestOptions::default())
        .expect("a cube")
        .cube;
    TestCube::new(found.centre, found.side.min(side)).expect("cube")
}

/// The multi-directional test of `cycles` cycles on `robot` in the cube
/// the search finds, shrunk to `side` (m) at most.
fn three_directions(robot: &Robot, side: f64, cycles: usize) -> (TestCube, TestPlan) {
    let cube = cube_of(robot, side);
    let options = TestOptions {
        cycles,
        approaches: Approaches::Three,
        ..TestOptions::default()
    };
    let plan = plan_test(robot, CubeChoice::Stated(cube), &options).expect("plan");
    (cube, plan)
}

/// A stated cube: the five poses where the standard puts them, held in
/// one orientation, within the limits, the program's targets the model's
/// poses at its joints; the rows in the order the robot runs them.
#[test]
fn a_stated_cube_is_planned_as_the_standard_asks() {
    let robot = ready("stanford");
    let (cube, plan) = three_directions(&robot, 0.1, 3);
    assert!(plan.orientation_held && !plan.searched);
    for (planned, point) in plan.poses.iter().zip(cube.poses()) {
        assert!((planned.target.translation.vector - point).norm() < 1e-9);
        let held = plan.poses[0].target.rotation.matrix();
        assert!((planned.target.rotation.matrix() - held).norm() < 1e-9);
        let joints = robot
            .joint_positions(&planned.motor_positions)
            .expect("joints");
        assert!(robot.within_limits(joints.as_slice()));
    }
    // P1 is the centre of the other four.
    let centre: Vector3<f64> = plan.poses[1..]
        .iter()
        .map(|point| point.target.translation.vector)
        .sum::<Vector3<f64>>()
        / 4.0;
    assert!((centre - plan.poses[0].target.translation.vector).norm() < 1e-9);
    let rows = plan.rows();
    assert_eq!(rows.len(), 3 * 5 * 3 * 2);
    assert_eq!(rows.iter().filter(|row| row.measured).count(), 3 * 5 * 3);
    assert_eq!(
        (rows[0].pose, rows[0].direction, rows[0].measured),
        (1, 1, false)
    );
    assert_eq!((rows[1].pose, rows[1].measured), (1, true));
    for row in &rows {
        let pose = terminal_pose(&robot, &row.point.motor_positions).expect("pose");
        assert!((pose.translation.vector - row.point.target.translation.vector).norm() < 1e-12);
        if !row.measured {
            let gap = (row.point.target.translation.vector
                - plan.poses[row.pose - 1].target.translation.vector)
                .norm();
            assert!((gap - 0.01).abs() < 1e-9, "{gap}");
        }
    }
}

/// Every ready robot: a cube found inside its working space, the five poses
/// reached within the limits, P1 the centre of the others to 1e-9 m.
#[test]
fn every_ready_robot_gets_a_cube_and_its_five_poses() {
    for ready_robot in gecaro_io::ready_robots() {
        let robot = ready(ready_robot.name);
        let plan = plan_test(&robot, CubeChoice::Largest, &TestOptions::default())
            .unwrap_or_else(|error| panic!("{}: {error}", ready_robot.name));
        assert!(plan.searched);
        assert!(
            plan.cube.side >= 0.01,
            "{}: {:?}",
            ready_robot.name,
            plan.cube
        );
        let side_mm = plan.cube.side * 1e3;
        assert!((side_mm - side_mm.round()).abs() < 1e-6);
        for (planned, point) in plan.poses.iter().zip(plan.cube.poses()) {
            assert!(
                (planned.target.translation.vector - point).norm() < 1e-9,
                "{}",
                ready_robot.name
            );
            let joints = robot
                .joint_positions(&planned.motor_positions)
                .expect("joints");
            assert!(
                robot.within_limits(joints.as_slice()),
                "{}",
                ready_robot.name
            );
        }
        let centre: Vector3<f64> = plan.poses[1..]
            .iter()
            .map(|point| point.target.translation.vector)
            .sum::<Vector3<f64>>()
            / 4.0;
        assert!((centre - plan.poses[0].target.translation.vector).norm() < 1e-9);
    }
}

/// A cube too large is refused naming it; a floor above the robot leaves
/// room for none; one cycle is refused.
#[test]
fn cubes_that_do_not_fit_are_refused_with_the_reason() {
    let robot = ready("stanford");
    let huge = TestCube::new(Vector3::new(0.5, 0.0, 0.5), 4.0).expect("cube");
    let error =
        plan_test(&robot, CubeChoice::Stated(huge), &TestOptions::default()).expect_err("huge");
    assert!(error.to_string().contains("not inside"), "{error}");
    let top = forward_kinematics(&robot, &[0.0; 6]).expect("fk").poses()[1]
        .translation
        .z;
    let floor = TestOptions {
        cell: Cell {
            floor: Some(top + 5.0),
            station: None,
        },
        ..TestOptions::default()
    };
    let error = plan_test(&robot, CubeChoice::Largest, &floor).expect_err("no room");
    assert!(error.to_string().contains("no test"), "{error}");
    let one = TestOptions {
        cycles: 1,
        ..TestOptions::default()
    };
    let error = plan_test(&robot, CubeChoice::Largest, &one).expect_err("one cycle");
    assert!(error.to_string().contains("at least 2"), "{error}");
}

/// The measured visits of `plan` run on `real`, with Gaussian noise σ per
/// axis (and `angle_sigma` about each axis), seen from `frame` (the
/// measurement frame's pose in the base frame).
fn run(
    plan: &TestPlan,
    real: &Robot,
    (sigma, angle_sigma): (f64, f64),
    frame: &IsometryMatrix3<f64>,
    sampler: &mut Sampler,
) -> Vec<Visit> {
    plan.rows()
        .into_iter()
        .filter(|row| row.measured)
        .map(|row| {
            let pose = terminal_pose(real, &row.point.motor_positions).expect("pose");
            let noisy = IsometryMatrix3::from_parts(
                Translation3::from(pose.translation.vector + sampler.gaussian_vector(sigma)),
                pose.rotation * sampler.gaussian_rotation(angle_sigma),
            );
            let seen = frame.inverse() * noisy;
            Visit {
                pose: row.pose,
                cycle: row.cycle,
                direction: row.direction,
                commanded: row.point.target,
                position: seen.translation.vector,
                orientation: Some(seen.rotation),
            }
        })
        .collect()
}

/// A simulated "real" robot: AP per pose equals an independent computation
/// (the barycentre of the real model's poses against the commanded one) to
/// 1e-9 m; RP, averaged over the five poses, within 10 % of 3.615 σ (the
/// χ(3) distribution's mean plus three standard deviations); a tracker
/// standing elsewhere, stated, gives the same; registered by a best fit,
/// the AP shrink (the fit absorbs their rigid part) and say so.
#[test]
fn a_simulated_robot_s_accuracy_and_repeatability_are_found() {
    let nominal = ready("industrial6");
    let mut sampler = Sampler::new(78);
    let real = perturbed_robot(&nominal, 0.3, &mut sampler).expect("real");
    let (_, plan) = three_directions(&nominal, 0.4, 30);
    let sigma = 2e-5;
    let visits = run(
        &plan,
        &real,
        (sigma, 1e-5),
        &IsometryMatrix3::identity(),
        &mut sampler,
    );
    let evaluation = evaluate_test(&visits, &Registration::Base).expect("evaluation");
    assert_eq!(evaluation.poses.len(), 5);
    assert_eq!(evaluation.directions, 3);
    assert!(evaluation.oriented);
    let mut repeatability = 0.0;
    for result in &evaluation.poses {
        let ours: Vec<&Visit> = visits
            .iter()
            .filter(|visit| visit.pose == result.pose && visit.direction == 1)
            .collect();
        let barycentre = ours
            .iter()
            .map(|visit| visit.position)
            .sum::<Vector3<f64>>()
            / ours.len() as f64;
        let independent =
            (barycentre - plan.poses[result.pose - 1].target.translation.vector).norm();
        assert!((result.characteristics.accuracy - independent).abs() < 1e-9);
        // The real robot is far off beyond the noise: AP is its error.
        let truth = terminal_pose(&real, &plan.poses[result.pose - 1].motor_positions)
            .expect("pose")
            .translation
            .vector;
        let real_error = (truth - plan.poses[result.pose - 1].target.translation.vector).norm();
        assert!(real_error > 10.0 * sigma, "{real_error}");
        assert!((result.characteristics.accuracy - real_error).abs() < 3.0 * sigma);
        // The approaches differ by noise only.
        let variation = result.variation.as_ref().expect("vAP");
        assert!(variation.position < 6.0 * sigma, "{}", variation.position);
        repeatability += result.characteristics.repeatability / 5.0;
    }
    let expected = 3.615 * sigma;
    assert!(
        (repeatability / expected - 1.0).abs() < 0.1,
        "RP {repeatability} against {expected}"
    );
    let distance = evaluation.distance.as_ref().expect("distance");
    assert!(distance.repeatability < 6.0 * sigma);

    // A tracker 3 m away, turned: stated, the same characteristics.
    let tracker = IsometryMatrix3::from_parts(
        Translation3::new(3.0, -1.0, 0.4),
        Rotation3::from_euler_angles(0.01, -0.02, 2.5),
    );
    let seen = run(
        &plan,
        &real,
        (sigma, 1e-5),
        &tracker,
        &mut Sampler::new(78_000),
    );
    let unregistered = evaluate_test(&seen, &Registration::Base).expect("base");
    assert!(
        unregistered.worst_accuracy() > 1.0,
        "{}",
        unregistered.worst_accuracy()
    );
    let stated = evaluate_test(&seen, &Registration::Stated(tracker)).expect("stated");
    for (a, b) in stated.poses.iter().zip(&evaluation.poses) {
        assert!((a.characteristics.accuracy - b.characteristics.accuracy).abs() < 6.0 * sigma);
    }
    let fitted = evaluate_test(&seen, &Registration::BestFit).expect("fit");
    assert!(fitted.worst_accuracy() < evaluation.worst_accuracy());
    // The frame found is the tracker's, but for the robot's own error it
    // absorbed: millimetres at the cube.
    let p1 = nalgebra::Point3::from(seen[0].position);
    assert!((fitted.frame * p1 - tracker * p1).norm() < 5e-3);
}
