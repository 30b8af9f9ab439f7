//! A parallel robot's stated work region (`work_region` of an
//! identification and a prediction): its actuators' ranges with their
//! units, the region its calibration is judged over instead of the whole
//! workspace.

use gecaro_calib::parallel_robots::work_region_centre;
use gecaro_core::JointRegion;
use gecaro_core::parallel_robot::ParallelRobot;

use crate::error::AppError;

/// `text` read as `robot`'s actuator ranges (`qm1=-12..12mm,…`, by
/// [`gecaro_io::parse_actuator_region`]); refused, naming `work_region`,
/// when it cannot be read or no pose puts every actuator at the middle of
/// its range (the region's poses are solved from the pose there).
pub(super) fn stated_work_region(
    robot: &ParallelRobot,
    text: &str,
) -> Result<JointRegion, AppError> {
    let region = gecaro_io::parse_actuator_region(text, robot)
        .map_err(|message| AppError::setting("work_region", message))?;
    if work_region_centre(robot, &region).is_err() {
        return Err(AppError::setting(
            "work_region",
            "no platform pose puts every actuator at the middle of its stated range: state \
             ranges the platform reaches together",
        ));
    }
    Ok(region)
}
