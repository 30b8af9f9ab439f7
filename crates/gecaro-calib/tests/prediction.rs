//! Predicted precision against Monte Carlo: the errors of the calibrated
//! robot at test poses, predicted by propagating eq. 11's covariance, and
//! measured over 1000 simulated calibrations, agree within 10 %.

use gecaro_calib::study::Samples;
use gecaro_calib::{
    Quiet,
    identifiability::random_samples,
    identification::IdentificationOptions,
    methods::{MethodOptions, method},
    prediction::{SimulatedRuns, monte_carlo, predict},
    simulation::Sampler,
};
use gecaro_io::load_robot;

#[test]
fn the_prediction_agrees_with_a_thousand_simulated_calibrations() {
    let robot = load_robot("stanford").expect("ready robot").robot;
    // Methods that observe where the robot is (link, plane and distance data
    // cannot see its world frame, whose real error then dominates the test
    // poses' errors: docs/planning.md).
    for name in ["position", "frame"] {
        let chosen = method(name, &MethodOptions::default()).expect("method");
        let count = 40;
        let planned =
            random_samples(&robot, chosen.as_ref(), Some(count), 21, &mut Quiet).expect("planned");
        let mut sampler = Sampler::new(5);
        let test_poses: Vec<Vec<f64>> = (0..100).map(|_| sampler.configuration(&robot)).collect();
        let noise = 1e-4;
        let predicted = predict(
            &robot,
            chosen.as_ref(),
            Samples::from(planned.as_slice()).as_slice(),
            noise,
            &test_poses,
            &robot.priority(),
        )
        .expect("prediction");
        assert!(
            predicted
                .parameters
                .iter()
                .all(|(_, sigma)| sigma.is_finite() && *sigma > 0.0)
        );
        let measured = monte_carlo(
            &robot,
            chosen.as_ref(),
            Samples::from(planned.as_slice()).as_slice(),
            &test_poses,
            SimulatedRuns {
                runs: 1000,
                seed: 1,
                noise,
                error_level: 0.1,
            },
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("Monte Carlo");
        assert_eq!(measured.not_converged, 0, "{name}");
        let ratio = |a: f64, b: f64| (a / b - 1.0).abs();
        let (p, m) = (predicted.errors, measured.errors);
        println!("{name}: predicted {p:?}, measured {m:?}");
        assert!(
            ratio(m.position_rms, p.position_rms) < 0.10,
            "{name}: {p:?} vs {m:?}"
        );
        assert!(
            ratio(m.position_max, p.position_max) < 0.15,
            "{name}: {p:?} vs {m:?}"
        );
        if let (Some(a), Some(b)) = (m.rotation_rms, p.rotation_rms) {
            assert!(ratio(a, b) < 0.10, "{name}: {p:?} vs {m:?}");
        }
    }
}
