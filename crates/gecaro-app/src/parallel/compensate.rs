//! Compensation for a parallel robot: a program of targets (base frame) —
//! platform poses for a platform that turns, tool-point positions for a
//! Delta's plate or, matching the position only, for a platform whose
//! calibration measured one point — turned into the actuator values of the
//! calibrated robot. Its inverse model is explicit, so each target is
//! exact — no search, no residual — and only a target beyond an actuator's
//! range, or outside the actuator values a calibration that holds there
//! only measured (its file's `measured` ranges, widened by a tenth), is
//! flagged. The corrected program is a data file (`qm1…qmk` and the
//! target: `x,y,z,qw,qx,qy,qz` of a pose, `x,y,z` of a tool point) that
//! every job reads back.
//!
//! A tool-point target of a platform that turns (`match` `position`) is
//! met with the platform frame turned as the program's `qw,qx,qy,qz` say
//! when it has them, else as at home (level): the pose `(R, y − R·t)` for
//! the target `y` and the calibrated tool point `t`. The point is met
//! exactly; the orientation is the calibration's. One measured point does
//! not observe the platform frame (six of its coordinates regrouped, held
//! at the nominal values), so the real platform's turn may differ from the
//! one commanded by the frame's error the point did not see — the
//! compensation says so.

use gecaro_calib::parallel_robots::PlatformMeasure;
use gecaro_calib::study::{Sample, Samples};
use gecaro_core::MEASURED_MARGIN;
use gecaro_core::parallel_model::ParallelModel;
use gecaro_core::parallel_robot::ParallelRobot;
use nalgebra::{Isometry3, Translation3};
use serde::{Deserialize, Serialize};

use super::load_parallel_robot;
use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::output::Output;
use crate::sources::{DataFormatSpec, DataSource};

/// A compensation of a program for a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelCompensateRequest {
    /// The nominal platform the program was written for.
    pub nominal: String,
    /// The calibrated platform.
    pub calibrated: String,
    /// The program: platform poses `x,y,z,qw,qx,qy,qz` (other columns,
    /// such as the nominal actuator values, are left aside).
    pub program: DataSource,
    /// Units and columns of the program.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// What a target asks (`pose`, the default: the platform frame's pose;
    /// `position`: the tool point's position, for a platform calibrated
    /// from one point). A Delta's plate only translates: its targets are
    /// tool points either way.
    #[serde(default, rename = "match")]
    pub matching: Option<String>,
    /// The corrected program (CSV).
    #[serde(flatten)]
    pub output: Output,
}

/// A compensated program, as `gecaro compensate … --json` prints it (m).
#[derive(Clone, Debug, Serialize)]
pub struct ParallelCompensated {
    /// Targets corrected.
    pub targets: usize,
    /// The largest change of an actuator value from the nominal platform's
    /// (in the actuators' unit, metres for a gain of 1).
    pub largest_correction: f64,
    /// The program's lines whose corrected actuator values are beyond a
    /// range, with the legs (1-based).
    pub outside_range: Vec<(Option<usize>, Vec<usize>)>,
    /// The program's lines whose corrected actuator values are outside the
    /// region the calibration measured (when it holds there only), with
    /// the actuators (1-based).
    pub outside_measured: Vec<(Option<usize>, Vec<usize>)>,
    /// What the targets were: `pose` (the platform frame's) or
    /// `position` (the tool point's).
    pub matched: &'static str,
    /// What the compensation cannot promise, in words (the orientation of
    /// a platform whose calibration did not observe its frame, a tool point
    /// its calibration did not observe).
    pub note: Option<String>,
    /// Where the corrected program was written.
    pub written: Option<String>,
    /// The corrected program (CSV).
    #[serde(skip)]
    pub text: String,
    /// What an actuator is called on this robot (`leg`, `arm`), for the
    /// flagged targets' words.
    #[serde(skip)]
    pub actuator_word: &'static str,
}

impl ParallelCompensated {
    /// The error a front end ends with when targets are flagged.
    pub fn failure(&self) -> Option<AppError> {
        let listed = |flagged: &[(Option<usize>, Vec<usize>)], what: &str| {
            let lines: Vec<String> = flagged
                .iter()
                .take(5)
                .map(|(line, actuators)| {
                    let actuators: Vec<String> =
                        actuators.iter().map(ToString::to_string).collect();
                    format!(
                        "line {} ({what} {})",
                        line.map_or_else(|| "?".into(), |line| line.to_string()),
                        actuators.join(", ")
                    )
                })
                .collect();
            format!(
                "{}{}",
                lines.join(", "),
                if flagged.len() > 5 { ", …" } else { "" }
            )
        };
        let mut problems = Vec::new();
        if !self.outside_range.is_empty() {
            problems.push(format!(
                "{} of {} targets need an actuator beyond its range on the calibrated platform: {}",
                self.outside_range.len(),
                self.targets,
                listed(&self.outside_range, self.actuator_word)
            ));
        }
        if !self.outside_measured.is_empty() {
            problems.push(format!(
                "{} of {} targets are outside the actuator values the calibration measured (its \
                 result holds there only): {}",
                self.outside_measured.len(),
                self.targets,
                listed(&self.outside_measured, self.actuator_word)
            ));
        }
        (!problems.is_empty()).then(|| {
            AppError::plain(
                ErrorKind::NotConverged,
                format!(
                    "{}; they are written, flagged here only",
                    problems.join("; ")
                ),
            )
        })
    }
}

impl ParallelCompensateRequest {
    /// Whether the program's header has the column `column` (`qm1`, `qw`),
    /// or a column the format maps to it.
    fn names_column(&self, files: &dyn Files, column: &str) -> Result<bool, AppError> {
        let mapped = format!("{column}=");
        if self.format.columns.as_deref().is_some_and(|columns| {
            columns
                .split(',')
                .any(|pair| pair.trim().starts_with(&mapped))
        }) {
            return Ok(true);
        }
        let head = match &self.program {
            DataSource::File(name) => {
                let opened = files.open(name, &["csv"])?;
                let mut head = Vec::new();
                std::io::Read::read_to_end(
                    &mut std::io::Read::take(opened.bytes.into_reader(), 1 << 16),
                    &mut head,
                )
                .map_err(|cause| gecaro_io::Error::Read {
                    path: opened.path.clone(),
                    cause,
                })?;
                String::from_utf8_lossy(&head).into_owned()
            }
            DataSource::Csv { text, .. } => text.chars().take(1 << 16).collect(),
            DataSource::Samples { samples, .. } => {
                return Ok(samples.as_slice().iter().any(|sample| match column {
                    "qm1" => !sample.motor_positions().is_empty(),
                    _ => sample.orientation().is_some(),
                }));
            }
        };
        let header = head
            .lines()
            .map(str::trim)
            .find(|line| !line.is_empty() && !line.starts_with('#'))
            .unwrap_or_default();
        Ok(header
            .split([',', ';', '\t'])
            .any(|field| field.trim().trim_matches('"') == column))
    }

    /// Runs the compensation.
    ///
    /// # Errors
    /// Robots or a program that cannot be read (its line), a file that
    /// cannot be written.
    pub fn run(&self, files: &dyn Files) -> Result<ParallelCompensated, AppError> {
        let nominal = load_parallel_robot(&self.nominal, files)?;
        let calibrated = load_parallel_robot(&self.calibrated, files)?;
        let turns = calibrated.robot.pose_freedom() == 6;
        let tool_points = match self.matching.as_deref().unwrap_or("pose") {
            "pose" => !turns,
            "position" => true,
            other => {
                return Err(AppError::setting(
                    "match",
                    format!("`{other}` is no match: pose or position"),
                ));
            }
        };
        let from = calibrated.calibrated_from.as_deref();
        let note = match from {
            Some("position") if turns && !tool_points => {
                // One measured point fixes the tool point, not the platform
                // frame (six of its coordinates are regrouped): a target pose
                // of that frame would be met in the calibration's gauge, not
                // on the real platform.
                return Err(AppError::plain(
                    ErrorKind::Input,
                    format!(
                        "{} was calibrated from one measured point (calibrated_from = \
                         \"position\"): its platform frame is not observed, so a program of \
                         platform poses cannot be compensated with it; compensate a program of \
                         tool points (match position), or calibrate from measured poses \
                         (frame) to compensate poses",
                        self.calibrated
                    ),
                ));
            }
            Some("distance") => {
                // Distances see neither where the base frame is nor how it
                // turns: a target in the base frame would be met in the
                // calibration's gauge.
                return Err(AppError::plain(
                    ErrorKind::Input,
                    format!(
                        "{} was calibrated from distances (calibrated_from = \"distance\"): its \
                         base frame is not observed, so targets stated in it cannot be \
                         compensated with it; calibrate from measured poses or points to \
                         compensate a program",
                        self.calibrated
                    ),
                ));
            }
            Some("position") if turns => Some(
                "the tool points are met; the platform's orientation is the calibration's: one \
                 measured point does not observe the platform frame, so the real platform may \
                 turn from the commanded orientation by the frame's error the point did not see"
                    .to_owned(),
            ),
            Some("leg") => Some(
                "a measuring leg sees no frame and no tool point: the targets are met in the \
                 frames joints 1–3 make at their stated coordinates, and the tool point is the \
                 file's, so they are met as far as the platform's base and tool are where the \
                 drawing puts them"
                    .to_owned(),
            ),
            Some("frame") if tool_points && turns => Some(
                "the tool point is the file's: a calibration from measured poses does not \
                 observe it, so the targets are met as far as it is right"
                    .to_owned(),
            ),
            _ => None,
        };
        self.output.check(files, "csv")?;
        // A program may carry the nominal actuator values (a data file, a
        // program written for the nominal platform): read and left aside.
        let actuators = if self.names_column(files, "qm1")? {
            super::actuator_types(&calibrated.robot)
        } else {
            Vec::new()
        };
        // A platform that turns is commanded by its frame's pose, or by its
        // tool point's position; one that only translates (a Delta's plate)
        // by its tool point's position, the point its calibration observed.
        let measure = if tool_points {
            PlatformMeasure::Point
        } else {
            PlatformMeasure::Pose
        };
        // Tool points of a platform that turns: turned as the program says
        // when it has orientations.
        let columns = if tool_points && turns && self.names_column(files, "qw")? {
            PlatformMeasure::Pose.columns()
        } else {
            measure.columns()
        };
        let read = self
            .program
            .read(files, &actuators, columns, &self.format.format()?)?;
        let home = calibrated.robot.home().rotation;
        // The platform's pose that puts `robot`'s tool point (or frame) on
        // the target.
        let pose_for = |robot: &ParallelRobot, target: &Sample| {
            let position = target.position.unwrap_or_default();
            if tool_points {
                let turn = if turns {
                    target.orientation.unwrap_or(home)
                } else {
                    nalgebra::UnitQuaternion::identity()
                };
                Isometry3::from_parts(Translation3::from(position - turn * robot.tool()), turn)
            } else {
                Isometry3::from_parts(
                    Translation3::from(position),
                    target.orientation.unwrap_or_default(),
                )
            }
        };
        let mut corrected = Vec::with_capacity(read.samples.len());
        let mut outside_range = Vec::new();
        let mut outside_measured = Vec::new();
        let measured = calibrated
            .measured_region
            .as_ref()
            .map(|region| region.widened(MEASURED_MARGIN));
        let mut unreached = Vec::new();
        let mut largest_correction = 0.0f64;
        for target in read.samples.to_rows() {
            let pose = pose_for(&calibrated.robot, &target);
            let Ok(actuators) = calibrated.robot.actuator_values(&pose) else {
                unreached.push(
                    target
                        .line
                        .map_or_else(|| "?".into(), |line| line.to_string()),
                );
                continue;
            };
            if let Ok(commanded) = nominal
                .robot
                .actuator_values(&pose_for(&nominal.robot, &target))
            {
                for (new, old) in actuators.iter().zip(&commanded) {
                    largest_correction = largest_correction.max((new - old).abs());
                }
            }
            let out = calibrated.robot.out_of_range(&actuators);
            if !out.is_empty() {
                outside_range.push((target.line, out));
            }
            if let Some(region) = &measured {
                let outside: Vec<usize> = region.outside(&actuators).map(|k| k + 1).collect();
                if !outside.is_empty() {
                    outside_measured.push((target.line, outside));
                }
            }
            let mut sample: Sample = measure.reading(&calibrated.robot, &pose, &actuators);
            sample.line = target.line;
            corrected.push(sample);
        }
        if !unreached.is_empty() {
            return Err(AppError::plain(
                ErrorKind::Input,
                format!(
                    "{} of the program's targets are out of the calibrated robot's reach (lines \
                     {}): nothing was written",
                    unreached.len(),
                    unreached
                        .iter()
                        .take(10)
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        let text = gecaro_io::format_samples(
            calibrated.robot.actuator_count(),
            measure.columns(),
            Samples::from(corrected.as_slice()).as_slice(),
        );
        let written = self.output.write(files, "csv", text.as_bytes())?;
        Ok(ParallelCompensated {
            targets: corrected.len(),
            largest_correction,
            outside_range,
            outside_measured,
            actuator_word: calibrated.robot.actuator_word(),
            matched: if tool_points { "position" } else { "pose" },
            note,
            written: written.map(|path| path.display().to_string()),
            text,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Flagged targets are worded with the robot's own actuators.
    #[test]
    fn a_deltas_flagged_targets_name_its_arms() {
        let compensated = ParallelCompensated {
            targets: 4,
            largest_correction: 0.001,
            outside_range: vec![(Some(3), vec![2])],
            outside_measured: vec![(Some(5), vec![1, 3])],
            matched: "position",
            note: None,
            written: None,
            text: String::new(),
            actuator_word: "arm",
        };
        let message = compensated.failure().expect("flagged").to_string();
        assert!(message.contains("line 3 (arm 2)"), "{message}");
        assert!(message.contains("line 5 (arm 1, 3)"), "{message}");
        assert!(!message.contains("leg"), "{message}");
    }
}
