//! Planning: every criterion's plan beats the best of 100 random subsets of
//! the same pool, planned configurations calibrate better than random ones
//! (held-out error, 6- and 7-axis robots, four methods), the test-pose
//! criterion agrees with the prediction, and the minimum distance holds.

use gecaro_calib::study::Samples;
use gecaro_calib::{
    Quiet,
    identifiability::random_samples,
    identification::{IdentificationOptions, evaluate, identify},
    methods::{CalibrationMethod, MethodOptions, method, units},
    planning::{Criterion, Plan, PlanRequest, assess_design, plan_configurations},
    prediction::predict,
    simulation::{Sampler, perturbed_robot, simulate_at},
    study::{Sample, Study},
};
use gecaro_core::Robot;
use gecaro_io::load_robot;

fn ready(name: &str) -> Robot {
    load_robot(name).expect("ready robot").robot
}

fn plan_with(
    robot: &Robot,
    chosen: &dyn CalibrationMethod,
    pool: &[Sample],
    request: &PlanRequest<'_>,
) -> Plan {
    plan_configurations(
        robot,
        chosen,
        Samples::from(pool).as_slice(),
        request,
        &robot.priority(),
        &mut Quiet,
    )
    .expect("a plan")
}

fn plan(robot: &Robot, name: &str, pool: &[Sample], count: usize) -> Plan {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    plan_with(robot, chosen.as_ref(), pool, &PlanRequest::new(count))
}

/// `count` units of `pool` drawn at random.
fn random_units(
    chosen: &dyn CalibrationMethod,
    pool: &[Sample],
    count: usize,
    sampler: &mut Sampler,
) -> Vec<Sample> {
    let pool_units = units(chosen, Samples::from(pool).as_slice());
    sampler
        .subset(pool_units.len(), count)
        .into_iter()
        .flat_map(|unit| pool_units[unit].iter().map(|index| pool[*index].clone()))
        .collect()
}

#[test]
fn the_plan_beats_the_best_of_a_hundred_random_subsets_and_is_deterministic() {
    for (robot, name, count) in [
        ("stanford", "position", 30),
        ("stanford", "distance", 60),
        ("panda", "point-link", 48),
    ] {
        let robot = ready(robot);
        let chosen = method(name, &MethodOptions::default()).expect("method");
        let pool = random_samples(&robot, chosen.as_ref(), Some(400), 7, &mut Quiet).expect("pool");
        let planned = plan(&robot, name, &pool, count);
        assert_eq!(planned.samples.len(), count, "{name}");
        let again = plan(&robot, name, &pool, count);
        assert_eq!(planned.chosen, again.chosen, "{name}: deterministic");
        let d = |design: &[Sample]| {
            assess_design(
                &robot,
                chosen.as_ref(),
                Samples::from(pool.as_slice()).as_slice(),
                Samples::from(design).as_slice(),
                &Criterion::D,
                &robot.priority(),
            )
            .expect("D")
            .log_det
        };
        let log_det = d(&planned.samples);
        let planned_log_det = planned.quality.log_det;
        assert!((log_det - planned_log_det).abs() < 1e-6 * log_det.abs().max(1.0));
        // The best of 100 random subsets of as many units.
        let mut sampler = Sampler::new(3);
        let best = (0..100)
            .map(|_| {
                d(&random_units(
                    chosen.as_ref(),
                    &pool,
                    planned.chosen.len(),
                    &mut sampler,
                ))
            })
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(
            planned_log_det > best,
            "{name}: plan D = {planned_log_det} ≤ best random {best}"
        );
    }
}

/// For each criterion, the plan's value (as assessed anew, independently of
/// the exchange) beats the best of 100 random subsets of as many units, and
/// the observability index the criterion stands for is the best of all plans.
#[test]
fn every_criterion_beats_the_best_of_a_hundred_random_subsets() {
    let robot = ready("stanford");
    let position = method("position", &MethodOptions::default()).expect("method");
    let pool = random_samples(&robot, position.as_ref(), Some(240), 17, &mut Quiet).expect("pool");
    let mut sampler = Sampler::new(8);
    let test_poses: Vec<Vec<f64>> = (0..50).map(|_| sampler.configuration(&robot)).collect();
    let criteria = [
        Criterion::D,
        Criterion::A,
        Criterion::E,
        Criterion::O4,
        Criterion::O5,
        Criterion::TestPoses(test_poses),
    ];
    let count = 24;
    let plans: Vec<Plan> = criteria
        .iter()
        .map(|criterion| {
            let request = PlanRequest {
                criterion: criterion.clone(),
                ..PlanRequest::new(count)
            };
            plan_with(&robot, position.as_ref(), &pool, &request)
        })
        .collect();
    let random: Vec<Vec<Sample>> = (0..100)
        .map(|_| random_units(position.as_ref(), &pool, count, &mut sampler))
        .collect();
    for (criterion, planned) in criteria.iter().zip(&plans) {
        let assess = |design: &[Sample]| {
            assess_design(
                &robot,
                position.as_ref(),
                Samples::from(pool.as_slice()).as_slice(),
                Samples::from(design).as_slice(),
                criterion,
                &robot.priority(),
            )
            .expect("assessed")
        };
        let mine = assess(&planned.samples);
        assert!(
            (mine.value - planned.quality.value).abs() < 1e-6 * mine.value.abs(),
            "{criterion:?}: {mine:?} vs {:?}",
            planned.quality
        );
        // A and test are minimised, the others maximised.
        let better = |a: f64, b: f64| match criterion {
            Criterion::A | Criterion::TestPoses(_) => a < b,
            _ => a > b,
        };
        for design in &random {
            let other = assess(design).value;
            assert!(
                better(mine.value, other),
                "{}: plan {} vs a random subset {other}",
                criterion.name(),
                mine.value
            );
        }
    }
    // The index a criterion maximises is largest in its own plan.
    let index = |plan: &Plan, criterion: &Criterion| {
        let o = plan.quality.observability;
        match criterion {
            Criterion::E => o.o3,
            Criterion::O4 => o.o4,
            Criterion::O5 => o.o5,
            _ => o.o1,
        }
    };
    // The exchanges are local searches: a plan made for one criterion may
    // end a little above another's own plan in that criterion's index
    // (measured: at most 0.3 %, O5 after the continuous-design start of the
    // D plans); more than 1 % would be a failure of the criterion's exchange.
    for (criterion, own) in criteria.iter().zip(&plans).skip(2).take(3) {
        for other in &plans {
            assert!(
                index(own, criterion) >= index(other, criterion) * (1.0 - 1e-2),
                "{}: its plan {} < another's {}",
                criterion.name(),
                index(own, criterion),
                index(other, criterion)
            );
        }
    }
}

/// The test-pose criterion's value is the prediction of [`predict`] (another
/// route: unscaled W_b and the covariance of eq. 11) per unit σ, and its plan
/// predicts a smaller error at those poses than the D-optimal plan.
#[test]
fn the_test_pose_criterion_is_the_predicted_error_and_lowers_it() {
    let robot = ready("panda");
    let frame = method("frame", &MethodOptions::default()).expect("method");
    let pool = random_samples(&robot, frame.as_ref(), Some(200), 5, &mut Quiet).expect("pool");
    let mut sampler = Sampler::new(6);
    // Where the robot will work: a small region around one configuration.
    let centre = sampler.configuration(&robot);
    let poses: Vec<Vec<f64>> = (0..40)
        .map(|_| {
            centre
                .iter()
                .map(|q| q + sampler.uniform(-0.2, 0.2))
                .collect()
        })
        .collect();
    let request = PlanRequest {
        criterion: Criterion::TestPoses(poses.clone()),
        ..PlanRequest::new(20)
    };
    let planned = plan_with(&robot, frame.as_ref(), &pool, &request);
    let d_optimal = plan_with(&robot, frame.as_ref(), &pool, &PlanRequest::new(20));
    let noise = 1e-4;
    let predicted = |samples: &[Sample]| {
        predict(
            &robot,
            frame.as_ref(),
            Samples::from(samples).as_slice(),
            noise,
            &poses,
            &robot.priority(),
        )
        .expect("prediction")
        .errors
        .position_rms
    };
    let (mine, d) = (predicted(&planned.samples), predicted(&d_optimal.samples));
    assert!(
        (mine / (planned.quality.value * noise) - 1.0).abs() < 1e-6,
        "predict {mine} vs the criterion {} × σ",
        planned.quality.value
    );
    assert!(mine < 0.95 * d, "test-pose plan {mine} vs D-optimal {d}");
}

/// With a minimum joint-space distance, no two chosen configurations (nor a
/// chosen and a kept one) are closer; an impossible distance is an error.
#[test]
fn chosen_configurations_keep_the_minimum_distance() {
    let robot = ready("stanford");
    let position = method("position", &MethodOptions::default()).expect("method");
    let pool = random_samples(&robot, position.as_ref(), Some(300), 3, &mut Quiet).expect("pool");
    let kept = random_samples(&robot, position.as_ref(), Some(5), 4, &mut Quiet).expect("kept");
    let joints = |sample: &Sample| robot.joint_positions(&sample.motor_positions).expect("q");
    let closest = |samples: &[Sample]| {
        let mut closest = f64::INFINITY;
        for (i, a) in samples.iter().enumerate() {
            for b in &samples[i + 1..] {
                closest = closest.min((joints(a) - joints(b)).norm());
            }
        }
        closest
    };
    let free = plan_with(&robot, position.as_ref(), &pool, &PlanRequest::new(30));
    let distance = 3.0;
    assert!(
        closest(&free.samples) < distance,
        "the constraint must bind"
    );
    for criterion in [Criterion::D, Criterion::O5] {
        let kept_samples = Samples::from(kept.as_slice());
        let request = PlanRequest {
            count: 35,
            kept: kept_samples.as_slice(),
            criterion,
            min_distance: distance,
        };
        let planned = plan_with(&robot, position.as_ref(), &pool, &request);
        assert_eq!(planned.samples.len(), 35);
        assert_eq!(planned.samples[..5], kept[..]);
        let chosen = &planned.samples[5..];
        assert!(closest(chosen) >= distance);
        for sample in chosen {
            assert!(
                kept.iter()
                    .all(|k| (joints(k) - joints(sample)).norm() >= distance)
            );
        }
    }
    let request = PlanRequest {
        min_distance: 30.0,
        ..PlanRequest::new(30)
    };
    let error = plan_configurations(
        &robot,
        position.as_ref(),
        Samples::from(pool.as_slice()).as_slice(),
        &request,
        &robot.priority(),
        &mut Quiet,
    )
    .expect_err("too far apart");
    assert!(
        matches!(
            error,
            gecaro_calib::Error::InvalidOption {
                setting: gecaro_calib::Setting::MinDistance,
                ..
            }
        ),
        "{error}"
    );
    assert!(error.to_string().contains("minimum distance"), "{error}");
}

/// Measuring sessions per design and seed.
const SESSIONS: usize = 5;

/// Simulated real robots per design comparison.
const REAL_ROBOTS: u64 = 20;
/// Comparisons of [`REAL_ROBOTS`] the plan must win.
const WINS_NEEDED: usize = 15;

/// N planned configurations against N random ones from the same pool,
/// identified on simulated measurements and evaluated on held-out data of the
/// same method. Each of [`REAL_ROBOTS`] seeds draws a real robot (error
/// level 0.1) and a random design, and compares the designs' mean held-out
/// error over [`SESSIONS`] measuring sessions (independent noise, σ 0.1 mm):
/// one session's error varies by ±30 % with the noise drawn, which would
/// make a single comparison a coin toss biased by the design, not a test of
/// it. The plan must win at least [`WINS_NEEDED`] of them (a coin toss does
/// so with probability 2 %), and its mean error over them must be the
/// smaller.
///
/// (It was 9 of 10 real robots. The Panda's point-link plans win about 88 %
/// of the comparisons, as measured over six pools: at that rate 9 of 10
/// fails for one pool in three, and a change of the inverse model that only
/// drew another pool failed it, 8 of 10, with the plan's mean error 15 %
/// below the random designs'. 15 of 20 fails for one pool in forty.)
fn planned_beats_random(robot: &str, name: &str, count: usize, pool_size: usize) {
    let robot = ready(robot);
    let chosen = method(name, &MethodOptions::default()).expect("method");
    let pool = chosen
        .sensor()
        .generate(&robot, pool_size, 0.0, &mut Sampler::new(11), &mut Quiet)
        .expect("pool");
    let planned = plan(&robot, name, &pool, count);
    let held_out = chosen
        .sensor()
        .generate(&robot, 2 * count, 0.0, &mut Sampler::new(12), &mut Quiet)
        .expect("held out");
    let (mut wins, mut planned_sum, mut random_sum) = (0, 0.0, 0.0);
    for seed in 0..REAL_ROBOTS {
        let mut sampler = Sampler::new(100 + seed);
        let real = perturbed_robot(&robot, 0.1, &mut sampler).expect("real");
        let random = random_units(chosen.as_ref(), &pool, planned.chosen.len(), &mut sampler);
        let check = Study::single(
            chosen.clone_method(),
            simulate_at(
                &real,
                chosen.as_ref(),
                Samples::from(held_out.as_slice()).as_slice(),
                0.0,
                &mut sampler,
                &mut Quiet,
            )
            .expect("held out"),
            "held out",
        );
        let mut error = |design: &[Sample]| {
            let mut sum = 0.0;
            for _ in 0..SESSIONS {
                let data = simulate_at(
                    &real,
                    chosen.as_ref(),
                    Samples::from(design).as_slice(),
                    1e-4,
                    &mut sampler,
                    &mut Quiet,
                )
                .expect("measured");
                let study = Study::single(chosen.clone_method(), data, "design");
                let result = identify(
                    &robot,
                    &study,
                    &IdentificationOptions::default(),
                    &mut Quiet,
                )
                .expect("identified");
                sum += evaluate(&result.calibrated, &check).expect("evaluated").rms;
            }
            sum / SESSIONS as f64
        };
        let (planned_error, random_error) = (error(&planned.samples), error(&random));
        if planned_error < random_error {
            wins += 1;
        }
        planned_sum += planned_error;
        random_sum += random_error;
    }
    assert!(
        wins >= WINS_NEEDED && planned_sum < random_sum,
        "{name}: planned configurations won {wins} of {REAL_ROBOTS}, mean held-out error \
         {:.4} mm planned, {:.4} mm random",
        1e3 * planned_sum / REAL_ROBOTS as f64,
        1e3 * random_sum / REAL_ROBOTS as f64
    );
}

#[test]
fn planned_configurations_calibrate_the_stanford_arm_better_than_random_ones() {
    planned_beats_random("stanford", "position", 12, 600);
    planned_beats_random("stanford", "frame", 8, 400);
    planned_beats_random("stanford", "distance", 60, 600);
    planned_beats_random("stanford", "point-link", 40, 400);
}

#[test]
fn planned_configurations_calibrate_the_panda_better_than_random_ones() {
    planned_beats_random("panda", "position", 16, 600);
    planned_beats_random("panda", "frame", 9, 400);
    planned_beats_random("panda", "distance", 80, 800);
    planned_beats_random("panda", "point-link", 48, 480);
}

/// Planned configurations measured on a simulated real robot, for every
/// method: the configurations stay where they were planned (moved onto the
/// method's constraint only, for links and planes), and they identify the
/// robot.
#[test]
fn every_method_measures_at_planned_configurations_and_identifies() {
    let robot = ready("stanford");
    let options = MethodOptions {
        plane: Some(
            gecaro_calib::methods::Plane::new(
                nalgebra::Vector3::from(gecaro_calib::table2::TABLE2_PLANE_NORMAL),
                nalgebra::Vector3::from(gecaro_calib::table2::STANFORD_PLANE_POINT),
            )
            .expect("plane"),
        ),
        ..MethodOptions::default()
    };
    for (name, count) in [
        ("position", 30),
        ("frame", 20),
        ("point-link", 60),
        ("frame-link", 40),
        ("plane1", 90),
        ("plane2", 90),
        ("distance", 100),
    ] {
        let chosen = method(name, &options).expect("method");
        let pool = chosen
            .sensor()
            .generate(&robot, 6 * count, 0.0, &mut Sampler::new(4), &mut Quiet)
            .expect("pool");
        let planned = plan_with(&robot, chosen.as_ref(), &pool, &PlanRequest::new(count));
        let mut sampler = Sampler::new(9);
        let real = perturbed_robot(&robot, 0.1, &mut sampler).expect("real");
        let data = simulate_at(
            &real,
            chosen.as_ref(),
            Samples::from(planned.samples.as_slice()).as_slice(),
            1e-5,
            &mut sampler,
            &mut Quiet,
        )
        .expect("measured");
        assert_eq!(data.len(), planned.samples.len(), "{name}");
        // How far each configuration moved (largest joint change).
        let moves: Vec<f64> = data
            .iter()
            .zip(&planned.samples)
            .map(|(a, b)| {
                a.motor_positions
                    .iter()
                    .zip(&b.motor_positions)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        let constrained = chosen.name().contains("link") || chosen.name().starts_with("plane");
        if constrained {
            // Moved onto the constraint, nearby; a few near a singularity or a
            // limit are reached from another start.
            let near = moves.iter().filter(|m| **m < 0.1).count();
            assert!(
                near * 10 >= 9 * moves.len(),
                "{name}: {near} of {} nearby",
                moves.len()
            );
        } else {
            assert!(
                moves.iter().all(|m| *m == 0.0),
                "{name}: configurations moved"
            );
        }
        let study = Study::single(chosen.clone_method(), data, "planned");
        let result = identify(
            &robot,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identified");
        assert!(
            result.after.rms < 0.05 * result.before.rms,
            "{name}: {} → {}",
            result.before.rms,
            result.after.rms
        );
    }
}
