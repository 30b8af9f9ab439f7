//! Robots in and out of other formats: URDF, Denavit–Hartenberg tables
//! (standard and Craig's modified), and SYMORO `.par` files.
//!
//! Every import gives an ordinary robot file (Khalil–Kleinfinger frames, eq.
//! 3) whose joint variables are the source's (same sign, same zero), plus
//! notes on what the conversion did; every export gives the text of the
//! other format plus notes on what it could not carry and where that went.
//! The rules per format are in `docs/interchange.md`.

use std::path::{Path, PathBuf};

use gecaro_core::Robot;
use nalgebra::DMatrix;

use crate::Error;
use crate::dh_table::{DhConvention, TableUnits};
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::output::{OutputPolicy, write_atomically};
use crate::robot_file::RobotFile;

/// A format gecaro converts robots from or to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum RobotFormat {
    /// ROS URDF (XML).
    Urdf,
    /// A standard Denavit–Hartenberg table (TOML or CSV).
    Dh,
    /// Craig's modified Denavit–Hartenberg table (TOML or CSV).
    Mdh,
    /// A SYMORO `.par` file (Khalil–Kleinfinger, serial robots).
    Symoro,
}

impl RobotFormat {
    /// The names the command line accepts.
    pub const NAMES: [&'static str; 4] = ["urdf", "dh", "mdh", "symoro"];

    /// The format of a name of [`RobotFormat::NAMES`].
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "urdf" => Some(RobotFormat::Urdf),
            "dh" => Some(RobotFormat::Dh),
            "mdh" => Some(RobotFormat::Mdh),
            "symoro" => Some(RobotFormat::Symoro),
            _ => None,
        }
    }

    /// The format a file's extension suggests: `.urdf`, `.par`; `.toml` and
    /// `.csv` tables say their convention inside or need `--from`.
    pub fn guess(path: &Path) -> Option<Self> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "urdf" | "xml" => Some(RobotFormat::Urdf),
            "par" => Some(RobotFormat::Symoro),
            _ => None,
        }
    }
}

/// Which chain to take from a URDF, and what to call the robot.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChainEnds {
    /// The base link (default: the root link).
    pub base: Option<String>,
    /// The tip link (default: the leaf with the most moving joints).
    pub tip: Option<String>,
    /// The robot's name (default: the file's).
    pub name: Option<String>,
}

/// Options of [`import_robot`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// The format; guessed from the extension (or a table's `convention`) when `None`.
    pub format: Option<RobotFormat>,
    /// URDF: the chain; all formats: the name.
    pub chain: ChainEnds,
    /// Tables: units of columns that do not state theirs.
    pub units: TableUnits,
}

/// A robot read from another format.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The robot, ready to be written as a robot file.
    pub file: RobotFile,
    /// What the conversion did that a user should know (folded joints,
    /// couplings, default limits).
    pub notes: Vec<String>,
}

/// Reads a robot from a file of another format.
///
/// # Errors
/// [`Error::Read`] when the file cannot be read (or is not a regular file),
/// [`Error::Parse`] naming the line and element of any problem, or
/// [`Error::Format`] when the format cannot be told.
pub fn import_robot(path: &Path, options: &ImportOptions) -> Result<Imported, Error> {
    let text = read_text(path, MAX_DESCRIPTION_BYTES)?;
    import_robot_text(&text, path, options)
}

/// [`import_robot`] from text; `path` names it in messages and gives the
/// extension.
///
/// # Errors
/// As [`import_robot`].
pub fn import_robot_text(
    text: &str,
    path: &Path,
    options: &ImportOptions,
) -> Result<Imported, Error> {
    let is_csv = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let format = options.format.or_else(|| RobotFormat::guess(path));
    let convention = match format {
        Some(RobotFormat::Dh) => Some(DhConvention::Standard),
        Some(RobotFormat::Mdh) => Some(DhConvention::Modified),
        _ => None,
    };
    let mut imported = match format {
        Some(RobotFormat::Urdf) => crate::urdf::import::import_urdf(text, path, &options.chain)?,
        Some(RobotFormat::Symoro) => crate::symoro::import_symoro(text, path)?,
        Some(RobotFormat::Dh | RobotFormat::Mdh) => {
            crate::dh_table::import_table(text, path, convention, is_csv, options.units)?
        }
        None if is_csv || has_extension(path, "toml") => {
            crate::dh_table::import_table(text, path, None, is_csv, options.units)?
        }
        None => {
            return Err(Error::Format {
                path: path.to_owned(),
                message: "cannot tell the format from the file name: give --from urdf, dh, mdh \
                          or symoro"
                    .into(),
            });
        }
    };
    if let Some(name) = &options.chain.name {
        imported.file.robot.set_name(name.clone());
    }
    Ok(imported)
}

fn has_extension(path: &Path, extension: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(extension))
}

/// A robot written in another format.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The text of the file.
    pub text: String,
    /// What a driver must apply to the motor values to get the file's joint
    /// values, when gains or couplings are not expressible in the format
    /// (YAML text, for `FILE.joint_calibration.yaml`).
    pub joint_calibration: Option<String>,
    /// What the conversion changed or moved elsewhere, for the user.
    pub notes: Vec<String>,
}

impl Exported {
    /// `FILE.joint_calibration.yaml`, where [`write`](Self::write) puts the
    /// joint calibration of the export to `FILE.ext`.
    pub fn joint_calibration_path(output: &Path) -> PathBuf {
        output.with_extension("joint_calibration.yaml")
    }

    /// Writes the export to `output`, and its joint calibration (if any) beside
    /// it: both files or neither. Every refusal happens before anything is
    /// written; when the second write fails, the first file (if new) is removed.
    /// Returns the files written, the export first.
    ///
    /// # Errors
    /// As [`write_atomically`] for either file.
    pub fn write(&self, output: &Path, policy: OutputPolicy) -> Result<Vec<PathBuf>, Error> {
        let calibration_path = Self::joint_calibration_path(output);
        for (path, needed) in [
            (output, true),
            (calibration_path.as_path(), self.joint_calibration.is_some()),
        ] {
            if needed && policy == OutputPolicy::KeepExisting && path.exists() {
                return Err(Error::OutputExists {
                    path: path.to_owned(),
                });
            }
        }
        let Some(calibration) = &self.joint_calibration else {
            write_atomically(output, self.text.as_bytes(), policy)?;
            return Ok(vec![output.to_owned()]);
        };
        let calibration_existed = calibration_path.exists();
        write_atomically(&calibration_path, calibration.as_bytes(), policy)?;
        if let Err(error) = write_atomically(output, self.text.as_bytes(), policy) {
            // The two files go together: no calibration beside a file that failed.
            if !calibration_existed {
                let _ = std::fs::remove_file(&calibration_path);
            }
            return Err(error);
        }
        Ok(vec![output.to_owned(), calibration_path])
    }
}

/// Writes a robot as URDF or as a DH / modified-DH table (TOML).
///
/// # Errors
/// What the format cannot carry at all (β in a DH table; SYMORO is read
/// only), in words a user can act on.
pub fn export_robot(file: &RobotFile, format: RobotFormat) -> Result<Exported, String> {
    match format {
        RobotFormat::Urdf => crate::urdf::export::export_urdf(file),
        RobotFormat::Dh => crate::dh_table::export_table(file, DhConvention::Standard),
        RobotFormat::Mdh => crate::dh_table::export_table(file, DhConvention::Modified),
        RobotFormat::Symoro => Err(
            "gecaro reads SYMORO .par files but does not write them; export to urdf, dh or mdh"
                .into(),
        ),
    }
}

/// The joint calibration of a robot whose map `M = Cj·diag(K)·Cm` (eq. 4)
/// is not the identity, for a format whose joint values are `M·qm` (offsets
/// folded into the file): YAML naming the file's joints.
pub(crate) fn joint_calibration(
    robot: &Robot,
    joint_names: &[String],
    format: &str,
) -> Option<String> {
    let map: &DMatrix<f64> = robot.motor_to_joint();
    if *map == DMatrix::identity(map.nrows(), map.ncols()) {
        return None;
    }
    let list = |values: Vec<String>| format!("[{}]", values.join(", "));
    let mut text = format!(
        "# gecaro joint calibration of `{}` (GECARO eq. 4, offsets folded into the {format}):\n\
         # the {format}'s joint values are q = M · qm, qm the motor (encoder) values, M = Cj·diag(K)·Cm.\n\
         # A driver applies this map before publishing joint states.\n",
        robot.name()
    );
    text.push_str(&format!(
        "joints: {}\nmatrix:\n",
        list(
            joint_names
                .iter()
                .map(|name| format!("\"{}\"", name.replace('"', "\\\"")))
                .collect()
        )
    ));
    for row in map.row_iter() {
        text.push_str(&format!(
            "  - {}\n",
            list(row.iter().map(|v| format!("{v:?}")).collect())
        ));
    }
    text.push_str(&format!(
        "gains: {}\n",
        list(
            robot
                .joints()
                .iter()
                .map(|joint| format!("{:?}", joint.gain))
                .collect()
        )
    ));
    Some(text)
}
