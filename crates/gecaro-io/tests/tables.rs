//! DH, modified-DH and SYMORO imports against hand-derived tables and an
//! independent product of DH matrices; exports read back.

use std::path::{Path, PathBuf};

use gecaro_core::{FrameType, Robot, terminal_pose};
use gecaro_io::{
    ImportOptions, Imported, RobotFormat, TableUnits, export_robot, import_robot,
    import_robot_text, load_robot,
};
use nalgebra::{IsometryMatrix3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/robots")
        .join(name)
}

fn import(name: &str, format: Option<RobotFormat>) -> Imported {
    import_robot(
        &data(name),
        &ImportOptions {
            format,
            ..ImportOptions::default()
        },
    )
    .unwrap_or_else(|error| panic!("{name}: {error}"))
}

fn assert_same_frames(got: &Robot, expected: &Robot, what: &str) {
    assert_eq!(got.frames().len(), expected.frames().len(), "{what}");
    for (j, (a, b)) in got.frames().iter().zip(expected.frames()).enumerate() {
        assert_eq!(a.frame_type, b.frame_type, "{what}, frame {j}");
        for (name, x, y) in [
            ("alpha", a.alpha, b.alpha),
            ("d", a.d, b.d),
            ("theta", a.theta, b.theta),
            ("r", a.r, b.r),
            ("beta", a.beta, b.beta),
        ] {
            assert!(
                (x - y).abs() < 1e-12,
                "{what}, frame {j}, {name}: {x} against {y}"
            );
        }
    }
}

fn max_fk_difference(a: &Robot, b: &Robot, seed: u64) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..100)
        .map(|_| {
            let qm: Vec<f64> = a
                .joints()
                .iter()
                .map(|joint| rng.random_range(joint.qmin..=joint.qmax))
                .collect();
            let (pa, pb) = (
                terminal_pose(a, &qm).expect("a"),
                terminal_pose(b, &qm).expect("b"),
            );
            (pa.to_homogeneous() - pb.to_homogeneous()).abs().max()
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_stanford_arm_of_table_1_as_a_symoro_file_is_the_ready_robot() {
    let imported = import("stanford.par", None);
    let ready = load_robot("stanford").expect("ready").robot;
    assert_same_frames(&imported.file.robot, &ready, "stanford.par");
    assert_eq!(imported.file.robot.name(), "Stanford");
    assert!(
        imported
            .notes
            .iter()
            .any(|note| note.contains("no joint limits"))
    );
}

#[test]
fn craig_s_puma_560_in_millimetres_and_degrees_is_the_ready_robot() {
    let imported = import("puma560_mdh.toml", None);
    let ready = load_robot("puma560").expect("ready").robot;
    assert_same_frames(&imported.file.robot, &ready, "puma560_mdh.toml");
    for (got, expected) in imported.file.robot.joints().iter().zip(ready.joints()) {
        assert!(
            (got.qmin - expected.qmin).abs() < 1e-12 && (got.qmax - expected.qmax).abs() < 1e-12
        );
    }
}

/// Rz(θ)·Tz(d)·Tx(a)·Rx(α): a standard DH step, written out independently.
fn dh_step(a: f64, alpha: f64, d: f64, theta: f64) -> IsometryMatrix3<f64> {
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = alpha.sin_cos();
    #[rustfmt::skip]
    let matrix = nalgebra::Matrix4::new(
        ct, -st * ca, st * sa, a * ct,
        st, ct * ca, -ct * sa, a * st,
        0.0, sa, ca, d,
        0.0, 0.0, 0.0, 1.0,
    );
    IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(matrix[(0, 3)], matrix[(1, 3)], matrix[(2, 3)]),
        nalgebra::Rotation3::from_matrix_unchecked(matrix.fixed_view::<3, 3>(0, 0).into_owned()),
    )
}

#[test]
fn a_standard_dh_csv_has_the_table_s_direct_model_and_the_hand_derived_frames() {
    let imported = import("puma560_dh.csv", Some(RobotFormat::Dh));
    let robot = &imported.file.robot;
    // Hand-derived: row j's a and α become d and α of frame j+1; θ, d stay on frame j.
    let expected = [
        // (alpha, d, theta, r) of frames 2..6
        (std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0),
        (0.0, 0.4318, 0.0, 0.15005),
        (-std::f64::consts::FRAC_PI_2, 0.0203, 0.0, 0.4318),
        (std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0),
        (-std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0),
    ];
    for (j, (alpha, d, theta, r)) in expected.iter().enumerate() {
        let frame = robot.frames()[j + 2];
        assert!(
            (frame.alpha - alpha).abs() < 1e-12
                && (frame.d - d).abs() < 1e-12
                && (frame.theta - theta).abs() < 1e-12
                && (frame.r - r).abs() < 1e-12,
            "frame {}: {frame:?}",
            j + 2
        );
    }
    let rows: [(f64, f64, f64); 6] = [
        (0.0, 90.0, 0.0),
        (431.8, 0.0, 0.0),
        (20.3, -90.0, 150.05),
        (0.0, 90.0, 431.8),
        (0.0, -90.0, 0.0),
        (0.0, 0.0, 0.0),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..100 {
        let q: Vec<f64> = robot
            .joints()
            .iter()
            .map(|j| rng.random_range(j.qmin..=j.qmax))
            .collect();
        let mut expected = dh_step(0.0, 0.0, 0.6604, 0.0);
        for ((a, alpha, d), q) in rows.iter().zip(&q) {
            expected *= dh_step(a * 1e-3, alpha.to_radians(), d * 1e-3, *q);
        }
        expected *= dh_step(0.0, 0.0, 0.05625, 0.0);
        let got = terminal_pose(robot, &q).expect("valid");
        assert!(
            (expected.to_homogeneous() - got.to_homogeneous())
                .abs()
                .max()
                < 1e-12
        );
    }
}

#[test]
fn tables_export_and_read_back_with_the_same_direct_model() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for name in [
        "stanford",
        "puma560",
        "panda",
        "scara",
        "industrial6",
        "ur10e",
    ] {
        let file = load_robot(name).expect("ready");
        let mut spec = file.robot.to_spec();
        // Calibrated-like: offsets and perturbed lengths and angles (β = 0).
        for joint in &mut spec.joints {
            joint.offset = rng.random_range(-0.05..0.05);
        }
        for frame in spec.frames.iter_mut().skip(1) {
            frame.alpha += rng.random_range(-0.01..0.01);
            frame.d += rng.random_range(-0.01..0.01);
        }
        let robot = Robot::new(spec).expect("valid");
        let file = gecaro_io::RobotFile {
            robot: robot.clone(),
            ..file
        };
        for convention in [RobotFormat::Dh, RobotFormat::Mdh] {
            let exported = export_robot(&file, convention).expect("β = 0");
            let back = import_robot_text(
                &exported.text,
                Path::new("table.toml"),
                &ImportOptions::default(),
            )
            .unwrap_or_else(|error| panic!("{name}: {error}\n{}", exported.text));
            // The table's joint value is q − offset: the same motor values reach the same poses.
            let mut shifted = robot.to_spec();
            for (joint, frame) in shifted
                .joints
                .iter_mut()
                .zip(shifted.frames.iter_mut().skip(1))
            {
                match frame.frame_type {
                    FrameType::Prismatic => frame.r += joint.offset,
                    _ => frame.theta += joint.offset,
                }
                joint.qmin -= joint.offset;
                joint.qmax -= joint.offset;
                joint.offset = 0.0;
            }
            let shifted = Robot::new(shifted).expect("valid");
            let difference = max_fk_difference(&shifted, &back.file.robot, 1);
            assert!(difference < 1e-12, "{name}, {convention:?}: {difference:e}");
        }
    }
}

#[test]
fn hayati_beta_has_no_place_in_a_dh_table() {
    let mut file = load_robot("stanford").expect("ready");
    let mut spec = file.robot.to_spec();
    spec.frames[3].beta = 0.001;
    file.robot = Robot::new(spec).expect("valid");
    let message = export_robot(&file, RobotFormat::Mdh).expect_err("β ≠ 0");
    assert!(
        message.contains("frame 3") && message.contains("URDF"),
        "{message}"
    );
}

fn table_error(text: &str, name: &str, format: Option<RobotFormat>) -> String {
    import_robot_text(
        text,
        Path::new(name),
        &ImportOptions {
            format,
            units: TableUnits::default(),
            ..ImportOptions::default()
        },
    )
    .expect_err("invalid")
    .to_string()
}

#[test]
fn bad_tables_name_the_file_and_line() {
    let csv = "type,a,alpha,d,theta\nR,0,0,0.3,0\nR,0.4,0,0\n";
    assert!(
        table_error(csv, "t.csv", Some(RobotFormat::Dh))
            .contains("t.csv:3: 4 values for 5 columns")
    );
    // Windows line ends, comments and blank lines before a record: the
    // record's own line.
    let csv = "# from a spreadsheet\r\ntype,a,alpha,d,theta\r\nR,0,0,0.3,0\r\n\r\n# next\r\nR,0.4,0,0\r\n";
    let error = table_error(csv, "t.csv", Some(RobotFormat::Dh));
    assert!(error.contains("t.csv:6: 4 values for 5 columns"), "{error}");
    let csv = "type,a,alpha,d,theta\nR,0,NaN,0.3,0\n";
    assert!(
        table_error(csv, "t.csv", Some(RobotFormat::Dh))
            .contains("t.csv:2: alpha: `NaN` is not a finite number")
    );
    let csv = "type,a,alpha,d,theta\nQ,0,0,0.3,0\n";
    assert!(table_error(csv, "t.csv", Some(RobotFormat::Mdh)).contains("t.csv:2: type"));
    assert!(table_error(csv, "t.csv", None).contains("name it (dh for standard"));
    let csv = "type,a_mm,alpha_deg,d_m,theta\nR,0,0,0.3,0\n";
    assert!(table_error(csv, "t.csv", Some(RobotFormat::Dh)).contains("different units"));
    let toml = "convention = \"dh\"\n[[joint]]\ntype = \"R\"\nalpha = nan\n";
    assert!(
        table_error(toml, "t.toml", None).contains("t.toml:4: alpha: NaN is not a finite number")
    );
    let toml = "[[joint]]\ntype = \"R\"\n";
    assert!(table_error(toml, "t.toml", None).contains("convention"));
    let toml = "convention = \"mdh\"\n[[joint]]\ntype = \"R\"\n";
    assert!(
        table_error(toml, "t.toml", Some(RobotFormat::Dh))
            .contains("the file says convention = \"mdh\"")
    );
}

#[test]
fn bad_symoro_files_are_clear_errors() {
    let stanford = std::fs::read_to_string(data("stanford.par")).expect("test file");
    let tree = stanford.replace("ant = {0,1,2,3,4,5,6}", "ant = {0,1,2,3,4,3,6}");
    assert!(table_error(&tree, "s.par", None).contains("a tree"));
    let unknown = stanford.replace("RL2 = 0.2\n", "");
    let message = table_error(&unknown, "s.par", None);
    assert!(
        message.contains("RL2") && message.contains("add a line `RL2 = <value>`"),
        "{message}"
    );
    let short = stanford.replace("d = {0,0,0,0,0,0,0.2}", "d = {0,0,0,0.2}");
    let message = table_error(&short, "s.par", None);
    assert!(
        message.contains("s.par:16: d") && message.contains("NF = 7"),
        "{message}"
    );
    let closed = stanford.replace("Type = 0", "Type = 2");
    assert!(table_error(&closed, "s.par", None).contains("closed-loop"));
    let bad_z = stanford.replace("Z = {1,0,0,0,", "Z = {2,0,0,0,");
    assert!(table_error(&bad_z, "s.par", None).contains("not a rotation"));
    // A base transform Z moves the robot in the world.
    let lifted = stanford.replace(
        "Z = {1,0,0,0,0,1,0,0,0,0,1,0,",
        "Z = {1,0,0,0,0,1,0,0,0,0,1,0.25,",
    );
    let robot = import_robot_text(&lifted, Path::new("s.par"), &ImportOptions::default())
        .expect("valid")
        .file
        .robot;
    let ready = load_robot("stanford").expect("ready").robot;
    let qm = [0.3, -0.5, 0.6, 0.2, 1.0, -0.4];
    let difference = terminal_pose(&robot, &qm).expect("v").translation.vector
        - terminal_pose(&ready, &qm).expect("v").translation.vector;
    assert!((difference - Vector3::new(0.0, 0.0, 0.25)).norm() < 1e-12);
}

/// Hostile SYMORO values (the second hardening round): a value written as a
/// 60,000-term sum is refused at once (it parsed in quadratic time, ~100 s),
/// `1e999` is "not a finite number" (the parser's internal message before),
/// and a chain of 50,000 symbol definitions is resolved in dependency order
/// (it said `A19384 without a value`); a definition through itself is an
/// error at its line.
#[test]
fn hostile_symoro_values_are_bounded_and_resolved_in_order() {
    let stanford = std::fs::read_to_string(data("stanford.par")).expect("test file");
    let long_sum = format!("RL2 = {}\n", vec!["0.00001"; 60_000].join("+"));
    let message = table_error(&stanford.replace("RL2 = 0.2\n", &long_sum), "s.par", None);
    assert!(
        message.contains("a SYMORO value is a short formula"),
        "{message}"
    );
    let message = table_error(
        &stanford.replace("RL2 = 0.2\n", "RL2 = 1e999\n"),
        "s.par",
        None,
    );
    assert!(
        message.contains("`1e999` is not a finite number"),
        "{message}"
    );
    // RL2 = A49999 + 0.1, A_k = A_(k-1) + 0.000002, A0 = 0.000002: RL2 = 0.2. The
    // definitions come in reverse, each before the one it uses.
    let mut chain = String::from("RL2 = A49999 + 0.1\n");
    for k in (1..50_000).rev() {
        chain += &format!("A{k} = A{} + 0.000002\n", k - 1);
    }
    chain += "A0 = 0.000002\n";
    let chained = stanford.replace("RL2 = 0.2\n", &chain);
    let robot = import_robot_text(&chained, Path::new("s.par"), &ImportOptions::default())
        .expect("a chain of definitions")
        .file
        .robot;
    let ready = load_robot("stanford").expect("ready").robot;
    let qm = [0.3, -0.5, 0.6, 0.2, 1.0, -0.4];
    let difference = terminal_pose(&robot, &qm).expect("v").translation.vector
        - terminal_pose(&ready, &qm).expect("v").translation.vector;
    assert!(difference.norm() < 1e-9, "{difference}");
    let cycle = stanford.replace("RL2 = 0.2\n", "RL2 = B + 0.1\nB = RL2 - 0.1\n");
    let message = table_error(&cycle, "s.par", None);
    assert!(message.contains("is defined through itself"), "{message}");
}
