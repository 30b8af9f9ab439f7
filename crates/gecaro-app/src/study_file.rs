//! Study files: several measurement sets calibrated together.
//!
//! ```toml
//! robot = "panda-ball.toml"     # relative to this file, or a ready robot's name
//! priority = "priority.toml"    # optional, as for `--priority`
//! # model = "elastic"           # optional, as for `--model` (a job's own overrides it)
//!
//! [[measurements]]
//! method = "point-link"
//! data = "sets.csv"             # relative to this file
//! sigma = 0.0003                # the sensor's standard deviation: metres (radians for orientations)
//! # sigma_rotation = 0.005      # optional: a separate σ for orientation rows (radians)
//!
//! [[measurements]]
//! method = "distance"
//! data = "pairs.csv"
//! sigma = 0.0001
//! # plane methods add: plane = "known" | "unknown", plane_normal = [..], plane_point = [..]
//! # optional: set_size = 4, orientation = "axis-angle" | "cross-products"
//!
//! [[measurements]]
//! method = "position"
//! data = "tracker.csv"          # as the tracker wrote it:
//! length_unit = "mm"            # positions (and prismatic joints) in mm
//! angle_unit = "deg"            # joint angles in degrees
//! columns = { x = "X", y = "Y", z = "Z", qm1 = "A1" }   # other column names
//! delimiter = ";"               # optional: found from the header by default
//! decimal_comma = true          # optional: allowed by default where fields are not comma-separated
//! sigma = 0.02                  # in the set's length unit (here mm): 20 µm
//! # sigma_rotation = 0.01       # in the set's angle unit (here degrees)
//! # payload = "20kg,0,0,120mm"  # optional: what the robot carried for the whole set
//!                               # (mass, and its centre in the tool frame; elastic joints),
//!                               # or: payload = { mass = "20kg", com = [0, 0, "120mm"] }
//! ```
//!
//! A σ is a number in its set's units (`length_unit`, `angle_unit`: metres and
//! radians unless said), or a text with its own unit: `sigma = "0.02mm"`,
//! `sigma_rotation = "0.01deg"`.
//!
//! `length_unit`, `angle_unit`, `columns`, `delimiter` and `decimal_comma`
//! may also stand at the top, for every set (a set's own `columns` add to
//! the top's and win), so that files written alike are described once.
//! An optional `[prior]` table puts a Gaussian prior on the parameters
//! (`length = "5mm"`, `angle = "0.5deg"`, `gain = "1%"`, and
//! `parameters = { d3 = "0.5mm" }` to override one parameter; see
//! [`gecaro_io::parse_prior`]).
//! Each set's rows are weighted by 1/σ, so that sets measured in different
//! units and with different sensors count by their precision. Columns a set
//! does not use are left alone and listed in [`StudyFile::notes`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use gecaro_calib::frames::FrameRole;
use gecaro_calib::study::DataColumn;
use gecaro_core::{FrameType, PriorityMatrix, Robot};
use serde::Deserialize;
use toml::Spanned;

use crate::study_spec::{SpecField, StudyData, StudyFile, StudyFiles, StudySpec};
use gecaro_io::Error;
use gecaro_io::RobotFile;
use gecaro_io::load_robot;
use gecaro_io::read_priority_file;
use gecaro_io::{DataFile, DataFormat, read_samples};

/// A study file's text: its statement, and where each of its keys stands.
#[derive(Debug)]
pub struct StudyText {
    /// What the file states.
    pub spec: StudySpec,
    /// The file, for messages.
    path: PathBuf,
    /// The file's text, for line numbers.
    text: String,
    /// The spans of its keys.
    located: Located,
}

/// The spans of a study file's keys (the lines its errors name).
#[derive(Debug, Default, Deserialize)]
struct Located {
    robot: Option<Spanned<toml::Value>>,
    priority: Option<Spanned<toml::Value>>,
    length_unit: Option<Spanned<toml::Value>>,
    angle_unit: Option<Spanned<toml::Value>>,
    prior: Option<Spanned<KeySpans>>,
    measurements: Option<Spanned<Vec<Spanned<KeySpans>>>>,
    #[serde(default)]
    tools: BTreeMap<String, Spanned<KeySpans>>,
    #[serde(default)]
    stations: BTreeMap<String, Spanned<KeySpans>>,
}

type KeySpans = BTreeMap<String, Spanned<toml::Value>>;

impl StudyText {
    /// The study file `path`'s text read: its keys and their types checked.
    ///
    /// # Errors
    /// [`Error::Parse`] with the line at fault.
    pub fn parse(text: String, path: &Path) -> Result<StudyText, Error> {
        let fail = |error: toml::de::Error| {
            let line = error
                .span()
                .map_or(1, |span| gecaro_io::line_at(&text, span.start));
            Error::parse(path, line, None, gecaro_io::toml_message(&error, &text))
        };
        let spec: StudySpec = toml::from_str(&text).map_err(fail)?;
        let located: Located = toml::from_str(&text).map_err(fail)?;
        Ok(StudyText {
            spec,
            path: path.to_owned(),
            text,
            located,
        })
    }

    /// The error for `field` of this file: its line, and the key.
    pub fn misplaced(&self, field: &SpecField, message: String) -> Error {
        let located = &self.located;
        let in_table = |table: &Spanned<KeySpans>, key: &str| {
            table
                .get_ref()
                .get(key)
                .map_or_else(|| table.span(), Spanned::span)
        };
        let top = |key: &str| match key {
            "robot" => located.robot.as_ref().map(Spanned::span),
            "priority" => located.priority.as_ref().map(Spanned::span),
            "length_unit" => located.length_unit.as_ref().map(Spanned::span),
            "angle_unit" => located.angle_unit.as_ref().map(Spanned::span),
            "prior.parameters" => located.prior.as_ref().map(|t| in_table(t, "parameters")),
            _ => located.prior.as_ref().map(|t| in_table(t, "length")),
        };
        let (span, key) = match field {
            SpecField::Top("measurements") => (
                located.measurements.as_ref().map(Spanned::span),
                "measurements".to_owned(),
            ),
            SpecField::Top(key) => (top(key), (*key).to_owned()),
            SpecField::Set(index, key) => (
                located
                    .measurements
                    .as_ref()
                    .and_then(|sets| sets.get_ref().get(*index))
                    .map(|set| in_table(set, key)),
                (*key).to_owned(),
            ),
            SpecField::Frame(role, name, key) => {
                let tables = match role {
                    FrameRole::Tool => &located.tools,
                    FrameRole::Station => &located.stations,
                };
                (
                    tables.get(name).map(|table| in_table(table, key)),
                    format!("{}s.{name}.{key}", role.as_str()),
                )
            }
        };
        let line = span.map_or(1, |span| gecaro_io::line_at(&self.text, span.start));
        Error::parse(&self.path, line, Some(key), message)
    }
}

/// A study file's names read on the file system, beside the file.
struct BesideStudyFile<'a> {
    text: &'a StudyText,
    folder: &'a Path,
}

impl StudyFiles for BesideStudyFile<'_> {
    type Error = Error;

    fn robot(&self, name: &str) -> Result<RobotFile, Error> {
        let path = self.folder.join(name);
        if path.is_file() {
            load_robot(&path.to_string_lossy())
        } else {
            load_robot(name)
        }
    }

    fn priority(&self, name: &str, robot: &Robot) -> Result<PriorityMatrix, Error> {
        read_priority_file(&self.folder.join(name), robot)
    }

    fn samples(
        &self,
        name: &str,
        joint_types: &[FrameType],
        columns: &[DataColumn],
        format: &DataFormat,
    ) -> Result<(DataFile, String), Error> {
        let path = self.folder.join(name);
        let read = read_samples(&path, joint_types, columns, format)?;
        Ok((read, path.display().to_string()))
    }

    fn misplaced(&self, field: &SpecField, message: String) -> Error {
        self.text.misplaced(field, message)
    }

    fn text(&self, name: &str) -> Result<(String, String), Error> {
        let path = self.folder.join(name);
        let text = std::fs::read_to_string(&path).map_err(|cause| Error::Read {
            path: path.clone(),
            cause,
        })?;
        Ok((text, path.display().to_string()))
    }
}

/// Reads a study file and everything it refers to.
///
/// # Errors
/// [`Error::Parse`] with the line of the study file at fault, or the errors
/// of the robot and data files it names.
pub fn read_study_file(path: &Path) -> Result<StudyFile, Error> {
    read_study_file_for(path, StudyData::Measured)
}

/// [`read_study_file`], its data files read for `data`.
///
/// # Errors
/// As [`read_study_file`].
pub fn read_study_file_for(path: &Path, data: StudyData) -> Result<StudyFile, Error> {
    let text = StudyText::parse(gecaro_io::read_description(path)?, path)?;
    let folder = path.parent().unwrap_or(Path::new("."));
    text.spec.build(
        &BesideStudyFile {
            text: &text,
            folder,
        },
        data,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A study of one position set in `folder`, with `sigma_line` in its table.
    fn study(folder: &Path, sigma_line: &str) -> Result<StudyFile, Error> {
        std::fs::write(
            folder.join("data.csv"),
            "qm1;qm2;qm3;qm4;qm5;qm6;X;Y;Z\n\
             0,1;0,2;0,3;0,1;0,2;0,3;100,5;200,25;300\n",
        )
        .expect("data");
        let path = folder.join("study.toml");
        std::fs::write(
            &path,
            format!(
                "robot = \"stanford\"\n[[measurements]]\nmethod = \"position\"\n\
                 data = \"data.csv\"\nlength_unit = \"mm\"\n\
                 columns = {{ x = \"X\", y = \"Y\", z = \"Z\" }}\n{sigma_line}\n"
            ),
        )
        .expect("study");
        read_study_file(&path)
    }

    #[test]
    fn sigmas_are_in_the_sets_units_or_their_own() {
        let folder = tempfile::tempdir().expect("folder");
        for line in [
            "sigma = 0.02",
            "sigma = \"0.02mm\"",
            "sigma = \"20um\"",
            "sigma = \"2e-5m\"",
        ] {
            let file = study(folder.path(), line).unwrap_or_else(|error| panic!("{line}: {error}"));
            let sigma = file.study.sets[0].sigma.expect("sigma");
            assert!((sigma - 2e-5).abs() < 1e-15, "{line}: {sigma}");
            // Fields separated by `;` with decimal commas, in millimetres.
            let position = file.study.sets[0]
                .samples
                .get(0)
                .position()
                .expect("position");
            assert!((position.x - 0.1005).abs() < 1e-12, "{position}");
        }
        let error = study(folder.path(), "sigma = \"0.02deg\"").expect_err("an angle");
        assert!(error.to_string().contains("must be a length"), "{error}");
        let error = study(folder.path(), "sigma = -1").expect_err("negative");
        assert!(
            error.to_string().contains("positive standard deviation"),
            "{error}"
        );
    }
}
