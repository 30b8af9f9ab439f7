//! One measured (or generated) configuration, the unit of every data set.
//!
//! A data set is a list of [`Sample`]s. Every sample has the motor variables
//! qm1..qmn of one configuration; which other fields a method needs is given by
//! its [`DataColumn`]s (and so are the columns of its CSV files).

use gecaro_core::LinkMass;
use nalgebra::{UnitQuaternion, Vector3};

/// One configuration with what was measured there.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Motor variables qm (eq. 4): radians or metres.
    pub motor_positions: Vec<f64>,
    /// Measured position of the origin of frame n+1 in the world frame (m).
    pub position: Option<Vector3<f64>>,
    /// Measured orientation of frame n+1 in the world frame.
    pub orientation: Option<UnitQuaternion<f64>>,
    /// Set id (link methods: same point/frame) or pair id (distance method).
    pub group: Option<u64>,
    /// Measured distance to the other configuration of the pair (m).
    pub distance: Option<f64>,
    /// Line of the data file this sample came from, for messages.
    pub line: Option<usize>,
    /// The payload carried at this configuration (its centre in frame
    /// n+1), when the data state one (issue 38).
    pub payload: Option<LinkMass>,
    /// The gravity torque of every joint (N·m, or N), the load an elastic
    /// robot's joints yield to; `None`: no load. Filled from the masses and
    /// the payload by [`crate::elastic::load_samples`].
    pub torques: Option<Vec<f64>>,
    /// The torques' derivatives with respect to gravity's two tilts (2n
    /// values: `∂τ_j/∂tilt1` for j = 1..n, then `∂τ_j/∂tilt2`;
    /// [`gecaro_core::gravity_loads_in`]), filled with them: an elastic
    /// robot's `tilt1`, `tilt2` load its joints through them.
    pub tilt_torques: Option<Vec<f64>>,
}

impl Sample {
    /// A sample with only a configuration.
    pub fn new(motor_positions: Vec<f64>) -> Self {
        Sample {
            motor_positions,
            position: None,
            orientation: None,
            group: None,
            distance: None,
            line: None,
            payload: None,
            torques: None,
            tilt_torques: None,
        }
    }

    /// Checks that this sample has the field of `column`, finite.
    ///
    /// # Errors
    /// What is missing or not finite, as a sentence.
    pub fn check_column(&self, column: DataColumn) -> Result<(), String> {
        let missing = || format!("missing {}", column.headers().join(", "));
        // Finite, and within what a robot cell holds (±1 km, as a robot
        // file's lengths; orientations are unit quaternions).
        let finite = |finite: bool, what: &str| {
            if finite {
                Ok(())
            } else {
                Err(format!(
                    "the measured {what} is not finite, or beyond ±{} m",
                    gecaro_core::MAX_MAGNITUDE
                ))
            }
        };
        let bounded = |v: &f64| v.is_finite() && v.abs() <= gecaro_core::MAX_MAGNITUDE;
        match column {
            DataColumn::Position => {
                let position = self.position.ok_or_else(missing)?;
                finite(position.iter().all(bounded), "position")
            }
            DataColumn::Orientation => {
                let orientation = self.orientation.ok_or_else(missing)?;
                finite(
                    orientation.coords.iter().all(|v| v.is_finite()),
                    "orientation",
                )
            }
            DataColumn::Set | DataColumn::Pair => self.group.map(|_| ()).ok_or_else(missing),
            DataColumn::Distance => {
                let distance = self.distance.ok_or_else(missing)?;
                finite(bounded(&distance), "distance")
            }
        }
    }
}

/// A group of columns of a data file beyond `qm1..qmn`, and the sample field it fills.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum DataColumn {
    /// `x, y, z`: [`Sample::position`].
    Position,
    /// `qw, qx, qy, qz` (a unit quaternion): [`Sample::orientation`].
    Orientation,
    /// `set`: [`Sample::group`], configurations reaching the same point or frame.
    Set,
    /// `pair`: [`Sample::group`], the two configurations of a distance.
    Pair,
    /// `distance`: [`Sample::distance`].
    Distance,
}

impl DataColumn {
    /// The grouping columns (set, pair) among `columns`: the columns of a
    /// data file of planned configurations, which carry no measurements.
    pub fn grouping(columns: &[DataColumn]) -> Vec<DataColumn> {
        columns
            .iter()
            .copied()
            .filter(|column| matches!(column, DataColumn::Set | DataColumn::Pair))
            .collect()
    }

    /// The CSV header names of this group of columns.
    pub fn headers(self) -> &'static [&'static str] {
        match self {
            DataColumn::Position => &["x", "y", "z"],
            DataColumn::Orientation => &["qw", "qx", "qy", "qz"],
            DataColumn::Set => &["set"],
            DataColumn::Pair => &["pair"],
            DataColumn::Distance => &["distance"],
        }
    }
}
