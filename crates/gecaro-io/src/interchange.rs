//! Robots in and out of other formats: URDF, Denavit–Hartenberg tables
//! (standard and Craig's modified), and SYMORO `.par` files.
//!
//! Every import gives an ordinary robot file (Khalil–Kleinfinger frames, eq.
//! 3) whose joint variables are the source's (same sign, same zero), plus
//! notes on what the conversion did; every export gives the text of the
//! other format plus notes on what it could not carry and where that went.
//! The rules per format are in `docs/interchange.md`.

use std::path::Path;

use crate::Error;
use crate::conversion::{ChainEnds, Exported, Imported};
use crate::dh::{DhConvention, TableUnits};
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
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
            crate::dh::import_table(text, path, convention, is_csv, options.units)?
        }
        None if is_csv || has_extension(path, "toml") => {
            crate::dh::import_table(text, path, None, is_csv, options.units)?
        }
        None => {
            return Err(Error::Format {
                path: path.to_owned(),
                message: "cannot tell the format from the file name: name it (urdf, dh, mdh \
                          or symoro)"
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

/// Writes a robot as URDF or as a DH / modified-DH table (TOML).
///
/// # Errors
/// What the format cannot carry at all (β in a DH table; SYMORO is read
/// only), in words a user can act on.
pub fn export_robot(file: &RobotFile, format: RobotFormat) -> Result<Exported, String> {
    match format {
        RobotFormat::Urdf => crate::urdf::export::export_urdf(file),
        RobotFormat::Dh => crate::dh::export_table(file, DhConvention::Standard),
        RobotFormat::Mdh => crate::dh::export_table(file, DhConvention::Modified),
        RobotFormat::Symoro => crate::symoro::export::export_symoro(file),
    }
}
