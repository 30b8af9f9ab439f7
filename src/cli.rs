//! The command line, declared with clap.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Geometric calibration of serial robots (GECARO, Khalil et al.).
///
/// ROBOT arguments are a robot file (TOML) or the name of a ready robot:
/// stanford, puma560, industrial6, scara, panda, ur10e.
#[derive(Debug, Parser)]
#[command(name = "gecaro", version, about, long_about = None, propagate_version = true)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

// Each command's arguments are built when it runs (`defer`): building all
// of them took 0.45 ms of every run, a thirtieth of a 5,000-configuration
// identification. The argument structs carry `//` comments, not doc comments:
// built after the command, a struct's doc comment would replace its description
// (`every_command_keeps_its_own_description` checks).
#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub(crate) enum Command {
    /// Show, check, create, convert or re-express robot files.
    #[command(subcommand)]
    Robot(RobotCommand),
    /// Direct geometric model: the end-effector frame at a configuration (eq. 1).
    Fk(ConfigurationArgs),
    /// The 6×Np Jacobian of the end-effector w.r.t. every parameter (Appendix II).
    Jacobian(ConfigurationArgs),
    /// Inverse geometric model: a configuration that puts the end-effector at a target.
    Ik(IkArgs),
    /// Identifiable (base) parameters of a method: QR of W (Appendix III).
    Identifiable(IdentifiableArgs),
    /// The paper's Table 2: identifiable parameters of all methods for a robot.
    Table2(Table2Args),
    /// Points generation: simulated measurements of a "real" robot for a method.
    Generate(GenerateArgs),
    /// Plan a calibration: the configurations to measure, chosen from a pool
    /// (D-, A-, E-optimal, O4, O5 or test-pose accuracy), or how many are enough (--curve).
    Plan(PlanArgs),
    /// Predict, before measuring, the precision of every identifiable
    /// parameter and the calibrated robot's error at test poses.
    Predict(PredictArgs),
    /// Identification: the robot's parameters from measurements (eq. 10, iterated).
    Identify(IdentifyArgs),
    /// Identify and write a self-contained HTML report with plots.
    Report(ReportArgs),
    /// Rank candidate models (which parameters may be identified) by their
    /// cross-validated held-out error.
    CompareModels(CompareModelsArgs),
    /// Error statistics of a (calibrated) robot on measurements.
    Evaluate(EvaluateArgs),
    /// Correct a robot program for the calibrated robot: the joint values
    /// that reach what the nominal program meant ("program filtering").
    Compensate(CompensateArgs),
    /// Teach a tool point by pivoting: the joint values of N ≥ 4 orientations with the tool's
    /// tip on one fixed point give the tip in frame n+1 (tool0) and the fixed point.
    Tcp(TcpArgs),
    /// A user frame from measured points: origin, x and xy (three points), or any number of
    /// points with their place in the frame (frame_x, frame_y, frame_z; least squares).
    Frame(FrameArgs),
    /// Join an instrument's export (x,y,z[,qw,qx,qy,qz]) with a controller's log
    /// (qm1..qmn) into one data file, by a key column or by row order; a shifted join is
    /// refused with its direction.
    Join(JoinArgs),
    /// Generate data for the Stanford arm and identify it with every method.
    Demo(DemoArgs),
    /// Serve the GECARO main page (robot table, seven method menus) on 127.0.0.1.
    Serve(ServeArgs),
}

#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub(crate) enum RobotCommand {
    /// Print the robot's table (j, σ, α, d, θ, r, β, K), limits and priority matrix.
    Show {
        /// Robot file or ready robot name.
        robot: String,
        /// Show angles in degrees.
        #[arg(long)]
        deg: bool,
    },
    /// Validate a robot file and explain every problem (file, line, key).
    Check {
        /// Robot file or ready robot name.
        robot: String,
    },
    /// Re-express a robot in another world frame and/or with another tool
    /// frame (frames 0, 1 and n, n+1 rewritten; same motion otherwise).
    Reframe {
        /// Robot file or ready robot name.
        robot: String,
        /// The robot's current world frame in the new one: position (metres)
        /// and unit quaternion, or the 16 numbers of its 4×4 matrix, row by row.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            value_name = "X,Y,Z,QW,QX,QY,QZ"
        )]
        world: Option<Vec<f64>>,
        /// The new tool frame in the current one (frame n+1): position
        /// (metres) and unit quaternion, or the 16 numbers of its 4×4 matrix, row by row.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            value_name = "X,Y,Z,QW,QX,QY,QZ"
        )]
        tool: Option<Vec<f64>>,
        /// Output robot file.
        #[arg(short, long)]
        output: PathBuf,
        /// Overwrite the output file if it exists.
        #[arg(long)]
        force: bool,
    },
    /// Re-express a robot calibrated in a measurement frame (a tracker's) in
    /// its own base frame, the nominal robot's: prints the measurement
    /// frame's pose in the robot's frame, writes the robot.
    Rebase(RebaseArgs),
    /// Convert a URDF, a DH / modified-DH table or a SYMORO .par file into a
    /// robot file (same joint variables: sign and zero).
    Import(ImportArgs),
    /// Write a robot as a URDF or a DH / modified-DH table (gains and
    /// couplings that the format cannot carry go to FILE's
    /// .joint_calibration.yaml beside it).
    Export(ExportArgs),
    /// Write a template robot file to edit.
    New {
        /// Joint types from joint 1 to n: R revolute, P prismatic (e.g. RRPRRR).
        #[arg(long)]
        joints: String,
        /// Output file.
        #[arg(short, long)]
        output: PathBuf,
        /// Overwrite the output file if it exists.
        #[arg(long)]
        force: bool,
    },
}

// Units of a file's columns that do not state theirs.
#[derive(Debug, Args)]
pub(crate) struct UnitArgs {
    /// Unit of the angles (joint angles, α, θ) where the file does not say.
    #[arg(long, value_parser = ["rad", "deg"], value_name = "rad|deg")]
    pub(crate) angle_unit: Option<String>,
    /// Unit of the lengths (positions, distances, a, d) where the file does not say.
    #[arg(long, value_parser = ["m", "mm"], value_name = "m|mm")]
    pub(crate) length_unit: Option<String>,
}

// How a data or program file is written: units and other column names.
#[derive(Debug, Args)]
pub(crate) struct DataFormatArgs {
    #[command(flatten)]
    pub(crate) units: UnitArgs,
    /// Columns under other names: NAME=COLUMN pairs (e.g. x=X_mm,qm1=A1);
    /// columns not used are left alone.
    #[arg(long, value_name = "NAME=COLUMN,..")]
    pub(crate) columns: Option<String>,
    /// The field separator: `,` `;` tab, or their names comma, semicolon, tab
    /// (default: found from the header line).
    #[arg(long, value_parser = delimiter_name, value_name = "auto|,|;|tab")]
    pub(crate) delimiter: Option<String>,
    /// Numbers are written with a decimal comma (`0,25`). Without it, a
    /// decimal comma is read where fields are separated by `;` or tabs.
    #[arg(long)]
    pub(crate) decimal_comma: bool,
    /// How orientations are written: quaternion (qw,qx,qy,qz, the default), or rx,ry,rz in
    /// the angle unit as rpy (fixed x, y, z), euler-xyz (intrinsic), euler-zyz or
    /// rotation-vector.
    #[arg(long, value_parser = names(&gecaro_io::RotationFormat::NAMES), value_name = "FORM")]
    pub(crate) rotation: Option<String>,
}

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

#[derive(Debug, Args)]
pub(crate) struct ConfigurationArgs {
    /// Robot file or ready robot name.
    pub(crate) robot: String,
    /// Motor variables qm1..qmn, comma separated (radians and metres, or
    /// the units of --angle-unit and --length-unit).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    pub(crate) qm: Vec<f64>,
    /// Units of --qm (and of the printed position; JSON stays in metres).
    #[command(flatten)]
    pub(crate) units: UnitArgs,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct IkArgs {
    /// Robot file or ready robot name.
    pub(crate) robot: String,
    /// Target position of the origin of frame n+1, world frame, metres.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z",
        required = true
    )]
    pub(crate) position: Vec<f64>,
    /// Target orientation of frame n+1 (unit quaternion); free when omitted.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "QW,QX,QY,QZ"
    )]
    pub(crate) orientation: Option<Vec<f64>>,
    /// Start configuration (motor variables); default: the middle of the
    /// joint ranges, then 20 seeded random starts if that one fails.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "QM1,.."
    )]
    pub(crate) start: Option<Vec<f64>>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

/// The method names of the registry, for clap's value list.
fn method_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        gecaro_calib::methods::METHODS.iter().map(|info| info.name),
    )
}

/// A value list of a library's names (its `NAMES`), so that the command
/// line offers and checks what the libraries parse.
/// A field separator by its character or its name (`;` or `semicolon`).
fn delimiter_name(text: &str) -> Result<String, String> {
    match gecaro_io::Delimiter::from_name(text) {
        Some(_) => Ok(text.to_owned()),
        None => Err(format!(
            "not a separator: give `,`, `;`, `tab` (or {})",
            gecaro_io::Delimiter::NAMES.join(", ")
        )),
    }
}

fn names(names: &'static [&'static str]) -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(names.iter().copied())
}

#[derive(Debug, Args)]
pub(crate) struct PlaneArgs {
    /// For plane1/plane2: is the plane (its normal for plane2) known, or identified too?
    /// Default: known when --plane-normal is given.
    #[arg(long, value_parser = ["known", "unknown"])]
    pub(crate) plane: Option<String>,
    /// Normal of the plane, world frame (e.g. 0.3,0.5,0.81).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "NX,NY,NZ"
    )]
    pub(crate) plane_normal: Option<Vec<f64>>,
    /// A point of the plane, world frame, metres (e.g. 0.3,0.2,0.6).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z"
    )]
    pub(crate) plane_point: Option<Vec<f64>>,
}

#[derive(Debug, Args)]
pub(crate) struct MethodArgs {
    /// The calibration method.
    #[arg(long, value_parser = method_names())]
    pub(crate) method: String,
    #[command(flatten)]
    pub(crate) options: MethodOptionArgs,
}

// Where the measurements come from: one method and its data, or a study file.
#[derive(Debug, Args)]
pub(crate) struct StudySource {
    /// Robot file or ready robot name (not with --study).
    #[arg(required_unless_present = "study")]
    pub(crate) robot: Option<String>,
    /// The calibration method (not with --study).
    #[arg(long, value_parser = method_names(), required_unless_present = "study")]
    pub(crate) method: Option<String>,
    #[command(flatten)]
    pub(crate) options: MethodOptionArgs,
    /// A study file: several measurement sets (method, data, σ each) used together.
    #[arg(long, value_name = "STUDY.toml", conflicts_with_all = ["robot", "method"])]
    pub(crate) study: Option<PathBuf>,
    /// Refuse data with joints outside their limits (by default a warning).
    #[arg(long)]
    pub(crate) strict_limits: bool,
    /// Units and column names of the data file (with --study: its keys).
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
}

#[derive(Debug, Args)]
pub(crate) struct MethodOptionArgs {
    #[command(flatten)]
    pub(crate) plane: PlaneArgs,
    /// Orientation difference for frame and frame-link (Appendix I): axis-angle
    /// (method 2, exact) or cross-products (method 1, first order).
    #[arg(long, value_parser = names(&gecaro_core::OrientationDifference::NAMES), default_value = "axis-angle")]
    pub(crate) orientation: String,
    /// Configurations per set when generating link data (default 4 for point-link, 2 for frame-link).
    #[arg(long)]
    pub(crate) set_size: Option<usize>,
}

#[derive(Debug, Args)]
pub(crate) struct IdentifiableArgs {
    #[command(flatten)]
    pub(crate) source: StudySource,
    /// Priority matrix (TOML: matrix = [[alpha, d, theta, r, beta, K], ...]); default: the robot's.
    #[arg(long, value_name = "FILE")]
    pub(crate) priority: Option<PathBuf>,
    /// Check these measured configurations (excitation check) instead of only random ones.
    #[arg(long, value_name = "FILE", conflicts_with = "study")]
    pub(crate) data: Option<PathBuf>,
    /// Number of random configurations (default: about 2.5 equations per unknown).
    #[arg(long)]
    pub(crate) count: Option<usize>,
    /// Seed of the random configurations.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// The model whose parameters are candidates, as identify --model takes it (full, no-gains,
    /// …, a priority file); elastic: every joint's compliance too, on the data's loads (the
    /// robot's masses, their payload columns; docs/elastic.md).
    #[arg(long, value_name = "MODEL")]
    pub(crate) model: Option<String>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct Table2Args {
    /// Robot file or ready robot name.
    #[arg(default_value = "stanford")]
    pub(crate) robot: String,
    /// Normal of the plane of the plane methods (default 0.3,0.5,0.81, as in the paper).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "NX,NY,NZ"
    )]
    pub(crate) plane_normal: Option<Vec<f64>>,
    /// A point of that plane (default: the middle of the robot's workspace).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z"
    )]
    pub(crate) plane_point: Option<Vec<f64>>,
    /// Seed of the random configurations.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
}

// The measuring cell: which random configurations can be measured.
#[derive(Debug, Args)]
pub(crate) struct CellArgs {
    /// Every joint origin and the tool stay at or above z = Z of the world
    /// frame (metres): an arm on a floor or a table.
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub(crate) floor: Option<f64>,
    /// A laser tracker at X,Y,Z (world frame, metres): the tool point must
    /// see it, the arm (at the level of its joint origins) out of the way.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z"
    )]
    pub(crate) station: Option<Vec<f64>>,
    /// The reflector's acceptance half-angle: the angle between the tool's
    /// z axis and the direction to the station (e.g. 30deg).
    #[arg(long, value_name = "ANGLE", requires = "station")]
    pub(crate) max_incidence: Option<String>,
    /// The smallest distance of the line of sight from the arm (metres).
    #[arg(long, value_name = "M", requires = "station")]
    pub(crate) clearance: Option<f64>,
}

#[derive(Debug, Args)]
pub(crate) struct GenerateArgs {
    /// Nominal robot (file or ready robot name).
    pub(crate) robot: String,
    #[command(flatten)]
    pub(crate) method: MethodArgs,
    /// Number of configurations (rows of the data file).
    #[arg(long, required_unless_present = "configurations")]
    pub(crate) count: Option<usize>,
    /// Measure at these configurations instead of random ones: a planned
    /// file (`gecaro plan`) or any data file's qm (and set or pair) columns.
    #[arg(long, value_name = "PLANNED.csv", conflicts_with = "count")]
    pub(crate) configurations: Option<PathBuf>,
    /// Units, columns and separator of the --configurations file (a plan
    /// written with --angle-unit deg is read with --angle-unit deg).
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// The "real" robot, as a robot file; default: the nominal one with errors at --error-level.
    #[arg(long, value_name = "REAL.toml", conflicts_with = "error_level")]
    pub(crate) real: Option<PathBuf>,
    /// Errors of the simulated real robot: ±L cm on lengths, ±L° on angles, ±L % on gains
    /// (default 1).
    #[arg(long, value_name = "L")]
    pub(crate) error_level: Option<f64>,
    /// Elastic joints: the drawn real robot's compliances, L·[2e-6, 1e-5] rad/(N·m) per joint,
    /// loaded by the robot file's masses (docs/elastic.md).
    #[arg(long, value_name = "L", conflicts_with = "real")]
    pub(crate) compliance_level: Option<f64>,
    /// The payload carried at every configuration: 20kg, or 20kg,0,0,120mm with its centre in
    /// the tool frame; written to the data file's payload columns.
    #[arg(long, value_name = "MASS[,X,Y,Z]")]
    pub(crate) payload: Option<String>,
    /// A measurement frame that is not levelled: the real robot's gravity leans by these two
    /// angles (tilt1, tilt2: about the world's x and y for gravity along −z) from its file's;
    /// elastic joints see it, and identify --model elastic-gravity finds it.
    #[arg(long, value_name = "A1,A2", allow_hyphen_values = true)]
    pub(crate) gravity_tilt: Option<String>,
    /// Sensor noise, standard deviation (metres; radians for orientations).
    #[arg(long, value_name = "SIGMA", default_value_t = 0.0)]
    pub(crate) noise: f64,
    #[command(flatten)]
    pub(crate) cell: CellArgs,
    /// Seed of every random draw (errors, configurations, noise).
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// Output data file (CSV).
    #[arg(short, long, value_name = "DATA.csv")]
    pub(crate) output: PathBuf,
    /// Also save the simulated real robot, so that the truth is known.
    #[arg(long, value_name = "REAL.toml")]
    pub(crate) real_out: Option<PathBuf>,
    /// Overwrite output files that exist.
    #[arg(long)]
    pub(crate) force: bool,
}

#[derive(Debug, Args)]
pub(crate) struct PlanArgs {
    /// Nominal robot (file or ready robot name; not with --study).
    #[arg(required_unless_present = "study")]
    pub(crate) robot: Option<String>,
    /// The calibration method (not with --study).
    #[arg(long, value_parser = method_names(), required_unless_present = "study")]
    pub(crate) method: Option<String>,
    #[command(flatten)]
    pub(crate) options: MethodOptionArgs,
    /// A whole cell: a study file whose sets (method, σ, reflector, station
    /// each) are planned as one D-optimal design; -o PLANNED.toml writes the
    /// planned study and each set's configurations beside it
    /// (PLANNED_1.csv, …), for `predict --study` and, measured, `identify --study`.
    #[arg(
        long,
        value_name = "STUDY.toml",
        conflicts_with_all = ["robot", "method", "candidates", "keep", "curve", "test_poses"]
    )]
    pub(crate) study: Option<PathBuf>,
    /// Number of configurations to measure (rows of the output; link sets and
    /// distance pairs come whole, so the count is rounded to whole units).
    #[arg(long, required_unless_present = "curve", conflicts_with = "curve")]
    pub(crate) count: Option<usize>,
    /// What the choice optimises: D-, A-, E-optimal, the observability
    /// indices O4 or O5, or the predicted position error at the test poses.
    #[arg(long, value_parser = names(&gecaro_calib::planning::Criterion::NAMES), default_value = "d")]
    pub(crate) criterion: String,
    /// Candidates: a data file's configurations (e.g. the poses a cell can reach).
    #[arg(long, value_name = "FILE", conflicts_with = "pool")]
    pub(crate) candidates: Option<PathBuf>,
    /// Or generate this many candidate configurations, as points generation
    /// does (within the joint limits; default 20 × --count, or 20 × the
    /// largest count of --curve).
    #[arg(long, value_name = "K")]
    pub(crate) pool: Option<usize>,
    #[command(flatten)]
    pub(crate) cell: CellArgs,
    /// Seed of the generated pool (and of the test poses and random designs).
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// Elastic joints: a payload each candidate may be measured with (repeat it: --payload 0kg
    /// --payload 20kg,0,0,100mm); the compliances join the design and the plan states each
    /// row's payload (docs/elastic.md).
    #[arg(
        long = "payload",
        value_name = "MASS[,X,Y,Z]",
        conflicts_with = "study"
    )]
    pub(crate) payloads: Vec<String>,
    /// Configurations measured already: part of the design, never dropped.
    #[arg(long, value_name = "FILE")]
    pub(crate) keep: Option<PathBuf>,
    /// Units, column names and separator of the configuration files read
    /// (--candidates, --keep, --test-poses) and of the plan written
    /// (--angle-unit deg for a teach pendant).
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// The smallest joint-space distance between two chosen configurations
    /// (Euclidean over the joint variables, radians and metres).
    #[arg(long, value_name = "D", default_value_t = 0.0)]
    pub(crate) min_distance: f64,
    #[command(flatten)]
    pub(crate) test_poses: TestPoseArgs,
    /// Instead of one plan: the predicted error against the number of
    /// configurations, planned versus random (e.g. 10,20,40,80,160).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "N,N,...",
        requires = "noise"
    )]
    pub(crate) curve: Option<Vec<usize>>,
    /// For --curve: the sensor's standard deviation (metres).
    #[arg(long, value_name = "SIGMA")]
    pub(crate) noise: Option<f64>,
    /// For --curve: write the curve as an SVG plot.
    #[arg(long, value_name = "CURVE.svg", requires = "curve")]
    pub(crate) plot: Option<PathBuf>,
    /// Output: the chosen configurations (qm1..qmn, and set or pair ids).
    #[arg(
        short,
        long,
        value_name = "PLANNED.csv",
        required_unless_present = "curve"
    )]
    pub(crate) output: Option<PathBuf>,
    /// Overwrite the output files if they exist.
    #[arg(long)]
    pub(crate) force: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

// Where the calibrated robot will work: the poses its accuracy is judged at.
#[derive(Debug, Args)]
pub(crate) struct TestPoseArgs {
    /// Test poses: a data file's configurations (default: random
    /// configurations within the joint limits, seeded by --seed).
    #[arg(long, value_name = "FILE")]
    pub(crate) test_poses: Option<PathBuf>,
    /// Number of random test poses when no file is given.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 200,
        conflicts_with = "test_poses"
    )]
    pub(crate) test_pose_count: usize,
}

#[derive(Debug, Args)]
pub(crate) struct PredictArgs {
    /// Nominal robot (file or ready robot name; not with --study).
    #[arg(required_unless_present = "study")]
    pub(crate) robot: Option<String>,
    /// The calibration method (not with --study).
    #[arg(long, value_parser = method_names(), required_unless_present = "study")]
    pub(crate) method: Option<String>,
    #[command(flatten)]
    pub(crate) options: MethodOptionArgs,
    /// The configurations to be measured (e.g. the output of `gecaro plan`).
    #[arg(long, value_name = "PLANNED.csv", required_unless_present = "study")]
    pub(crate) data: Option<PathBuf>,
    /// A whole cell: a study file whose sets (method, σ, reflector, station
    /// each) are predicted together; their data files need only their
    /// configurations.
    #[arg(
        long,
        value_name = "STUDY.toml",
        conflicts_with_all = ["robot", "method", "data", "noise", "monte_carlo"]
    )]
    pub(crate) study: Option<PathBuf>,
    /// Units, column names and separator of the plan and test-pose files.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// The sensor's standard deviation (metres; radians for orientation rows).
    #[arg(
        long,
        value_name = "SIGMA",
        required_unless_present = "study",
        allow_negative_numbers = true
    )]
    pub(crate) noise: Option<f64>,
    #[command(flatten)]
    pub(crate) test_poses: TestPoseArgs,
    /// Also run K simulated calibrations and report the errors measured.
    #[arg(long, value_name = "K")]
    pub(crate) monte_carlo: Option<usize>,
    /// For --monte-carlo: the simulated real robots' error level (1 = ±1 cm, ±1°).
    #[arg(long, default_value_t = 0.1)]
    pub(crate) error_level: f64,
    /// Seed of the test poses and the simulations.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// The model predicted, as identify --model takes it (full, no-gains, …, a priority file);
    /// elastic: the compliances too, loaded by the robot's masses and the plan's payload columns
    /// (docs/elastic.md).
    #[arg(long, value_name = "MODEL", conflicts_with = "study")]
    pub(crate) model: Option<String>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

// What an identification runs on and how: shared by `identify` and `report`.
#[derive(Debug, Args)]
pub(crate) struct IdentificationRunArgs {
    #[command(flatten)]
    pub(crate) source: StudySource,
    /// Measurements (CSV).
    #[arg(
        long,
        value_name = "DATA.csv",
        required_unless_present = "study",
        conflicts_with = "study"
    )]
    pub(crate) data: Option<PathBuf>,
    /// The sensor's standard deviation: with its unit (20um, 0.02mm), or a
    /// number in the data's length unit (--length-unit; metres by default).
    /// Also the orientations' unless --sigma-rotation. The rows are weighted
    /// by 1/σ and the verdict tests the residuals against it (exit 5 when
    /// they are beyond or far below it). A study file states σ per set.
    #[arg(long, value_name = "σ", conflicts_with = "study")]
    pub(crate) sigma: Option<gecaro_io::StandardDeviation>,
    /// The σ of the orientation rows: with its unit (0.01deg), or a number in
    /// the data's angle unit (--angle-unit; radians by default).
    #[arg(long, value_name = "σ", requires = "sigma")]
    pub(crate) sigma_rotation: Option<gecaro_io::StandardDeviation>,
    /// Priority matrix (TOML: matrix = [[alpha, d, theta, r, beta, K], ...]); default: the robot's.
    #[arg(long, value_name = "FILE")]
    pub(crate) priority: Option<PathBuf>,
    /// Step rule: gauss-newton (the paper's plain steps, damped only when a
    /// step would increase the residual) or lm (Levenberg–Marquardt from the
    /// first step).
    #[arg(long, value_parser = names(&gecaro_calib::identification::Solver::NAMES), default_value = "gauss-newton")]
    pub(crate) solver: String,
    /// Iteration limit.
    #[arg(long, default_value_t = gecaro_calib::identification::DEFAULT_MAX_ITERATIONS)]
    pub(crate) max_iterations: usize,
    /// Loss: l2 (least squares, the paper), or a robust loss that discounts
    /// gross errors (iteratively reweighted least squares; docs/methods.md).
    #[arg(long, value_parser = names(&gecaro_calib::identification::LossKind::NAMES), default_value = "l2")]
    pub(crate) loss: String,
    /// Scale k of the robust loss, in robust σ (default: huber 1.345,
    /// cauchy 2.385, tukey 4.685).
    #[arg(long, value_name = "K")]
    pub(crate) loss_scale: Option<f64>,
    /// Report observations whose residual exceeds this many robust σ as outliers.
    #[arg(long, value_name = "K", default_value_t = gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD)]
    pub(crate) outlier_threshold: f64,
    /// Drop the outliers and identify again, once.
    #[arg(long)]
    pub(crate) reject: bool,
    /// Gaussian prior around the nominal values: σ of lengths, angles and
    /// gains with their units, e.g. 5mm,0.5deg,1% (maximum a posteriori;
    /// a study file's [prior] table gives per-parameter σ too).
    #[arg(long, value_name = "σ,σ,σ")]
    pub(crate) prior: Option<String>,
    /// Which parameters may be identified: full (the priority matrix),
    /// no-gains, no-beta, kinematic (neither), offsets (joint offsets only),
    /// elastic (full and every joint's compliance, loaded by the robot's
    /// masses and the data's payload; docs/elastic.md), elastic-gravity
    /// (elastic and gravity's two tilts, for a measurement frame that is not
    /// levelled), or a priority-matrix file. Default: a study's `model`, else
    /// full.
    #[arg(long, value_name = "MODEL")]
    pub(crate) model: Option<String>,
    /// The region the calibrated robot will be used in, over which the
    /// verdict predicts its error: joint ranges with their units, e.g.
    /// q1=-90..90deg,q3=0..120deg (joints not named: their limits; default:
    /// the joint limits). A result that holds in the measured region only
    /// is not trusted (exit 5) and its file keeps that region.
    #[arg(long, value_name = "q1=MIN..MAXdeg,..")]
    pub(crate) work_region: Option<String>,
}

#[derive(Debug, Args)]
pub(crate) struct IdentifyArgs {
    #[command(flatten)]
    pub(crate) run: IdentificationRunArgs,
    /// Write the calibrated robot (nominal + identified deviations) to this file.
    #[arg(short, long, value_name = "CALIBRATED.toml")]
    pub(crate) output: Option<PathBuf>,
    /// Write the plots as SVG into this folder (created if missing): convergence.svg,
    /// errors_histogram.svg, errors_per_configuration.svg.
    #[arg(long, value_name = "DIR")]
    pub(crate) plot: Option<PathBuf>,
    /// Write every observation's error before and after, with its file and
    /// lines, to this CSV file (columns in docs/methods.md); written whether
    /// or not the identification converged, to find what went wrong.
    #[arg(long, value_name = "RESIDUALS.csv")]
    pub(crate) residuals: Option<PathBuf>,
    /// Overwrite output files that exist.
    #[arg(long)]
    pub(crate) force: bool,
    /// Write the best iterate even when the identification did not converge.
    #[arg(long)]
    pub(crate) write_unconverged: bool,
    /// Compare the model with the next smaller one (full → no-gains →
    /// kinematic → offsets) and, for a smaller model, the full one, by region
    /// folds, the ends of each joint's measured range held out, and suggest
    /// one that predicts better
    /// (5–15× the identification's time). By default it runs when the data
    /// are small (at most 1,500 equations: 500 positions, 250 frames).
    #[arg(long, conflicts_with = "no_check_model")]
    pub(crate) check_model: bool,
    /// Do not compare the model with its neighbours, however small the data.
    #[arg(long)]
    pub(crate) no_check_model: bool,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub(crate) json: bool,
    /// Also K-fold cross-validate (folds by configuration, set or pair): the
    /// held-out error per fold and overall.
    #[arg(long, value_name = "K")]
    pub(crate) cv: Option<usize>,
    /// Seed of the cross-validation folds.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// How the folds hold observations out: random (default:
    /// interpolation) or regions (the ends of each joint's measured range:
    /// extrapolation).
    #[arg(long, value_parser = names(&gecaro_calib::validation::Folds::NAMES), default_value = "random", requires = "cv")]
    pub(crate) folds_by: String,
}

#[derive(Debug, Args)]
pub(crate) struct CompareModelsArgs {
    #[command(flatten)]
    pub(crate) run: IdentificationRunArgs,
    /// The candidate models, comma-separated: offsets, kinematic, no-gains,
    /// no-beta, full, or priority-matrix files.
    #[arg(
        long,
        value_name = "MODEL,MODEL",
        default_value = "offsets,kinematic,no-gains,no-beta,full"
    )]
    pub(crate) models: String,
    /// Folds of the cross-validation.
    #[arg(long, value_name = "K", default_value_t = 5)]
    pub(crate) cv: usize,
    /// Seed of the folds (the same folds for every model; random folds).
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// How the folds hold observations out: regions (the lowest and the
    /// highest 1/K of each joint's measured range in turn, so that a
    /// parameter that only interpolates loses) or random (rows dealt at
    /// random: interpolation).
    #[arg(long, value_parser = names(&gecaro_calib::validation::Folds::NAMES), default_value = "regions")]
    pub(crate) folds_by: String,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct ReportArgs {
    #[command(flatten)]
    pub(crate) run: IdentificationRunArgs,
    /// The report (one self-contained HTML file).
    #[arg(short, long, value_name = "REPORT.html")]
    pub(crate) output: PathBuf,
    /// Overwrite the report if it exists.
    #[arg(long)]
    pub(crate) force: bool,
}

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
pub(crate) struct EvaluateArgs {
    /// The (calibrated) robot (file or ready robot name).
    pub(crate) robot: String,
    /// The method of the data (not with --study).
    #[arg(long, value_parser = method_names(), required_unless_present = "study")]
    pub(crate) method: Option<String>,
    #[command(flatten)]
    pub(crate) options: MethodOptionArgs,
    /// Measurements (CSV), ideally not those used for identification.
    #[arg(
        long,
        value_name = "DATA.csv",
        required_unless_present = "study",
        conflicts_with = "study"
    )]
    pub(crate) data: Option<PathBuf>,
    /// A study file whose measurement sets the robot is evaluated on (its
    /// robot is replaced by ROBOT; its named tools and stations as stated).
    #[arg(long, value_name = "STUDY.toml", conflicts_with = "method")]
    pub(crate) study: Option<PathBuf>,
    /// Units and column names of the data file.
    #[command(flatten)]
    pub(crate) format: DataFormatArgs,
    /// Refuse data with joints outside their limits (by default a warning).
    #[arg(long)]
    pub(crate) strict_limits: bool,
    /// Data measured in another frame (another tracker position): register it in closed form
    /// on this share of the rows (spread over the file), `30%`, and judge the robot on the
    /// others; `all` registers and judges on every row (said so).
    #[arg(long, value_name = "N%|all", conflicts_with = "study")]
    pub(crate) register: Option<String>,
    /// Print JSON instead of text.
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

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every command, deferred ones included (their arguments are built
    /// when they run), passes clap's checks: no two arguments with the same
    /// name or flag, defaults among their possible values.
    #[test]
    fn the_command_line_is_well_formed() {
        super::Cli::command().debug_assert();
    }

    /// Every command keeps its own description once its deferred arguments
    /// are built: a doc comment on an argument struct, applied after the
    /// command's, would replace it.
    #[test]
    fn every_command_keeps_its_own_description() {
        fn descriptions(command: &clap::Command) -> Vec<(String, String, String)> {
            let text = |about: Option<&clap::builder::StyledStr>| {
                about.map(ToString::to_string).unwrap_or_default()
            };
            let own = (
                command.get_name().to_owned(),
                text(command.get_about()),
                text(command.get_long_about()),
            );
            // Building adds clap's own `help` commands.
            std::iter::once(own)
                .chain(
                    command
                        .get_subcommands()
                        .filter(|sub| sub.get_name() != "help")
                        .flat_map(descriptions),
                )
                .collect()
        }
        let declared = super::Cli::command();
        let mut built = super::Cli::command();
        built.build();
        let declared = descriptions(&declared);
        assert!(declared.len() > 20, "{} commands", declared.len());
        assert_eq!(declared, descriptions(&built));
    }
}
