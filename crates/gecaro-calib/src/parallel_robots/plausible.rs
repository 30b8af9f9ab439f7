//! How far a parallel robot's parameters may move from their nominal
//! values before no platform's error explains it (a mistaken file, data of
//! another robot, or data in another frame): the bounds of the verdict's
//! plausibility and of the measurement frame's registration.

/// A joint centre, length or tool coordinate that moved further than this
/// from its nominal value (m) is no platform's error but a mistaken file
/// or data set; measured positions further than this from the nominal
/// robot's, RMS, are in another frame.
pub(super) const PLAUSIBLE_LENGTH: f64 = 0.05;

/// An angle (a Delta's arm azimuth or offset) that moved further than this
/// (rad, 5°), the same.
pub(super) const PLAUSIBLE_ANGLE: f64 = 0.087;

/// A gain off its nominal value by more than this fraction, the same.
pub(super) const PLAUSIBLE_GAIN: f64 = 0.1;
