//! What is measured of a platform, and how precisely.

use gecaro_core::gough_stewart::GoughStewart;
use gecaro_data::sample::{DataColumn, Sample};
use nalgebra::{Isometry3, Translation3, Vector3};

use crate::Error;

/// What a sensor measures of the platform at each configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlatformMeasure {
    /// The platform frame's pose in the base frame (`frame`: columns
    /// `x, y, z, qw, qx, qy, qz`).
    Pose,
    /// The tool point's position in the base frame (`position`: columns
    /// `x, y, z`).
    Point,
}

impl PlatformMeasure {
    /// Both, in the order they are listed to users.
    pub const ALL: [PlatformMeasure; 2] = [PlatformMeasure::Pose, PlatformMeasure::Point];

    /// The name of the serial method that measures the same (`frame`,
    /// `position`), and the data files' columns are that method's.
    pub fn name(self) -> &'static str {
        match self {
            PlatformMeasure::Pose => "frame",
            PlatformMeasure::Point => "position",
        }
    }

    /// The measure called `name` (`frame` or `position`).
    ///
    /// # Errors
    /// [`Error::UnknownMethod`] listing the two.
    pub fn named(name: &str) -> Result<Self, Error> {
        Self::ALL
            .into_iter()
            .find(|measure| measure.name() == name)
            .ok_or_else(|| Error::UnknownMethod {
                name: name.to_owned(),
                available: Self::ALL.iter().map(|m| m.name()).collect(),
            })
    }

    /// The measured columns of a data file, after `qm1…qm6`.
    pub fn columns(self) -> &'static [DataColumn] {
        match self {
            PlatformMeasure::Pose => &[DataColumn::Position, DataColumn::Orientation],
            PlatformMeasure::Point => &[DataColumn::Position],
        }
    }

    /// Equations a measured configuration gives: a leg each for a pose,
    /// a coordinate each for a point.
    pub fn rows_per_sample(self) -> usize {
        match self {
            PlatformMeasure::Pose => gecaro_core::gough_stewart::LEGS,
            PlatformMeasure::Point => 3,
        }
    }

    /// Whether `platform`'s tool point is measured (its 3 parameters in
    /// the equations).
    pub fn measures_tool(self) -> bool {
        self == PlatformMeasure::Point
    }

    /// A measured pose of a sample (the point's for [`Point`](Self::Point),
    /// level).
    ///
    /// # Errors
    /// [`Error::InvalidData`] naming the sample's line when a column is
    /// missing.
    pub(super) fn measured(self, sample: &Sample) -> Result<Isometry3<f64>, Error> {
        let missing = |what: &str| Error::InvalidData {
            line: sample.line,
            message: format!("the {} measure needs the {what}", self.name()),
        };
        let position = sample.position.ok_or_else(|| missing("position x, y, z"))?;
        let rotation = match self {
            PlatformMeasure::Pose => sample
                .orientation
                .ok_or_else(|| missing("orientation qw, qx, qy, qz"))?,
            PlatformMeasure::Point => nalgebra::UnitQuaternion::identity(),
        };
        Ok(Isometry3::from_parts(
            Translation3::from(position),
            rotation,
        ))
    }

    /// What the sensor reads of `platform` at `pose`, as a sample with the
    /// actuator values `actuators`.
    pub fn reading(
        self,
        platform: &GoughStewart,
        pose: &Isometry3<f64>,
        actuators: &[f64],
    ) -> Sample {
        let mut sample = Sample::new(actuators.to_vec());
        match self {
            PlatformMeasure::Pose => {
                sample.position = Some(pose.translation.vector);
                sample.orientation = Some(pose.rotation);
            }
            PlatformMeasure::Point => sample.position = Some(platform.tool_point(pose)),
        }
        sample
    }
}

/// The sensor's noise: σ of a position coordinate (m) and of a rotation
/// angle (rad, for measured poses).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformNoise {
    /// σ of each position coordinate (m).
    pub length: f64,
    /// σ of each rotation angle (rad).
    pub angle: f64,
}

impl PlatformNoise {
    /// The variance of leg `i`'s equation from a measured pose's noise:
    /// `σ_p² + σ_r²·‖R·b × u‖²` (`arm` = R·b, `unit` = u).
    pub(super) fn leg_variance(self, arm: &Vector3<f64>, unit: &Vector3<f64>) -> f64 {
        self.length.powi(2) + self.angle.powi(2) * arm.cross(unit).norm_squared()
    }
}
