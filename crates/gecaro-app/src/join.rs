//! An instrument's export joined with a controller's log as a job
//! ([`JoinRequest`], issue 74): `gecaro join`, Python `gecaro.join`, the
//! page's `/api/join`. The files as they are written
//! ([`gecaro_io::join_tables`]); the joined data file in gecaro's units,
//! read back as `identify --data` reads it before it is written.
//!
//! **A shifted join** (one file with a row more at its top, joined by row
//! order or by keys counted from another origin) puts every point beside
//! another row's joints. Where the distance between two measured points
//! is frame-free, so is the distance between the robot's tool at their
//! configurations: with the robot's model, the RMS difference of the
//! consecutive distances is computed for the rows as joined and moved by
//! ±1 … ±[`MAX_SHIFT`] rows. A shift that explains them at least twice as
//! well ([`SHIFT_RATIO`]) as the join itself is refused with its
//! direction; a correct join is never near it (any shift pairs unrelated
//! poses), so a tool point a few centimetres from frame n+1 does not raise
//! it.

use std::path::{Path, PathBuf};

use gecaro_core::terminal_pose;
use gecaro_io::{JoinSpec, Joined};
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::measurements::Unknown;
use crate::output::Output;
use crate::sources::{CsvInput, DataFormatSpec, DataSource, RobotSource};

/// The largest shift tried, in rows either way.
pub const MAX_SHIFT: usize = 3;

/// A shift is named when it explains the distances this many times better
/// than the join as made.
pub const SHIFT_RATIO: f64 = 2.0;

/// Rows below which no shift is tried: too few distances to tell.
const MIN_SHIFT_ROWS: usize = 8;

/// The largest file joined (bytes).
const MAX_JOIN_BYTES: u64 = 512 << 20;

/// Two files to join (see the module docs).
#[derive(Clone, Debug, Deserialize)]
pub struct JoinRequest {
    /// The robot: its joints (the log's columns and units) and its model
    /// (the shift check).
    pub robot: RobotSource,
    /// The instrument's export.
    pub tracker: DataSource,
    /// The controller's log.
    pub log: DataSource,
    /// The key column of both files (of the tracker's, when `log_key` is
    /// given); none: by row order.
    #[serde(default)]
    pub key: Option<String>,
    /// The key column of the log, when its name differs.
    #[serde(default)]
    pub log_key: Option<String>,
    /// The tracker's units, column names, separator.
    #[serde(default)]
    pub tracker_format: DataFormatSpec,
    /// The log's units, column names, separator.
    #[serde(default)]
    pub log_format: DataFormatSpec,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A log row nothing measured, as JSON gives it.
#[derive(Clone, Debug, Serialize)]
pub struct UnmeasuredJson {
    /// Its key.
    pub key: String,
    /// Its line in the log.
    pub line: usize,
}

/// A join as JSON gives it (the page, `/api/join`).
#[derive(Clone, Debug, Serialize)]
pub struct JoinedJson {
    /// The joined rows.
    pub rows: usize,
    /// Whether they carry orientations.
    pub orientations: bool,
    /// Log rows nothing measured, left out.
    pub unmeasured: Vec<UnmeasuredJson>,
    /// The sentence that says so ([`JoinedData::unmeasured_note`]).
    pub unmeasured_note: Option<String>,
    /// The RMS difference between measured and modelled consecutive
    /// distances (m), when there were rows enough to check.
    pub distance_rms: Option<f64>,
    /// The joined data file's text.
    pub csv: String,
    /// Where it was written.
    pub output: Option<String>,
}

/// Two files joined.
#[derive(Clone, Debug)]
pub struct JoinedData {
    /// The join: the data file's text, rows, log rows left out.
    pub joined: Joined,
    /// The RMS difference (m) between measured and modelled consecutive
    /// distances, as joined (`None` for too few rows).
    pub distance_rms: Option<f64>,
    /// Where it was written, if asked for.
    pub saved: Option<PathBuf>,
}

impl JoinedData {
    /// What a user should know of the log rows nothing measured (left out),
    /// the first five named with their lines; `None` when there are none.
    pub fn unmeasured_note(&self) -> Option<String> {
        let unmeasured = &self.joined.unmeasured;
        if unmeasured.is_empty() {
            return None;
        }
        let shown: Vec<String> = unmeasured
            .iter()
            .take(5)
            .map(|(key, line)| format!("{key} (line {line})"))
            .collect();
        Some(format!(
            "{} log row(s) have no measured point and are left out: {}{}",
            unmeasured.len(),
            shown.join(", "),
            if unmeasured.len() > 5 { ", …" } else { "" }
        ))
    }

    /// The JSON document (`output` as `name` says it when written).
    pub fn document(&self, name: Option<&str>) -> JoinedJson {
        JoinedJson {
            rows: self.joined.points.len(),
            orientations: self.joined.orientations,
            unmeasured: self
                .joined
                .unmeasured
                .iter()
                .map(|(key, line)| UnmeasuredJson {
                    key: key.clone(),
                    line: *line,
                })
                .collect(),
            unmeasured_note: self.unmeasured_note(),
            distance_rms: self.distance_rms,
            csv: self.joined.text.clone(),
            output: self.saved.as_ref().and(name).map(str::to_owned),
        }
    }
}

impl JoinRequest {
    /// A join of `tracker` and `log` for `robot`, by row order.
    pub fn new(robot: RobotSource, tracker: DataSource, log: DataSource) -> Self {
        JoinRequest {
            robot,
            tracker,
            log,
            key: None,
            log_key: None,
            tracker_format: DataFormatSpec::default(),
            log_format: DataFormatSpec::default(),
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// Joins the files, checks the join, and writes it if asked (the output
    /// checked before any work).
    ///
    /// # Errors
    /// Files that cannot be read or joined, a shifted join, a result that
    /// does not read back as data.
    pub fn run(&self, files: &dyn Files) -> Result<JoinedData, AppError> {
        self.unknown.check()?;
        self.output.check(files, "csv")?;
        let robot = self.robot.load(files)?;
        let (tracker_text, tracker_path) = read_table(&self.tracker, files)?;
        let (log_text, log_path) = read_table(&self.log, files)?;
        let spec = JoinSpec {
            joint_types: gecaro_io::joint_types(&robot.robot),
            key: self.key.clone(),
            log_key: self.log_key.clone(),
            tracker: self.tracker_format.format()?,
            log: self.log_format.format()?,
        };
        let joined = gecaro_io::join_tables(
            (&tracker_text, &tracker_path),
            (&log_text, &log_path),
            &spec,
        )?;
        let distances = distance_mismatch(&robot.robot, &joined)?;
        if let Some((shift, moved, as_joined)) = distances.shift {
            return Err(AppError::plain(
                ErrorKind::Input,
                format!(
                    "the join looks shifted: the distances between the measured points match the \
                     robot's when each point takes the joints of the log row {} {} (RMS {:.3} \
                     mm), not as joined (RMS {:.3} mm); {}",
                    shift.unsigned_abs(),
                    // Point k beside configuration k − shift.
                    if shift > 0 {
                        "before its own"
                    } else {
                        "after its own"
                    },
                    moved * 1e3,
                    as_joined * 1e3,
                    if self.key.is_some() {
                        "check the keys' numbering in both files"
                    } else {
                        "one file has rows the other lacks at its top: join by a key column, or \
                         remove them"
                    }
                ),
            ));
        }
        // Every file gecaro writes, gecaro reads back.
        let method = if joined.orientations {
            [
                gecaro_calib::study::DataColumn::Position,
                gecaro_calib::study::DataColumn::Orientation,
            ]
            .to_vec()
        } else {
            vec![gecaro_calib::study::DataColumn::Position]
        };
        gecaro_io::parse_samples(
            joined.text.as_bytes(),
            Path::new("the joined data"),
            &spec.joint_types,
            &method,
            &gecaro_io::DataFormat::default(),
        )?;
        let saved = self.output.write(files, "csv", joined.text.as_bytes())?;
        Ok(JoinedData {
            joined,
            distance_rms: distances.as_joined,
            saved,
        })
    }
}

/// The text of a file to join, and the path its messages name.
fn read_table(source: &DataSource, files: &dyn Files) -> Result<(String, PathBuf), AppError> {
    let label = source.label();
    let input = match source {
        DataSource::File(name) => CsvInput::File(name),
        DataSource::Csv { text, .. } => CsvInput::Text {
            text,
            label: &label,
        },
        DataSource::Samples { .. } => {
            return Err(AppError::plain(
                ErrorKind::Input,
                format!("{label}: a join reads files as they are written, not samples"),
            ));
        }
    };
    input.read_text(files, MAX_JOIN_BYTES, "a file to join")
}

/// What the consecutive distances say of a join.
struct Distances {
    /// Their RMS mismatch as joined.
    as_joined: Option<f64>,
    /// A shift that explains them [`SHIFT_RATIO`] times better: the shift,
    /// its RMS and the join's.
    shift: Option<(isize, f64, f64)>,
}

/// The RMS difference between the measured and the modelled distances of
/// consecutive rows, with each point taken `shift` rows away from its
/// configuration, for the shifts of the module docs.
///
/// # Errors
/// A configuration the model cannot take (a joint value beyond reason).
fn distance_mismatch(robot: &gecaro_core::Robot, joined: &Joined) -> Result<Distances, AppError> {
    let count = joined.points.len();
    if count < MIN_SHIFT_ROWS {
        return Ok(Distances {
            as_joined: None,
            shift: None,
        });
    }
    let modelled: Vec<Vector3<f64>> = joined
        .configurations
        .iter()
        .map(|qm| {
            terminal_pose(robot, qm)
                .map(|pose| (pose * Point3::origin()).coords)
                .map_err(AppError::from)
        })
        .collect::<Result<_, _>>()?;
    let rms = |shift: isize| {
        let (mut sum, mut terms) = (0.0, 0usize);
        for i in 0..count.saturating_sub(1) {
            let (Some(a), Some(b)) = (
                i.checked_add_signed(shift).filter(|k| *k < count),
                (i + 1).checked_add_signed(shift).filter(|k| *k < count),
            ) else {
                continue;
            };
            let measured = (joined.points[b] - joined.points[a]).norm();
            let model = (modelled[i + 1] - modelled[i]).norm();
            sum += (measured - model).powi(2);
            terms += 1;
        }
        (terms > 0).then(|| (sum / terms as f64).sqrt())
    };
    let as_joined = rms(0);
    let shift = as_joined.and_then(|joined_rms| {
        (1..=MAX_SHIFT as isize)
            .flat_map(|s| [s, -s])
            .filter_map(|s| rms(s).map(|value| (s, value)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .filter(|(_, value)| value * SHIFT_RATIO < joined_rms)
            .map(|(s, value)| (s, value, joined_rms))
    });
    Ok(Distances { as_joined, shift })
}
