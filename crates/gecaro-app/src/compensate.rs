//! Compensation as a job: a program written for the nominal robot, corrected
//! for the calibrated one ("program filtering"); targets it cannot reach
//! within the limits are flagged, never dropped.

use gecaro_calib::Observer;
use gecaro_calib::compensation::{
    CompensatedPoint, CompensationStatus, Match, ProgramPoint, ProgramTarget, compensate,
};
use gecaro_calib::elastic::commanded_under_load;
use gecaro_io::{ProgramFile, RobotFile};
use serde::Deserialize;

use crate::documents::{CompensatedJson, CompensationJson};
use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::measurements::Unknown;
use crate::method::parse_name;
use crate::rebase::{check_same_frame, rebased_file};
use crate::sources::{CsvInput, DataFormatSpec, RobotSource, check_row_count};

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
    /// coordinates; [`crate::rebase`]). Without it, robots in different
    /// frames are refused.
    #[serde(default)]
    pub rebase: bool,
    /// The payload the robot will carry (`12kg`, `12kg,0,0,80mm`): an
    /// elastic calibrated robot's joints are commanded where they come to
    /// rest on the targets under its weight and the links' (docs/elastic.md).
    pub payload: Option<String>,
    /// Write the corrected program (CSV) here.
    pub save_as: Option<String>,
    /// Replace a file that exists.
    #[serde(default)]
    pub overwrite: bool,
    #[serde(flatten)]
    unknown: Unknown,
}

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
    pub saved: Option<std::path::PathBuf>,
    /// The nominal robot.
    pub nominal: RobotFile,
}

/// An elastic calibrated robot's solutions moved to where its joints are
/// commanded so that, yielding to gravity with `payload`, they come to rest
/// on them ([`commanded_under_load`]).
///
/// # Errors
/// A payload that is not one, or given for a rigid robot (it would change
/// nothing: calibrate with the elastic model).
fn unload(
    calibrated: &RobotFile,
    payload: Option<&str>,
    results: &mut [CompensatedPoint],
) -> Result<(), AppError> {
    let payload = payload
        .map(|text| crate::loads::payload(text, "payload"))
        .transpose()?;
    if !calibrated.robot.is_elastic() {
        return match payload {
            Some(_) => Err(AppError::setting(
                "payload",
                "the calibrated robot is rigid, so a payload changes none of its poses: \
                 calibrate with the elastic model (model elastic) to compensate its weight",
            )),
            None => Ok(()),
        };
    }
    for result in results {
        result.motor_positions = commanded_under_load(
            &calibrated.robot,
            &calibrated.masses,
            payload.as_ref(),
            &result.motor_positions,
        )?;
    }
    Ok(())
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
            payload: None,
            save_as: None,
            overwrite: false,
            unknown: Unknown::default(),
        }
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
        if self.rebase {
            calibrated = rebased_file(&calibrated, &nominal.robot)?.1;
        } else {
            check_same_frame(&nominal.robot, &calibrated.robot)?;
        }
        if let Some(name) = &self.save_as {
            files.check_output(name, "csv", self.overwrite)?;
        }
        let label = self.program.label();
        let input = match &self.program {
            ProgramSource::File(name) => Some(CsvInput::File(name)),
            ProgramSource::Csv { text, .. } => Some(CsvInput::Text {
                text,
                label: &label,
            }),
            ProgramSource::Points(_) => None,
        };
        let mut program = input
            .map(|input| {
                let format = self.format.format()?;
                let program = input.parse(files, |reader, path| {
                    Ok(gecaro_io::parse_program(
                        reader,
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
        let mut results = compensate(
            &nominal.robot,
            &calibrated.robot,
            &points,
            matching,
            observer,
        )?;
        unload(&calibrated, self.payload.as_deref(), &mut results)?;
        let corrected = program
            .as_ref()
            .map(|program| program.format_corrected(&results));
        let saved = match (&self.save_as, &corrected) {
            (Some(name), Some(corrected)) => {
                Some(files.write(name, "csv", corrected.as_bytes(), self.overwrite)?)
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

    /// The lines of the targets with `status`.
    pub fn lines_with(&self, status: CompensationStatus) -> Vec<usize> {
        self.results
            .iter()
            .enumerate()
            .filter(|(_, result)| result.status == status)
            .map(|(index, _)| self.line(index))
            .collect()
    }

    /// The largest residual of a reached target (m).
    pub fn largest_position_error(&self) -> f64 {
        self.results
            .iter()
            .filter(|result| result.status != CompensationStatus::NotReached)
            .map(|result| result.position_error)
            .fold(0.0, f64::max)
    }

    /// The largest change of a joint between the program and the correction,
    /// in the program file's unit: (value, unit, joint number, line).
    pub fn largest_correction(&self) -> Option<(f64, &'static str, usize, usize)> {
        let program = self.program.as_ref()?;
        let mut largest: Option<(f64, &'static str, usize, usize)> = None;
        for (index, (point, result)) in self.points.iter().zip(&self.results).enumerate() {
            if result.status != CompensationStatus::Reached {
                continue;
            }
            let original = match &point.target {
                ProgramTarget::Joints(qm) => Some(qm),
                _ => point.joints.as_ref(),
            };
            for (j, (before, after)) in original
                .into_iter()
                .flatten()
                .zip(&result.motor_positions)
                .enumerate()
            {
                let (change, unit) = program.joint_in_file_unit(j, (after - before).abs());
                if largest.is_none_or(|(value, ..)| change > value) {
                    largest = Some((change, unit, j + 1, program.line(index)));
                }
            }
        }
        largest
    }

    /// Why the corrected program is not to be run as it is: targets
    /// reconfigured, beyond a limit or not reached.
    pub fn failure(&self) -> Option<AppError> {
        let flagged = self
            .results
            .iter()
            .filter(|result| result.status != CompensationStatus::Reached)
            .count();
        (flagged > 0).then(|| {
            AppError::plain(
                ErrorKind::NotConverged,
                format!(
                    "{flagged} of {} targets are flagged{}; check them before running the program",
                    self.results.len(),
                    self.saved
                        .as_ref()
                        .map_or_else(String::new, |path| format!(" in {}", path.display()))
                ),
            )
        })
    }

    /// The JSON document (`gecaro compensate --json`).
    pub fn document(&self) -> CompensationJson {
        let reconfigured = self.lines_with(CompensationStatus::Reconfigured);
        let outside = self.lines_with(CompensationStatus::OutsideLimits);
        let not_reached = self.lines_with(CompensationStatus::NotReached);
        CompensationJson {
            targets: self.results.len(),
            reached: self.results.len() - reconfigured.len() - outside.len() - not_reached.len(),
            reconfigured,
            outside_limits: outside,
            not_reached,
            largest_position_error: self.largest_position_error(),
            largest_correction: self.largest_correction().map_or(0.0, |(value, ..)| value),
            output: self.saved.as_ref().map(|path| path.display().to_string()),
            points: self
                .results
                .iter()
                .enumerate()
                .map(|(index, result)| CompensatedJson {
                    line: self.line(index),
                    status: result.status.word(),
                    motor_positions: result.motor_positions.clone(),
                    position_error: result.position_error,
                    rotation_error: result.rotation_error,
                })
                .collect(),
        }
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
