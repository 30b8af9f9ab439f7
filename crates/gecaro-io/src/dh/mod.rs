//! Denavit–Hartenberg tables, as datasheets give them: standard DH
//! (`Rz(θ)·Tz(d)·Tx(a)·Rx(α)` per row) and Craig's modified DH
//! (`Rx(α)·Tx(a)·Rz(θ)·Tz(d)` per row, the Khalil–Kleinfinger form without β).
//!
//! TOML:
//!
//! ```toml
//! name = "PUMA 560"
//! convention = "dh"            # "dh" (standard) or "mdh" (Craig's modified)
//! angle_unit = "deg"           # "rad" (default) or "deg"
//! length_unit = "mm"           # "m" (default) or "mm"
//! [base]                       # optional: the table's first frame in the world (URDF xyz, rpy)
//! xyz = [0, 0, 0]
//! rpy = [0, 0, 0]
//! [tool]                       # optional: the tool in the table's last frame
//! xyz = [0, 0, 56.25]
//! rpy = [0, 0, 0]
//! [[joint]]                    # one row per joint, base to tip
//! type = "R"                   # R (revolute: q is added to theta) or P (prismatic: q is added to d)
//! a = 0
//! alpha = -90
//! d = 0
//! theta = 0                    # the value at q = 0 (the joint's offset)
//! qmin = -160                  # optional limits of q (joint unit: angle or length)
//! qmax = 160
//! ```
//!
//! CSV: a header naming the columns `type,a,alpha,d,theta` and optionally
//! `qmin,qmax` and `name` (a label), in any order; a column's unit may be
//! part of its name (`a_mm`, `alpha_deg`, `d_m`, `theta_rad`). Rows of type
//! `base` (first) and `tool` (last) give fixed steps in the table's convention.
//! The convention comes from `--from dh|mdh`.
//!
//! The joint variables are the table's: q_j is added to θ_j or d_j, and
//! gecaro's frame j has that same q_j. Standard DH rows map to frames shifted
//! by one (row j's a, α belong to frame j+1); the base and tool transforms
//! enter through [`gecaro_core::Robot::reframed`].

mod convert;
mod csv;
mod export;
mod table;
mod toml;

use std::path::Path;

use crate::Error;
use crate::conversion::Imported;

pub(crate) use export::export_table;
pub use table::{DhConvention, TableUnits};

/// Imports a DH or MDH table (TOML, or CSV when `is_csv`); `convention`
/// comes from the command line and must agree with the file's.
pub(crate) fn import_table(
    text: &str,
    path: &Path,
    convention: Option<DhConvention>,
    is_csv: bool,
    units: TableUnits,
) -> Result<Imported, Error> {
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let table = if is_csv {
        let convention = convention.ok_or_else(|| {
            format_error(
                "a CSV table does not say its convention: name it (dh for standard, mdh for \
                 Craig's modified)"
                    .into(),
            )
        })?;
        csv::parse_csv(text, path, units, convention)?
    } else {
        toml::parse_toml(text, path, units)?
    };
    let convention = match (convention, table.convention) {
        (Some(given), Some(file)) if given != file => {
            return Err(format_error(format!(
                "the file says convention = \"{}\", but {} was asked for",
                file.name(),
                given.name()
            )));
        }
        (Some(convention), _) | (None, Some(convention)) => convention,
        (None, None) => {
            return Err(format_error(
                "the table does not say its convention: add convention = \"dh\" or \"mdh\", or \
                 name it (dh or mdh)"
                    .into(),
            ));
        }
    };
    convert::robot_of_table(&table, convention, path)
}
