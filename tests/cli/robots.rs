//! Robot files from the command line: shown, checked, created, re-framed; bad command lines.

use super::*;

#[test]
fn robot_show_prints_the_table_and_priorities() {
    command("robot show stanford")
        .assert()
        .success()
        .stdout(predicate::str::contains("RRPRRR"))
        .stdout(predicate::str::contains("Priority matrix"))
        .stdout(predicate::str::contains("1.570796"));
}

/// The loads of elastic joints: a robot with masses lists them; one that
/// states a compliance lists every joint's; a rigid robot without masses
/// prints neither (its table unchanged).
#[test]
fn robot_show_prints_masses_and_compliances() {
    command("robot show industrial6")
        .assert()
        .success()
        .stdout(predicate::str::contains("Masses (51.3 kg;"))
        .stdout(predicate::str::contains("Compliances").not());
    let folder = tempfile::tempdir().expect("folder");
    let rigid = folder.path().join("arm.toml");
    gecaro()
        .args([
            "robot",
            "new",
            "--joints",
            "RR",
            "-o",
            rigid.to_str().expect("UTF-8"),
        ])
        .assert()
        .success();
    let text = std::fs::read_to_string(&rigid).expect("written");
    // After joint 1's gain line.
    let at = text.find("\nK = ").expect("a gain line") + 1;
    let end = at + text[at..].find('\n').expect("its end") + 1;
    let stated = format!("{}compliance = 5e-6\n{}", &text[..end], &text[end..]);
    assert_ne!(stated, text, "{text}");
    let elastic = folder.path().join("elastic.toml");
    std::fs::write(&elastic, stated).expect("written");
    gecaro()
        .args(["robot", "show", elastic.to_str().expect("UTF-8")])
        .assert()
        .success()
        .stdout(predicate::str::contains("c1 = 5.0e-6, c2 = 0"));
    command("robot show stanford")
        .assert()
        .success()
        .stdout(predicate::str::contains("Masses").not());
}

#[test]
fn robot_show_of_the_stanford_arm_is_table_1() {
    // The whole text, column widths and all: a change of layout shows up here
    // as a diff to review (`cargo insta review`), not as a silent change.
    let output = command("robot show stanford").output().expect("runs");
    assert!(output.status.success());
    insta::assert_snapshot!(String::from_utf8(output.stdout).expect("utf-8"));
}

#[test]
fn every_ready_robot_checks_out() {
    for name in [
        "stanford",
        "puma560",
        "industrial6",
        "scara",
        "panda",
        "ur10e",
    ] {
        gecaro()
            .args(["robot", "check", name])
            .assert()
            .success()
            .stdout(predicate::str::starts_with("ok:"));
    }
    // And the files in robots/ are the same robots.
    for entry in std::fs::read_dir("robots").expect("robots/") {
        let path = entry.expect("entry").path();
        command("robot check").arg(&path).assert().success();
    }
}

#[test]
fn robot_check_names_file_line_and_key() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("broken.toml");
    let text = std::fs::read_to_string("robots/stanford.toml").expect("stanford");
    std::fs::write(&path, text.replace("sigma = 1", "sigma = 7")).expect("write");
    command("robot check")
        .arg(&path)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("broken.toml:25: frame 3, sigma"))
        .stderr(predicate::str::contains("panicked").not());
}

#[test]
fn robot_new_writes_a_loadable_template_and_refuses_to_overwrite() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("arm.toml");
    command("robot new --joints RRPRRR -o")
        .arg(&path)
        .assert()
        .success();
    command("robot check")
        .arg(&path)
        .assert()
        .success()
        .stdout(predicate::str::contains("RRPRRR"));
    let before = std::fs::read(&path).expect("read");
    command("robot new --joints RR -o")
        .arg(&path)
        .assert()
        .code(3)
        .stderr(predicate::str::contains("--force"));
    assert_eq!(std::fs::read(&path).expect("read"), before);
    command("robot new --joints RR --force -o")
        .arg(&path)
        .assert()
        .success();
    assert!(Path::new(&path).exists());
}

#[test]
fn robot_reframe_keeps_every_link_s_mass_on_its_body() {
    // Masses on links 2 and 6 and on the tool, and a tilted gravity: after a
    // new world and a new tool, gravity loads every joint as before.
    let folder = tempfile::tempdir().expect("temporary folder");
    let stanford = gecaro_io::load_robot("stanford").expect("stanford");
    let mut file = gecaro_io::RobotFile::of(stanford.robot.clone());
    for (frame, mass, com) in [
        (2, 5.0, [0.1, 0.0, 0.02]),
        (6, 1.5, [0.0, 0.01, 0.04]),
        (7, 8.0, [0.0, 0.0, 0.1]),
    ] {
        file.masses
            .set_link(
                frame,
                gecaro_core::LinkMass {
                    mass,
                    com: com.into(),
                },
            )
            .expect("mass");
    }
    file.masses
        .set_gravity(nalgebra::Vector3::new(0.2, 0.0, -9.8))
        .expect("gravity");
    let original = folder.path().join("loaded.toml");
    std::fs::write(&original, gecaro_io::format_robot_file(&file)).expect("written");
    let moved = folder.path().join("moved.toml");
    command("robot reframe")
        .arg(&original)
        .args([
            "--world",
            "0.1,0.2,-0.5,0.9238795325112867,0,0.3826834323650898,0",
            "--tool",
            "0,0.05,0.1,0.7071067811865476,0.7071067811865476,0,0",
            "-o",
        ])
        .arg(&moved)
        .assert()
        .success();
    let before = gecaro_io::load_robot(original.to_str().expect("path")).expect("before");
    let after = gecaro_io::load_robot(moved.to_str().expect("path")).expect("after");
    assert!(!after.masses.is_empty());
    for q in [
        [0.3, -0.4, 0.6, 0.2, 0.9, -1.1],
        [-2.0, 1.0, 0.2, 3.0, -1.0, 0.5],
    ] {
        let torques = |file: &gecaro_io::RobotFile| {
            gecaro_core::gravity_torques(&file.robot, &file.masses, None, &q).expect("torques")
        };
        let (a, b) = (torques(&before), torques(&after));
        assert!((&a - &b).norm() < 1e-9 * a.norm(), "{a} vs {b}");
    }
}

#[test]
fn robot_reframe_moves_the_world_and_tool_frames_and_nothing_else() {
    use nalgebra::{IsometryMatrix3, Matrix3, Quaternion, Translation3, UnitQuaternion};
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("moved.toml");
    // The old world 0.5 m below and turned 45° about y; a tool 0.1 m out along
    // z and 5 cm along y, turned 90° about x.
    let (world, tool) = (
        "0.1,0.2,-0.5,0.9238795325112867,0,0.3826834323650898,0",
        "0,0.05,0.1,0.7071067811865476,0.7071067811865476,0,0",
    );
    gecaro()
        .args([
            "robot", "reframe", "stanford", "--world", world, "--tool", tool, "-o",
        ])
        .arg(&path)
        .assert()
        .success()
        .stdout(predicate::str::contains("frames 0, 1 and 6, 7 rewritten"));
    let pose = |text: &str| -> IsometryMatrix3<f64> {
        let v: Vec<f64> = text
            .split(',')
            .map(|x| x.parse().expect("number"))
            .collect();
        let rotation = UnitQuaternion::from_quaternion(Quaternion::new(v[3], v[4], v[5], v[6]));
        IsometryMatrix3::from_parts(
            Translation3::new(v[0], v[1], v[2]),
            rotation.to_rotation_matrix(),
        )
    };
    let fk = |robot: &str, qm: &str| -> IsometryMatrix3<f64> {
        let json = json_output(&["fk", robot, "--qm", qm, "--json"]);
        let p = as_f64s(&json["position"]);
        let rows: Vec<Vec<f64>> = json["rotation"]
            .as_array()
            .expect("rows")
            .iter()
            .map(as_f64s)
            .collect();
        let rotation = Matrix3::from_fn(|i, j| rows[i][j]);
        IsometryMatrix3::from_parts(
            Translation3::new(p[0], p[1], p[2]),
            nalgebra::Rotation3::from_matrix_unchecked(rotation),
        )
    };
    let moved = path.to_str().expect("utf-8 path");
    for qm in [
        "0,0,0.5,0,0,0",
        "0.3,-0.4,0.6,0.2,0.9,-1.1",
        "-2,1,0.2,3,-1,0.5",
    ] {
        let expected = pose(world) * fk("stanford", qm) * pose(tool);
        let got = fk(moved, qm);
        let difference = expected.inverse() * got;
        assert!(
            difference.translation.vector.norm() < 1e-9
                && (difference.rotation.matrix() - Matrix3::identity()).norm() < 1e-9,
            "{qm}: {difference:?}"
        );
    }
    // Only one of the two: frames 0, 1 only; nothing asked: a usage error, no file.
    let world_only = folder.path().join("world.toml");
    gecaro()
        .args(["robot", "reframe", "stanford", "--world", world, "-o"])
        .arg(&world_only)
        .assert()
        .success()
        .stdout(predicate::str::contains("frames 0, 1 rewritten"));
    let nothing = folder.path().join("nothing.toml");
    command("robot reframe stanford -o")
        .arg(&nothing)
        .assert()
        .failure()
        .stderr(predicate::str::contains("give --world, --tool or both"));
    command("robot reframe stanford --tool 0,0,0,2,0,0,0 -o")
        .arg(&nothing)
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "--tool: (qw, qx, qy, qz) has norm 2.000000",
        ));
    assert!(!nothing.exists());
}

#[test]
fn bad_command_lines_are_clear_errors() {
    command("fk stanfrod --qm 0,0,0,0,0,0")
        .assert()
        .code(3)
        .stderr(predicate::str::contains("ready robots: stanford, puma560"));
    command("fk stanford --qm 0,0")
        .assert()
        .code(3)
        .stderr(predicate::str::contains("needs 6 motor values"));
    command("fk stanford --qm 0,x").assert().code(2);
    command("fk no/such/robot.toml --qm 0")
        .assert()
        .code(3)
        .stderr(predicate::str::contains("no/such/robot.toml"));
}
