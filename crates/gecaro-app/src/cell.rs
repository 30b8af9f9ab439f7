//! The measuring cell of a points generation or a plan, as a user states it:
//! a floor height, a tracker station and its reflector's acceptance
//! half-angle ([`gecaro_calib::cell`]).

use gecaro_calib::cell::{Cell, DEFAULT_CLEARANCE, Station};
use nalgebra::Vector3;
use serde::Deserialize;

use crate::error::{AppError, ErrorKind};

/// The cell of a request: `"cell": {"floor": 0.0, "station": [2.3, 0, 0.4],
/// "max_incidence": "30deg", "clearance": 0.05}` on the web; `--floor`,
/// `--station`, `--max-incidence`, `--clearance` on the command line.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CellSpec {
    /// Every joint origin and the tool stay at or above z = floor (world
    /// frame, metres).
    pub floor: Option<f64>,
    /// The tracker station in the world frame (metres): the tool point must
    /// see it, no link in between.
    pub station: Option<[f64; 3]>,
    /// The reflector's acceptance half-angle with its unit (`30deg`,
    /// `0.5rad`); needs a station.
    pub max_incidence: Option<String>,
    /// The smallest distance of the line of sight from the arm (metres,
    /// default 0.05); needs a station.
    pub clearance: Option<f64>,
}

impl CellSpec {
    /// The cell.
    ///
    /// # Errors
    /// An angle without its unit, settings that need a station without one,
    /// and the cell's own checks ([`Cell::check`]).
    pub fn cell(&self) -> Result<Cell, AppError> {
        self.cell_seen_from(None)
    }

    /// The cell of a measurement set whose instrument stands at `station`
    /// (a study's named station, in the world frame) when given, else at
    /// the spec's station: the floor, incidence and clearance are the cell's,
    /// the line of sight that station's.
    ///
    /// # Errors
    /// As [`cell`](Self::cell).
    pub fn cell_seen_from(&self, station: Option<Vector3<f64>>) -> Result<Cell, AppError> {
        let max_incidence = self
            .max_incidence
            .as_deref()
            .map(|text| {
                gecaro_io::parse_angle(text)
                    .map_err(|message| AppError::setting("max_incidence", message))
            })
            .transpose()?;
        let position = station.or(self.station.map(Vector3::from));
        let station = match position {
            Some(position) => Some(Station {
                position,
                max_incidence,
                clearance: self.clearance.unwrap_or(DEFAULT_CLEARANCE),
            }),
            None => {
                if max_incidence.is_some() || self.clearance.is_some() {
                    return Err(AppError::setting(
                        "station",
                        "an incidence or a clearance is the station's: give the station too",
                    ));
                }
                None
            }
        };
        let cell = Cell {
            floor: self.floor,
            station,
        };
        cell.check()?;
        Ok(cell)
    }
}

/// Refuses a generation in which `misses` configurations (`what`) could not
/// be drawn within the cell.
///
/// # Errors
/// [`ErrorKind::Numerical`] when `misses` is not zero.
pub(crate) fn refuse_misses(misses: usize, what: &str) -> Result<(), AppError> {
    if misses == 0 {
        return Ok(());
    }
    Err(AppError::plain(
        ErrorKind::Numerical,
        format!(
            "the cell leaves next to nothing to measure: {misses} {what} fell outside it (the \
             first after {} tries); lower the floor, move the station or widen the incidence",
            gecaro_calib::simulation::CELL_DRAWS
        ),
    ))
}
