//! The arguments of the paper's functions and around them: identifiable
//! parameters, Table 2, generation, planning, prediction, identification,
//! models compared, the report, evaluation.

use std::path::PathBuf;

use clap::Args;

use super::common::*;

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

#[derive(Debug, Args)]
pub(crate) struct GenerateArgs {
    /// Nominal robot (file or ready robot name).
    pub(crate) robot: String,
    #[command(flatten)]
    pub(crate) method: MethodArgs,
    #[command(flatten)]
    pub(crate) leg: LegArgs,
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
    /// (default 1); for a parallel robot ±L mm, ±L mrad, ±L·10⁻³ on gains.
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
    /// For --monte-carlo: the simulated real robots' error level (1 = ±1 cm, ±1°; for a
    /// parallel robot ±1 mm, ±1 mrad).
    #[arg(long, default_value_t = 0.1)]
    pub(crate) error_level: f64,
    /// Seed of the test poses and the simulations.
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// A parallel robot's work region, over which the calibrated robot's
    /// error is predicted (and --monte-carlo's calibrations judged):
    /// actuator ranges with their units, e.g. qm1=-12..12mm (default: the
    /// whole workspace). A serial robot's prediction is judged at its test
    /// poses: give those in the region with --test-poses.
    #[arg(long, value_name = "qm1=MIN..MAXmm,..", conflicts_with = "study")]
    pub(crate) work_region: Option<String>,
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
    #[command(flatten)]
    pub(crate) leg: LegArgs,
    /// Measurements (CSV). A parallel robot takes it again for each set
    /// measured from another tracker station (each station's frame is
    /// identified with the platform); a serial robot's several sets go in a
    /// study file (--study).
    #[arg(
        long,
        value_name = "DATA.csv",
        required_unless_present = "study",
        conflicts_with = "study",
        action = clap::ArgAction::Append
    )]
    pub(crate) data: Vec<PathBuf>,
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
    /// the joint limits); a parallel robot's actuator ranges, e.g.
    /// qm1=-10..10mm. A result that holds in the measured region only is not
    /// trusted (exit 5) and its file keeps that region.
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
    /// Seed of the cross-validation folds (with --cv only: nothing else of
    /// an identification is random).
    #[arg(long, default_value_t = gecaro_calib::simulation::DEFAULT_SEED, requires = "cv")]
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
