//! The arguments of the work around a calibration in the cell: a tool
//! point, a join of files, a user frame, compensation, the demo, the
//! page's server.

use std::path::PathBuf;

use clap::Args;

use super::common::*;

#[derive(Debug, Args)]
pub(crate) struct TcpArgs {
    /// The robot (file or ready robot name; a calibrated one gives the tip in its calibrated
    /// frame n+1).
    pub(crate) robot: String,
    /// The configurations (CSV): qm1..qmn, one row per orientation.
    #[arg(long, value_name = "PIVOT.csv")]
    pub(crate) data: PathBuf,
    /// Units and column names of the file.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// Print JSON instead of text (lengths in metres).
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct JoinArgs {
    /// The instrument's export (CSV): x,y,z and, when measured, qw,qx,qy,qz per point.
    pub(crate) tracker: PathBuf,
    /// The controller's log (CSV): qm1..qmn per configuration.
    pub(crate) log: PathBuf,
    /// The robot (file or ready robot name): its joints, and its model to check the join.
    #[arg(long)]
    pub(crate) robot: String,
    /// The key column (a point's name or number) of both files; without it, rows are joined
    /// in order and the files must have as many.
    #[arg(long, value_name = "COLUMN")]
    pub(crate) key: Option<String>,
    /// The log's key column, when its name differs from the export's.
    #[arg(long, value_name = "COLUMN", requires = "key")]
    pub(crate) log_key: Option<String>,
    /// The export's columns under other names (x=X_mm,y=Y_mm,z=Z_mm).
    #[arg(long, value_name = "NAME=COLUMN,..")]
    pub(crate) tracker_columns: Option<String>,
    /// The log's columns under other names (qm1=A1,qm2=A2,…).
    #[arg(long, value_name = "NAME=COLUMN,..")]
    pub(crate) log_columns: Option<String>,
    /// The export's length unit (m or mm; default m).
    #[arg(long, value_name = "m|mm")]
    pub(crate) length_unit: Option<String>,
    /// The log's angle unit (rad or deg; default rad).
    #[arg(long, value_name = "rad|deg")]
    pub(crate) angle_unit: Option<String>,
    /// The log's length unit, of its prismatic joints (m or mm; default m).
    #[arg(long, value_name = "m|mm")]
    pub(crate) log_length_unit: Option<String>,
    /// How the export writes orientations: quaternion (qw,qx,qy,qz, the default), or rx,ry,rz
    /// as rpy, euler-xyz, euler-zyz or rotation-vector (written as quaternions).
    #[arg(long, value_name = "FORMAT", value_parser = names(&gecaro_io::RotationFormat::NAMES))]
    pub(crate) rotation: Option<String>,
    /// The angle unit of the export's rx,ry,rz (rad or deg; default rad).
    #[arg(long, value_name = "rad|deg", requires = "rotation")]
    pub(crate) rotation_unit: Option<String>,
    /// The joined data file (CSV, metres and radians).
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Overwrite the output if it exists.
    #[arg(long)]
    pub(crate) force: bool,
}

#[derive(Debug, Args)]
pub(crate) struct FrameArgs {
    /// The points (CSV): name,x,y,z as measured, with the points origin, x and xy, or
    /// with frame_x,frame_y,frame_z.
    #[arg(long, value_name = "POINTS.csv")]
    pub(crate) points: PathBuf,
    /// Units and column names of the file.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// Print JSON instead of text (lengths in metres, the quaternion w, x, y, z).
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct CompensateArgs {
    /// The nominal robot the program was written with (file or ready robot name).
    pub(crate) nominal: String,
    /// The calibrated robot (file).
    pub(crate) calibrated: String,
    /// The program (CSV): joint targets qm1..qmn, or Cartesian targets
    /// x,y,z[,qw,qx,qy,qz] (world frame), other columns kept.
    #[arg(long, value_name = "PROGRAM.csv")]
    pub(crate) program: PathBuf,
    /// Units and column names of the program.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// What a joint target asks: the whole pose of frame n+1, or only its
    /// position (robots calibrated from position measurements, whose tool
    /// orientation is not identified).
    #[arg(long = "match", value_parser = names(&gecaro_calib::compensation::Match::NAMES), default_value = "pose")]
    pub(crate) matching: String,
    /// The calibrated robot stands in a measurement frame (a tracker's) and
    /// the program in robot coordinates: re-express the robot in the
    /// nominal's base frame first (`robot rebase`). Without it, robots in
    /// different frames are refused.
    #[arg(long)]
    pub(crate) rebase: bool,
    /// The program is in the base its owner defines: register it by points measured in the
    /// calibration's frame beside their place in that base (the file of `robot rebase
    /// --base-points`), and re-express the calibrated robot in it first.
    #[arg(long, value_name = "POINTS.csv", conflicts_with = "rebase")]
    pub(crate) base_points: Option<PathBuf>,
    /// Or by the circles of joints 1 and 2 turned alone (the file of `robot rebase
    /// --base-circles`; its angles in radians unless its units line says otherwise).
    #[arg(long, value_name = "CIRCLES.csv", conflicts_with_all = ["rebase", "base_points"])]
    pub(crate) base_circles: Option<PathBuf>,
    /// The length unit of the base-points or circles file (m or mm; default m).
    #[arg(long, value_name = "m|mm")]
    pub(crate) base_points_unit: Option<String>,
    /// The payload the robot will carry: 12kg, or 12kg,0,0,80mm with its centre in the tool
    /// frame. An elastic calibrated robot (identify --model elastic) is commanded where it
    /// comes to rest on the targets under this load and its links' weight.
    #[arg(long, value_name = "MASS[,X,Y,Z]")]
    pub(crate) payload: Option<String>,
    /// The tool the program's targets are for: a tool the calibration identified (a study's
    /// reflector, by its name in the calibrated file's [tools]), or its pose in frame n+1,
    /// 0,0,120mm[,qw,qx,qy,qz] or the 16 numbers of its 4×4 matrix, row by row. Frame n+1
    /// itself when omitted — refused where the calibration never observed it (every set
    /// measured a named tool).
    #[arg(long, value_name = "NAME|X,Y,Z[,QW,QX,QY,QZ]")]
    pub(crate) tool: Option<String>,
    /// With --match position: the largest turn of the tool a target may be left with
    /// before it is flagged (default 1deg).
    #[arg(long, value_name = "ANGLE")]
    pub(crate) max_tool_turn: Option<String>,
    /// The corrected program (CSV): the program's columns with corrected
    /// joints, then residual, residual_rotation and status.
    #[arg(short, long, value_name = "CORRECTED.csv")]
    pub(crate) output: PathBuf,
    /// Overwrite the output file if it exists.
    #[arg(long)]
    pub(crate) force: bool,
    /// Print JSON instead of text, listing every target (the program is then
    /// held in memory; without it, it is corrected as it is read).
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Error level of the simulated real robot.
    #[arg(long, value_name = "L", default_value_t = 3.0)]
    pub(crate) error_level: f64,
    /// Sensor noise, standard deviation (metres, radians).
    #[arg(long, value_name = "SIGMA", default_value_t = 5e-5)]
    pub(crate) noise: f64,
    /// Seed of every random draw.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
}

#[derive(Debug, Args)]
pub(crate) struct ServeArgs {
    /// Port on 127.0.0.1 (0: any free port).
    #[arg(long, default_value_t = 8080)]
    pub(crate) port: u16,
    /// The folder of robot and data files the page may open and save (nothing outside it).
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub(crate) dir: PathBuf,
    /// Open the page in the default browser.
    #[arg(long)]
    pub(crate) open: bool,
}
