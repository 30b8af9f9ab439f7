//! Compensation as a job: a program written for the nominal robot, corrected
//! for the calibrated one ("program filtering"); targets it cannot reach
//! within the limits are flagged, never dropped.

mod summary;
mod tool;

use gecaro_calib::compensation::{CompensatedPoint, Compensator, Match, ProgramPoint};
use gecaro_calib::elastic::commanded_under_load;
use gecaro_calib::{Observer, report_step};
use gecaro_core::{LinkMass, Robot};
use gecaro_io::{CorrectedProgram, ProgramFile, ProgramLayout, ProgramReader, RobotFile};
use nalgebra::IsometryMatrix3;
use serde::Deserialize;
use std::path::PathBuf;

use crate::base_frame::{BasePointsSource, BaseRegistration};
use crate::documents::{CompensatedJson, CompensationJson};
use crate::error::AppError;
use crate::files::{Files, Opened};
use crate::measurements::Unknown;
use crate::method::parse_name;
use crate::output::Output;
use crate::rebase::{check_same_frame, owner_base, rebased_file};
use crate::sources::{CsvInput, DataFormatSpec, DataSource, RobotSource, check_row_count};

pub use crate::documents::LargestCorrection;
pub use summary::CompensationSummary;

/// Where a program's targets come from (JSON: `{"file": name}` or
/// `{"csv": {"text": …, "name": …}}`, as a request's data).
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ProgramSource {
    /// A program file (CSV): joint targets `qm1..qmn`, or Cartesian targets
    /// `x,y,z[,qw,qx,qy,qz]`, other columns kept.
    File(String),
    /// A program file's text (an upload), with a name for messages.
    Csv {
        /// The file's content.
        text: String,
        /// Its name (for messages).
        name: Option<String>,
    },
    /// Targets given already (Python arrays).
    #[serde(skip)]
    Points(Vec<ProgramPoint>),
}

/// A program to correct; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct CompensateRequest {
    /// The nominal robot the program was written with.
    pub nominal: RobotSource,
    /// The calibrated robot.
    pub calibrated: RobotSource,
    /// The program.
    pub program: ProgramSource,
    /// Units and column names of a program file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// What a joint target asks: `pose` (default) or `position`.
    #[serde(default, rename = "match")]
    pub matching: Option<String>,
    /// Re-express the calibrated robot in the nominal's base frame first (a
    /// robot calibrated in a tracker's frame, a program in robot
    /// coordinates; `crate::rebase`). Without it, robots in different
    /// frames are refused.
    #[serde(default)]
    pub rebase: bool,
    /// The base as its owner defines it, registered by points
    /// (`crate::base_frame`): the calibrated robot is re-expressed in it
    /// first, instead of in the nominal's convention (`rebase`).
    #[serde(default)]
    pub base_points: Option<BasePointsSource>,
    /// Or by the circles of joints 1 and 2 turned alone
    /// (`crate::base_circles`): a position data file.
    #[serde(default)]
    pub base_circles: Option<DataSource>,
    /// Units and column names of the base-points or circles file.
    #[serde(default)]
    pub base_points_format: DataFormatSpec,
    /// The payload the robot will carry (`12kg`, `12kg,0,0,80mm`): an
    /// elastic calibrated robot's joints are commanded where they come to
    /// rest on the targets under its weight and the links' (docs/elastic.md).
    pub payload: Option<String>,
    /// The tool the program's targets are for: a tool the calibration
    /// identified (its name in the calibrated file's `[tools]`), or its
    /// pose in frame n+1 (`0,0,120mm[,qw,qx,qy,qz]`); frame n+1 itself when
    /// omitted (see the `tool` module).
    pub tool: Option<String>,
    /// The largest turn of the tool a position match may leave (an angle
    /// with its unit, [`DEFAULT_MAX_TOOL_TURN`] when omitted): targets
    /// turned more are flagged.
    pub max_tool_turn: Option<String>,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// The largest turn of the tool a position match leaves unflagged (rad):
/// 1°, 17 mm at a metre — beyond what a process holding its tool square
/// (welding, drilling, dispensing) tolerates.
pub const DEFAULT_MAX_TOOL_TURN: f64 = std::f64::consts::PI / 180.0;

/// A corrected program.
#[derive(Clone, Debug)]
pub struct Compensated {
    /// The program file, when the program came from one (its targets
    /// moved to `points`).
    pub program: Option<ProgramFile>,
    /// The targets.
    pub points: Vec<ProgramPoint>,
    /// Per target: the corrected joints, the residual and the status.
    pub results: Vec<CompensatedPoint>,
    /// The corrected program file's text (the program's columns, units and
    /// separator; the joints corrected), when the program came from a file.
    pub corrected: Option<String>,
    /// A name to offer it under: `weld.csv` → `weld-compensated.csv`.
    pub corrected_name: Option<String>,
    /// Where the corrected program was written, if asked for.
    pub saved: Option<PathBuf>,
    /// The nominal robot.
    pub nominal: RobotFile,
    /// The counts, flagged lines and largest residual and correction.
    pub summary: CompensationSummary,
    /// The base registered by points, when they were given.
    pub registration: Option<BaseRegistration>,
}

/// A program file corrected as it was read ([`CompensateRequest::run_streamed`]).
#[derive(Clone, Debug)]
pub struct CompensatedFile {
    /// The program's columns (units, kind, columns not read).
    pub layout: ProgramLayout,
    /// The counts, flagged lines and largest residual and correction.
    pub summary: CompensationSummary,
    /// Where the corrected program was written.
    pub saved: PathBuf,
    /// The base registered by points, when they were given.
    pub registration: Option<BaseRegistration>,
}

/// What moves an elastic calibrated robot's solutions to where its joints
/// are commanded so that, yielding to gravity with the payload, they come
/// to rest on them ([`commanded_under_load`]).
struct Unloading {
    payload: Option<LinkMass>,
}

impl Unloading {
    /// The unloading of `calibrated` carrying `payload`; `None` for a rigid
    /// robot.
    ///
    /// # Errors
    /// A payload that is not one, or given for a rigid robot (it would
    /// change nothing: calibrate with the elastic model).
    fn new(calibrated: &RobotFile, payload: Option<&str>) -> Result<Option<Self>, AppError> {
        let payload = payload
            .map(|text| crate::loads::payload(calibrated, text, "payload"))
            .transpose()?;
        if calibrated.robot.is_elastic() {
            return Ok(Some(Unloading { payload }));
        }
        match payload {
            Some(_) => Err(AppError::setting(
                "payload",
                "the calibrated robot is rigid, so a payload changes none of its poses: \
                 calibrate with the elastic model (model elastic) to compensate its weight",
            )),
            None => Ok(None),
        }
    }

    /// `results` of `calibrated` moved to where its joints are commanded.
    fn apply(
        &self,
        calibrated: &RobotFile,
        results: &mut [CompensatedPoint],
    ) -> Result<(), AppError> {
        for result in results {
            result.motor_positions = commanded_under_load(
                &calibrated.robot,
                &calibrated.masses,
                self.payload.as_ref(),
                &result.motor_positions,
            )?;
        }
        Ok(())
    }
}

/// The robots and settings of a request, checked before any work.
struct Prepared {
    matching: Match,
    nominal: RobotFile,
    calibrated: RobotFile,
    /// The nominal and calibrated robots solved: with the program's tool
    /// as their frame n+1 when one is given.
    solved: (Robot, Robot),
    /// The largest tool turn left unflagged (rad).
    max_tool_turn: f64,
    /// The base registered by points, when they were given.
    registration: Option<BaseRegistration>,
    /// An elastic robot's solutions moved for its loads.
    unloading: Option<Unloading>,
}

/// The name a corrected copy of the program `label` (a file name or an
/// upload's) is offered under: `weld.csv` → `weld-compensated.csv`.
fn corrected_name(label: &str) -> String {
    let file = std::path::Path::new(label)
        .file_stem()
        .and_then(|stem| stem.to_str())
        .filter(|stem| !stem.is_empty())
        .unwrap_or("program");
    format!("{file}-compensated.csv")
}

impl ProgramSource {
    /// The name of the program in messages.
    pub fn label(&self) -> String {
        match self {
            ProgramSource::File(name) => name.clone(),
            ProgramSource::Csv { name, .. } => {
                name.clone().unwrap_or_else(|| "uploaded program".into())
            }
            ProgramSource::Points(_) => "the targets given".into(),
        }
    }

    /// The CSV the program is read from, named `label` in messages (its
    /// [`label`](Self::label)); `None` for targets given already.
    pub(crate) fn csv<'a>(&'a self, label: &'a str) -> Option<CsvInput<'a>> {
        match self {
            ProgramSource::File(name) => Some(CsvInput::File(name)),
            ProgramSource::Csv { text, .. } => Some(CsvInput::Text { text, label }),
            ProgramSource::Points(_) => None,
        }
    }
}

impl CompensateRequest {
    /// A correction of `program` from `nominal` to `calibrated`.
    pub fn new(nominal: RobotSource, calibrated: RobotSource, program: ProgramSource) -> Self {
        CompensateRequest {
            nominal,
            calibrated,
            program,
            format: DataFormatSpec::default(),
            matching: None,
            rebase: false,
            base_points: None,
            base_circles: None,
            base_points_format: DataFormatSpec::default(),
            payload: None,
            tool: None,
            max_tool_turn: None,
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// The robots and the match, the output checked: all a run needs
    /// before any work.
    fn prepare(&self, files: &dyn Files) -> Result<Prepared, AppError> {
        self.unknown.check()?;
        let matching = parse_name(
            "match",
            self.matching.as_deref(),
            &Match::NAMES,
            Match::from_name,
        )?
        .unwrap_or_default();
        let nominal = self.nominal.load(files)?;
        let mut calibrated = self.calibrated.load(files)?;
        let mut registration = None;
        if self.rebase && (self.base_points.is_some() || self.base_circles.is_some()) {
            return Err(AppError::setting(
                if self.base_points.is_some() {
                    "base_points"
                } else {
                    "base_circles"
                },
                "the base is registered by its points or circles, or by the nominal's convention \
                 (rebase): give one of them",
            ));
        }
        if let Some(registered) = owner_base(
            files,
            (self.base_points.as_ref(), self.base_circles.as_ref()),
            &self.base_points_format,
            &calibrated,
            &nominal,
        )? {
            calibrated = registered.rebased(&calibrated)?;
            registration = Some(registered);
            // The owner's base and the nominal's: one robot, millimetres apart.
            check_same_frame(&nominal.robot, &calibrated.robot)?;
        } else if self.rebase {
            calibrated = rebased_file(&calibrated, &nominal.robot)?.1;
        } else {
            check_same_frame(&nominal.robot, &calibrated.robot)?;
        }
        let solved = match tool::program_tool(&calibrated, self.tool.as_deref())? {
            Some(pose) => {
                let world = IsometryMatrix3::identity();
                (
                    nominal.robot.reframed(&world, &pose)?,
                    calibrated.robot.reframed(&world, &pose)?,
                )
            }
            None => (nominal.robot.clone(), calibrated.robot.clone()),
        };
        let max_tool_turn = match self.max_tool_turn.as_deref() {
            None => DEFAULT_MAX_TOOL_TURN,
            Some(text) => gecaro_io::parse_angle(text)
                .map_err(|message| AppError::setting("max_tool_turn", message))?,
        };
        if let Some(name) = &self.output.save_as {
            // The taught program is never replaced, whatever `overwrite` says.
            if let ProgramSource::File(program) = &self.program
                && files.is_same_file(program, name)
            {
                return Err(AppError::setting(
                    "save_as",
                    format!(
                        "{name} is the program itself: a corrected program never replaces the \
                         taught one; write it to another file"
                    ),
                ));
            }
            files.check_output(name, "csv", self.output.overwrite)?;
        }
        Ok(Prepared {
            matching,
            unloading: Unloading::new(&calibrated, self.payload.as_deref())?,
            nominal,
            calibrated,
            solved,
            max_tool_turn,
            registration,
        })
    }

    /// Corrects every target, writes the corrected program if asked (checked
    /// before any work); `observer` hears of the targets done.
    ///
    /// # Errors
    /// Bad files or settings, robots of different joints, an interruption.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<Compensated, AppError> {
        let Prepared {
            matching,
            nominal,
            calibrated,
            unloading,
            solved,
            max_tool_turn,
            registration,
        } = self.prepare(files)?;
        let label = self.program.label();
        let input = self.program.csv(&label);
        let mut program = input
            .map(|input| {
                let format = self.format.format()?;
                let program = input.parse(files, |mut content, path| {
                    Ok(gecaro_io::parse_program(
                        content.reader(),
                        path,
                        &nominal.robot,
                        &format,
                    )?)
                })?;
                check_row_count(files, &label, program.points.len(), "targets")?;
                Ok::<_, AppError>(program)
            })
            .transpose()?;
        // A program file's targets move here (a million are not copied).
        let points = match (&mut program, &self.program) {
            (Some(program), _) => std::mem::take(&mut program.points),
            (None, ProgramSource::Points(points)) => points.clone(),
            (None, _) => Vec::new(),
        };
        let mut results = Compensator::new(&solved.0, &solved.1, matching)?
            .within(calibrated.measured_region.clone())
            .compensate_all(&points, observer)?;
        if let Some(unloading) = &unloading {
            unloading.apply(&calibrated, &mut results)?;
        }
        let mut summary = CompensationSummary::limiting_tool_turn(max_tool_turn);
        summary.add(
            &points,
            &results,
            |index| {
                program
                    .as_ref()
                    .map_or(index, |program| program.line(index))
            },
            program.as_ref().map(ProgramFile::layout),
        );
        let corrected = program
            .as_ref()
            .map(|program| program.format_corrected(&results));
        let saved = match (&self.output.save_as, &corrected) {
            (Some(name), Some(corrected)) => {
                Some(files.write(name, "csv", corrected.as_bytes(), self.output.overwrite)?)
            }
            (Some(_), None) => {
                return Err(AppError::setting(
                    "save_as",
                    "a corrected program is written for a program file",
                ));
            }
            (None, _) => None,
        };
        Ok(Compensated {
            corrected_name: corrected.as_ref().map(|_| corrected_name(&label)),
            corrected,
            program,
            points,
            results,
            saved,
            nominal,
            summary,
            registration,
        })
    }

    /// Corrects a program file and writes the corrected program as it reads
    /// it, a block of targets at a time, in memory that does not grow with
    /// the program: what `gecaro compensate` does with a million targets.
    /// The output is written atomically, as by [`run`](Self::run): an error
    /// or an interruption leaves nothing behind. `observer` hears of the
    /// targets done, of an estimated total (from the bytes read).
    ///
    /// # Errors
    /// As [`run`](Self::run); a program that is not a file, or no `save_as`.
    pub fn run_streamed(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<CompensatedFile, AppError> {
        let (ProgramSource::File(name), Some(save_as)) = (&self.program, &self.output.save_as)
        else {
            return Err(AppError::setting(
                "save_as",
                "a program is corrected as it is read from a program file into a file named by save_as",
            ));
        };
        let prepared = self.prepare(files)?;
        let calibrated = &prepared.calibrated;
        let (nominal, solved_calibrated) = (&prepared.solved.0, &prepared.solved.1);
        let format = self.format.format()?;
        let Opened { path, bytes } = files.open(name, &["csv"])?;
        let length = bytes.length();
        let mut reader = bytes.into_reader();
        let mut program = ProgramReader::new(&mut reader, &path, nominal, &format)?;
        let layout = program.layout().clone();
        let mut compensator = Compensator::new(nominal, solved_calibrated, prepared.matching)?
            .within(calibrated.measured_region.clone());
        let mut summary = CompensationSummary::limiting_tool_turn(prepared.max_tool_turn);
        let mut corrected: Option<CorrectedProgram<'_>> = None;
        let saved = files.write_streamed(save_as, "csv", self.output.overwrite, &mut |output| {
            let failed = |error: std::io::Error| {
                AppError::from(gecaro_io::Error::Write {
                    path: PathBuf::from(save_as),
                    message: error.to_string(),
                })
            };
            while let Some(block) = program.next_block()? {
                check_row_count(files, name, program.targets(), "targets")?;
                let before = compensator.done();
                let bytes_read = program.bytes_read().max(1) as f64;
                // The total, estimated from the share of the file read.
                let estimate = |done: usize| {
                    length.map_or(done, |length| {
                        ((done as f64 * length as f64 / bytes_read).round() as usize).max(done)
                    })
                };
                let mut results = compensator.compensate_in_parts(&block.points, |done| {
                    let done = before + done;
                    report_step(observer, done, estimate(done))
                })?;
                if let Some(unloading) = &prepared.unloading {
                    unloading.apply(calibrated, &mut results)?;
                }
                // The first block decides the columns and the decimal mark.
                let corrected = match &mut corrected {
                    Some(corrected) => corrected,
                    None => {
                        let oriented = results.iter().any(|result| result.rotation_error.is_some());
                        let created = corrected.insert(CorrectedProgram::new(
                            &layout,
                            oriented,
                            block.comma_seen(),
                        ));
                        output.write_all(&created.header()).map_err(failed)?;
                        created
                    }
                };
                corrected
                    .write_rows(&block, &results, output)
                    .map_err(failed)?;
                summary.add(
                    &block.points,
                    &results,
                    |index| block.line(index),
                    Some(&layout),
                );
            }
            Ok(())
        })?;
        Ok(CompensatedFile {
            layout,
            summary,
            saved,
            registration: prepared.registration,
        })
    }
}

impl Compensated {
    /// The line (file) or row (0-based, arrays) of target `index`.
    pub fn line(&self, index: usize) -> usize {
        self.program
            .as_ref()
            .map_or(index, |program| program.line(index))
    }

    /// Why the corrected program is not to be run as it is: targets
    /// reconfigured, beyond a limit or not reached.
    pub fn failure(&self) -> Option<AppError> {
        self.summary.failure(self.saved.as_deref())
    }

    /// The JSON document (`gecaro compensate --json`).
    pub fn document(&self) -> CompensationJson {
        let mut document = self.summary.document(
            self.saved.as_ref().map(|path| path.display().to_string()),
            self.results
                .iter()
                .enumerate()
                .map(|(index, result)| CompensatedJson {
                    line: self.line(index),
                    status: result.status.word(),
                    motor_positions: result.motor_positions.clone(),
                    position_error: result.position_error,
                    rotation_error: result.rotation_error,
                    tool_turn: result.tool_turn,
                })
                .collect(),
        );
        document.registration = self.registration.as_ref().map(BaseRegistration::document);
        document
    }
}

impl CompensatedFile {
    /// The JSON document: counts, flagged lines and the file written; no
    /// `points` (they are in the file).
    pub fn document(&self) -> CompensationJson {
        let mut document = self
            .summary
            .document(Some(self.saved.display().to_string()), Vec::new());
        document.registration = self.registration.as_ref().map(BaseRegistration::document);
        document
    }

    /// Why the corrected program is not to be run as it is.
    pub fn failure(&self) -> Option<AppError> {
        self.summary.failure(Some(&self.saved))
    }
}

#[cfg(test)]
mod tests {
    use super::corrected_name;

    #[test]
    fn a_corrected_program_is_named_after_the_program() {
        assert_eq!(corrected_name("weld.csv"), "weld-compensated.csv");
        assert_eq!(corrected_name("cell/path.csv"), "path-compensated.csv");
        assert_eq!(corrected_name(""), "program-compensated.csv");
    }
}
