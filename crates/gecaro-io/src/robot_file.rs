//! A robot as a file holds it: the robot and what only the file knows (its
//! description, the unit its angles were written in, the URDF names it came
//! from). Robot files themselves are TOML ([`crate::robot_toml`]).

use std::path::{Path, PathBuf};

use gecaro_core::{JointRegion, MassModel, Robot};
use nalgebra::{IsometryMatrix3, Vector3};

use crate::urdf::names::UrdfNames;

/// The unit of the angles written in a robot file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum AngleUnit {
    /// Radians (the default, and what gecaro writes).
    #[default]
    Radians,
    /// Degrees (`angle_unit = "deg"`).
    Degrees,
}

/// A robot as read from or written to a file, with the file-only details.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotFile {
    /// The robot.
    pub robot: Robot,
    /// Free text kept from the file's `description` key.
    pub description: Option<String>,
    /// The unit the file's angles were written in.
    pub angle_unit: AngleUnit,
    /// The names and link frames of the URDF the robot was imported from
    /// (the `[urdf]` table), for writing it back.
    pub urdf: Option<UrdfNames>,
    /// The masses its frames carry and gravity (`mass`, `com` of a frame,
    /// `gravity`): the loads of elastic joints. None stated by default.
    pub masses: MassModel,
    /// The region of the joint space a calibration's data covered (each
    /// joint frame's `measured` range), when the calibrated robot holds
    /// there only: compensation and evaluation flag poses outside it.
    pub measured_region: Option<JointRegion>,
    /// The tools a calibration identified with the robot (a study's
    /// reflectors, the `[tools]` table), each posed in frame n+1: what
    /// `compensate --tool NAME` compensates.
    pub tools: Vec<IdentifiedTool>,
    /// Whether the calibration that made this robot observed its frame
    /// n+1; `false` (`tool_frame_observed = false`) when every set
    /// measured a named tool, so frame n+1 kept its nominal pose and only
    /// the tools' poses in it are calibrated (docs/studies.md).
    pub tool_frame_observed: bool,
}

/// A tool identified with a robot: its name and its pose in the robot's
/// tool frame n+1 (metres).
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifiedTool {
    /// Its name (a study's `[tools.NAME]`).
    pub name: String,
    /// Its pose in frame n+1.
    pub pose: IsometryMatrix3<f64>,
}

impl RobotFile {
    /// The file of `robot` alone: no description, angles in radians, no
    /// URDF names, no masses (for the other fields, `..RobotFile::of(robot)`).
    pub fn of(robot: Robot) -> Self {
        let masses = MassModel::new(robot.frames().len());
        RobotFile {
            robot,
            description: None,
            angle_unit: AngleUnit::Radians,
            urdf: None,
            masses,
            measured_region: None,
            tools: Vec::new(),
            tool_frame_observed: true,
        }
    }

    /// The gravity the file states (m/s², world frame): the masses' gravity
    /// leaning by the robot's gravity tilts, which an identification with
    /// `elastic-gravity` moves and a file read holds at zero
    /// ([`MassModel::tilted`]). What both writers write.
    pub fn stated_gravity(&self) -> Vector3<f64> {
        self.masses.tilted(self.robot.gravity_tilt()).gravity()
    }

    /// The same file with the robot's gravity tilts folded into the masses'
    /// gravity and the robot holding none: the model unchanged, as a file
    /// states it.
    pub fn with_gravity_tilt_folded(mut self) -> Self {
        self.masses = self.masses.tilted(self.robot.gravity_tilt());
        self.robot = self.robot.untilted();
        self
    }
}

/// The robot's name for a file without `name`: the file's stem.
pub fn fallback_name(path: &Path) -> String {
    path.file_stem().map_or_else(
        || "robot".into(),
        |stem| stem.to_string_lossy().into_owned(),
    )
}

/// A name for text that does not come from a file, such as a ready robot.
pub(crate) fn virtual_path(name: &str) -> PathBuf {
    PathBuf::from(format!("<{name}>"))
}
