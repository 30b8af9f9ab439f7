//! Robots from and to other formats as jobs (`docs/interchange.md`): a
//! URDF, a DH or modified-DH table or a SYMORO file read into a robot file,
//! with the joint calibration beside it when there is one
//! ([`ImportRequest`]), a robot written as a URDF or a DH table, with its
//! joint calibration beside it when the format cannot carry gains or
//! couplings ([`ExportRequest`]): an export imports to the same motion.

use std::path::{Path, PathBuf};

use gecaro_io::{ChainEnds, Exported, ImportOptions, RobotFile, RobotFormat, TableUnits};
use serde::Deserialize;

use crate::error::{AppError, ErrorKind, Part};
use crate::files::Files;
use crate::measurements::Unknown;
use crate::method::parse_name;
use crate::output::Output;
use crate::sources::{RobotSource, angle_unit, length_unit};

/// The format of a name: `urdf`, `dh`, `mdh`, `symoro`.
fn format(key: &str, name: Option<&str>) -> Result<Option<RobotFormat>, AppError> {
    parse_name(key, name, &RobotFormat::NAMES, RobotFormat::from_name)
}

/// A robot read from another format; see the module docs.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct ImportRequest {
    /// The file: `.urdf`, `.par`, or a table (`.toml` with `convention`, `.csv`).
    pub file: String,
    /// The file's content, uploaded: `file` is then only its name (for its
    /// extension and messages), and no file beside it (a URDF's joint
    /// calibration) is read.
    pub text: Option<String>,
    /// Its format, when the file does not tell: `urdf`, `dh`, `mdh`, `symoro`.
    pub format: Option<String>,
    /// URDF: the link whose frame is the world frame (default: the root).
    pub base: Option<String>,
    /// URDF: the link whose frame is frame n+1 (default: the leaf with the
    /// most moving joints).
    pub tip: Option<String>,
    /// The robot's name (default: the file's).
    pub name: Option<String>,
    /// Tables: the unit of lengths that do not state theirs (`m`, `mm`).
    pub length_unit: Option<String>,
    /// Tables: the unit of angles that do not state theirs (`rad`, `deg`).
    pub angle_unit: Option<String>,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A robot read from another format, and where it was written.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The robot file and what the conversion did.
    pub imported: gecaro_io::Imported,
    /// Where the robot file was written, if asked for.
    pub saved: Option<PathBuf>,
}

impl ImportRequest {
    /// An import of `file`, its format told by its name.
    pub fn new(file: impl Into<String>) -> Self {
        ImportRequest {
            file: file.into(),
            ..ImportRequest::default()
        }
    }

    /// Reads the file and writes the robot file if asked (checked first).
    ///
    /// # Errors
    /// A file that cannot be read or converted (naming the line), settings
    /// that are not understood, an output that exists.
    pub fn run(&self, files: &dyn Files) -> Result<Imported, AppError> {
        self.unknown.check()?;
        let options = ImportOptions {
            format: format("format", self.format.as_deref())?,
            chain: ChainEnds {
                base: self.base.clone(),
                tip: self.tip.clone(),
                name: self.name.clone(),
            },
            units: TableUnits {
                length: length_unit(self.length_unit.as_deref())?,
                angle: angle_unit(self.angle_unit.as_deref())?,
            },
        };
        self.output.check(files, "toml")?;
        let (path, text) = match &self.text {
            Some(text) => (PathBuf::from(&self.file), text.clone()),
            None => files.read_text(&self.file, &["urdf", "par", "toml", "csv", "xml"])?,
        };
        let imported = gecaro_io::import_robot_text(&text, &path, &options).map_err(|error| {
            AppError::from(error).with_help(vec![
                Part::Text("an import is told its format with ".into()),
                Part::Setting("format".into()),
                Part::Text(" (urdf, dh, mdh, symoro), a URDF's chain with ".into()),
                Part::Setting("base".into()),
                Part::Text(" and ".into()),
                Part::Setting("tip".into()),
                Part::Text(" (link names), a table's units with ".into()),
                Part::Setting("length_unit".into()),
                Part::Text(" and ".into()),
                Part::Setting("angle_unit".into()),
            ])
        })?;
        let mut imported = imported;
        let calibration = joint_calibration_name(&self.file);
        if self.text.is_none()
            && !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("par"))
            && files.is_file(&calibration)
        {
            let (calibration_path, text) = files.read_text(&calibration, &["yaml"])?;
            gecaro_io::apply_joint_calibration(&mut imported.file, &text, &calibration_path)?;
            imported.notes.push(format!(
                "read the joint calibration beside it ({calibration}): the gains and couplings \
                 the export could not carry"
            ));
        }
        let saved = match &self.output.save_as {
            Some(name) => Some(files.write(
                name,
                "toml",
                gecaro_io::robot_file_text(&imported.file, std::path::Path::new(name))?.as_bytes(),
                self.output.overwrite,
            )?),
            None => None,
        };
        Ok(Imported { imported, saved })
    }
}

/// A robot written in another format; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct ExportRequest {
    /// The robot.
    pub robot: RobotSource,
    /// `urdf`, `dh` or `mdh`.
    pub to: String,
    /// Re-express the robot in this nominal robot's base frame first (a
    /// robot calibrated in a tracker's frame, exported in its own;
    /// `crate::rebase`).
    pub rebase: Option<RobotSource>,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A robot in another format, and where it was written.
#[derive(Clone, Debug)]
pub struct ExportedRobot {
    /// The robot.
    pub robot: RobotFile,
    /// The format.
    pub format: RobotFormat,
    /// The text, the joint calibration and the notes.
    pub exported: Exported,
    /// The files written: the export, then its joint calibration.
    pub saved: Vec<PathBuf>,
}

/// The words of a format in messages.
pub fn format_name(format: RobotFormat) -> &'static str {
    match format {
        RobotFormat::Urdf => "a URDF",
        RobotFormat::Dh => "a standard DH table",
        RobotFormat::Mdh => "a modified DH table",
        RobotFormat::Symoro => "a SYMORO file",
    }
}

impl ExportRequest {
    /// An export of `robot` to the format `to`.
    pub fn new(robot: RobotSource, to: impl Into<String>) -> Self {
        ExportRequest {
            robot,
            to: to.into(),
            rebase: None,
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// Converts the robot and writes both files, or neither (every refusal
    /// before the first write; the joint calibration removed when the export
    /// itself cannot be written).
    ///
    /// # Errors
    /// A format that cannot carry the robot, files that exist or cannot be
    /// written.
    pub fn run(&self, files: &dyn Files) -> Result<ExportedRobot, AppError> {
        self.unknown.check()?;
        let format = format("to", Some(&self.to))?.unwrap_or(RobotFormat::Urdf);
        let mut robot = self.robot.load(files)?;
        if let Some(nominal) = &self.rebase {
            robot = crate::rebase::rebased_file(&robot, &nominal.load(files)?.robot)?.1;
        }
        // A table has no Hayati β: the nearest robot without it, its error
        // stated (or refused beyond what a table may carry).
        let joints = 2..=robot.robot.joint_count();
        let nearest = if format != RobotFormat::Urdf
            && robot
                .robot
                .frames()
                .iter()
                .enumerate()
                .any(|(j, frame)| joints.contains(&j) && frame.beta != 0.0)
        {
            Some(crate::nearest_table::nearest_without_beta(
                &robot.robot,
                format_name(format),
            )?)
        } else {
            None
        };
        let written = match &nearest {
            Some(nearest) => RobotFile {
                robot: nearest.robot.clone(),
                ..robot.clone()
            },
            None => robot.clone(),
        };
        let mut exported = gecaro_io::export_robot(&written, format).map_err(|message| {
            AppError::plain(
                ErrorKind::Usage,
                format!(
                    "{} cannot be written as {}: {message}",
                    robot.robot.name(),
                    format_name(format)
                ),
            )
        })?;
        if let Some(nearest) = &nearest {
            exported.notes.insert(0, nearest.note());
        }
        let saved = match &self.output.save_as {
            Some(name) => write_export(&exported, format, name, self.output.overwrite, files)?,
            None => Vec::new(),
        };
        Ok(ExportedRobot {
            robot,
            format,
            exported,
            saved,
        })
    }
}

/// Writes an export in `format` to `name` and its joint calibration (if
/// any) beside it: both files or neither (every refusal before the first
/// write; the joint calibration removed when the export itself cannot be
/// written). Returns the files written, the export first.
///
/// # Errors
/// Files that exist (without `overwrite`) or cannot be written.
pub fn write_export(
    exported: &Exported,
    format: RobotFormat,
    name: &str,
    overwrite: bool,
    files: &dyn Files,
) -> Result<Vec<PathBuf>, AppError> {
    let extension = match format {
        RobotFormat::Urdf => "urdf",
        RobotFormat::Symoro => "par",
        RobotFormat::Dh | RobotFormat::Mdh => "toml",
    };
    let calibration = joint_calibration_name(name);
    files.check_output(name, extension, overwrite)?;
    if exported.joint_calibration.is_some() {
        files.check_output(&calibration, "yaml", overwrite)?;
    }
    let calibration_existed = files.is_file(&calibration);
    let mut saved = Vec::new();
    if let Some(text) = &exported.joint_calibration {
        saved.push(files.write(&calibration, "yaml", text.as_bytes(), overwrite)?);
    }
    match files.write(name, extension, exported.text.as_bytes(), overwrite) {
        Ok(path) => saved.insert(0, path),
        Err(error) => {
            // The two files go together: no calibration beside a file that failed.
            if exported.joint_calibration.is_some() && !calibration_existed {
                files.remove(&calibration);
            }
            return Err(error);
        }
    }
    Ok(saved)
}

/// `FILE.joint_calibration.yaml`, where an export to `FILE.ext` puts its
/// joint calibration.
pub fn joint_calibration_name(output: &str) -> String {
    Path::new(output)
        .with_extension("joint_calibration.yaml")
        .to_string_lossy()
        .into_owned()
}
