//! Argument groups the commands share: units and formats of data files,
//! configurations, the method and its options, the cell.

use std::path::PathBuf;

use clap::Args;

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
pub(super) fn method_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        gecaro_calib::methods::METHODS
            .iter()
            .map(|info| info.name)
            .chain([gecaro_calib::parallel_robots::PlatformMeasure::Leg.name()]),
    )
}

/// A value list of a library's names (its `NAMES`), so that the command
/// line offers and checks what the libraries parse.
/// A field separator by its character or its name (`;` or `semicolon`).
pub(super) fn delimiter_name(text: &str) -> Result<String, String> {
    match gecaro_io::Delimiter::from_name(text) {
        Some(_) => Ok(text.to_owned()),
        None => Err(format!(
            "not a separator: give `,`, `;`, `tab` (or {})",
            gecaro_io::Delimiter::NAMES.join(", ")
        )),
    }
}

pub(super) fn names(names: &'static [&'static str]) -> clap::builder::PossibleValuesParser {
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

// A parallel robot's measuring leg (`--method leg`): a redundant leg
// sensor, or a ballbar between a base and a platform socket. (A line
// comment: a flattened struct's doc comment would become the command's
// description.)
#[derive(Debug, Args)]
pub(crate) struct LegArgs {
    /// For --method leg (a parallel robot's measuring leg: a redundant leg
    /// sensor, or a ballbar between two sockets): its base socket's centre
    /// in the base frame, with units (250mm,-100mm,0).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub(crate) leg_base: Option<String>,
    /// For --method leg: its platform socket's centre in the platform
    /// frame, with units.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub(crate) leg_platform: Option<String>,
    /// For --method leg: metres of length per unit of its reading (default
    /// 1: the reading is a length in the data's unit).
    #[arg(long, value_name = "K")]
    pub(crate) leg_gain: Option<f64>,
}

impl LegArgs {
    /// The options given, by name (for a serial robot, which has no leg).
    pub(crate) fn given(&self) -> [(&'static str, bool); 3] {
        [
            ("--leg-base", self.leg_base.is_some()),
            ("--leg-platform", self.leg_platform.is_some()),
            ("--leg-gain", self.leg_gain.is_some()),
        ]
    }
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
