//! A study set's σ measured rather than stated (issue 78): a repeatability
//! file — poses revisited, each row its `pose` and the attained `x,y,z`
//! (an ISO 9283 test's measured file serves as it is) — read in the set's
//! format, and the pooled σ of its poses
//! ([`gecaro_calib::iso9283::pooled_noise`]) taken as the set's σ, the
//! noise its verdict tests the residuals against.

use std::collections::BTreeMap;
use std::path::Path;

use gecaro_calib::compensation::ProgramTarget;
use gecaro_calib::iso9283::{PooledNoise, pooled_noise};
use gecaro_core::Robot;
use gecaro_io::{DataFormat, Error};
use nalgebra::Vector3;

/// The pooled noise of the repeatability file `text` (named `label` in
/// messages), read as `format` says.
///
/// # Errors
/// [`Error::Parse`] naming the file: no `pose` column, no positions, a pose
/// visited once.
pub(crate) fn repeatability_noise(
    text: &str,
    label: &str,
    format: &DataFormat,
) -> Result<PooledNoise, Error> {
    let path = Path::new(label);
    // A file of points, no joints: read by a one-joint robot's program reader.
    let reader = Robot::template("points", "R").map_err(|error| Error::Format {
        path: path.to_owned(),
        message: error.to_string(),
    })?;
    let file = gecaro_io::parse_program(text.as_bytes(), path, &reader, format)?;
    if !file.has_column("pose") {
        return Err(Error::parse(
            path,
            1,
            None,
            "a repeatability file names each row's pose (a `pose` column) beside its x,y,z",
        ));
    }
    let mut groups: BTreeMap<String, Vec<Vector3<f64>>> = BTreeMap::new();
    for (index, point) in file.points.iter().enumerate() {
        let position = match &point.target {
            ProgramTarget::Position(position) => *position,
            ProgramTarget::Pose(pose) => pose.translation.vector,
            ProgramTarget::Joints(_) => {
                return Err(Error::parse(
                    path,
                    file.line(index),
                    None,
                    "a repeatability file's rows are measured positions (x,y,z)",
                ));
            }
        };
        let pose = file
            .field(index, "pose")
            .unwrap_or_default()
            .trim()
            .to_owned();
        groups.entry(pose).or_default().push(position);
    }
    let groups: Vec<Vec<Vector3<f64>>> = groups.into_values().collect();
    pooled_noise(&groups).map_err(|error| Error::Format {
        path: path.to_owned(),
        message: error.to_string(),
    })
}
