//! The verdict of an identification against simulated truth: a fit that
//! explains the data to the stated noise says so, one that does not says by
//! how much, and data or iterations that cannot give a solution are named.

use crate::util::{simulated, stanford};
use gecaro_calib::identification::Warning;
use gecaro_calib::study::Samples;
use gecaro_calib::{
    Quiet,
    identification::{IdentificationOptions, Outcome, Solver, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot},
    study::Study,
};

/// Position data of a Stanford arm with level-0.5 errors, noise σ = 0.02 mm.
fn study(method_name: &str, count: usize, stated: Option<f64>, seed: u64) -> Study {
    const NOISE: f64 = 2e-5;
    let chosen = method(method_name, &MethodOptions::default()).expect("method");
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&stanford(), 0.5, &mut sampler).expect("real");
    let samples = simulated(&real, chosen.as_ref(), count, NOISE, &mut sampler);
    let mut study = Study::single(chosen, samples, "simulated");
    study.sets[0].sigma = stated;
    study
}

fn fit(
    study: &Study,
    options: &IdentificationOptions,
) -> gecaro_calib::identification::Identification {
    identify(&stanford(), study, options, &mut Quiet).expect("identification")
}

#[test]
fn the_stated_noise_is_tested() {
    // The true σ: the test passes, σ̂/σ near 1, in 95 of 100 seeds at least
    // (the level is 1 %).
    let mut passed = 0;
    for seed in 0..20 {
        let result = fit(
            &study("position", 60, Some(2e-5), seed),
            &Default::default(),
        );
        let test = result.verdict.noise_test.expect("σ stated");
        assert!(
            (test.sigma_ratio - 1.0).abs() < 0.2,
            "σ̂/σ {}",
            test.sigma_ratio
        );
        if result.verdict.outcome == Outcome::FitsNoise {
            passed += 1;
            assert!(result.verdict.summary.contains("fit the stated noise"));
        }
    }
    assert!(passed >= 18, "the true σ passed {passed} of 20 times");
    // A σ five times too small: the test fails and says by how much.
    let result = fit(&study("frame", 40, Some(4e-6), 3), &Default::default());
    assert_eq!(result.verdict.outcome, Outcome::ExceedsNoise);
    let ratio = result.verdict.noise_test.expect("σ stated").sigma_ratio;
    assert!((ratio - 5.0).abs() < 1.0, "σ̂/σ {ratio}");
    assert!(!result.verdict.outcome.trusted());
    assert!(result.verdict.summary.contains("× the stated noise"));
    assert!(result.failure().is_none(), "a misfit is still a solution");
}

#[test]
fn a_sigma_good_to_a_few_per_cent_fits_at_tracker_rates() {
    // 20,000 positions (ν ≈ 60,000): the test alone resolves σ̂/σ to about
    // 1 %, finer than any datasheet states σ. Stated 2 % off either way, the
    // fit is trusted (before SIGMA_MARGIN: "below" / "exceeds the noise");
    // 10 % off, it is not, and the sentence says which way.
    const NOISE: f64 = 2e-5;
    let data = study("position", 20_000, None, 4);
    let judged = |stated: f64| {
        let mut data = data.clone();
        data.sets[0].sigma = Some(stated);
        fit(&data, &Default::default()).verdict
    };
    for factor in [0.98, 1.02] {
        let verdict = judged(NOISE * factor);
        assert_eq!(verdict.outcome, Outcome::FitsNoise, "{}", verdict.summary);
        let test = verdict.noise_test.expect("σ stated");
        assert!(test.passed && (test.sigma_ratio * factor - 1.0).abs() < 0.01);
    }
    let overstated = judged(NOISE * 1.1);
    assert_eq!(
        overstated.outcome,
        Outcome::BelowNoise,
        "{}",
        overstated.summary
    );
    let understated = judged(NOISE * 0.9);
    assert_eq!(
        understated.outcome,
        Outcome::ExceedsNoise,
        "{}",
        understated.summary
    );
    assert!(!overstated.outcome.trusted() && !understated.outcome.trusted());
}

/// What [`SIGMA_MARGIN`] lets through, judged on held-out poses: a model
/// error the geometric model cannot represent (a smooth error of the joint
/// angles, such as a gear's eccentricity) hides under the margin only while
/// it is below σ·√((1 + margin)² − 1) = 0.32 σ a coordinate, and the
/// calibrated robot is then that close to the real one; at 0.5 σ the
/// global test names it.
///
/// [`SIGMA_MARGIN`]: gecaro_calib::identification::SIGMA_MARGIN
#[test]
fn the_sigma_margin_hides_only_a_model_error_below_a_third_of_sigma() {
    use gecaro_calib::identification::SIGMA_MARGIN;
    use gecaro_calib::simulation::held_out_configurations;
    use gecaro_core::terminal_pose;
    const NOISE: f64 = 2e-5;
    let chosen = method("position", &MethodOptions::default()).expect("method");
    let mut sampler = Sampler::new(9);
    let real = perturbed_robot(&stanford(), 0.5, &mut sampler).expect("real");
    let clean = simulated(&real, chosen.as_ref(), 5000, 0.0, &mut sampler);
    let noise: Vec<_> = (0..clean.len())
        .map(|_| sampler.gaussian_vector(NOISE))
        .collect();
    // The unmodelled error at motor positions q, RMS `size` σ a coordinate
    // over the workspace (each term's mean square is 1/2).
    let unmodelled = |q: &[f64], size: f64| {
        size * NOISE
            * std::f64::consts::SQRT_2
            * nalgebra::Vector3::new((3.0 * q[0]).sin(), (2.0 * q[1]).cos(), (q[0] + q[3]).sin())
    };
    let held_out = held_out_configurations(&real, 300, &mut sampler);
    let judged = |size: f64| {
        let mut rows = clean.clone();
        for (row, noise) in rows.iter_mut().zip(&noise) {
            let error = unmodelled(&row.motor_positions, size);
            row.position = row.position.map(|position| position + error + noise);
        }
        let mut study = Study::single(
            method("position", &MethodOptions::default()).expect("method"),
            rows.into_iter().collect::<Samples>(),
            "simulated",
        );
        study.sets[0].sigma = Some(NOISE);
        let result = fit(&study, &Default::default());
        // Held out: the calibrated robot against the real one with its
        // unmodelled error, RMS a coordinate, in units of σ.
        let squares: f64 = held_out
            .iter()
            .map(|q| {
                let truth =
                    terminal_pose(&real, q).expect("real").translation.vector + unmodelled(q, size);
                let predicted = terminal_pose(&result.calibrated, q)
                    .expect("calibrated")
                    .translation
                    .vector;
                (predicted - truth).norm_squared()
            })
            .sum();
        let held_out_rms = (squares / (3.0 * held_out.len() as f64)).sqrt() / NOISE;
        (result.verdict, held_out_rms)
    };
    let hidden = 0.25;
    let (verdict, held_out_rms) = judged(hidden);
    let test = verdict.noise_test.expect("σ stated");
    assert_eq!(verdict.outcome, Outcome::FitsNoise, "{}", verdict.summary);
    // The bare test (no margin) would have seen it.
    assert!(
        test.chi_square > test.critical / (1.0 + SIGMA_MARGIN).powi(2),
        "σ̂/σ {}",
        test.sigma_ratio
    );
    let bound = ((1.0 + SIGMA_MARGIN).powi(2) - 1.0).sqrt();
    assert!(
        held_out_rms < bound,
        "held out {held_out_rms} σ a coordinate, above the margin's {bound} σ"
    );
    assert!(held_out_rms > 0.5 * hidden, "held out {held_out_rms} σ");
    let (verdict, _) = judged(0.5);
    assert_eq!(
        verdict.outcome,
        Outcome::ExceedsNoise,
        "{}",
        verdict.summary
    );
}

#[test]
fn without_a_sigma_the_residual_is_reported_in_units() {
    let result = fit(&study("frame", 40, None, 4), &Default::default());
    let verdict = &result.verdict;
    assert_eq!(verdict.outcome, Outcome::Untested);
    assert!(verdict.noise_test.is_none());
    // Lengths and angles both carry the simulated noise (2e-5 m and rad).
    for sigma in [verdict.residual_length, verdict.residual_angle] {
        let sigma = sigma.expect("both kinds of rows");
        assert!((sigma / 2e-5 - 1.0).abs() < 0.25, "residual σ {sigma}");
    }
    assert!(
        verdict.summary.contains("no σ was stated"),
        "{}",
        verdict.summary
    );
    assert!(verdict.summary.contains(" mm") && verdict.summary.contains('°'));
}

#[test]
fn copies_of_one_configuration_are_degenerate_data() {
    let mut copies = study("position", 1, None, 5);
    let one = copies.sets[0].samples.get(0).to_sample();
    copies.sets[0].samples = vec![one; 200].into();
    // The excitation check keeps the 3 unknowns one point determines, and
    // the residual goes to 0: the verdict names the data, not a "0 mm" fit.
    let result = fit(&copies, &Default::default());
    assert_eq!(result.verdict.outcome, Outcome::Degenerate);
    assert_eq!(result.verdict.distinct_configurations, 1);
    assert_eq!(result.verdict.configurations, 200);
    assert!(result.failure().is_some());
    assert!(
        result
            .verdict
            .summary
            .contains("1 distinct configuration of 200"),
        "{}",
        result.verdict.summary
    );
}

#[test]
fn an_iteration_limit_is_not_convergence() {
    // Levenberg–Marquardt has no second route to take after the limit.
    let options = IdentificationOptions {
        max_iterations: 1,
        solver: Solver::LevenbergMarquardt,
        ..Default::default()
    };
    let result = fit(&study("position", 60, Some(2e-5), 6), &options);
    assert_eq!(result.verdict.outcome, Outcome::NotConverged);
    assert!(result.verdict.summary.starts_with("not converged"));
    assert!(result.failure().is_some());
}

#[test]
fn regrouped_parameters_say_what_they_stand_for() {
    let result = fit(&study("point-link", 80, None, 7), &Default::default());
    let relations = result.rank.relations();
    let mut regrouped = 0;
    for parameter in &result.parameters {
        match relations.iter().find(|r| r.base == parameter.name) {
            Some(relation) if !relation.absorbed.is_empty() => {
                regrouped += 1;
                assert!(parameter.is_regrouped());
                let combination = parameter.combination().expect("a combination");
                assert!(combination.starts_with(&parameter.name), "{combination}");
                for (name, _) in &relation.absorbed {
                    assert!(
                        combination.contains(name.as_str()),
                        "{combination} lacks {name}"
                    );
                }
            }
            _ => {
                assert!(!parameter.is_regrouped(), "{}", parameter.name);
                assert!(parameter.combination().is_none());
            }
        }
    }
    assert!(
        regrouped > 0,
        "the Stanford's point link regroups parameters"
    );
}

#[test]
fn a_measurement_frame_two_metres_away_converges_to_the_noise_floor() {
    // The tracker stands 2 m from where the robot file says, turned 90°
    // about z, and the reflector sits off the nominal tool point: the
    // closed-form start (Horn/Kabsch) puts the iterations where the paper's
    // linearisation holds, and both solvers reach the floor.
    let nominal = stanford();
    let moved = nalgebra::IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(2.0, 0.0, 0.4),
        nalgebra::Rotation3::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
    );
    let reflector = nalgebra::IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(0.04, 0.025, 0.09),
        nalgebra::Rotation3::identity(),
    );
    let mut sampler = Sampler::new(2);
    let far = perturbed_robot(&nominal, 0.3, &mut sampler)
        .expect("real")
        .reframed(&moved, &reflector)
        .expect("reframed");
    // Every method that identifies the base: position and frame measure.
    for name in ["position", "frame"] {
        let measured = method(name, &MethodOptions::default()).expect("method");
        let mut measure = |count| {
            let samples = simulated(&far, measured.as_ref(), count, 1e-5, &mut sampler);
            Study::single(measured.clone_method(), samples, "far")
        };
        let (train, check) = (measure(100), measure(100));
        let floor = gecaro_calib::identification::evaluate(&far, &check)
            .expect("floor")
            .rms;
        for solver in [Solver::GaussNewton, Solver::LevenbergMarquardt] {
            let options = IdentificationOptions {
                solver,
                ..Default::default()
            };
            let result = fit(&train, &options);
            assert!(
                result.verdict.outcome.trusted(),
                "{}",
                result.verdict.summary
            );
            assert!(
                result
                    .warnings
                    .iter()
                    .any(|w| matches!(w, Warning::ClosedFormStart { .. }))
            );
            let held_out = gecaro_calib::identification::evaluate(&result.calibrated, &check)
                .expect("held out")
                .rms;
            assert!(
                held_out < 1.2 * floor,
                "{name}, {solver:?}: {held_out} vs floor {floor}"
            );
        }
    }
}

#[test]
fn a_gain_thirty_percent_off_is_implausible() {
    // A wrong gear ratio in the robot file: the data determine K3 well, and
    // no real robot has a gain 30 % off its nominal.
    let nominal = stanford();
    let mut real = nominal.clone();
    let k3 = gecaro_core::ParameterId::new(gecaro_core::ParameterKind::Gain, 3);
    real.set_parameter(k3, 1.3).expect("gain");
    let position = method("position", &MethodOptions::default()).expect("method");
    let samples = simulated(&real, position.as_ref(), 60, 1e-5, &mut Sampler::new(3));
    let result = fit(
        &Study::single(position, samples, "gears"),
        &Default::default(),
    );
    assert_eq!(
        result.verdict.outcome,
        Outcome::Implausible,
        "{}",
        result.verdict.summary
    );
    let named = &result.verdict.implausible;
    assert!(
        named
            .iter()
            .any(|p| p.name == "K3" && p.why.contains("+30.0 %")),
        "{named:?}"
    );
}

#[test]
fn strongly_correlated_pairs_are_named_and_agree_with_repeated_measurements() {
    // The Stanford's z0 and z1 are 0.1 rad apart: r0 and r1 slide along
    // nearly the same line. The reported ρ(r0, r1) is checked against the
    // spread of 40 identifications from fresh noise at the same
    // configurations (an independent route to the same number).
    use gecaro_calib::simulation::simulate_at;
    let nominal = stanford();
    let position = method("position", &MethodOptions::default()).expect("method");
    let mut sampler = Sampler::new(11);
    let real = perturbed_robot(&nominal, 0.3, &mut sampler).expect("real");
    let planned = simulated(&nominal, position.as_ref(), 60, 0.0, &mut sampler);
    let identify_once = |sampler: &mut Sampler| {
        let samples = simulate_at(
            &real,
            position.as_ref(),
            Samples::from(planned.as_slice()).as_slice(),
            1e-5,
            sampler,
            &mut Quiet,
        )
        .expect("data");
        fit(
            &Study::single(position.clone_method(), samples, "repeated"),
            &Default::default(),
        )
    };
    let reported = identify_once(&mut sampler);
    let rho = reported
        .correlated
        .iter()
        .find(|(a, b, _)| (a == "r0" && b == "r1") || (a == "r1" && b == "r0"))
        .map(|(_, _, rho)| *rho)
        .expect("r0 and r1 named as correlated");
    assert!(rho < -0.95, "ρ {rho}");
    assert!(
        reported
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::Correlated(_)))
    );
    let value = |result: &gecaro_calib::identification::Identification, name: &str| {
        result
            .parameters
            .iter()
            .find(|p| p.name == name)
            .expect("identified")
            .identified
    };
    let runs: Vec<(f64, f64)> = (0..40)
        .map(|_| {
            let result = identify_once(&mut sampler);
            (value(&result, "r0"), value(&result, "r1"))
        })
        .collect();
    let mean = |f: &dyn Fn(&(f64, f64)) -> f64| runs.iter().map(f).sum::<f64>() / runs.len() as f64;
    let (m0, m1) = (mean(&|r| r.0), mean(&|r| r.1));
    let covariance = mean(&|r| (r.0 - m0) * (r.1 - m1));
    let (v0, v1) = (mean(&|r| (r.0 - m0).powi(2)), mean(&|r| (r.1 - m1).powi(2)));
    let sampled = covariance / (v0 * v1).sqrt();
    assert!(
        (sampled - rho).abs() < 0.03,
        "reported {rho}, sampled {sampled}"
    );
}

/// A link or plane calibration of `robot` at error level `level` (σ 0.01 mm
/// stated), with `pairs` distance pairs beside it; then the nominal and the
/// calibrated robot judged against the real one on 300 held-out
/// configurations (registered tool points).
fn judged(
    robot: &str,
    name: &str,
    level: f64,
    seed: u64,
    pairs: usize,
) -> (
    gecaro_calib::identification::Identification,
    gecaro_calib::simulation::Judgement,
    gecaro_calib::simulation::Judgement,
) {
    use gecaro_calib::simulation::{held_out_configurations, judge};
    const NOISE: f64 = 1e-5;
    let nominal = gecaro_io::load_robot(robot).expect("ready robot").robot;
    let options = MethodOptions {
        plane: name
            .starts_with("plane")
            .then(|| gecaro_calib::table2::default_plane(&nominal).expect("plane")),
        ..MethodOptions::default()
    };
    let chosen = method(name, &options).expect("method");
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&nominal, level, &mut sampler).expect("real");
    let count = if name.starts_with("plane") { 120 } else { 80 };
    let samples = simulated(&real, chosen.as_ref(), count, NOISE, &mut sampler);
    let mut study = Study::single(chosen, samples, "simulated");
    if pairs > 0 {
        let distance = method("distance", &MethodOptions::default()).expect("method");
        let samples = simulated(&real, distance.as_ref(), 2 * pairs, NOISE, &mut sampler);
        study
            .sets
            .append(&mut Study::single(distance, samples, "pairs").sets);
    }
    for set in &mut study.sets {
        set.sigma = Some(NOISE);
    }
    let result = identify(
        &nominal,
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("identification");
    let held_out = held_out_configurations(&real, 300, &mut sampler);
    let before = judge(&nominal, &real, &held_out).expect("judge");
    let after = judge(&result.calibrated, &real, &held_out).expect("judge");
    (result, before, after)
}

#[test]
fn link_and_plane_calibrations_keep_the_most_likely_scale_and_say_it_is_not_measured() {
    // Before: the paper's base set put the scale where a short length held
    // at nominal put it, 24 of 24 such runs worse than the nominal robot
    // (PUMA 560 point link at level 1: 143 and 308 mm against 29 mm).
    for robot in ["puma560", "industrial6"] {
        for name in ["point-link", "plane2", "frame-link"] {
            for seed in [1, 2] {
                let (result, nominal, calibrated) = judged(robot, name, 1.0, seed, 0);
                let case = format!("{robot} {name} seed {seed}");
                // Judged against the real robot, far better than the nominal
                // one (frame link: the tool is not observed).
                let gain = if name == "frame-link" { 1.5 } else { 2.5 };
                assert!(
                    calibrated.rms * gain < nominal.rms,
                    "{case}: {} mm held out against {} mm nominal",
                    calibrated.rms * 1e3,
                    nominal.rms * 1e3
                );
                // The size is the nominal robot's within the lengths' own
                // errors (±1 cm at level 1).
                assert!(
                    (calibrated.scale - 1.0).abs() < 0.02,
                    "{case}: {}",
                    calibrated.scale
                );
                // Never trusted; the verdict says what is missing.
                let verdict = &result.verdict;
                assert!(!verdict.outcome.trusted(), "{case}: {}", verdict.summary);
                assert!(verdict.summary.contains("scale is not measured"), "{case}");
                let scale = verdict.coverage.scale.expect("an unobserved scale");
                assert!(scale.std > 0.0 && scale.std < 0.03, "{case}: {scale:?}");
                assert_eq!(
                    verdict.coverage.tool_observed,
                    name != "frame-link",
                    "{case}"
                );
                if verdict.outcome != Outcome::Incomplete {
                    assert!(
                        matches!(verdict.outcome, Outcome::ExceedsNoise | Outcome::BelowNoise),
                        "{case}: {}",
                        verdict.summary
                    );
                }
            }
        }
    }
}

#[test]
fn honest_point_link_data_pass_the_noise_test() {
    // The true σ stated, level 0.3: before, 8 of 10 seeds were rejected
    // (the paper's base set, no second pass). The test's level is 1 % per
    // side; at most 1 in 10 may fail.
    let mut alarms = Vec::new();
    for seed in 1..=10 {
        let (result, _, _) = judged("puma560", "point-link", 0.3, seed, 0);
        let test = result.verdict.noise_test.expect("σ stated");
        if !test.passed {
            alarms.push((seed, test.sigma_ratio));
        }
    }
    assert!(alarms.len() <= 1, "{alarms:?}");
}

#[test]
fn point_link_with_ten_distance_pairs_reaches_the_noise_floor() {
    // Ten pairs measure the scale: the study is trusted when it fits, and
    // held out it comes near the floor (√(3σ² + RMS²)/√3σ; before: 5.8–18×).
    const NOISE: f64 = 1e-5;
    let mut ratios = Vec::new();
    for robot in ["puma560", "industrial6"] {
        for seed in [1, 3, 5] {
            let (result, _, calibrated) = judged(robot, "point-link", 1.0, seed, 10);
            let floor = 3.0 * NOISE * NOISE;
            let ratio = ((floor + calibrated.rms.powi(2)) / floor).sqrt();
            assert!((calibrated.scale - 1.0).abs() < 1e-3, "{robot} {seed}");
            assert!(result.verdict.coverage.scale.is_none());
            assert_eq!(
                result.verdict.outcome.trusted(),
                result.verdict.noise_test.expect("σ stated").passed,
                "{robot} {seed}: {}",
                result.verdict.summary
            );
            ratios.push(ratio);
        }
    }
    // The target is 1.5; over 20 seeds the median is 1.14 and one run
    // in 20 is at 1.56 (the estimate's variance: docs/methods.md).
    ratios.sort_by(f64::total_cmp);
    assert!(ratios[ratios.len() / 2] < 1.25, "{ratios:?}");
    assert!(ratios[ratios.len() - 1] < 1.5, "{ratios:?}");
}

#[test]
fn a_levelled_tracker_is_not_a_singular_measurement_frame() {
    // A tracker 3.8 m away whose z axis is 0.033° from the Panda's axis 1:
    // before, r0 = +821 m and r1 = −821 m (condition number 1e9) with
    // Gauss–Newton, the iteration limit with Levenberg–Marquardt, both
    // "fitting the noise".
    use gecaro_calib::identification::StopReason;
    use gecaro_calib::simulation::{held_out_configurations, judge};
    use gecaro_core::{ParameterId, ParameterKind};
    use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};
    const NOISE: f64 = 1e-5;
    let nominal = gecaro_io::load_robot("panda").expect("panda").robot;
    let tracker = IsometryMatrix3::from_parts(
        Translation3::new(3.84, 0.3, -0.5),
        Rotation3::from_axis_angle(&Vector3::z_axis(), 40_f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::x_axis(), 0.033_f64.to_radians()),
    );
    let in_tracker = nominal
        .reframed(&tracker, &IsometryMatrix3::identity())
        .expect("reframed");
    let position = method("position", &MethodOptions::default()).expect("method");
    for seed in 1..=3 {
        let mut sampler = Sampler::new(seed);
        let real = perturbed_robot(&in_tracker, 1.0, &mut sampler).expect("real");
        let samples = simulated(&real, position.as_ref(), 60, NOISE, &mut sampler);
        let mut study = Study::single(position.clone_method(), samples, "tracker");
        study.sets[0].sigma = Some(NOISE);
        let held_out = held_out_configurations(&real, 300, &mut sampler);
        for solver in [Solver::GaussNewton, Solver::LevenbergMarquardt] {
            let options = IdentificationOptions {
                solver,
                ..IdentificationOptions::default()
            };
            let result = identify(&nominal, &study, &options, &mut Quiet).expect("identify");
            let case = format!("seed {seed}, {solver:?}");
            assert_eq!(result.stop_reason, StopReason::Converged, "{case}");
            assert!(
                result.condition_number < 1e5,
                "{case}: κ {}",
                result.condition_number
            );
            for frame in [0, 1] {
                let r = result.calibrated.parameter(ParameterId {
                    frame,
                    kind: ParameterKind::R,
                });
                assert!(r.abs() < 1.0, "{case}: r{frame} = {r} m");
            }
            assert!(
                result.verdict.outcome.trusted(),
                "{case}: {}",
                result.verdict.summary
            );
            let error = judge(&result.calibrated, &real, &held_out).expect("judge");
            assert!(
                error.rms < 3.0 * NOISE,
                "{case}: {} mm held out",
                error.rms * 1e3
            );
        }
    }
}

/// Rows pasted again and a file named twice in a study: the copies are
/// named and the result is not trusted, although the fit "fits the noise"
/// (40 rows pasted 100 times gave σ 11.6× too small, trusted).
#[test]
fn exact_copies_are_named_and_not_trusted() {
    let honest = fit(&study("position", 40, Some(2e-5), 6), &Default::default());
    assert_eq!(honest.verdict.copies, 0);
    assert!(
        honest.verdict.outcome.trusted(),
        "{}",
        honest.verdict.summary
    );
    let mut pasted = study("position", 40, Some(2e-5), 6);
    let rows = pasted.sets[0].samples.clone();
    pasted.sets[0].samples = rows
        .iter()
        .cycle()
        .take(40 * 100)
        .map(|sample| sample.to_sample())
        .collect();
    let result = fit(&pasted, &Default::default());
    assert_eq!(result.verdict.outcome, Outcome::Repeated);
    assert_eq!(result.verdict.copies, 3960);
    assert!(!result.verdict.outcome.trusted());
    assert!(
        result
            .verdict
            .summary
            .contains("3960 of the 4000 measurements are exact copies"),
        "{}",
        result.verdict.summary
    );
    // The same file twice in a study.
    let mut twice = study("position", 40, Some(2e-5), 6);
    let again = twice.sets[0].clone();
    twice.sets.push(again);
    let result = fit(&twice, &Default::default());
    assert_eq!(result.verdict.outcome, Outcome::Repeated);
    assert_eq!(result.verdict.copies, 40);
}

/// A repeatability study, the same 40 configurations measured 25 times
/// with fresh noise added: 40 distinct configurations and no copies. Pasting two
/// of its rows again (one with a position written as −0 where the other
/// has 0) makes two copies, whatever the order of the rows.
#[test]
fn repeated_poses_measured_again_are_not_copies() {
    let poses = study("position", 40, Some(2e-5), 7);
    let mut sampler = Sampler::new(8);
    let mut rows: Vec<_> = poses.sets[0]
        .samples
        .iter()
        .cycle()
        .take(40 * 25)
        .map(|sample| {
            let mut row = sample.to_sample();
            let noise = sampler.gaussian_vector(2e-5);
            row.position = row.position.map(|position| position + noise);
            row
        })
        .collect();
    let mut repeated = poses.clone();
    repeated.sets[0].samples = rows.iter().cloned().collect();
    let result = fit(&repeated, &Default::default());
    assert_eq!(result.verdict.distinct_configurations, 40);
    assert_eq!(result.verdict.copies, 0);
    // (The rows share the first draw's noise as well: their residuals
    // exceed the stated σ, which is the global test's business.)
    assert_ne!(result.verdict.outcome, Outcome::Repeated);
    // Rows 3 and 500 again, at the front and at the back; the second with
    // a zero coordinate, written once as 0 and once as −0.
    rows[500].position.as_mut().expect("position").x = 0.0;
    let mut negative = rows[500].clone();
    negative.position.as_mut().expect("position").x = -0.0;
    rows.insert(0, rows[3].clone());
    rows.push(negative);
    repeated.sets[0].samples = rows.into_iter().collect();
    let result = fit(&repeated, &Default::default());
    assert_eq!(result.verdict.distinct_configurations, 40);
    assert_eq!(result.verdict.copies, 2);
    assert_eq!(result.verdict.outcome, Outcome::Repeated);
}

/// A robust loss weighs the fit, not the test: with a scale below the
/// residuals' spread (`huber 0.5`, `cauchy 0.5`) a σ stated 1.7× too small
/// fails the global test, the true σ passes it with any loss, and without a
/// σ the residual σ is the noise's (it was 1e-150 mm).
#[test]
fn a_robust_loss_weighs_the_fit_not_the_test() {
    use gecaro_calib::identification::{Loss, LossKind};
    const NOISE: f64 = 2e-5;
    let losses = [
        Loss::with_scale(LossKind::Huber, 0.5).expect("loss"),
        Loss::with_scale(LossKind::Cauchy, 0.5).expect("loss"),
        Loss::new(LossKind::Huber),
        Loss::new(LossKind::Tukey),
    ];
    for loss in losses {
        let options = IdentificationOptions {
            loss,
            ..IdentificationOptions::default()
        };
        let mut fits = 0;
        for seed in 0..5 {
            let data = study("position", 60, Some(NOISE), seed);
            let honest = fit(&data, &options).verdict;
            fits += usize::from(honest.outcome == Outcome::FitsNoise);
            let mut understated = data.clone();
            understated.sets[0].sigma = Some(NOISE / 1.7);
            let verdict = fit(&understated, &options).verdict;
            assert_eq!(
                verdict.outcome,
                Outcome::ExceedsNoise,
                "{loss:?}: {}",
                verdict.summary
            );
            let ratio = verdict.noise_test.expect("σ stated").sigma_ratio;
            assert!((ratio / 1.7 - 1.0).abs() < 0.25, "{loss:?}: σ̂/σ {ratio}");
            let mut unstated = data.clone();
            unstated.sets[0].sigma = None;
            let result = fit(&unstated, &options);
            let residual = result.verdict.residual_length.expect("lengths");
            assert!(
                (residual / NOISE - 1.0).abs() < 0.25,
                "{loss:?}: residual σ {residual}"
            );
            // A scale that weighs most observations down is named.
            let named = result
                .warnings
                .iter()
                .any(|w| matches!(w, Warning::LossScale(_)));
            assert_eq!(named, loss.scale < 1.0, "{loss:?}: {:?}", result.warnings);
        }
        assert!(fits >= 4, "{loss:?}: the true σ passed {fits} of 5 times");
    }
}

/// Repeated poses measure the noise: a σ stated twice too large (a
/// datasheet's) hides a model error of √3 σ from the stated-σ test, not from
/// the lack-of-fit test against the repeats; honest data with repeats fit,
/// whatever σ is stated.
#[test]
fn repeated_poses_measure_the_noise_and_judge_the_fit() {
    use gecaro_calib::simulation::simulate_at;
    use gecaro_calib::study::Sample;
    use nalgebra::Vector3;
    const NOISE: f64 = 2e-5;
    let nominal = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let position = method("position", &MethodOptions::default()).expect("method");
    // An error no geometric model holds, smooth in the joints, √3 σ a
    // coordinate in RMS (each term's mean square is 1/2).
    let unmodelled = |q: &[f64], size: f64| {
        let amplitude = size * 2.0_f64.sqrt();
        Vector3::new(
            amplitude * (2.0 * q[1] + q[2]).sin(),
            amplitude * (q[0] - 3.0 * q[2]).cos(),
            amplitude * (2.0 * q[3] + q[1]).sin(),
        )
    };
    let mut fits_with_repeats = 0;
    for seed in 0..8 {
        let mut sampler = Sampler::new(40 + seed);
        let real = perturbed_robot(&nominal, 0.5, &mut sampler).expect("real");
        // 90 poses, and 12 poses measured 3 times each (the encoders'
        // jitter of a commanded pose: 1 µrad).
        let mut configurations: Vec<Vec<f64>> =
            (0..90).map(|_| sampler.configuration(&nominal)).collect();
        for _ in 0..12 {
            let pose = sampler.configuration(&nominal);
            for _ in 0..3 {
                configurations.push(pose.iter().map(|q| q + sampler.gaussian(1e-6)).collect());
            }
        }
        let planned: Samples = configurations
            .iter()
            .map(|q| Sample::new(q.clone()))
            .collect();
        let clean = simulate_at(
            &real,
            position.as_ref(),
            planned.as_slice(),
            NOISE,
            &mut sampler,
            &mut Quiet,
        )
        .expect("measured");
        let with_error = |size: f64| {
            let samples: Vec<Sample> = clean
                .iter()
                .zip(&configurations)
                .map(|(sample, q)| {
                    let mut sample = sample.clone();
                    sample.position = sample.position.map(|p| p + unmodelled(q, size));
                    sample
                })
                .collect();
            let mut study = Study::single(position.clone_method(), samples, "repeats.csv");
            study.sets[0].sigma = Some(2.0 * NOISE);
            study
        };
        // The model error hidden by a σ stated 2× too large: the repeats see it.
        let fitted = |study: &Study| {
            identify(
                &nominal,
                study,
                &IdentificationOptions::default(),
                &mut Quiet,
            )
            .expect("identified")
            .verdict
        };
        let hidden = fitted(&with_error(3.0_f64.sqrt() * NOISE));
        let repeats = hidden.repeatability.as_ref().expect("repeated poses");
        assert_eq!(repeats.poses, 12);
        assert_eq!(repeats.degrees_of_freedom, 72);
        assert!(!repeats.passed(), "seed {seed}: {}", hidden.summary);
        assert_eq!(hidden.outcome, Outcome::ExceedsNoise, "{}", hidden.summary);
        assert!(
            hidden.summary.contains("repeated poses measure"),
            "{}",
            hidden.summary
        );
        // Honest data, σ stated 2× too large: the repeats say the fit is
        // at the noise, and that the stated σ is twice it.
        let honest = fitted(&with_error(0.0));
        let measured = honest
            .repeatability
            .as_ref()
            .expect("repeated poses")
            .sigma_ratio;
        assert!(
            (measured - 0.5).abs() < 0.15,
            "seed {seed}: σ_pe {measured}× the stated"
        );
        if honest.outcome == Outcome::FitsNoise {
            fits_with_repeats += 1;
            assert!(honest.summary.contains("× that"), "{}", honest.summary);
        }
    }
    assert!(
        fits_with_repeats >= 7,
        "{fits_with_repeats} of 8 honest fits passed"
    );
}

/// A tool stated half a turn off about the flange's axis, with frame data:
/// the closed-form start registers the tool's rotation as well as its
/// point, and the fit reaches the noise (before: 34,439× the noise, K6 off
/// by 82 %, "implausible").
#[test]
fn a_tool_stated_half_a_turn_off_is_found_by_the_start() {
    use gecaro_core::{ParameterId, ParameterKind};
    const NOISE: f64 = 2e-5;
    let nominal = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let frame = method("frame", &MethodOptions::default()).expect("method");
    for seed in [1, 2, 3] {
        let mut sampler = Sampler::new(seed);
        let mut real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let theta7 = ParameterId::new(ParameterKind::Theta, 7);
        real.set_parameter(theta7, real.parameter(theta7) + std::f64::consts::PI)
            .expect("turned");
        let samples = simulated(&real, frame.as_ref(), 60, NOISE, &mut sampler);
        let mut study = Study::single(frame.clone_method(), samples, "tool180.csv");
        study.sets[0].sigma = Some(NOISE);
        let result = identify(
            &nominal,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identified");
        assert_eq!(
            result.verdict.outcome,
            Outcome::FitsNoise,
            "seed {seed}: {}",
            result.verdict.summary
        );
        assert!(
            result
                .warnings
                .iter()
                .any(|w| matches!(w, Warning::ClosedFormStart { .. })),
            "{:?}",
            result.warnings
        );
    }
}

/// The closed-form start honours the priority matrix: a tool the user holds
/// (frame 7 at priority 0) stays where the robot file states it while the
/// start registers a measurement frame 2 m away (before, the start moved
/// the tool point by the noise, "0.555 mm, NaN° from the robot file's").
#[test]
fn the_start_leaves_what_the_priority_matrix_holds() {
    use gecaro_core::{ParameterId, ParameterKind};
    let nominal = stanford();
    let moved = nalgebra::IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(2.0, 0.0, 0.4),
        nalgebra::Rotation3::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
    );
    let mut sampler = Sampler::new(6);
    let far = perturbed_robot(&nominal, 0.3, &mut sampler)
        .expect("real")
        .reframed(&moved, &nalgebra::IsometryMatrix3::identity())
        .expect("reframed");
    // The real tool is the nominal's.
    let mut real = far.clone();
    for kind in [
        ParameterKind::Alpha,
        ParameterKind::D,
        ParameterKind::Theta,
        ParameterKind::R,
        ParameterKind::Beta,
    ] {
        let id = ParameterId::new(kind, 7);
        real.set_parameter(id, nominal.parameter(id)).expect("tool");
    }
    let position = method("position", &MethodOptions::default()).expect("method");
    let samples = simulated(&real, position.as_ref(), 100, 1e-5, &mut sampler);
    let study = Study::single(position, samples, "far");
    let mut priority = nominal.priority();
    for kind in [
        ParameterKind::Alpha,
        ParameterKind::D,
        ParameterKind::Theta,
        ParameterKind::R,
        ParameterKind::Beta,
    ] {
        priority.set(ParameterId::new(kind, 7), 0);
    }
    let options = IdentificationOptions {
        priority: Some(priority),
        ..IdentificationOptions::default()
    };
    let result = fit(&study, &options);
    assert!(
        result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::ClosedFormStart { .. })),
        "{:?}",
        result.warnings
    );
    for kind in [
        ParameterKind::Alpha,
        ParameterKind::D,
        ParameterKind::Theta,
        ParameterKind::R,
    ] {
        let id = ParameterId::new(kind, 7);
        assert_eq!(
            result.calibrated.parameter(id),
            nominal.parameter(id),
            "{id}"
        );
    }
}

/// A tool point 0.4 mm off axis 6, frame data: θ6 and θ7 are one direction
/// of the data (ρ = −1.000). Where their split is known to no better than
/// 1°, θ7 is held at its stated value and θ6 carries their sum, so no split
/// drifts into "implausible"; every fit is trusted.
#[test]
fn a_split_the_data_cannot_make_is_held() {
    use gecaro_core::{ParameterId, ParameterKind};
    const NOISE: f64 = 2e-5;
    let mut nominal = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let d7 = ParameterId::new(ParameterKind::D, 7);
    let theta7 = ParameterId::new(ParameterKind::Theta, 7);
    nominal.set_parameter(d7, 4e-4).expect("d7");
    let frame = method("frame", &MethodOptions::default()).expect("method");
    let mut held = 0;
    for seed in 1..=6 {
        let mut sampler = Sampler::new(seed);
        let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let samples = simulated(&real, frame.as_ref(), 60, NOISE, &mut sampler);
        let mut study = Study::single(frame.clone_method(), samples, "flange.csv");
        study.sets[0].sigma = Some(NOISE);
        study.sets[0].sigma_rotation = Some(NOISE);
        let result = identify(
            &nominal,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identified");
        assert!(
            result.verdict.outcome.trusted(),
            "seed {seed}: {}",
            result.verdict.summary
        );
        if result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::SplitHeld(_)))
        {
            held += 1;
            assert_eq!(
                result.calibrated.parameter(theta7),
                nominal.parameter(theta7)
            );
        } else {
            let split = result.parameters.iter().find(|p| p.name == "theta7");
            assert!(
                split.is_none_or(|p| p.std <= 0.0175),
                "seed {seed}: {split:?}"
            );
        }
    }
    assert!(held >= 1, "no seed held the split");
}
