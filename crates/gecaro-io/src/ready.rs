//! The library of ready robots shipped in the repository's `robots/` folder,
//! embedded in the binary so that `gecaro fk stanford ...` works anywhere.

use std::path::Path;

use crate::Error;
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::parallel_file::{ParallelRobotFile, is_parallel_robot_text, parse_parallel_robot_file};
use crate::robot_file::{RobotFile, virtual_path};
use crate::robot_toml::{parse_robot_file, read_robot_file};

/// A robot of the library.
#[derive(Copy, Clone, Debug)]
pub struct ReadyRobot {
    /// The name to use on the command line (`stanford`).
    pub name: &'static str,
    /// The robot file's text.
    pub text: &'static str,
}

macro_rules! ready {
    ($($name:literal),* $(,)?) => {
        &[$(ReadyRobot { name: $name, text: include_str!(concat!("../../../robots/", $name, ".toml")) }),*]
    };
}

const READY: &[ReadyRobot] = ready![
    "stanford",
    "puma560",
    "industrial6",
    "scara",
    "panda",
    "ur10e"
];

/// The ready parallel robots ([`crate::ParallelRobotFile`]s).
const READY_PARALLEL: &[ReadyRobot] = ready!["hexapod", "delta"];

/// All ready parallel robots, in the order they are listed to users.
pub fn ready_parallel_robots() -> &'static [ReadyRobot] {
    READY_PARALLEL
}

/// The ready parallel robot called `name` (case-insensitive), parsed;
/// `None` when there is no such ready robot.
///
/// # Errors
/// Never for the shipped files (every ready robot is tested), but the parse
/// error is passed on rather than hidden.
pub fn ready_parallel_robot(name: &str) -> Option<Result<ParallelRobotFile, Error>> {
    READY_PARALLEL
        .iter()
        .find(|ready| ready.name.eq_ignore_ascii_case(name))
        .map(|ready| parse_parallel_robot_file(ready.text, &virtual_path(ready.name)))
}

/// A parallel robot from a path or, when no such file exists, a ready
/// parallel robot's name.
///
/// # Errors
/// [`Error::UnknownRobot`] (listing the ready parallel robots) when neither
/// exists, a serial robot's file named as such, and the file's own errors.
pub fn load_parallel_robot(path_or_name: &str) -> Result<ParallelRobotFile, Error> {
    let path = Path::new(path_or_name);
    let (text, path) = if path.is_file() {
        (read_text(path, MAX_DESCRIPTION_BYTES)?, path.to_owned())
    } else {
        return ready_parallel_robot(path_or_name).unwrap_or_else(|| {
            Err(Error::UnknownRobot {
                name: path_or_name.to_owned(),
                available: READY_PARALLEL
                    .iter()
                    .map(|ready| ready.name.to_owned())
                    .collect(),
            })
        });
    };
    if !is_parallel_robot_text(&text) {
        return Err(Error::Format {
            path,
            message: "a serial robot's file (no `kind = \"parallel\"`), where a parallel robot's \
                      is read"
                .into(),
        });
    }
    parse_parallel_robot_file(&text, &path)
}

/// All ready robots, in the order they are listed to users.
pub fn ready_robots() -> &'static [ReadyRobot] {
    READY
}

/// The ready robot called `name` (case-insensitive), parsed.
///
/// Returns `None` when there is no such ready robot.
///
/// # Errors
/// A ready parallel robot's name ([`Error::Format`]: a parallel robot where a
/// serial one is read, said so for every job and front end); never for the
/// shipped files otherwise (every ready robot is tested), but the parse
/// error is passed on rather than hidden.
pub fn ready_robot(name: &str) -> Option<Result<RobotFile, Error>> {
    if let Some(ready) = READY_PARALLEL
        .iter()
        .find(|ready| ready.name.eq_ignore_ascii_case(name))
    {
        return Some(Err(crate::robot_toml::parallel_robot_here(&virtual_path(
            ready.name,
        ))));
    }
    READY
        .iter()
        .find(|ready| ready.name.eq_ignore_ascii_case(name))
        .map(|ready| parse_robot_file(ready.text, &virtual_path(ready.name)))
}

/// A robot from a path or, when no such file exists, a ready robot's name.
///
/// # Errors
/// [`Error::UnknownRobot`] (listing the ready robots) when neither exists, and
/// the file's own errors otherwise.
pub fn load_robot(path_or_name: &str) -> Result<RobotFile, Error> {
    let path = Path::new(path_or_name);
    if path.is_file() {
        return read_robot_file(path);
    }
    ready_robot(path_or_name).unwrap_or_else(|| {
        if path.extension().is_some() || path_or_name.contains(std::path::MAIN_SEPARATOR) {
            // Looks like a path: say the file is missing rather than list robots only.
            Err(Error::Read {
                path: path.to_owned(),
                cause: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!(
                        "no such file (ready robots: {})",
                        READY.iter().map(|r| r.name).collect::<Vec<_>>().join(", ")
                    ),
                ),
            })
        } else {
            Err(Error::UnknownRobot {
                name: path_or_name.to_owned(),
                available: READY.iter().map(|ready| ready.name.to_owned()).collect(),
            })
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot_toml::format_robot_file;

    #[test]
    fn every_ready_robot_loads_and_round_trips() {
        for ready in ready_robots() {
            let file = ready_robot(ready.name)
                .expect("listed")
                .unwrap_or_else(|error| panic!("{}: {error}", ready.name));
            let again = parse_robot_file(&format_robot_file(&file), Path::new("again.toml"))
                .unwrap_or_else(|error| panic!("{}: {error}", ready.name));
            assert_eq!(file.robot.frames(), again.robot.frames(), "{}", ready.name);
            assert_eq!(file.robot.joints().len(), again.robot.joints().len());
            assert_eq!(file.masses, again.masses, "{}", ready.name);
        }
    }

    /// The industrial6's masses (a KR 6 class arm of about 52 kg) load its
    /// joints as such an arm's are: stretched out level, the shoulder holds
    /// 108 N·m, a 6 kg payload adds its m·g·L (56 N·m), and nothing turns
    /// about the vertical axis 1 (docs/elastic.md).
    #[test]
    fn the_industrial6_weighs_what_its_class_weighs() {
        let file = ready_robot("industrial6").expect("listed").expect("loads");
        let total: f64 = (0..file.robot.frames().len())
            .filter_map(|frame| file.masses.link(frame))
            .map(|link| link.mass)
            .sum();
        assert!((total - 51.3).abs() < 1e-9, "{total}");
        // Stretched out level: the upper arm along x at q2 = 0, the forearm
        // along it at q3 = −90° (the flange 0.98 m out, 35 mm above axis 2).
        let level = [0.0, 0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0];
        let arm =
            gecaro_core::gravity_torques(&file.robot, &file.masses, None, &level).expect("torques");
        let payload = gecaro_core::LinkMass {
            mass: 6.0,
            com: nalgebra::Vector3::zeros(),
        };
        let loaded =
            gecaro_core::gravity_torques(&file.robot, &file.masses, Some(&payload), &level)
                .expect("torques");
        assert!(arm[0].abs() < 1e-9, "axis 1 is vertical: {arm}");
        assert!((100.0..120.0).contains(&arm[1].abs()), "shoulder: {arm}");
        // A payload at the flange: m·g times its lever, the flange's x less
        // axis 2's (horizontal along y, 25 mm out).
        let flange = gecaro_core::forward_kinematics(&file.robot, &level)
            .expect("pose")
            .world_from_tool()
            .translation
            .vector;
        let lever = flange.x - 0.025;
        let added = (loaded[1] - arm[1]).abs();
        assert!(
            (added - 6.0 * gecaro_core::STANDARD_GRAVITY * lever).abs() < 1e-6,
            "{added} vs m·g·L = {}",
            6.0 * gecaro_core::STANDARD_GRAVITY * lever
        );
    }

    #[test]
    fn unknown_names_list_the_library() {
        let error = load_robot("stanfrod").expect_err("no such robot");
        let message = error.to_string();
        assert!(
            message.contains("stanford") && message.contains("puma560"),
            "{message}"
        );
    }
}
