//! A robot program's points as gecaro reads and writes them: targets
//! (joints, a point, a pose of frame n+1 in the world frame) with the
//! program's joints, and what compensation made of each
//! (`gecaro_calib::compensation` computes them; file formats read and
//! write them). Metres and radians.

use nalgebra::{IsometryMatrix3, Vector3};

/// One target of a program.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgramTarget {
    /// Motor values of the program: the pose the nominal model gives them.
    Joints(Vec<f64>),
    /// A point for the origin of frame n+1 (world frame, metres).
    Position(Vector3<f64>),
    /// A pose of frame n+1 (world frame).
    Pose(IsometryMatrix3<f64>),
}

/// A target and, for Cartesian ones, the program's joints if it has them.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramPoint {
    /// What the robot must reach.
    pub target: ProgramTarget,
    /// The program's joints for a Cartesian target (start and reference of
    /// the closest solution); ignored for joint targets, which are their own.
    pub joints: Option<Vec<f64>>,
}

/// What became of one target.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum CompensationStatus {
    /// Reached within the joint limits.
    Reached,
    /// Reached within the limits, but with a joint moved by more than
    /// a reconfiguration's threshold (1 rad or 1 m, `gecaro_calib::compensation::RECONFIGURATION`) from the program's: another branch (shoulder,
    /// elbow), a wrist turned about a singularity, or a joint of a full
    /// turn's range turned the other way round past its limit. Written,
    /// flagged: the robot would swing there.
    Reconfigured,
    /// Reached within the limits in the program's configuration, but
    /// outside the region the calibration's data covered
    /// (`gecaro_calib::compensation::Compensator::within`): the calibrated model is extrapolated
    /// there, and may be far off (written, flagged).
    OutsideRegion,
    /// Reached only with a joint beyond its limit, even turned by whole
    /// turns (the values are written, flagged).
    OutsideLimits,
    /// Not reached: the start joints are kept.
    NotReached,
}

impl CompensationStatus {
    /// The word written in output files: `ok`, `reconfigured`,
    /// `outside-region`, `outside-limits`, `not-reached`.
    pub fn word(self) -> &'static str {
        match self {
            CompensationStatus::Reached => "ok",
            CompensationStatus::Reconfigured => "reconfigured",
            CompensationStatus::OutsideRegion => "outside-region",
            CompensationStatus::OutsideLimits => "outside-limits",
            CompensationStatus::NotReached => "not-reached",
        }
    }
}

/// A compensated target.
#[derive(Clone, Debug, PartialEq)]
pub struct CompensatedPoint {
    /// The motor values to send (eq. 4).
    pub motor_positions: Vec<f64>,
    /// Distance between the target point and where the calibrated robot
    /// puts frame n+1 at these values (metres).
    pub position_error: f64,
    /// Angle between the target orientation and the calibrated robot's
    /// (radians); `None` for a point target.
    pub rotation_error: Option<f64>,
    /// For a joint target matched by position (a match by position): the
    /// angle (radians) by which frame n+1 of the calibrated robot at these
    /// values is turned from the orientation the nominal model gives the
    /// program's joints — what a position match leaves free; `None`
    /// otherwise, and for a target not reached.
    pub tool_turn: Option<f64>,
    /// Reached, in another configuration, outside the measured region,
    /// beyond a limit, or not reached.
    pub status: CompensationStatus,
}
