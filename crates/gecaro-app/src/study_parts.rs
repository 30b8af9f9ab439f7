//! The parts of a study statement that stand on their own: a `[prior]`
//! table ([`PriorSpec`]), a named tool's or station's stated pose
//! ([`FrameSpec`]), and the unit names a study, a set or a frame may give.
//! A leaf beneath `study_spec.rs`, which states the whole study.

use std::collections::BTreeMap;

use gecaro_calib::identification::Prior;
use gecaro_core::Robot;
use gecaro_io::{AngleUnit, DataUnits, LengthUnit};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};
use serde::{Deserialize, Serialize};

/// A `[prior]` table: σ of lengths, angles and gains, and per parameter.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PriorSpec {
    /// σ of every length (`"5mm"`).
    pub length: String,
    /// σ of every angle (`"0.5deg"`).
    pub angle: String,
    /// σ of every gain (`"1%"`).
    pub gain: String,
    /// σ of single parameters (`d3 = "0.5mm"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameters: Option<BTreeMap<String, String>>,
}

/// A named tool or station: its stated pose (see the module docs).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    /// Its origin in the parent frame, three numbers in its length unit.
    pub position: Vec<f64>,
    /// Roll, pitch, yaw in its angle unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy: Option<Vec<f64>>,
    /// A unit quaternion `[w, x, y, z]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quaternion: Option<Vec<f64>>,
    /// `m` or `mm` (the study's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<String>,
    /// `rad` or `deg` (the study's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_unit: Option<String>,
}

impl PriorSpec {
    /// The prior for `robot`, or the key at fault and why.
    pub(crate) fn build(&self, robot: &Robot) -> Result<Prior, (&'static str, String)> {
        let text = format!("{},{},{}", self.length, self.angle, self.gain);
        let mut prior = gecaro_io::parse_prior(&text).map_err(|message| ("prior", message))?;
        for (name, value) in self.parameters.iter().flatten() {
            let entry = gecaro_io::parse_override(name, value)
                .map_err(|message| ("prior.parameters", message))?;
            prior.overrides.push(entry);
        }
        prior
            .check(robot)
            .map_err(|error| ("prior.parameters", error.to_string()))?;
        Ok(prior)
    }
}

impl FrameSpec {
    /// The stated pose (metres), or the key at fault and why.
    pub(crate) fn pose(
        &self,
        defaults: DataUnits,
    ) -> Result<IsometryMatrix3<f64>, (&'static str, String)> {
        let units = DataUnits {
            length: length_unit(self.length_unit.as_deref(), defaults.length)
                .map_err(|message| ("length_unit", message))?,
            angle: angle_unit(self.angle_unit.as_deref(), defaults.angle)
                .map_err(|message| ("angle_unit", message))?,
        };
        let three = |values: &[f64], key: &'static str| match values {
            [x, y, z] if [x, y, z].iter().all(|v| v.is_finite()) => Ok(Vector3::new(*x, *y, *z)),
            [_, _, _] => Err((key, "needs finite numbers".to_owned())),
            other => Err((key, format!("needs three numbers, got {}", other.len()))),
        };
        let position = three(&self.position, "position")? * units.length.to_metres();
        let rotation = match (&self.rpy, &self.quaternion) {
            (Some(_), Some(_)) => {
                return Err((
                    "quaternion",
                    "give the orientation as rpy or as a quaternion, not both".into(),
                ));
            }
            (Some(rpy), None) => {
                let scale = match units.angle {
                    AngleUnit::Degrees => std::f64::consts::PI / 180.0,
                    AngleUnit::Radians => 1.0,
                };
                let angles = three(rpy, "rpy")? * scale;
                Rotation3::from_euler_angles(angles.x, angles.y, angles.z)
            }
            (None, Some(quaternion)) => match quaternion.as_slice() {
                [w, x, y, z] => gecaro_io::unit_quaternion(*w, *x, *y, *z)
                    .map_err(|message| ("quaternion", message))?
                    .to_rotation_matrix(),
                other => {
                    return Err((
                        "quaternion",
                        format!("needs four numbers [w, x, y, z], got {}", other.len()),
                    ));
                }
            },
            (None, None) => Rotation3::identity(),
        };
        Ok(IsometryMatrix3::from_parts(
            Translation3::from(position),
            rotation,
        ))
    }
}

/// A length unit's name, or `default` when none is given.
pub(crate) fn length_unit(name: Option<&str>, default: LengthUnit) -> Result<LengthUnit, String> {
    match name {
        None => Ok(default),
        Some(name) => LengthUnit::parse(name),
    }
}

/// An angle unit's name, or `default` when none is given.
pub(crate) fn angle_unit(name: Option<&str>, default: AngleUnit) -> Result<AngleUnit, String> {
    match name {
        None => Ok(default),
        Some(name) => AngleUnit::parse(name),
    }
}
