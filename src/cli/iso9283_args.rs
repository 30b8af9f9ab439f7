//! The arguments of ISO 9283's acceptance test: its program planned, what
//! was measured evaluated.

use std::path::PathBuf;

use clap::{Args, Subcommand};

use super::common::*;

#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub(crate) enum Iso9283Command {
    /// Plan the test: the cube (stated, or the largest found), its five poses P1–P5 and the
    /// cycles as a program of joint values and commanded poses (columns pose, cycle,
    /// direction, measure, qm1..qmn, x,y,z[,qw,qx,qy,qz]); `compensate` corrects it for a
    /// calibrated robot, so that before and after run the same test.
    Plan(Iso9283PlanArgs),
    /// Evaluate the test from what was measured: per pose AP and RP (position and
    /// orientation), vAP with three directions, AD and RD between P2 and P4, before and
    /// after calibration.
    Evaluate(Iso9283EvaluateArgs),
}

#[derive(Debug, Args)]
pub(crate) struct Iso9283PlanArgs {
    /// The robot (file or ready robot name): the nominal model the controller runs.
    pub(crate) robot: String,
    /// The test cube: `auto` (the largest found inside the working space and the cell), or
    /// its centre and side with units, CX,CY,CZ,SIDE (800mm,0,600mm,400mm; base frame).
    #[arg(long, value_name = "auto|CX,CY,CZ,SIDE", allow_hyphen_values = true)]
    pub(crate) cube: Option<String>,
    /// Cycles (ISO 9283 asks for 30).
    #[arg(long, default_value_t = gecaro_calib::iso9283::DEFAULT_CYCLES)]
    pub(crate) cycles: usize,
    /// Approach directions: 1 (the pose test) or 3 (multi-directional: along x, y and z).
    #[arg(long, default_value_t = 1)]
    pub(crate) directions: usize,
    /// The measuring cell.
    #[command(flatten)]
    pub(crate) cell: CellArgs,
    /// Units, column names and separator of the program written.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// The program (CSV).
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Overwrite the output if it exists.
    #[arg(long)]
    pub(crate) force: bool,
    /// Print JSON instead of text (lengths in metres).
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct Iso9283EvaluateArgs {
    /// The test's program (`gecaro iso9283 plan`'s).
    #[arg(long, value_name = "TEST.csv")]
    pub(crate) program: PathBuf,
    /// What was measured: pose, cycle (direction) and the attained x,y,z (qw,qx,qy,qz).
    #[arg(long, value_name = "MEASURED.csv")]
    pub(crate) data: PathBuf,
    /// What was measured running the compensated program (after calibration).
    #[arg(long, value_name = "MEASURED.csv")]
    pub(crate) after: Option<PathBuf>,
    /// The robot the program was planned on: checks the program's targets against it.
    #[arg(long)]
    pub(crate) robot: Option<String>,
    /// The measurement frame: base (the measurements are in the robot's base frame),
    /// best-fit (a rigid fit of the poses' barycentres), or its pose in the base frame with
    /// units, X,Y,Z[,QW,QX,QY,QZ] or the 16 numbers of its matrix.
    #[arg(long, value_name = "base|best-fit|POSE", allow_hyphen_values = true)]
    pub(crate) frame: Option<String>,
    /// Units, column names, separator and rotation form of the measured files.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// The load carried, as the report states it (rated, or 10 % of it).
    #[arg(long)]
    pub(crate) load: Option<String>,
    /// The speed (100 %, 50 % or 10 % of the rated speed).
    #[arg(long)]
    pub(crate) speed: Option<String>,
    /// The warm-up before the test.
    #[arg(long)]
    pub(crate) warm_up: Option<String>,
    /// The measurement system.
    #[arg(long)]
    pub(crate) instrument: Option<String>,
    /// Its uncertainty.
    #[arg(long)]
    pub(crate) uncertainty: Option<String>,
    /// Write the report, one self-contained HTML file (tables, the cube with the errors, a
    /// bullseye per pose).
    #[arg(short, long, value_name = "REPORT.html")]
    pub(crate) output: Option<PathBuf>,
    /// Overwrite the report if it exists.
    #[arg(long)]
    pub(crate) force: bool,
    /// Print JSON instead of text (lengths in metres, angles in radians).
    #[arg(long)]
    pub(crate) json: bool,
}
