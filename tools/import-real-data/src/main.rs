//! Converts the measured datasets of `shared/realdata` into gecaro's formats
//! under `examples/real/` (robot TOML, data CSV, study TOML, README, licence).
//!
//! ```sh
//! cargo run -p import-real-data -- ../shared/realdata examples/real
//! ```
//!
//! Decisions (see docs/real-data.md):
//! - Nominal robots are the datasets' verified URDF tables (YAML, full
//!   precision) with design values for the unknown frames: the URDF world and
//!   camera frames (UR10e), the documented board position and camera mount
//!   rounded to a centimetre and a degree (FR3).
//! - Where a world or tool z axis is (nearly) parallel to a joint axis, the
//!   Khalil table puts the common normal far away or loses a degree of
//!   freedom; the world and tool frames are re-expressed by known rotations
//!   (`Robot::reframed`), applied exactly to the measurements too: world and
//!   camera frames tilted 45° about their x axes; ball tools (points, whose
//!   frame orientation is free) tilted 30° so that θ_n does not rest on the
//!   ball's 0.1 mm offset from the last axis.
//! - Held-out data: whole tool placements for the ball datasets (every other
//!   placement), every third pose for the camera datasets.

use gecaro_calib::study::{DataColumn, Sample, Samples};
use gecaro_core::{Frame, FrameType, Joint, Robot, RobotSpec};
use gecaro_io::{OutputPolicy, RobotFile, format_robot_file, format_samples, write_atomically};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use std::error::Error;
use std::fmt::Write as _;
use std::path::Path;

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// A configuration and the measured pose of the camera there.
type Pose = (Vec<f64>, IsometryMatrix3<f64>);

/// Tilt of re-expressed world and camera frames.
const FRAME_TILT_DEGREES: f64 = 45.0;
/// Tilt of re-expressed ball (point) tool frames.
const BALL_TILT_DEGREES: f64 = 30.0;
/// Distance between the two socket centres of a MUKCa placement (m).
const SOCKET_DISTANCE: f64 = 0.050;

fn main() -> Result<()> {
    let arguments: Vec<String> = std::env::args().collect();
    let [_, source, output] = arguments.as_slice() else {
        eprintln!("usage: import-real-data SHARED_REALDATA_FOLDER OUTPUT_FOLDER");
        std::process::exit(2);
    };
    let (source, output) = (Path::new(source), Path::new(output));
    std::fs::create_dir_all(output)?;
    for (name, robot, limits) in [
        ("panda_3", "panda", panda_limits()),
        ("dinova_2", "gen3lite", gen3lite_limits()),
    ] {
        import_mukca(source, output, name, robot, &limits)?;
    }
    import_ur10e(source, output)?;
    import_fr3(source, output)?;
    println!("wrote {}", output.display());
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, text.as_bytes(), OutputPolicy::Overwrite)?;
    Ok(())
}

fn copy(from: &Path, to: &Path) -> Result<()> {
    write(to, &std::fs::read_to_string(from)?)
}

/// A nominal robot from a `[j, sigma, alpha, d, theta, r, beta, K]` YAML table.
fn table_robot(path: &Path, name: &str, limits: &[(f64, f64)]) -> Result<Robot> {
    let text = std::fs::read_to_string(path)?;
    let mut frames = Vec::new();
    for line in text.lines() {
        let Some(start) = line.find('[') else {
            continue;
        };
        if !line.trim_start().starts_with("- [") {
            continue;
        }
        let end = line[start..].find(']').ok_or("unterminated row")? + start;
        let values: Vec<f64> = line[start + 1..end]
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()?;
        let [_, sigma, alpha, d, theta, r, beta, _] = values.as_slice() else {
            return Err(format!("{}: a row needs 8 values: {line}", path.display()).into());
        };
        let frame_type = FrameType::from_sigma(*sigma as i64).ok_or("bad sigma")?;
        frames.push(Frame {
            frame_type,
            alpha: *alpha,
            d: *d,
            theta: *theta,
            r: *r,
            beta: *beta,
        });
    }
    let joints = limits
        .iter()
        .map(|(qmin, qmax)| Joint {
            qmin: *qmin,
            qmax: *qmax,
            offset: 0.0,
            gain: 1.0,
        })
        .collect();
    Ok(Robot::new(RobotSpec::rigid(
        name.to_owned(),
        frames,
        joints,
    ))?)
}

fn tilt_x(degrees: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::identity(),
        Rotation3::from_axis_angle(&Vector3::x_axis(), degrees.to_radians()),
    )
}

fn panda_limits() -> Vec<(f64, f64)> {
    vec![
        (-2.8973, 2.8973),
        (-1.7628, 1.7628),
        (-2.8973, 2.8973),
        (-3.0718, -0.0698),
        (-2.8973, 2.8973),
        (-0.0175, 3.7525),
        (-2.8973, 2.8973),
    ]
}

/// Gen3 lite limits of `urdf/gen3lite_ideal.urdf` (joint_1..joint_6).
fn gen3lite_limits() -> Vec<(f64, f64)> {
    vec![
        (-2.68, 2.68),
        (-2.61, 2.61),
        (-2.61, 2.61),
        (-2.57, 2.57),
        (-2.53, 2.53),
        (-2.09, 2.09),
    ]
}

/// Reads a headerless CSV of joint angles (one configuration per line).
fn read_configurations(path: &Path) -> Result<Vec<Vec<f64>>> {
    let text = std::fs::read_to_string(path)?;
    text.lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            line.split(',')
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .map_err(|e| format!("{}: {e}: {line}", path.display()).into())
                })
                .collect()
        })
        .collect()
}

/// One socket group: configurations that put the ball at the same point.
struct Socket {
    placement: String,
    hole: usize,
    configurations: Vec<Vec<f64>>,
    /// Whether its point can pair with the other hole of the placement.
    pairs: bool,
}

fn import_mukca(
    source: &Path,
    output: &Path,
    set: &str,
    robot_name: &str,
    limits: &[(f64, f64)],
) -> Result<()> {
    let folder = source.join("mukca_pointlink");
    let table = folder.join(format!("mdh_{robot_name}_urdf_ball.yaml"));
    let nominal = table_robot(
        &table,
        &format!("{robot_name} with ball (MUKCa {set})"),
        limits,
    )?;
    // The ball is a point: tilting its frame changes no position, and gives θ_n
    // a well-defined meaning (the ball is ~0.1 mm from the last axis).
    let robot = nominal.reframed(&IsometryMatrix3::identity(), &tilt_x(BALL_TILT_DEGREES))?;
    let mut placements: Vec<String> = std::fs::read_dir(folder.join("data").join(set))?
        .filter_map(|entry| entry.ok())
        .filter(|entry| entry.path().is_dir())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    placements.sort();
    let mut sockets = Vec::new();
    for placement in &placements {
        for hole in 0..2 {
            let path = folder
                .join("data")
                .join(set)
                .join(placement)
                .join(format!("hole_{hole}.csv"));
            let configurations = read_configurations(&path)?;
            if set == "dinova_2" && placement == "front_rotated" && hole == 1 {
                // comments.txt: the tool fell off after 11 points: two sockets.
                let (first, second) = configurations.split_at(11);
                for part in [first, second] {
                    sockets.push(Socket {
                        placement: placement.clone(),
                        hole,
                        configurations: part.to_vec(),
                        pairs: false,
                    });
                }
                continue;
            }
            sockets.push(Socket {
                placement: placement.clone(),
                hole,
                configurations,
                pairs: true,
            });
        }
    }
    let out = output.join(format!("mukca_{set}"));
    std::fs::create_dir_all(&out)?;
    let n = robot.joint_count();
    let priority = robot.priority();
    let mut summary = String::new();
    for (part, held_out) in [("train", false), ("test", true)] {
        let chosen: Vec<&String> = placements
            .iter()
            .enumerate()
            .filter(|(index, _)| (index % 2 == 1) == held_out)
            .map(|(_, placement)| placement)
            .collect();
        let mut sets = Vec::new();
        let mut pairs = Vec::new();
        let mut pair_id = 0;
        for (socket_id, socket) in sockets.iter().enumerate() {
            if !chosen.contains(&&socket.placement) {
                continue;
            }
            for configuration in &socket.configurations {
                sets.push(Sample {
                    group: Some(socket_id as u64 + 1),
                    ..Sample::new(configuration.clone())
                });
            }
            if socket.hole == 0 && socket.pairs {
                let other = sockets
                    .iter()
                    .find(|s| s.placement == socket.placement && s.hole == 1 && s.pairs);
                if let Some(other) = other {
                    for (first, second) in socket.configurations.iter().zip(&other.configurations) {
                        pair_id += 1;
                        for configuration in [first, second] {
                            pairs.push(Sample {
                                group: Some(pair_id),
                                distance: Some(SOCKET_DISTANCE),
                                ..Sample::new(configuration.clone())
                            });
                        }
                    }
                }
            }
        }
        write(
            &out.join(format!("{part}_sets.csv")),
            &format_samples(
                n,
                &[DataColumn::Set],
                Samples::from(sets.as_slice()).as_slice(),
            ),
        )?;
        write(
            &out.join(format!("{part}_pairs.csv")),
            &format_samples(
                n,
                &[DataColumn::Pair, DataColumn::Distance],
                Samples::from(pairs.as_slice()).as_slice(),
            ),
        )?;
        let _ = writeln!(
            summary,
            "- `{part}_sets.csv`, `{part}_pairs.csv`: placements {} ({} configurations, {} pairs)",
            chosen
                .iter()
                .map(|p| format!("`{p}`"))
                .collect::<Vec<_>>()
                .join(", "),
            sets.len(),
            pairs.len() / 2
        );
    }
    write(
        &out.join("robot.toml"),
        &format_robot_file(&RobotFile {
            description: Some(format!(
                "{robot_name} with the MUKCa ball, nominal URDF table ({}), ball frame tilted {BALL_TILT_DEGREES}° about x",
                table
                    .file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default()
            )),
            ..RobotFile::of(robot)
        }),
    )?;
    write(
        &out.join("study.toml"),
        "# Point link (ball in a socket) and the 50 mm between the two sockets of a placement.\n\
         robot = \"robot.toml\"\n\n[[measurements]]\nmethod = \"point-link\"\ndata = \"train_sets.csv\"\n\
         sigma = 0.0003\n\n[[measurements]]\nmethod = \"distance\"\ndata = \"train_pairs.csv\"\nsigma = 0.0001\n",
    )?;
    copy(&folder.join("LICENSE"), &out.join("LICENSE"))?;
    // A light model for noisy arms: joint offsets and the ball only.
    let mut light = String::from(
        "# Joint offsets (theta_j) and the ball (theta_n, r_n, frame n+1) only: a light model for arms\n\
         # whose joint play would be learnt by a full model. Rows: frames 0..n+1; columns: alpha, d, theta, r, beta, K.\n\
         matrix = [\n",
    );
    for (frame, row) in priority.rows().iter().enumerate() {
        let keep = |column: usize| match frame {
            0 => false,
            j if j < n => column == 2,
            j if j == n => column == 2 || column == 3,
            _ => true,
        };
        let cells: Vec<String> = row
            .iter()
            .enumerate()
            .map(|(c, p)| if keep(c) { p.to_string() } else { "0".into() })
            .collect();
        let _ = writeln!(light, "    [{}],", cells.join(", "));
    }
    light.push_str("]\n");
    write(&out.join("priority_offsets.toml"), &light)?;
    write(
        &out.join("README.md"),
        &format!(
            "# MUKCa `{set}`: point link + distance, real measurements\n\n\
             Source: repository `platonics-delft/kinematics_calibration` (MUKCa), MIT licence (`LICENSE`),\n\
             copied data of `data/{set}/` as prepared in gecaro's `shared/realdata/mukca_pointlink`.\n\
             A ball on the robot's flange sits in one of two sockets 50 mm apart; each socket of each tool\n\
             placement is a point-link set, each placement gives distance pairs (50 mm).\n\n\
             Converted by `cargo run -p import-real-data -- ../shared/realdata examples/real`.\n\n{summary}\n\
             Calibrate on the training placements and check the held-out ones:\n\n```sh\n\
             gecaro identify --study study.toml -o calibrated.toml\n\
             gecaro evaluate robot.toml --method point-link --data test_sets.csv\n\
             gecaro evaluate calibrated.toml --method point-link --data test_sets.csv\n\
             gecaro evaluate calibrated.toml --method distance --data test_pairs.csv\n```\n\n\
             `priority_offsets.toml` identifies only the joint offsets and the ball (`--priority`), a light\n\
             model for arms with joint play. Results: `docs/real-data.md`.\n"
        ),
    )?;
    Ok(())
}

/// Writes the frame-measure data of poses `world_from_camera` at configurations.
fn frame_samples(poses: &[Pose]) -> Vec<Sample> {
    poses
        .iter()
        .map(|(configuration, pose)| Sample {
            position: Some(pose.translation.vector),
            orientation: Some(UnitQuaternion::from_rotation_matrix(&pose.rotation)),
            ..Sample::new(configuration.clone())
        })
        .collect()
}

/// Writes a camera dataset: robot, training and held-out data (every third
/// pose), a priority file for the base and camera frames only, a README.
fn write_camera_example(
    out: &Path,
    robot: Robot,
    description: &str,
    poses: &[Pose],
    readme: &str,
) -> Result<()> {
    std::fs::create_dir_all(out)?;
    let n = robot.joint_count();
    let columns = [DataColumn::Position, DataColumn::Orientation];
    let (train, test): (Vec<_>, Vec<_>) = poses
        .iter()
        .cloned()
        .enumerate()
        .partition(|(index, _)| index % 3 != 2);
    let strip =
        |list: Vec<(usize, Pose)>| list.into_iter().map(|(_, pose)| pose).collect::<Vec<_>>();
    let (train, test) = (strip(train), strip(test));
    write(
        &out.join("train.csv"),
        &format_samples(
            n,
            &columns,
            Samples::from(frame_samples(&train).as_slice()).as_slice(),
        ),
    )?;
    write(
        &out.join("test.csv"),
        &format_samples(
            n,
            &columns,
            Samples::from(frame_samples(&test).as_slice()).as_slice(),
        ),
    )?;
    // Base (frames 0, 1) and camera (joint n's offsets, frame n+1) only.
    let priority = robot.priority();
    let mut text = String::from(
        "# Identify only the measurement frame (frames 0, 1) and the camera frame (theta_n, r_n, frame n+1).\n\
         # Rows: frames 0..n+1; columns: alpha, d, theta, r, beta, K.\nmatrix = [\n",
    );
    for (frame, row) in priority.rows().iter().enumerate() {
        let keep = |column: usize| match frame {
            0 => true,
            1 => column < 5,
            j if j == n => column == 2 || column == 3,
            j if j == n + 1 => true,
            _ => false,
        };
        let cells: Vec<String> = row
            .iter()
            .enumerate()
            .map(|(c, p)| if keep(c) { p.to_string() } else { "0".into() })
            .collect();
        let _ = writeln!(text, "    [{}],", cells.join(", "));
    }
    text.push_str("]\n");
    write(&out.join("priority_frames.toml"), &text)?;
    let study = |priority: &str| {
        format!(
            "# Frame measure by a camera: about 3 mm and 0.6 degree.\nrobot = \"robot.toml\"\n{priority}\n\
             [[measurements]]\nmethod = \"frame\"\ndata = \"train.csv\"\nsigma = 0.003\nsigma_rotation = 0.01\n"
        )
    };
    write(&out.join("study.toml"), &study(""))?;
    write(
        &out.join("study_frames.toml"),
        &study("priority = \"priority_frames.toml\""),
    )?;
    write(
        &out.join("robot.toml"),
        &format_robot_file(&RobotFile {
            description: Some(description.to_owned()),
            ..RobotFile::of(robot)
        }),
    )?;
    write(
        &out.join("README.md"),
        &format!(
            "{readme}\n\nConverted by `cargo run -p import-real-data -- ../shared/realdata examples/real`:\n\
             `train.csv` ({} poses), `test.csv` ({} poses, every third one held out). World and camera frames are\n\
             re-expressed by known {FRAME_TILT_DEGREES}° tilts about their x axes (robot and measurements alike), so\n\
             that no measured axis is parallel to a joint axis (docs/real-data.md). `study_frames.toml` identifies\n\
             the measurement and camera frames only (`priority_frames.toml`), `study.toml` the whole model; both\n\
             weight the camera as 3 mm and 0.01 rad.\n\n```sh\n\
             gecaro identify --study study_frames.toml -o frames.toml\n\
             gecaro identify --study study.toml -o calibrated.toml\n\
             gecaro evaluate frames.toml --method frame --data test.csv\n\
             gecaro evaluate calibrated.toml --method frame --data test.csv\n```\n\nResults: `docs/real-data.md`.\n",
            train.len(),
            test.len()
        ),
    )?;
    Ok(())
}

fn import_ur10e(source: &Path, output: &Path) -> Result<()> {
    let folder = source.join("figaroh_ur10e_camera");
    let limits = vec![(-std::f64::consts::TAU, std::f64::consts::TAU); 6]
        .into_iter()
        .enumerate()
        .map(|(j, limit)| {
            if j == 2 {
                (-std::f64::consts::PI, std::f64::consts::PI)
            } else {
                limit
            }
        })
        .collect::<Vec<_>>();
    let nominal = table_robot(
        &folder.join("mdh_ur10e_urdfworld_camera.yaml"),
        "UR10e with wrist camera",
        &limits,
    )?;
    let (world, camera) = (tilt_x(FRAME_TILT_DEGREES), tilt_x(FRAME_TILT_DEGREES));
    let robot = nominal.reframed(&world, &camera)?;
    let text = std::fs::read_to_string(folder.join("calibration.csv"))?;
    let mut poses = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()?;
        let [x, y, z, roll, pitch, yaw, q @ ..] = values.as_slice() else {
            return Err("calibration.csv: 12 columns expected".into());
        };
        // R = Rz(yaw)·Ry(pitch)·Rx(roll) (pinocchio rpy).
        let measured = IsometryMatrix3::from_parts(
            Translation3::new(*x, *y, *z),
            Rotation3::from_euler_angles(*roll, *pitch, *yaw),
        );
        poses.push((q.to_vec(), world * measured * camera));
    }
    std::fs::create_dir_all(output.join("ur10e_camera"))?;
    copy(
        &folder.join("LICENSE-figaroh-Apache-2.0"),
        &output
            .join("ur10e_camera")
            .join("LICENSE-figaroh-Apache-2.0"),
    )?;
    write_camera_example(
        &output.join("ur10e_camera"),
        robot,
        "UR10e, URDF world and URDF camera optical frame (design values), both tilted 45° about x",
        &poses,
        "# UR10e with a wrist camera: frame measure, real measurements\n\n\
         Source: repository `thanhndv212/figaroh-plus` (FIGAROH), `examples/ur10/data/calibration.csv`,\n\
         Apache-2.0 (`LICENSE-figaroh-Apache-2.0`), as prepared in gecaro's `shared/realdata/figaroh_ur10e_camera`.\n\
         23 poses of a RealSense camera on the wrist seen from a fixed target; the measurement frame and the\n\
         camera frame are unknown (the nominal robot starts from the URDF's world and optical frame).",
    )
}

fn import_fr3(source: &Path, output: &Path) -> Result<()> {
    let folder = source.join("philnad_fr3_camera");
    // The Panda's (= FR3's) nominal table with the flange panda_link8 as frame 8.
    let flange = gecaro_io::ready_robot("panda")
        .ok_or("no ready panda")??
        .robot;
    // Design values: the board about (-0.66, 0.59, 0.01) m from the base, axes
    // aligned (the fitted pose rounded to a centimetre and a degree); the
    // camera mount as documented by the source: (94.5, -9, 40.55) mm, 90° about z.
    let board_from_base =
        IsometryMatrix3::from_parts(Translation3::new(-0.66, 0.59, 0.01), Rotation3::identity());
    let flange_from_camera = IsometryMatrix3::from_parts(
        Translation3::new(0.0945, -0.009, 0.04055),
        Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
    );
    let (world, camera) = (tilt_x(FRAME_TILT_DEGREES), tilt_x(FRAME_TILT_DEGREES));
    let mut robot = flange.reframed(&(world * board_from_base), &(flange_from_camera * camera))?;
    robot.set_name("Franka Research 3 with wrist camera");
    let text = std::fs::read_to_string(folder.join("fr3_camera_in_board.csv"))?;
    let mut poses = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()?;
        let (q, rest) = values.split_at(7);
        let [x, y, z, qx, qy, qz, qw, ..] = rest else {
            return Err("fr3_camera_in_board.csv: 21 columns expected".into());
        };
        let rotation =
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(*qw, *qx, *qy, *qz))
                .to_rotation_matrix();
        let measured = IsometryMatrix3::from_parts(Translation3::new(*x, *y, *z), rotation);
        poses.push((q.to_vec(), world * measured * camera));
    }
    let out = output.join("fr3_camera");
    std::fs::create_dir_all(&out)?;
    copy(&folder.join("LICENSE"), &out.join("LICENSE"))?;
    write_camera_example(
        &out,
        robot,
        "Franka Research 3 (Panda table), board frame and camera frame from design values, both tilted 45° about x",
        &poses,
        "# Franka Research 3 with a wrist camera: frame measure, real measurements\n\n\
         Source: repository `PhilNad/robot-arm-kinematic-calibration`, `Examples/calib_data.pickle`, MIT\n\
         (`LICENSE`), as converted in gecaro's `shared/realdata/philnad_fr3_camera` (camera pose in the board\n\
         frame). 114 poses of a RealSense D405 on the flange pointing at a fixed board; the board and\n\
         camera frames start from design values (the board's documented place rounded to 1 cm and 1°, the\n\
         source's camera mount).",
    )
}
