//! D-optimal planning: the plan beats random subsets of the same pool on the
//! D-criterion, and planned configurations calibrate better than random ones.

use std::ops::ControlFlow;

use gecaro_calib::{
    IdentificationOptions, MethodOptions, Sample, Sampler, Study, design_log_det, evaluate,
    identify, method, perturbed_robot, plan_d_optimal, random_samples, units,
};
use gecaro_core::{Robot, terminal_pose};
use gecaro_io::load_robot;

fn ready(name: &str) -> Robot {
    load_robot(name).expect("ready robot").robot
}

fn plan(robot: &Robot, name: &str, pool: &[Sample], count: usize) -> gecaro_calib::Plan {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    plan_d_optimal(
        robot,
        chosen.as_ref(),
        pool,
        count,
        &[],
        &robot.priority(),
        |_, _| ControlFlow::Continue(()),
    )
    .expect("a plan")
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
        let pool = random_samples(&robot, chosen.as_ref(), Some(400), 7).expect("pool");
        let planned = plan(&robot, name, &pool, count);
        assert_eq!(planned.samples.len(), count, "{name}");
        let again = plan(&robot, name, &pool, count);
        assert_eq!(planned.chosen, again.chosen, "{name}: deterministic");
        let log_det = design_log_det(
            &robot,
            chosen.as_ref(),
            &pool,
            &planned.samples,
            &robot.priority(),
        )
        .expect("D");
        assert!((log_det - planned.log_det).abs() < 1e-6 * log_det.abs().max(1.0));
        // The best of 100 random subsets of as many units.
        let pool_units = units(chosen.as_ref(), &pool);
        let mut sampler = Sampler::new(3);
        let mut best = f64::NEG_INFINITY;
        for _ in 0..100 {
            let subset: Vec<Sample> = sampler
                .subset(pool_units.len(), planned.chosen.len())
                .into_iter()
                .flat_map(|unit| pool_units[unit].iter().map(|index| pool[*index].clone()))
                .collect();
            let value = design_log_det(&robot, chosen.as_ref(), &pool, &subset, &robot.priority())
                .expect("D");
            best = best.max(value);
        }
        assert!(
            planned.log_det > best,
            "{name}: plan D = {} ≤ best random {best}",
            planned.log_det
        );
    }
}

/// Position measurements of `real` at the configurations of `samples`.
fn measured(real: &Robot, samples: &[Sample], noise: f64, sampler: &mut Sampler) -> Vec<Sample> {
    samples
        .iter()
        .map(|sample| {
            let mut sample = Sample::new(sample.motor_positions.clone());
            let point = terminal_pose(real, &sample.motor_positions)
                .expect("pose")
                .translation
                .vector;
            sample.position = Some(point + sampler.gaussian_vector(noise));
            sample
        })
        .collect()
}

#[test]
fn planned_configurations_calibrate_better_than_random_ones_in_nine_seeds_of_ten() {
    let robot = ready("stanford");
    let position = method("position", &MethodOptions::default()).expect("method");
    let pool = random_samples(&robot, position.as_ref(), Some(300), 11).expect("pool");
    let planned = plan(&robot, "position", &pool, 16);
    let held_out = random_samples(&robot, position.as_ref(), Some(200), 12).expect("held out");
    let mut wins = 0;
    for seed in 0..10 {
        let mut sampler = Sampler::new(100 + seed);
        let real = perturbed_robot(&robot, 0.3, &mut sampler).expect("real");
        let random: Vec<Sample> = (0..16)
            .map(|i| pool[(i * 17 + seed as usize * 7) % pool.len()].clone())
            .collect();
        let error = |design: &[Sample], sampler: &mut Sampler| {
            let data = measured(&real, design, 1e-4, sampler);
            let study = Study::single(position.clone_method(), data, "design");
            let result =
                identify(&robot, &study, &IdentificationOptions::default()).expect("identified");
            let check = Study::single(
                position.clone_method(),
                measured(&real, &held_out, 0.0, sampler),
                "held out",
            );
            evaluate(&result.calibrated, &check).expect("evaluated").rms
        };
        let (planned_error, random_error) = (
            error(&planned.samples, &mut sampler),
            error(&random, &mut sampler),
        );
        if planned_error < random_error {
            wins += 1;
        }
    }
    assert!(wins >= 9, "planned configurations won {wins} of 10");
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
            gecaro_calib::Plane::new(
                nalgebra::Vector3::from(gecaro_calib::TABLE2_PLANE_NORMAL),
                nalgebra::Vector3::from(gecaro_calib::STANFORD_PLANE_POINT),
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
            .generate(&robot, 6 * count, 0.0, &mut Sampler::new(4))
            .expect("pool");
        let planned = plan_d_optimal(
            &robot,
            chosen.as_ref(),
            &pool,
            count,
            &[],
            &robot.priority(),
            |_, _| ControlFlow::Continue(()),
        )
        .expect("plan");
        let mut sampler = Sampler::new(9);
        let real = perturbed_robot(&robot, 0.1, &mut sampler).expect("real");
        let data =
            gecaro_calib::simulate_at(&real, chosen.as_ref(), &planned.samples, 1e-5, &mut sampler)
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
        let result =
            identify(&robot, &study, &IdentificationOptions::default()).expect("identified");
        assert!(
            result.after.rms < 0.05 * result.before.rms,
            "{name}: {} → {}",
            result.before.rms,
            result.after.rms
        );
    }
}
