//! The test evaluated: the program's commanded poses, the measured file's
//! attained ones joined to them by pose, cycle and direction, the
//! measurement frame registered as the request says (never silently), and
//! the characteristics per pose — before and, when a second measured file
//! is given, after calibration.

use std::collections::HashMap;

use gecaro_calib::compensation::ProgramTarget;
use gecaro_calib::iso9283::{Registration, TestEvaluation, Visit, evaluate_test};
use gecaro_core::Robot;
use gecaro_io::{DataFormat, ProgramFile};
use nalgebra::{IsometryMatrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use crate::compensate::ProgramSource;
use crate::error::AppError;
use crate::files::Files;
use crate::measurements::Unknown;
use crate::output::Output;
use crate::sources::{DataFormatSpec, RobotSource};

/// Attained poses farther than this from their commanded ones (m) are not
/// the robot's error but another frame's: 50 mm, as an evaluation's.
const FRAME_MISMATCH: f64 = 0.05;

/// The largest program or measured file read (bytes).
const MAX_TEST_BYTES: u64 = 64 << 20;

/// The conditions of the test the report states (clause 6; free text as
/// the engineer writes them: "rated, 12 kg", "100 %", "30 min").
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct TestConditions {
    /// The load carried (rated, or 10 % of it).
    pub load: Option<String>,
    /// The speed (100 %, 50 % or 10 % of the rated speed).
    pub speed: Option<String>,
    /// The warm-up before the test.
    pub warm_up: Option<String>,
    /// The measurement system.
    pub instrument: Option<String>,
    /// Its uncertainty.
    pub uncertainty: Option<String>,
}

/// A test to evaluate (JSON: `{"program": {"file": "test.csv"}, "data":
/// {"file": "measured.csv"}, "frame": "best-fit"}`).
#[derive(Clone, Debug, Deserialize)]
pub struct Iso9283EvaluateRequest {
    /// The robot the program was planned on (optional: it checks that the
    /// program's targets are its poses at the program's joints).
    #[serde(default)]
    pub robot: Option<RobotSource>,
    /// The test's program (`gecaro iso9283 plan`'s).
    pub program: ProgramSource,
    /// What was measured: `pose`, `cycle` (and `direction`) with the
    /// attained `x,y,z` (and `qw,qx,qy,qz`, or another rotation form).
    pub data: ProgramSource,
    /// What was measured after calibration (the program compensated).
    #[serde(default)]
    pub after: Option<ProgramSource>,
    /// Units, column names, separator and rotation form of the measured
    /// files.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The measurement frame: `base` (default: the measurements are in the
    /// robot's base frame), `best-fit`, or its pose in the base frame with
    /// units (`3,0,0.4m,qw,qx,qy,qz`, or the 16 numbers of its matrix).
    #[serde(default)]
    pub frame: Option<String>,
    /// The test's conditions, reported as given.
    #[serde(default)]
    pub conditions: TestConditions,
    /// Where the HTML report is written (`save_as`, checked before any
    /// work) and whether it may replace a file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// What the user of an evaluated test should know, worded by `Display`.
#[derive(Clone, Debug, PartialEq)]
pub enum TestWarning {
    /// The program's targets are not the given robot's poses at its joints.
    OffModel {
        /// The program.
        program: String,
        /// The largest gap (m).
        largest: f64,
        /// The robot.
        robot: String,
    },
    /// In the base frame, attained poses far beyond any robot's error.
    AnotherFrame {
        /// The measured file.
        data: String,
        /// The largest AP_P (m).
        largest: f64,
    },
    /// The frame registered by a best fit, which absorbs a rigid error.
    BestFit {
        /// The measured file.
        data: String,
    },
}

impl std::fmt::Display for TestWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TestWarning::OffModel {
                program,
                largest,
                robot,
            } => write!(
                f,
                "{program}'s targets are up to {:.3} mm from {robot}'s poses at the program's \
                 joints: the program was not planned on this robot (or was edited)",
                largest * 1e3
            ),
            TestWarning::AnotherFrame { data, largest } => write!(
                f,
                "{data}: the attained poses are up to {:.1} mm from the commanded ones — not a \
                 robot's error but another frame's: the measurements are not in the robot's \
                 base frame; state the instrument's pose (frame) or register it by a best fit",
                largest * 1e3
            ),
            TestWarning::BestFit { data } => write!(
                f,
                "{data}: the measurement frame was registered by a best fit of the poses' \
                 barycentres: AP excludes the part of the robot's error that is a rigid motion \
                 of the cube"
            ),
        }
    }
}

/// One measured file evaluated.
#[derive(Clone, Debug)]
pub struct MeasuredTest {
    /// The file as messages name it.
    pub label: String,
    /// The characteristics.
    pub evaluation: TestEvaluation,
}

/// An evaluated test.
#[derive(Clone, Debug)]
pub struct EvaluatedTest {
    /// The program as messages name it.
    pub program: String,
    /// The robot's name, when given.
    pub robot: Option<String>,
    /// Before calibration (or the only measurement).
    pub before: MeasuredTest,
    /// After calibration.
    pub after: Option<MeasuredTest>,
    /// The conditions stated.
    pub conditions: TestConditions,
    /// What a user should know.
    pub warnings: Vec<TestWarning>,
    /// Where the HTML report was written.
    pub saved_report: Option<std::path::PathBuf>,
}

/// One pose's characteristics as JSON gives them (m, rad).
#[derive(Clone, Debug, Serialize)]
pub struct PoseResultJson {
    /// 1–5.
    pub pose: usize,
    /// Its commanded position (base frame).
    pub commanded: [f64; 3],
    /// Cycles measured.
    pub cycles: usize,
    /// The barycentre of the attained positions.
    pub barycentre: [f64; 3],
    /// AP: `p`, its components `x, y, z`; `a, b, c` about x, y, z when
    /// orientations were measured.
    pub ap: serde_json::Map<String, serde_json::Value>,
    /// RP: `l`; `a, b, c` (3 S, the standard's ±) when orientations were
    /// measured.
    pub rp: serde_json::Map<String, serde_json::Value>,
    /// vAP (`p`; `a, b, c`), with three directions.
    pub vap: Option<serde_json::Map<String, serde_json::Value>>,
    /// The attained positions (base frame), direction 1.
    pub attained: Vec<[f64; 3]>,
}

/// One measured file's results as JSON gives them.
#[derive(Clone, Debug, Serialize)]
pub struct MeasuredTestJson {
    /// The measured file.
    pub data: String,
    /// How the measurement frame was registered: `base`, `stated`,
    /// `best_fit`.
    pub registration: &'static str,
    /// The measurement frame's pose in the base frame: position (m).
    pub frame_position: [f64; 3],
    /// Its orientation (w, x, y, z).
    pub frame_quaternion: [f64; 4],
    /// Whether orientations were measured.
    pub oriented: bool,
    /// Approach directions.
    pub directions: usize,
    /// Per pose.
    pub poses: Vec<PoseResultJson>,
    /// Distance accuracy and repeatability between P2 and P4:
    /// `commanded`, `mean`, `ad`, `rd`.
    pub distance: Option<serde_json::Map<String, serde_json::Value>>,
    /// The largest AP_P of the poses.
    pub worst_ap: f64,
    /// The largest RP_l of the poses.
    pub worst_rp: f64,
}

/// An evaluated test as JSON gives it (`gecaro iso9283 evaluate --json`).
#[derive(Clone, Debug, Serialize)]
pub struct TestEvaluationJson {
    /// The robot, when given.
    pub robot: Option<String>,
    /// The program.
    pub program: String,
    /// Before calibration (or the only measurement).
    pub before: MeasuredTestJson,
    /// After calibration.
    pub after: Option<MeasuredTestJson>,
    /// The conditions stated.
    pub conditions: TestConditions,
    /// What a user should know.
    pub warnings: Vec<String>,
}

/// `values` under `names`, as a JSON object.
fn named(names: &[&str], values: &[f64]) -> serde_json::Map<String, serde_json::Value> {
    names
        .iter()
        .zip(values)
        .map(|(name, value)| ((*name).to_owned(), serde_json::json!(value)))
        .collect()
}

impl MeasuredTest {
    fn document(&self) -> MeasuredTestJson {
        let evaluation = &self.evaluation;
        let oriented = evaluation.oriented;
        let q = UnitQuaternion::from_rotation_matrix(&evaluation.frame.rotation);
        let poses = evaluation
            .poses
            .iter()
            .map(|result| {
                let c = &result.characteristics;
                let mut ap = named(
                    &["p", "x", "y", "z"],
                    &[
                        c.accuracy,
                        c.accuracy_components.x,
                        c.accuracy_components.y,
                        c.accuracy_components.z,
                    ],
                );
                let mut rp = named(&["l"], &[c.repeatability]);
                if oriented {
                    ap.extend(named(&["a", "b", "c"], &c.orientation_accuracy));
                    rp.extend(named(&["a", "b", "c"], &c.orientation_repeatability));
                }
                let vap = result.variation.as_ref().map(|variation| {
                    let mut vap = named(&["p"], &[variation.position]);
                    if oriented {
                        vap.extend(named(&["a", "b", "c"], &variation.orientation));
                    }
                    vap
                });
                PoseResultJson {
                    pose: result.pose,
                    commanded: result.commanded.translation.vector.into(),
                    cycles: c.cycles,
                    barycentre: c.barycentre.into(),
                    ap,
                    rp,
                    vap,
                    attained: result.attained.iter().map(|x| (*x).into()).collect(),
                }
            })
            .collect();
        MeasuredTestJson {
            data: self.label.clone(),
            registration: match evaluation.registration {
                Registration::Base => "base",
                Registration::Stated(_) => "stated",
                Registration::BestFit => "best_fit",
            },
            frame_position: evaluation.frame.translation.vector.into(),
            frame_quaternion: [q.w, q.i, q.j, q.k],
            oriented,
            directions: evaluation.directions,
            poses,
            distance: evaluation.distance.as_ref().map(|distance| {
                named(
                    &["commanded", "mean", "ad", "rd"],
                    &[
                        distance.commanded,
                        distance.mean,
                        distance.accuracy,
                        distance.repeatability,
                    ],
                )
            }),
            worst_ap: evaluation.worst_accuracy(),
            worst_rp: evaluation.worst_repeatability(),
        }
    }
}

impl EvaluatedTest {
    /// The self-contained HTML report (`gecaro_report::acceptance_report`);
    /// `command` is the command that made it, as the report states.
    ///
    /// # Errors
    /// A plot that cannot be drawn.
    pub fn report(&self, command: &str) -> Result<String, AppError> {
        let conditions = &self.conditions;
        let stated: [(&str, Option<&str>); 5] = [
            ("load", conditions.load.as_deref()),
            ("speed", conditions.speed.as_deref()),
            ("warm-up", conditions.warm_up.as_deref()),
            ("measurement system", conditions.instrument.as_deref()),
            ("its uncertainty", conditions.uncertainty.as_deref()),
        ];
        let words: Vec<String> = self.warnings.iter().map(ToString::to_string).collect();
        fn measured(test: &MeasuredTest) -> gecaro_report::MeasuredInput<'_> {
            gecaro_report::MeasuredInput {
                label: &test.label,
                evaluation: &test.evaluation,
            }
        }
        Ok(gecaro_report::acceptance_report(
            &gecaro_report::AcceptanceInput {
                robot: self.robot.as_deref(),
                program: &self.program,
                before: measured(&self.before),
                after: self.after.as_ref().map(measured),
                conditions: &stated,
                warnings: &words,
                command,
            },
        )?)
    }

    /// The JSON document.
    pub fn document(&self) -> TestEvaluationJson {
        TestEvaluationJson {
            robot: self.robot.clone(),
            program: self.program.clone(),
            before: self.before.document(),
            after: self.after.as_ref().map(MeasuredTest::document),
            conditions: self.conditions.clone(),
            warnings: self.warnings.iter().map(ToString::to_string).collect(),
        }
    }
}

/// The key of a visit: pose, cycle, direction.
type Key = (usize, usize, usize);

/// A source's text and its name in messages.
fn read_source(
    source: &ProgramSource,
    files: &dyn Files,
    what: &str,
) -> Result<(String, String), AppError> {
    let label = source.label();
    let Some(input) = source.csv(&label) else {
        return Err(AppError::setting(
            what,
            "the test's files are read from CSV (a file or its text)",
        ));
    };
    let (text, _) = input.read_text(files, MAX_TEST_BYTES, what)?;
    Ok((text, label))
}

/// `text` read as a program of `robot`.
fn parse(
    text: &str,
    label: &str,
    robot: &Robot,
    format: &DataFormat,
) -> Result<ProgramFile, AppError> {
    Ok(gecaro_io::parse_program(
        text.as_bytes(),
        std::path::Path::new(label),
        robot,
        format,
    )?)
}

/// The whole-number field `name` of row `index` (`default` when the file
/// has no such column).
fn key_field(
    file: &ProgramFile,
    (label, index): (&str, usize),
    name: &str,
    default: Option<usize>,
) -> Result<usize, AppError> {
    let line = file.line(index);
    match file.field(index, name) {
        Some(text) => text.trim().parse::<usize>().map_err(|_| {
            AppError::setting(
                "data",
                format!("{label}, line {line}: `{name}` holds '{text}', not a whole number"),
            )
        }),
        None => default.ok_or_else(|| {
            AppError::setting(
                "data",
                format!(
                    "{label} has no `{name}` column: the test's files name each row's pose and \
                     cycle (and direction)"
                ),
            )
        }),
    }
}

impl Iso9283EvaluateRequest {
    /// An evaluation of `data` measured running `program`.
    pub fn new(program: ProgramSource, data: ProgramSource) -> Self {
        Iso9283EvaluateRequest {
            robot: None,
            program,
            data,
            after: None,
            format: DataFormatSpec::default(),
            frame: None,
            conditions: TestConditions::default(),
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// The registration asked for.
    fn registration(&self) -> Result<Registration, AppError> {
        Ok(match self.frame.as_deref().map(str::trim) {
            None | Some("base") => Registration::Base,
            Some("best-fit" | "best_fit") => Registration::BestFit,
            Some(text) => {
                let pose = gecaro_io::parse_pose(text, "measurement frame", "the base frame")
                    .map_err(|message| {
                        AppError::setting(
                            "frame",
                            format!("`base`, `best-fit`, or the frame's pose: {message}"),
                        )
                    })?;
                Registration::Stated(pose)
            }
        })
    }

    /// Reads the files and evaluates the test.
    ///
    /// # Errors
    /// Files that cannot be read, rows that are not the program's visits,
    /// poses with fewer than two cycles, bad settings.
    pub fn run(&self, files: &dyn Files) -> Result<EvaluatedTest, AppError> {
        self.unknown.check()?;
        self.output.check(files, "html")?;
        let registration = self.registration()?;
        let format = self.format.format()?;
        let (program_text, program_label) = read_source(&self.program, files, "program")?;
        let given = self
            .robot
            .as_ref()
            .map(|robot| robot.load(files))
            .transpose()?;
        let robot = match &given {
            Some(file) => file.robot.clone(),
            None => {
                let joints = gecaro_io::header_names(program_text.as_bytes(), true)
                    .unwrap_or_default()
                    .iter()
                    .filter(|name| {
                        name.strip_prefix("qm").is_some_and(|rest| {
                            !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit())
                        })
                    })
                    .count();
                Robot::template("program", &"R".repeat(joints.max(1)))?
            }
        };
        let program = parse(
            &program_text,
            &program_label,
            &robot,
            &DataFormat::default(),
        )?;
        let mut warnings = Vec::new();
        let mut commanded: HashMap<Key, IsometryMatrix3<f64>> = HashMap::new();
        let mut off_model: f64 = 0.0;
        for (index, point) in program.points.iter().enumerate() {
            let at = (program_label.as_str(), index);
            let measured = key_field(&program, at, "measure", Some(1))? == 1;
            if !measured {
                continue;
            }
            let key = (
                key_field(&program, at, "pose", None)?,
                key_field(&program, at, "cycle", None)?,
                key_field(&program, at, "direction", Some(1))?,
            );
            let target = match &point.target {
                ProgramTarget::Pose(pose) => *pose,
                ProgramTarget::Position(position) => {
                    IsometryMatrix3::translation(position.x, position.y, position.z)
                }
                ProgramTarget::Joints(_) => {
                    return Err(AppError::setting(
                        "program",
                        format!(
                            "{program_label} has joint targets only: the test's program states \
                             the commanded pose of each row (x,y,z[,qw,qx,qy,qz]), as `gecaro \
                             iso9283 plan` writes it"
                        ),
                    ));
                }
            };
            if let (Some(file), Some(joints)) = (&given, &point.joints) {
                let model = gecaro_core::terminal_pose(&file.robot, joints)?;
                off_model =
                    off_model.max((model.translation.vector - target.translation.vector).norm());
            }
            commanded.insert(key, target);
        }
        if off_model > 1e-6 {
            warnings.push(TestWarning::OffModel {
                program: program_label.clone(),
                largest: off_model,
                robot: robot.name().to_owned(),
            });
        }
        let measure = |source: &ProgramSource, what: &str| -> Result<MeasuredTest, AppError> {
            let (text, label) = read_source(source, files, what)?;
            let file = parse(&text, &label, &robot, &format)?;
            let mut visits = Vec::with_capacity(file.points.len());
            for (index, point) in file.points.iter().enumerate() {
                let at = (label.as_str(), index);
                let key = (
                    key_field(&file, at, "pose", None)?,
                    key_field(&file, at, "cycle", None)?,
                    key_field(&file, at, "direction", Some(1))?,
                );
                let Some(target) = commanded.get(&key) else {
                    return Err(AppError::setting(
                        what,
                        format!(
                            "{label}, line {}: pose {}, cycle {}, direction {} is not a measured \
                             visit of {program_label}",
                            file.line(index),
                            key.0,
                            key.1,
                            key.2
                        ),
                    ));
                };
                let (position, orientation) = match &point.target {
                    ProgramTarget::Pose(pose) => (pose.translation.vector, Some(pose.rotation)),
                    ProgramTarget::Position(position) => (*position, None),
                    ProgramTarget::Joints(_) => {
                        return Err(AppError::setting(
                            what,
                            format!(
                                "{label} has no measured positions: its rows need x,y,z (and \
                                 qw,qx,qy,qz for orientations)"
                            ),
                        ));
                    }
                };
                visits.push(Visit {
                    pose: key.0,
                    cycle: key.1,
                    direction: key.2,
                    commanded: *target,
                    position,
                    orientation,
                });
            }
            let evaluation = evaluate_test(&visits, &registration)
                .map_err(|error| AppError::setting(what, format!("{label}: {error}")))?;
            Ok(MeasuredTest { label, evaluation })
        };
        let before = measure(&self.data, "data")?;
        let after = self
            .after
            .as_ref()
            .map(|source| measure(source, "after"))
            .transpose()?;
        for measured in std::iter::once(&before).chain(&after) {
            let worst = measured.evaluation.worst_accuracy();
            match measured.evaluation.registration {
                Registration::Base if worst > FRAME_MISMATCH => {
                    warnings.push(TestWarning::AnotherFrame {
                        data: measured.label.clone(),
                        largest: worst,
                    });
                }
                Registration::BestFit => warnings.push(TestWarning::BestFit {
                    data: measured.label.clone(),
                }),
                _ => {}
            }
        }
        let mut evaluated = EvaluatedTest {
            program: program_label,
            robot: given.map(|file| file.robot.name().to_owned()),
            before,
            after,
            conditions: self.conditions.clone(),
            warnings,
            saved_report: None,
        };
        if let Some(name) = &self.output.save_as {
            let report = evaluated.report(&format!("gecaro iso9283 evaluate → {name}"))?;
            evaluated.saved_report = self.output.write(files, "html", report.as_bytes())?;
        }
        Ok(evaluated)
    }
}
