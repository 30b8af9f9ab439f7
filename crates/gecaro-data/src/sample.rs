//! One measured (or generated) configuration as a row, the unit a data set
//! is built from.
//!
//! Every sample has the motor variables qm1..qmn of one configuration; which
//! other fields a method needs is given by its [`DataColumn`]s (and so are
//! the columns of its CSV files). A data set itself is held as columns
//! ([`Samples`](crate::samples::Samples)); a `Sample` is what generators make
//! one configuration at a time and what an edit of a data set changes.

use gecaro_core::LinkMass;
use nalgebra::{UnitQuaternion, Vector3};
use smallvec::SmallVec;

/// The motor variables of one configuration, held in place up to seven
/// joints (a longer chain spills to the heap): a million samples are a
/// million allocations fewer.
pub type MotorPositions = SmallVec<[f64; 7]>;

/// One configuration with what was measured there.
///
/// A sample is compact (200 bytes, no allocation for up to seven joints):
/// generators and edits hold many of them. What loads an elastic robot's
/// joints and the uncertainty an instrument states for the row, which most
/// samples do not carry, sit behind a pointer each ([`Sample::loads`],
/// [`Sample::sigma`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Motor variables qm (eq. 4): radians or metres.
    pub motor_positions: MotorPositions,
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
    /// The payload and the joint loads at this configuration, when the
    /// data state them (issue 38); `None`: no load.
    pub loads: Option<Box<SampleLoads>>,
    /// The standard deviations the instrument states for this row's
    /// measurement, when the data give them; `None`: the set's σ.
    pub sigma: Option<Box<RowSigma>>,
}

/// The standard deviations an instrument states for one measured row (a
/// tracker's or a 6-D probe's per-point uncertainty): they stand for the
/// set's σ in this row's weight (rows are multiplied by 1/σ, eq. 8 with a
/// diagonal weight), so that a point measured far from the instrument, or
/// through a poor line of sight, counts less. `None`: the set's σ.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RowSigma {
    /// σ of the row's lengths (positions, distances), metres, > 0.
    pub length: Option<f64>,
    /// σ of the row's orientation angles, radians, > 0.
    pub angle: Option<f64>,
}

impl RowSigma {
    /// The σ of lengths and of angles as stored in a data set's column
    /// (`0`: not stated; a stated 0 is no standard deviation, refused by
    /// [`check`](Self::check) where it is made).
    pub(crate) fn stored(self) -> [f64; 2] {
        [self.length.unwrap_or(0.0), self.angle.unwrap_or(0.0)]
    }

    /// The σ stored as [`stored`](Self::stored) writes it; `None` when
    /// neither is stated.
    pub(crate) fn of_stored([length, angle]: [f64; 2]) -> Option<RowSigma> {
        // 0 is "not stated"; any other value is kept, to be checked.
        let stated = |value: f64| (value != 0.0).then_some(value);
        let sigma = RowSigma {
            length: stated(length),
            angle: stated(angle),
        };
        (sigma.length.is_some() || sigma.angle.is_some()).then_some(sigma)
    }

    /// The largest σ of lengths a row may state (m): a cell's size
    /// ([`gecaro_core::MAX_MAGNITUDE`]).
    pub const MAX_LENGTH: f64 = gecaro_core::MAX_MAGNITUDE;

    /// The largest σ of angles a row may state (rad): half a turn.
    pub const MAX_ANGLE: f64 = std::f64::consts::PI;

    /// Whether `sigma` (m) is a σ of lengths a row may state: above 0, at
    /// most [`MAX_LENGTH`](Self::MAX_LENGTH).
    pub fn admits_length(sigma: f64) -> bool {
        sigma > 0.0 && sigma <= Self::MAX_LENGTH
    }

    /// Whether `sigma` (rad) is a σ of angles a row may state: above 0, at
    /// most [`MAX_ANGLE`](Self::MAX_ANGLE).
    pub fn admits_angle(sigma: f64) -> bool {
        sigma > 0.0 && sigma <= Self::MAX_ANGLE
    }

    /// Checks that each stated σ is one a row may state
    /// ([`admits_length`](Self::admits_length),
    /// [`admits_angle`](Self::admits_angle)).
    ///
    /// # Errors
    /// A sentence naming the σ at fault.
    pub fn check(self) -> Result<(), String> {
        if let Some(length) = self.length
            && !Self::admits_length(length)
        {
            return Err(format!(
                "the row's σ of lengths {length} m is not a standard deviation (> 0, at most {} m)",
                Self::MAX_LENGTH
            ));
        }
        if let Some(angle) = self.angle
            && !Self::admits_angle(angle)
        {
            return Err(format!(
                "the row's σ of angles {angle} rad is not a standard deviation (> 0, ≤ π)"
            ));
        }
        Ok(())
    }
}

/// What loads the joints of an elastic robot at one configuration.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleLoads {
    /// The payload carried at this configuration (its centre in frame
    /// n+1), when the data state one.
    pub payload: Option<LinkMass>,
    /// The gravity torque of every joint (N·m, or N), the load an elastic
    /// robot's joints yield to; `None`: no load. Filled from the masses and
    /// the payload by `gecaro_calib::elastic::load_samples`.
    pub torques: Option<Vec<f64>>,
    /// The torques' derivatives with respect to gravity's two tilts (2n
    /// values: `∂τ_j/∂tilt1` for j = 1..n, then `∂τ_j/∂tilt2`;
    /// [`gecaro_core::gravity_loads_in`]), filled with them: an elastic
    /// robot's `tilt1`, `tilt2` load its joints through them.
    pub tilt_torques: Option<Vec<f64>>,
}

impl Sample {
    /// A sample with only a configuration (held in place up to seven
    /// joints, whatever the capacity of the vector it came in).
    pub fn new(motor_positions: impl Into<MotorPositions>) -> Self {
        let mut motor_positions = motor_positions.into();
        motor_positions.shrink_to_fit();
        Sample {
            motor_positions,
            position: None,
            orientation: None,
            group: None,
            distance: None,
            line: None,
            loads: None,
            sigma: None,
        }
    }

    /// The payload carried at this configuration, if the data state one.
    pub fn payload(&self) -> Option<&LinkMass> {
        self.loads.as_ref()?.payload.as_ref()
    }

    /// The gravity torque of every joint ([`SampleLoads::torques`]).
    pub fn torques(&self) -> Option<&[f64]> {
        self.loads.as_ref()?.torques.as_deref()
    }

    /// The torques' derivatives with respect to gravity's two tilts
    /// ([`SampleLoads::tilt_torques`]).
    pub fn tilt_torques(&self) -> Option<&[f64]> {
        self.loads.as_ref()?.tilt_torques.as_deref()
    }

    /// The loads of this sample, made (empty) if it had none.
    pub fn loads_mut(&mut self) -> &mut SampleLoads {
        self.loads.get_or_insert_with(Box::default)
    }

    /// This sample carrying `payload` (none: unloaded).
    pub fn set_payload(&mut self, payload: Option<LinkMass>) {
        if payload.is_some() || self.loads.is_some() {
            self.loads_mut().payload = payload;
        }
    }

    /// Checks that this sample has the field of `column`, finite.
    ///
    /// # Errors
    /// What is missing or not finite, as a sentence.
    pub fn check_column(&self, column: DataColumn) -> Result<(), String> {
        check_fields(
            column,
            self.position,
            self.orientation,
            self.group,
            self.distance,
        )
    }
}

/// Checks that the field of `column` is there, finite (see
/// [`Sample::check_column`]).
pub(crate) fn check_fields(
    column: DataColumn,
    position: Option<Vector3<f64>>,
    orientation: Option<UnitQuaternion<f64>>,
    group: Option<u64>,
    distance: Option<f64>,
) -> Result<(), String> {
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
    let admitted = |values: &[f64]| values.iter().all(|value| column.admits(*value));
    match column {
        DataColumn::Position => {
            let position = position.ok_or_else(missing)?;
            finite(admitted(position.as_slice()), "position")
        }
        DataColumn::Orientation => {
            let orientation = orientation.ok_or_else(missing)?;
            finite(admitted(orientation.coords.as_slice()), "orientation")
        }
        DataColumn::Set | DataColumn::Pair => group.map(|_| ()).ok_or_else(missing),
        DataColumn::Distance => {
            let distance = distance.ok_or_else(missing)?;
            finite(admitted(&[distance]), "distance")
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
    /// Whether a measured value of this column is one [`Sample::check_column`]
    /// admits: finite, and a length within what a robot cell holds
    /// (±[`gecaro_core::MAX_MAGNITUDE`], as a robot file's lengths); the
    /// grouping columns' ids are any.
    pub(crate) fn admits(self, value: f64) -> bool {
        match self {
            DataColumn::Position | DataColumn::Distance => {
                value.is_finite() && value.abs() <= gecaro_core::MAX_MAGNITUDE
            }
            DataColumn::Orientation => value.is_finite(),
            DataColumn::Set | DataColumn::Pair => true,
        }
    }

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

#[cfg(test)]
mod tests {
    use super::*;

    /// A tracker's million samples stay compact: the motor variables of a
    /// seven-joint robot in place, the loads behind one pointer.
    #[test]
    fn a_sample_is_compact_and_keeps_seven_joints_in_place() {
        assert!(std::mem::size_of::<Sample>() <= 200);
        let mut joints = Vec::with_capacity(16);
        joints.extend([0.1; 7]);
        let sample = Sample::new(joints);
        assert!(!sample.motor_positions.spilled());
        assert_eq!(sample.payload(), None);
        assert_eq!(sample.torques(), None);
    }
}
