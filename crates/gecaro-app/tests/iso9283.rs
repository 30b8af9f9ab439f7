//! ISO 9283's test end to end on a simulated "real" robot: planned on the
//! nominal model, run and measured before calibration, the program
//! compensated with the calibrated model and run again: the calibrated AP
//! at the noise level.

use gecaro_app::{
    CompensateRequest, DataSource, GenerateRequest, IdentifyRequest, Iso9283EvaluateRequest,
    Iso9283PlanRequest, LocalFiles, Measurements, MethodSpec, ProgramSource, RobotSource,
};
use gecaro_calib::Quiet;
use gecaro_calib::simulation::Sampler;
use gecaro_core::{Robot, terminal_pose};
use nalgebra::UnitQuaternion;

/// The measured file of `program` (its text) run on `real`: each measured
/// row's pose, cycle, direction and attained pose, noise σ per axis.
fn measure(program: &str, nominal: &Robot, real: &Robot, sigma: f64, seed: u64) -> String {
    let file = gecaro_io::parse_program(
        program.as_bytes(),
        std::path::Path::new("program.csv"),
        nominal,
        &gecaro_io::DataFormat::default(),
    )
    .expect("program");
    let mut sampler = Sampler::new(seed);
    let mut text = String::from("pose,cycle,direction,x,y,z,qw,qx,qy,qz\n");
    for (index, point) in file.points.iter().enumerate() {
        if file.field(index, "measure") != Some("1") {
            continue;
        }
        let joints = point.joints.as_ref().expect("joints");
        let pose = terminal_pose(real, joints).expect("pose");
        let position = pose.translation.vector + sampler.gaussian_vector(sigma);
        let q = UnitQuaternion::from_rotation_matrix(&pose.rotation);
        text.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            file.field(index, "pose").expect("pose"),
            file.field(index, "cycle").expect("cycle"),
            file.field(index, "direction").expect("direction"),
            position.x,
            position.y,
            position.z,
            q.w,
            q.i,
            q.j,
            q.k
        ));
    }
    text
}

#[test]
fn the_test_before_and_after_calibration() {
    let sigma = 1e-5;
    // The real robot and a calibration of it.
    let mut generate = GenerateRequest::new(
        RobotSource::Named("industrial6".into()),
        MethodSpec::named("frame"),
        80,
    );
    generate.noise = sigma;
    generate.seed = Some(78);
    let generated = generate.run(&LocalFiles, &mut Quiet).expect("generated");
    let nominal = generated.nominal.robot.clone();
    let real = generated.real.robot.clone();
    let identify = IdentifyRequest::new(Measurements {
        robot: Some(RobotSource::Named("industrial6".into())),
        method: Some(MethodSpec::named("frame")),
        data: Some(DataSource::Samples {
            samples: generated.samples.clone(),
            label: "generated".into(),
        }),
        ..Measurements::default()
    });
    let identified = identify.run(&LocalFiles, &mut Quiet).expect("identified");
    assert!(identified.converged());
    let calibrated = identified.calibrated();

    // The test, planned on the nominal model, run before calibration.
    let mut plan = Iso9283PlanRequest::new(RobotSource::Named("industrial6".into()));
    plan.cycles = Some(10);
    let planned = plan.run(&LocalFiles).expect("plan");
    let before = measure(&planned.program, &nominal, &real, sigma, 1);

    // The same program compensated, run after.
    let compensate = CompensateRequest::new(
        RobotSource::Named("industrial6".into()),
        RobotSource::Loaded(Box::new(calibrated)),
        ProgramSource::Csv {
            text: planned.program.clone(),
            name: Some("test.csv".into()),
        },
    );
    let compensated = compensate
        .run(&LocalFiles, &mut Quiet)
        .expect("compensated");
    let corrected = compensated.corrected.expect("a corrected program");
    let after = measure(&corrected, &nominal, &real, sigma, 2);

    let mut evaluate = Iso9283EvaluateRequest::new(
        ProgramSource::Csv {
            text: planned.program.clone(),
            name: Some("test.csv".into()),
        },
        ProgramSource::Csv {
            text: before,
            name: Some("before.csv".into()),
        },
    );
    evaluate.robot = Some(RobotSource::Named("industrial6".into()));
    evaluate.after = Some(ProgramSource::Csv {
        text: after,
        name: Some("after.csv".into()),
    });
    let evaluated = evaluate.run(&LocalFiles).expect("evaluated");
    assert!(evaluated.warnings.is_empty(), "{:?}", evaluated.warnings);
    let before = &evaluated.before.evaluation;
    let after = &evaluated.after.as_ref().expect("after").evaluation;
    assert!(before.oriented && after.oriented);
    eprintln!(
        "AP before {:.4} mm, after {:.4} mm; RP {:.4} / {:.4} mm",
        before.worst_accuracy() * 1e3,
        after.worst_accuracy() * 1e3,
        before.worst_repeatability() * 1e3,
        after.worst_repeatability() * 1e3
    );
    // Before: the real robot's error, far beyond the noise; after: the
    // noise level (the barycentre of 10 cycles is within ~σ of the truth,
    // and the calibration's own error is of the noise's order).
    assert!(
        before.worst_accuracy() > 50.0 * sigma,
        "{}",
        before.worst_accuracy()
    );
    assert!(
        after.worst_accuracy() < 5.0 * sigma,
        "{}",
        after.worst_accuracy()
    );
    // Repeatability is the noise's, before and after alike.
    for evaluation in [before, after] {
        assert!(evaluation.worst_repeatability() < 6.0 * sigma);
    }
    let document = evaluated.document();
    let json = serde_json::to_value(&document).expect("json");
    assert!(json["before"]["poses"][0]["ap"]["p"].as_f64().is_some());
    assert!(json["after"]["poses"][4]["rp"]["l"].as_f64().is_some());
    assert!(json["before"]["distance"]["rd"].as_f64().is_some());
}

/// A measured row that is no visit of the program is refused naming its
/// line; a file in another frame is named as such; without a pose column,
/// the file is refused naming the column.
#[test]
fn measured_files_that_do_not_fit_are_named() {
    let planned = Iso9283PlanRequest::new(RobotSource::Named("industrial6".into()))
        .run(&LocalFiles)
        .expect("plan");
    let program = || ProgramSource::Csv {
        text: planned.program.clone(),
        name: Some("test.csv".into()),
    };
    let data = |text: &str| ProgramSource::Csv {
        text: text.into(),
        name: Some("measured.csv".into()),
    };
    let p1 = planned.plan.poses[0].target.translation.vector;
    let row = |cycle: usize, dx: f64| format!("1,{cycle},{},{},{}\n", p1.x + dx, p1.y, p1.z);
    let off = format!(
        "pose,cycle,x,y,z\n{}{}{}",
        row(1, 0.0),
        row(2, 1e-5),
        row(31, 0.0)
    );
    let error = Iso9283EvaluateRequest::new(program(), data(&off))
        .run(&LocalFiles)
        .expect_err("cycle 31");
    let message = error.message(gecaro_app::Dialect::CommandLine);
    assert!(
        message.contains("line 4") && message.contains("cycle 31"),
        "{message}"
    );
    let far = format!("pose,cycle,x,y,z\n{}{}", row(1, 3.0), row(2, 3.0));
    let evaluated = Iso9283EvaluateRequest::new(program(), data(&far))
        .run(&LocalFiles)
        .expect("far");
    assert!(
        evaluated.warnings.iter().any(|w| matches!(
            w,
            gecaro_app::TestWarning::AnotherFrame { .. }
        ) && w.to_string().contains("another frame")),
        "{:?}",
        evaluated.warnings
    );
    let error = Iso9283EvaluateRequest::new(program(), data("cycle,x,y,z\n1,0,0,0\n"))
        .run(&LocalFiles)
        .expect_err("no pose");
    assert!(
        error
            .message(gecaro_app::Dialect::CommandLine)
            .contains("no `pose` column"),
        "{}",
        error.message(gecaro_app::Dialect::CommandLine)
    );
}
