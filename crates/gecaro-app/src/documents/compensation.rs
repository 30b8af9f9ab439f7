//! A corrected program's document.

use serde::Serialize;

/// One corrected target.
#[derive(Clone, Debug, Serialize)]
pub struct CompensatedJson {
    /// Its line in the program file (or its row, 0-based).
    pub line: usize,
    /// `reached`, `outside-limits` or `not-reached`.
    pub status: &'static str,
    /// The corrected motor variables.
    pub motor_positions: Vec<f64>,
    /// The calibrated robot's remaining position error there (m).
    pub position_error: f64,
    /// Its orientation error (rad), for pose targets.
    pub rotation_error: Option<f64>,
    /// The tool's turn a position match left (rad), for joint targets
    /// matched by position.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool_turn: Option<f64>,
}

/// The largest change of a joint between a program and its correction.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct LargestCorrection {
    /// The change, in the program file's unit.
    pub value: f64,
    /// That unit's name.
    pub unit: &'static str,
    /// The joint (1-based).
    pub joint: usize,
    /// The target's line.
    pub line: usize,
}

/// A corrected program (`gecaro compensate --json`).
#[derive(Clone, Debug, Serialize)]
pub struct CompensationJson {
    /// Targets in the program.
    pub targets: usize,
    /// Targets reached within the limits in the program's configuration.
    pub reached: usize,
    /// Lines of the targets reached within the limits in another
    /// configuration (a joint moved by more than a radian).
    pub reconfigured: Vec<usize>,
    /// Lines of the targets reached outside the joint ranges the
    /// calibration's data covered (a calibrated robot that holds there only).
    pub outside_region: Vec<usize>,
    /// Lines of the targets reached only beyond a joint limit.
    pub outside_limits: Vec<usize>,
    /// Lines of the targets not reached.
    pub not_reached: Vec<usize>,
    /// The largest residual of a reached target (m).
    pub largest_position_error: f64,
    /// The largest joint correction, in the program's unit.
    pub largest_correction: f64,
    /// The same with its unit, joint and line (`0.9360 rad (joint 5, line
    /// 7)`); absent for targets given as arrays.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_correction_at: Option<LargestCorrection>,
    /// The largest turn of the tool a position match left (rad); absent for
    /// a pose match.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_tool_turn: Option<f64>,
    /// Lines of the targets a position match reached with the tool turned
    /// beyond the tolerance (`max_tool_turn`).
    pub turned: Vec<usize>,
    /// The corrected program file, when written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    /// Every target (none listed for a program corrected as it was read:
    /// they are in its file).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<CompensatedJson>,
    /// The owner's base registered by points, when they were given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub registration: Option<crate::base_frame::BaseRegistrationJson>,
}
