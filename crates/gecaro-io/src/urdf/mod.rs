//! URDF in and out (parsed and written by `urdf-rs`; no XML of our own).
//!
//! - [`import`]: the serial chain between two links of a URDF as a robot, with
//!   the URDF's joint variables (sign and zero) and its names kept.
//! - [`export`]: a robot as a URDF chain with those names, offsets folded into
//!   the joint origins, mimic couplings as `<mimic>`, and a joint calibration
//!   for the driver where gains or couplings are not expressible.
//! - [`names`]: what a robot keeps of the URDF it came from.

pub(crate) mod bounds;
pub(crate) mod export;
pub(crate) mod import;
pub(crate) mod names;

use gecaro_core::{Robot, frame_transform};
use nalgebra::IsometryMatrix3;

/// The world poses of frames 0..n+1 at joint variables q = 0 (eq. 1–3).
pub(crate) fn frame_poses(robot: &Robot) -> Vec<IsometryMatrix3<f64>> {
    robot
        .frames()
        .iter()
        .scan(IsometryMatrix3::identity(), |pose, frame| {
            *pose *= frame_transform(frame, 0.0);
            Some(*pose)
        })
        .collect()
}
