//! The arguments of `robot import`, `robot export` and `robot rebase`.

use std::path::PathBuf;

use clap::Args;

use super::common::*;

#[derive(Debug, Args)]
pub(crate) struct ImportArgs {
    /// The file: .urdf, .par, or a table (.toml with `convention`, or .csv with --from).
    pub(crate) file: PathBuf,
    /// Its format (default: from the extension, or the table's `convention`).
    #[arg(long, value_parser = names(&gecaro_io::RobotFormat::NAMES))]
    pub(crate) from: Option<String>,
    /// URDF: the link whose frame is the world frame (default: the root link).
    #[arg(long, value_name = "LINK")]
    pub(crate) base: Option<String>,
    /// URDF: the link whose frame is the end-effector frame n+1 (default: the
    /// leaf with the most moving joints).
    #[arg(long, value_name = "LINK")]
    pub(crate) tip: Option<String>,
    /// The robot's name (default: the file's).
    #[arg(long)]
    pub(crate) name: Option<String>,
    #[command(flatten)]
    pub(crate) units: UnitArgs,
    /// Output robot file.
    #[arg(short, long, value_name = "ROBOT.toml")]
    pub(crate) output: PathBuf,
    /// Overwrite the output file if it exists.
    #[arg(long)]
    pub(crate) force: bool,
}

#[derive(Debug, Args)]
pub(crate) struct ExportArgs {
    /// Robot file or ready robot name.
    pub(crate) robot: String,
    /// The format to write: urdf, dh, mdh or symoro.
    #[arg(long, value_parser = names(&gecaro_io::RobotFormat::NAMES))]
    pub(crate) to: String,
    /// Output file (.urdf, .toml for a table, .par for SYMORO).
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Export the robot re-expressed in this nominal robot's base frame (a
    /// robot calibrated in a tracker's frame; see `robot rebase`).
    #[arg(long, value_name = "NOMINAL")]
    pub(crate) rebase: Option<String>,
    /// Overwrite the output files if they exist.
    #[arg(long)]
    pub(crate) force: bool,
}

#[derive(Debug, Args)]
pub(crate) struct RebaseArgs {
    /// The calibrated robot (file), in the calibration's measurement frame.
    pub(crate) robot: String,
    /// The nominal robot (file or ready robot name), in the robot's own base frame.
    #[arg(long)]
    pub(crate) nominal: String,
    /// The base as its owner defines it: points measured in the calibration's frame
    /// (x,y,z) beside the same points in the base frame from the drawing
    /// (base_x,base_y,base_z), optionally named (name); at least 3 not on one line.
    /// Without it, the base is the nominal's convention (joint 1's axis, x towards axis 2).
    #[arg(long, value_name = "POINTS.csv")]
    pub(crate) base_points: Option<PathBuf>,
    /// The base as its maker defines it, measured by circles: a position data file
    /// (qm1..qmn,x,y,z) of a point on the arm while joint 1 turned alone, and while joint 2
    /// turned alone with joint 1 held (at least 4 points each). z along axis 1, the origin
    /// where the common normal of axes 1 and 2 meets it, x along that normal at joint 1's zero,
    /// placed as the nominal robot places them.
    #[arg(long, value_name = "CIRCLES.csv", conflicts_with = "base_points")]
    pub(crate) base_circles: Option<PathBuf>,
    /// Units and column names of the base-points or circles file.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// Output robot file: the calibrated robot in its own base frame.
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Overwrite the output file if it exists.
    #[arg(long)]
    pub(crate) force: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}
