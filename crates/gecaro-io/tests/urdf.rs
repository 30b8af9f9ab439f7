//! URDF import and export against an independent forward model: the `k`
//! crate (openrr) loads the same URDF files with its own parser and tree.
//! The URDFs and their licences are in `tests/data/urdf/` (README there).

use std::path::{Path, PathBuf};

use gecaro_core::{FrameType, Robot, terminal_pose};
use gecaro_io::{ChainEnds, ImportOptions, Imported, RobotFormat, import_robot};
use nalgebra::IsometryMatrix3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/urdf")
        .join(name)
}

fn import(file: &str, base: Option<&str>, tip: Option<&str>) -> Result<Imported, gecaro_io::Error> {
    import_robot(
        &data(file),
        &ImportOptions {
            chain: ChainEnds {
                base: base.map(str::to_owned),
                tip: tip.map(str::to_owned),
                name: None,
            },
            ..ImportOptions::default()
        },
    )
}

/// The pose of `tip` in `base` by k, with the chain's joints at `positions`
/// (by joint name) and every other joint at 0.
fn k_pose(file: &str, base: &str, tip: &str, positions: &[(String, f64)]) -> IsometryMatrix3<f64> {
    let chain = k::Chain::<f64>::from_urdf_file(data(file)).expect("k reads the URDF");
    for node in chain.iter() {
        let name = node.joint().name.clone();
        if let Some((_, q)) = positions.iter().find(|(joint, _)| *joint == name) {
            node.set_joint_position(*q).expect("within k's limits");
        }
    }
    chain.update_transforms();
    let world = |link: &str| {
        chain
            .find_link(link)
            .map(|node| node.world_transform().expect("updated"))
            .unwrap_or_else(k::Isometry3::identity)
    };
    from_k(&(world(base).inverse() * world(tip)))
}

/// A transform of k's nalgebra in ours.
fn from_k(pose: &k::Isometry3<f64>) -> IsometryMatrix3<f64> {
    let matrix = pose.to_homogeneous();
    IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(matrix[(0, 3)], matrix[(1, 3)], matrix[(2, 3)]),
        nalgebra::Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_fn(|i, j| {
            matrix[(i, j)]
        })),
    )
}

/// The largest difference of FK between the imported robot and k, over 100
/// random configurations within the limits.
fn worst_difference(file: &str, base: &str, tip: &str, imported: &Imported, seed: u64) -> f64 {
    let robot = &imported.file.robot;
    let names = imported.file.urdf.as_ref().expect("URDF names kept");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = 0.0_f64;
    for _ in 0..100 {
        let mut qm: Vec<f64> = robot
            .joints()
            .iter()
            .map(|joint| rng.random_range(joint.qmin..=joint.qmax))
            .collect();
        // A mimic joint's own variable is the deviation from the relation: 0.
        for (j, value) in qm.iter_mut().enumerate() {
            let row = robot.joint_coupling().row(j);
            if row.iter().enumerate().any(|(c, v)| c != j && *v != 0.0) {
                *value = 0.0;
            }
        }
        let q = robot.joint_positions(&qm).expect("valid");
        let positions: Vec<(String, f64)> = names
            .joints
            .iter()
            .zip(q.iter())
            .map(|(joint, q)| (joint.name.clone(), *q))
            .collect();
        let expected = k_pose(file, base, tip, &positions);
        let got = terminal_pose(robot, &qm).expect("valid");
        worst = worst.max(
            (expected.to_homogeneous() - got.to_homogeneous())
                .abs()
                .max(),
        );
    }
    worst
}

fn check(file: &str, base: &str, tip: Option<&str>, expected_tip: &str, joints: &str) -> Imported {
    let imported = import(file, None, tip).unwrap_or_else(|error| panic!("{file}: {error}"));
    assert_eq!(imported.file.robot.joint_letters(), joints, "{file}");
    assert_eq!(
        imported.file.urdf.as_ref().expect("names").tip_link,
        expected_tip
    );
    let worst = worst_difference(file, base, expected_tip, &imported, 7);
    assert!(worst < 1e-12, "{file}: FK differs from k by {worst:e}");
    // No common normal far away: every length of the table within a few metres.
    for frame in imported.file.robot.frames() {
        assert!(
            frame.d.abs() < 3.0 && frame.r.abs() < 3.0,
            "{file}: {frame:?}"
        );
    }
    imported
}

#[test]
fn industrial_arm_with_negative_and_x_axes_and_a_base_leaf() {
    // KUKA KR16-2: axes (0 0 −1), (−1 0 0); a `base` leaf beside `tool0`,
    // whose rounded rpy puts its z 4.9e-12 rad from axis 6 (Hayati β).
    let imported = check("kuka_kr16_2.urdf", "base_link", None, "tool0", "RRRRRR");
    assert_eq!(imported.file.robot.joints()[1].qmin, -2.70526034059);
}

/// Issue 38: the chain's masses from the links' `<inertial>`. Gravity loads
/// every joint of the imported robot as the URDF itself says: −∂V/∂q by
/// central differences, V summed over every link of the file with k's
/// forward model and urdf-rs's inertials (an independent route).
#[test]
fn the_chain_s_masses_load_the_joints_as_the_urdf_says() {
    for (file, tip) in [("kuka_kr16_2.urdf", None), ("ur10e.urdf", Some("tool0"))] {
        let imported = import(file, None, tip).unwrap_or_else(|error| panic!("{file}: {error}"));
        let robot = &imported.file.robot;
        let masses = &imported.file.masses;
        assert!(!masses.is_empty(), "{file}");
        assert!(
            imported
                .notes
                .iter()
                .any(|note| note.contains("<inertial>")),
            "{file}: {:?}",
            imported.notes
        );
        let names = imported.file.urdf.as_ref().expect("names");
        let urdf = urdf_rs::read_file(data(file)).expect("urdf-rs reads it");
        let chain = k::Chain::<f64>::from_urdf_file(data(file)).expect("k reads it");
        let potential = |q: &[f64]| -> f64 {
            for node in chain.iter() {
                let name = node.joint().name.clone();
                if let Some(index) = names.joints.iter().position(|joint| joint.name == name) {
                    node.set_joint_position_unchecked(q[index]);
                }
            }
            chain.update_transforms();
            urdf.links
                .iter()
                .filter(|link| link.inertial.mass.value > 0.0)
                .map(|link| {
                    let world = chain
                        .find_link(&link.name)
                        .map(|node| from_k(&node.world_transform().expect("updated")))
                        .unwrap_or_else(IsometryMatrix3::identity);
                    let centre = world
                        * nalgebra::Point3::from(nalgebra::Vector3::from(
                            link.inertial.origin.xyz.0,
                        ));
                    link.inertial.mass.value * gecaro_core::STANDARD_GRAVITY * centre.z
                })
                .sum()
        };
        for qm in [
            [0.3, -0.7, 0.4, 1.1, -0.5, 2.0],
            [-1.0, -1.2, 0.9, -0.3, 1.4, -1.0],
        ] {
            let q = robot.joint_positions(&qm).expect("valid");
            let torques = gecaro_core::gravity_torques(robot, masses, None, &qm).expect("torques");
            for j in 0..q.len() {
                let h = 1e-6;
                let (mut up, mut down) = (q.clone(), q.clone());
                up[j] += h;
                down[j] -= h;
                let gradient = (potential(up.as_slice()) - potential(down.as_slice())) / (2.0 * h);
                assert!(
                    (torques[j] + gradient).abs() < 1e-5 * (1.0 + gradient.abs()),
                    "{file} joint {}: {} vs −∂V/∂q = {}",
                    j + 1,
                    torques[j],
                    -gradient
                );
            }
        }
    }
}

#[test]
fn seven_axis_arms() {
    check(
        "kuka_lbr_iiwa_14_r820.urdf",
        "base_link",
        None,
        "tool0",
        "RRRRRRR",
    );
    check(
        "panda.urdf",
        "panda_link0",
        Some("ball_link"),
        "ball_link",
        "RRRRRRR",
    );
}

#[test]
fn a_prismatic_torso_and_intermediate_fixed_joints() {
    // PR2: torso_lift_joint (prismatic), then the 7-axis right arm with fixed
    // joints between its moving ones (r_upper_arm_joint, r_forearm_joint,
    // continuous forearm and wrist rolls).
    let imported = check(
        "pr2.urdf",
        "base_footprint",
        Some("r_gripper_tool_frame"),
        "r_gripper_tool_frame",
        "PRRRRRRR",
    );
    assert!(
        imported
            .notes
            .iter()
            .any(|note| note.contains("fixed joint(s) folded"))
    );
    // The Panda's finger is a prismatic joint after seven revolute ones.
    check(
        "panda.urdf",
        "panda_link0",
        Some("panda_leftfinger"),
        "panda_leftfinger",
        "RRRRRRRP",
    );
}

#[test]
fn the_real_data_urdfs() {
    check("ur10e.urdf", "world", Some("tool0"), "tool0", "RRRRRR");
    check(
        "ur10e.urdf",
        "world",
        Some("camera_color_optical_frame"),
        "camera_color_optical_frame",
        "RRRRRR",
    );
    check(
        "gen3lite_ideal.urdf",
        "base_link",
        Some("ball_link"),
        "ball_link",
        "RRRRRR",
    );
    // Axes 2 and 3 of the rounded file are 7.3e-6 rad from parallel (a common
    // normal would be 38 km away): Hayati's β carries the tilt.
    let rounded = check(
        "gen3lite.urdf",
        "base_link",
        Some("ball_link"),
        "ball_link",
        "RRRRRR",
    );
    let frame = rounded.file.robot.frames()[3];
    assert!(
        frame.beta.abs() > 1e-6 && frame.beta.abs() < 1e-4,
        "{frame:?}"
    );
}

/// Rows `[j, sigma, alpha, d, theta, r, beta, K]` of a realdata YAML table.
fn yaml_table(path: &Path) -> Vec<[f64; 8]> {
    let text = std::fs::read_to_string(path).expect("realdata table");
    text.lines()
        .filter_map(|line| {
            let row = line.trim().strip_prefix("- [")?;
            let values: Vec<f64> = row[..row.find(']')?]
                .split(',')
                .map(|v| v.trim().parse().expect("number"))
                .collect();
            values.try_into().ok()
        })
        .collect()
}

fn realdata(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/realdata")
        .join(name)
}

fn assert_rows_equal(robot: &Robot, table: &[[f64; 8]], rows: std::ops::Range<usize>, what: &str) {
    for j in rows {
        let frame = robot.frames()[j];
        let row = table[j];
        // Angles compare modulo a full turn (−π is written +π).
        let turn = |angle: f64| angle.sin().atan2(angle.cos());
        for (name, got, expected) in [
            ("alpha", turn(frame.alpha - row[2]), 0.0),
            ("d", frame.d, row[3]),
            ("theta", turn(frame.theta - row[4]), 0.0),
            ("r", frame.r, row[5]),
            ("beta", turn(frame.beta - row[6]), 0.0),
        ] {
            assert!(
                (got - expected).abs() < 1e-12,
                "{what}, frame {j}, {name}: {got} against {expected}"
            );
        }
    }
}

#[test]
fn imports_give_the_verified_tables_of_the_real_data() {
    // shared/realdata's tables were derived independently and checked
    // against pinocchio; the import reproduces them row for row.
    let folder = realdata("");
    if !folder.is_dir() {
        eprintln!("shared/realdata not beside the project: skipped");
        return;
    }
    for (tip, table) in [
        ("tool0", "mdh_ur10e_urdfworld_tool0.yaml"),
        (
            "camera_color_optical_frame",
            "mdh_ur10e_urdfworld_camera.yaml",
        ),
    ] {
        let robot = import("ur10e.urdf", None, Some(tip))
            .expect("imports")
            .file
            .robot;
        let rows = yaml_table(&realdata("figaroh_ur10e_camera").join(table));
        assert_rows_equal(&robot, &rows, 0..8, table);
    }
    // The ball tables treat the ball as a point (its frame parallel to z_n);
    // the joint frames are the same, and so is the ball's position.
    for (file, table, n) in [
        ("panda.urdf", "mdh_panda_urdf_ball.yaml", 7),
        ("gen3lite_ideal.urdf", "mdh_gen3lite_urdf_ball.yaml", 6),
    ] {
        let robot = import(file, None, Some("ball_link"))
            .expect("imports")
            .file
            .robot;
        let rows = yaml_table(&realdata("mukca_pointlink").join(table));
        assert_rows_equal(&robot, &rows, 0..n, table);
        let tool = robot.frames()[n + 1];
        assert!(
            (tool.d.abs() - rows[n + 1][3].abs()).abs() < 1e-12,
            "{table}: {tool:?}"
        );
        assert!((tool.r - rows[n + 1][5]).abs() < 1e-12, "{table}: {tool:?}");
    }
}

#[test]
fn the_ur10e_example_robot_is_the_imported_urdf_reframed_as_documented() {
    // examples/real/ur10e_camera/robot.toml: the URDF's world and camera
    // frames, both tilted 45° about x (docs/real-data.md).
    let imported = import("ur10e.urdf", None, Some("camera_color_optical_frame")).expect("imports");
    let tilt = IsometryMatrix3::from_parts(
        nalgebra::Translation3::identity(),
        nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::x_axis(), 45f64.to_radians()),
    );
    let reframed = imported.file.robot.reframed(&tilt, &tilt).expect("valid");
    let example = gecaro_io::read_robot_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/real/ur10e_camera/robot.toml"),
    )
    .expect("example");
    for (j, (got, expected)) in reframed
        .frames()
        .iter()
        .zip(example.robot.frames())
        .enumerate()
    {
        for (name, a, b) in [
            ("alpha", got.alpha, expected.alpha),
            ("d", got.d, expected.d),
            ("theta", got.theta, expected.theta),
            ("r", got.r, expected.r),
            ("beta", got.beta, expected.beta),
        ] {
            assert!((a - b).abs() < 1e-9, "frame {j}, {name}: {a} against {b}");
        }
    }
}

fn import_error(file: &str, base: Option<&str>, tip: Option<&str>) -> String {
    match import(file, base, tip) {
        Ok(_) => panic!("{file}: expected an error"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn branches_and_bad_chains_are_clear_errors() {
    // The Panda's two fingers tie: the user must choose.
    let message = import_error("panda.urdf", None, None);
    assert!(
        message.contains("panda_leftfinger")
            && message.contains("panda_rightfinger")
            && message.contains("choose the tip link"),
        "{message}"
    );
    // The right finger mimics the left one, which is not in its chain.
    let message = import_error("panda.urdf", None, Some("panda_rightfinger"));
    assert!(
        message.contains("panda_finger_joint2") && message.contains("mimics"),
        "{message}"
    );
    assert!(
        message.starts_with(&format!("{}:", data("panda.urdf").display())),
        "{message}"
    );
    let message = import_error("panda.urdf", None, Some("no_such_link"));
    assert!(message.contains("no link `no_such_link`"), "{message}");
    let message = import_error("panda.urdf", Some("panda_link5"), Some("panda_link2"));
    assert!(
        message.contains("not below the base link `panda_link5`"),
        "{message}"
    );
    let message = import_error("panda.urdf", Some("panda_link8"), Some("panda_hand_tcp"));
    assert!(
        message.contains("no revolute, continuous or prismatic joint"),
        "{message}"
    );
}

fn import_text(text: &str) -> Result<Imported, gecaro_io::Error> {
    gecaro_io::import_robot_text(
        text,
        Path::new("arm.urdf"),
        &ImportOptions {
            format: Some(RobotFormat::Urdf),
            ..ImportOptions::default()
        },
    )
}

const ARM: &str = r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="l3"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0.1 0 0.2" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <joint name="j3" type="revolute">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.4 0 0" rpy="0 0 0.3"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
    <mimic joint="j2" multiplier="-0.5" offset="0.1"/>
  </joint>
</robot>
"#;

#[test]
fn an_exact_mimic_becomes_a_coupling_with_the_urdf_s_motion() {
    let imported = import_text(ARM).expect("valid");
    let robot = &imported.file.robot;
    assert_eq!(robot.joint_coupling()[(2, 1)], -0.5);
    assert_eq!(robot.joints()[2].offset, 0.1);
    assert!(
        imported
            .notes
            .iter()
            .any(|note| note.contains("mimics `j2`")),
        "{:?}",
        imported.notes
    );
    // By hand: q3 = −0.5·q2 + 0.1 at qm3 = 0, against the URDF chain through k.
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("arm.urdf");
    std::fs::write(&path, ARM).expect("write");
    let chain = k::Chain::<f64>::from_urdf_file(&path).expect("k reads it");
    for (q1, q2) in [(0.3, -0.4), (-1.1, 0.9)] {
        chain
            .set_joint_positions(&[q1, q2, 0.0])
            .expect("within limits");
        chain.update_transforms();
        let expected = from_k(
            &chain
                .find_link("l3")
                .expect("l3")
                .world_transform()
                .expect("updated"),
        )
        .to_homogeneous();
        let got = terminal_pose(robot, &[q1, q2, 0.0])
            .expect("valid")
            .to_homogeneous();
        assert!((expected - got).abs().max() < 1e-12);
    }
}

#[test]
fn malformed_files_name_the_line_and_element() {
    let cases: Vec<(String, &str, &str)> = vec![
        (ARM.replace("<link name=\"l3\"/>", "<link name=\"l3\">"), "arm.urdf:26: not well-formed XML", "expected `</link>`, but `</robot>` was found"),
        (ARM.replace("type=\"revolute\">\n    <parent link=\"l2\"", "type=\"revolut\">\n    <parent link=\"l2\""), "arm.urdf:19:", "revolut"),
        (ARM.replace("<axis xyz=\"0 0 1\"/>\n    <limit lower=\"-2\" upper=\"2\" effort=\"1\" velocity=\"1\"/>\n    <mimic", "<axis xyz=\"0 0 0\"/>\n    <limit lower=\"-2\" upper=\"2\" effort=\"1\" velocity=\"1\"/>\n    <mimic"), "arm.urdf:19: joint \"j3\":", "has no direction"),
        (ARM.replace("xyz=\"0.4 0 0\"", "xyz=\"0.4 nan 0\""), "joint \"j3\"", "not a finite number"),
        (ARM.replace("type=\"revolute\">\n    <parent link=\"l1\"", "type=\"floating\">\n    <parent link=\"l1\""), "joint \"j2\"", "choose a base link below it"),
        (ARM.replace("<child link=\"l3\"/>", "<child link=\"l1\"/>"), "joint \"j3\"", "closed loop"),
        (ARM.replace("<parent link=\"l2\"/>", "<parent link=\"l9\"/>"), "joint \"j3\"", "`l9` is not a <link>"),
        (ARM.replace("<mimic joint=\"j2\"", "<mimic joint=\"j7\""), "joint \"j3\"", "mimics joint `j7`"),
        ("<robot name=\"x\"><xacro:macro name=\"m\"/></robot>".into(), "arm.urdf:1:", "expand it first"),
        ("plain text".into(), "arm.urdf:", "not a valid URDF"),
    ];
    for (text, place, words) in cases {
        let message = import_text(&text).expect_err("malformed").to_string();
        assert!(
            message.contains(place) && message.contains(words),
            "{message}"
        );
    }
}

#[test]
fn a_urdf_file_gives_an_ordinary_robot_file() {
    let imported = import("kuka_kr16_2.urdf", None, None).expect("imports");
    let text = gecaro_io::format_robot_file(&imported.file);
    let again = gecaro_io::parse_robot_file(&text, Path::new("kr16.toml")).expect("reads back");
    assert_eq!(again.robot, imported.file.robot);
    assert_eq!(again.robot.frames()[1].frame_type, FrameType::Revolute);
    // The link frames are written as quaternions: equal to rounding.
    let (names, read) = (
        imported.file.urdf.expect("names"),
        again.urdf.expect("names"),
    );
    for (a, b) in names.joints.iter().zip(&read.joints) {
        assert_eq!((&a.name, &a.link), (&b.name, &b.link));
        assert!(
            (a.frame_from_link.to_homogeneous() - b.frame_from_link.to_homogeneous())
                .abs()
                .max()
                < 1e-15
        );
    }
}

/// Writes a URDF text to a temporary file for k.
fn temporary_urdf(text: &str) -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().expect("temporary folder");
    let path = folder.path().join("exported.urdf");
    std::fs::write(&path, text).expect("write");
    (folder, path)
}

/// The largest difference between gecaro's FK of `robot` at qm and k's FK
/// of the URDF file at `q_urdf(qm)` (all chain joints named in `names`).
fn exported_difference(
    robot: &Robot,
    urdf: &Path,
    base: &str,
    tip: &str,
    names: &[String],
    q_urdf: impl Fn(&[f64]) -> Vec<f64>,
    seed: u64,
) -> f64 {
    let chain = k::Chain::<f64>::from_urdf_file(urdf).expect("k reads the export");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = 0.0_f64;
    for _ in 0..100 {
        let qm: Vec<f64> = robot
            .joints()
            .iter()
            .map(|joint| rng.random_range(joint.qmin..=joint.qmax) - joint.offset)
            .collect();
        for (name, q) in names.iter().zip(q_urdf(&qm)) {
            chain
                .find(name)
                .expect("joint")
                .set_joint_position_unchecked(q);
        }
        chain.update_transforms();
        let world = |link: &str| {
            from_k(
                &chain
                    .find_link(link)
                    .map_or_else(k::Isometry3::identity, |n| {
                        n.world_transform().expect("updated")
                    }),
            )
        };
        let expected = world(base).inverse() * world(tip);
        let got = terminal_pose(robot, &qm).expect("valid");
        worst = worst.max(
            (expected.to_homogeneous() - got.to_homogeneous())
                .abs()
                .max(),
        );
    }
    worst
}

/// A calibrated-looking robot: β on every frame, offsets, perturbed lengths (K = 1).
fn calibrated(robot: &Robot, rng: &mut ChaCha8Rng) -> Robot {
    let mut spec = robot.to_spec();
    for frame in spec.frames.iter_mut().skip(1) {
        frame.alpha += rng.random_range(-0.01..0.01);
        frame.d += rng.random_range(-0.005..0.005);
        frame.theta += rng.random_range(-0.01..0.01);
        frame.r += rng.random_range(-0.005..0.005);
        frame.beta = rng.random_range(-0.005..0.005);
    }
    for joint in &mut spec.joints {
        joint.offset = rng.random_range(-0.02..0.02);
    }
    Robot::new(spec).expect("valid")
}

#[test]
fn calibrated_robots_export_to_urdf_and_read_back_with_the_same_direct_model() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut robots: Vec<gecaro_io::RobotFile> = [
        "stanford",
        "puma560",
        "panda",
        "scara",
        "ur10e",
        "industrial6",
    ]
    .iter()
    .map(|name| gecaro_io::load_robot(name).expect("ready"))
    .collect();
    robots.push(
        import("kuka_kr16_2.urdf", None, None)
            .expect("imports")
            .file,
    );
    robots.push(
        import(
            "pr2.urdf",
            Some("base_footprint"),
            Some("r_gripper_tool_frame"),
        )
        .expect("imports")
        .file,
    );
    for file in robots {
        let robot = calibrated(&file.robot, &mut rng);
        let file = gecaro_io::RobotFile {
            robot: robot.clone(),
            ..file
        };
        let exported = gecaro_io::export_robot(&file, RobotFormat::Urdf).expect("exports");
        assert!(
            exported.joint_calibration.is_none(),
            "{}: K = 1, no coupling",
            robot.name()
        );
        let (_folder, path) = temporary_urdf(&exported.text);
        let names: Vec<String> = match &file.urdf {
            Some(kept) => kept.joints.iter().map(|joint| joint.name.clone()).collect(),
            None => (1..=robot.joint_count())
                .map(|j| format!("joint_{j}"))
                .collect(),
        };
        let (base, tip) = file
            .urdf
            .as_ref()
            .map_or(("base_link".to_owned(), "tool0".to_owned()), |kept| {
                (kept.base_link.clone(), kept.tip_link.clone())
            });
        // k on the exported URDF: its joint values are the motor values (q − offset).
        let worst = exported_difference(&robot, &path, &base, &tip, &names, |qm| qm.to_vec(), 4);
        assert!(
            worst < 1e-12,
            "{}: exported URDF differs by {worst:e}",
            robot.name()
        );
        // And gecaro reads it back to the same direct model.
        let back = import_robot(&path, &ImportOptions::default())
            .unwrap_or_else(|error| panic!("{}: {error}", robot.name()))
            .file
            .robot;
        let mut rng_q = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..100 {
            let qm: Vec<f64> = robot
                .joints()
                .iter()
                .map(|j| rng_q.random_range(j.qmin..=j.qmax) - j.offset)
                .collect();
            let (a, b) = (
                terminal_pose(&robot, &qm).expect("a"),
                terminal_pose(&back, &qm).expect("b"),
            );
            assert!(
                (a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-12,
                "{}",
                robot.name()
            );
        }
        if file.urdf.is_none() {
            assert!(
                exported.notes.iter().any(|note| note.contains("folded")),
                "{:?}",
                exported.notes
            );
        }
    }
}

#[test]
fn an_imported_urdf_exports_with_its_names_and_link_frames() {
    // Every link of the original chain stays where it was: the export can
    // replace the chain in its ROS description.
    let file = import("kuka_kr16_2.urdf", None, None)
        .expect("imports")
        .file;
    let exported = gecaro_io::export_robot(&file, RobotFormat::Urdf).expect("exports");
    let (_folder, path) = temporary_urdf(&exported.text);
    let original = k::Chain::<f64>::from_urdf_file(data("kuka_kr16_2.urdf")).expect("original");
    let written = k::Chain::<f64>::from_urdf_file(&path).expect("export");
    let links = [
        "base_link",
        "link_1",
        "link_2",
        "link_3",
        "link_4",
        "link_5",
        "link_6",
        "tool0",
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for _ in 0..20 {
        let q: Vec<f64> = file
            .robot
            .joints()
            .iter()
            .map(|j| rng.random_range(j.qmin..=j.qmax))
            .collect();
        for chain in [&original, &written] {
            for (j, value) in q.iter().enumerate() {
                chain
                    .find(&format!("joint_a{}", j + 1))
                    .expect("joint")
                    .set_joint_position_unchecked(*value);
            }
            chain.update_transforms();
        }
        for link in links {
            let pose = |chain: &k::Chain<f64>| {
                from_k(
                    &chain
                        .find_link(link)
                        .map_or_else(k::Isometry3::identity, |n| {
                            n.world_transform().expect("updated")
                        }),
                )
            };
            let difference = (pose(&original).to_homogeneous() - pose(&written).to_homogeneous())
                .abs()
                .max();
            assert!(difference < 1e-12, "link {link}: {difference:e}");
        }
    }
    assert!(
        exported.text.contains("name=\"joint_a6-tool0\""),
        "{}",
        exported.text
    );
}

#[test]
fn gains_go_to_a_joint_calibration_and_mimics_stay_mimics() {
    let mut file = import("kuka_kr16_2.urdf", None, None)
        .expect("imports")
        .file;
    let mut spec = file.robot.to_spec();
    spec.joints[1].gain = 1.002;
    file.robot = Robot::new(spec).expect("valid");
    let exported = gecaro_io::export_robot(&file, RobotFormat::Urdf).expect("exports");
    let calibration = exported
        .joint_calibration
        .as_deref()
        .expect("K ≠ 1 has to go somewhere");
    assert!(
        calibration.contains("1.002") && calibration.contains("joint_a2"),
        "{calibration}"
    );
    assert!(
        exported
            .notes
            .iter()
            .any(|note| note.contains("not expressible"))
    );
    let (_folder, path) = temporary_urdf(&exported.text);
    let names: Vec<String> = (1..=6).map(|j| format!("joint_a{j}")).collect();
    let map = file.robot.motor_to_joint().clone();
    let worst = exported_difference(
        &file.robot,
        &path,
        "base_link",
        "tool0",
        &names,
        |qm| {
            (&map * nalgebra::DVector::from_column_slice(qm))
                .as_slice()
                .to_vec()
        },
        6,
    );
    assert!(worst < 1e-12, "{worst:e}");

    let arm = import_text(ARM).expect("valid").file;
    let exported = gecaro_io::export_robot(&arm, RobotFormat::Urdf).expect("exports");
    assert!(exported.joint_calibration.is_none());
    assert!(
        exported
            .text
            .contains("<mimic joint=\"j2\" multiplier=\"-0.5\" offset=\"0.1\""),
        "{}",
        exported.text
    );
    let back = import_text(&exported.text).expect("reads back").file.robot;
    assert_eq!(back.joint_coupling(), arm.robot.joint_coupling());
}

#[test]
fn a_reframed_robot_exports_its_original_base_and_tip_links() {
    let file = import("ur10e.urdf", None, Some("tool0"))
        .expect("imports")
        .file;
    let tilt = IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(0.1, -0.2, 0.3),
        nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::x_axis(), 0.7),
    );
    let robot = file.robot.reframed(&tilt, &tilt).expect("valid");
    let names = file
        .urdf
        .as_ref()
        .expect("names")
        .reframed(&file.robot, &robot, &tilt, &tilt);
    let reframed = gecaro_io::RobotFile {
        robot: robot.clone(),
        urdf: Some(names),
        ..file.clone()
    };
    let exported = gecaro_io::export_robot(&reframed, RobotFormat::Urdf).expect("exports");
    // This URDF's base link is itself called `world`: the new root takes another name.
    assert!(
        exported.text.contains("<link name=\"gecaro_world\""),
        "{}",
        exported.text
    );
    let (_folder, path) = temporary_urdf(&exported.text);
    let joints: Vec<String> = file
        .urdf
        .as_ref()
        .expect("names")
        .joints
        .iter()
        .map(|j| j.name.clone())
        .collect();
    // `world` (the original base link) → tool0 of the export is the original chain.
    let worst = exported_difference(
        &file.robot,
        &path,
        "world",
        "tool0",
        &joints,
        |qm| qm.to_vec(),
        2,
    );
    assert!(worst < 1e-12, "{worst:e}");
}

/// A reflector stated in the robot's tool frame n+1 — an imported URDF's
/// `tool0` — not in Khalil–Kleinfinger's frame n, which the import may
/// turn: on the KR16-2, `tool0` is turned 90° about y from link 6. Points
/// computed by k (`tool0` · p) are what the imported robot's frame n+1
/// gives with the reflector stated at p (a study's named tool is stated in
/// frame n+1: `gecaro_calib::frames`); stated in frame n, 5 cm off or more.
#[test]
fn a_reflector_is_stated_in_the_urdf_s_tool0() {
    let file = "kuka_kr16_2.urdf";
    let imported = check(file, "base_link", None, "tool0", "RRRRRR");
    let robot = &imported.file.robot;
    let names = imported.file.urdf.as_ref().expect("URDF names kept");
    // Frame n (6) and frame n+1 (tool0) differ: a statement in one is not
    // one in the other.
    let last = robot.frames().len() - 1;
    let tool0_in_frame_n = gecaro_core::frame_transform(&robot.frames()[last], 0.0);
    assert!(
        tool0_in_frame_n.rotation.angle() > 1.0,
        "frame n is tool0 here: {tool0_in_frame_n:?}"
    );
    let reflector = nalgebra::Point3::new(0.04, 0.025, 0.09);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut in_tool0, mut in_frame_n) = (0.0f64, f64::INFINITY);
    for _ in 0..20 {
        let qm: Vec<f64> = robot
            .joints()
            .iter()
            .map(|joint| rng.random_range(joint.qmin..=joint.qmax))
            .collect();
        let q = robot.joint_positions(&qm).expect("valid");
        let positions: Vec<(String, f64)> = names
            .joints
            .iter()
            .zip(q.iter())
            .map(|(joint, q)| (joint.name.clone(), *q))
            .collect();
        let measured = k_pose(file, "base_link", "tool0", &positions) * reflector;
        let tool = terminal_pose(robot, &qm).expect("pose");
        in_tool0 = in_tool0.max((tool * reflector - measured).norm());
        let frame_n = tool * tool0_in_frame_n.inverse();
        in_frame_n = in_frame_n.min((frame_n * reflector - measured).norm());
    }
    assert!(in_tool0 < 1e-9, "stated in tool0: {in_tool0} m");
    assert!(in_frame_n > 0.05, "stated in frame n: {in_frame_n} m");
}

/// An elastic robot with masses exported to URDF comes back whole: the
/// masses through each link's `<inertial>`, the compliances through the
/// joint calibration file; every joint carries the same gravity torque.
#[test]
fn an_elastic_robot_with_masses_round_trips_through_urdf() {
    let mut file = gecaro_io::load_robot("industrial6").expect("ready");
    file.robot
        .set_compliances(Some(vec![0.0, 6e-6, 9e-6, 4e-6, 7e-6, 3e-6]))
        .expect("elastic");
    let exported = gecaro_io::export_robot(&file, RobotFormat::Urdf).expect("exports");
    assert!(
        exported.text.contains("<mass value=\"12\""),
        "{}",
        exported.text
    );
    let calibration = exported.joint_calibration.expect("the compliances");
    let (_folder, path) = temporary_urdf(&exported.text);
    let mut back = import_robot(&path, &ImportOptions::default())
        .expect("imports")
        .file;
    gecaro_io::apply_joint_calibration(&mut back, &calibration, &path).expect("applies");
    assert_eq!(back.robot.compliances(), file.robot.compliances());
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let payload = gecaro_core::LinkMass {
        mass: 6.0,
        com: nalgebra::Vector3::new(0.0, 0.02, 0.08),
    };
    for _ in 0..20 {
        let qm: Vec<f64> = file
            .robot
            .joints()
            .iter()
            .map(|j| rng.random_range(j.qmin..=j.qmax))
            .collect();
        let torques = |file: &gecaro_io::RobotFile| {
            gecaro_core::gravity_torques(&file.robot, &file.masses, Some(&payload), &qm).expect("τ")
        };
        let (before, after) = (torques(&file), torques(&back));
        assert!(
            (&before - &after).amax() < 1e-9 * before.amax(),
            "{before} vs {after}"
        );
    }
}
