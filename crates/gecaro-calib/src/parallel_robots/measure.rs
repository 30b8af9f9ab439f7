//! What is measured of a parallel robot's platform, and how precisely.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::{DataColumn, Sample};
use nalgebra::{Isometry3, Translation3};

use crate::Error;

/// What a sensor measures of the platform at each configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlatformMeasure {
    /// The platform frame's pose in the base frame (`frame`: columns
    /// `x, y, z, qw, qx, qy, qz`); for a platform that turns.
    Pose,
    /// The tool point's position in the base frame (`position`: columns
    /// `x, y, z`).
    Point,
    /// The distance between the tool point's positions at two
    /// configurations (`distance`, a ballbar or a tracker's distances:
    /// columns `pair` and `distance`, two consecutive rows a pair, both
    /// carrying the distance), as the serial robots' distance method.
    Distance,
    /// A measuring leg's reading at each configuration (`leg`: column
    /// `distance`, the reading; the leg's mount stated,
    /// [`MeasuringLeg`](super::MeasuringLeg)): no instrument outside the
    /// robot.
    Leg,
}

impl PlatformMeasure {
    /// Every measure, in the order they are listed to users.
    pub const ALL: [PlatformMeasure; 4] = [
        PlatformMeasure::Pose,
        PlatformMeasure::Point,
        PlatformMeasure::Distance,
        PlatformMeasure::Leg,
    ];

    /// The name of the serial method that measures the same (`frame`,
    /// `position`, `distance`; `leg`, a parallel robot's own); the data
    /// files' columns are that method's.
    pub fn name(self) -> &'static str {
        match self {
            PlatformMeasure::Pose => "frame",
            PlatformMeasure::Point => "position",
            PlatformMeasure::Distance => "distance",
            PlatformMeasure::Leg => "leg",
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

    /// The measured columns of a data file, after `qm1…qmk`.
    pub fn columns(self) -> &'static [DataColumn] {
        match self {
            PlatformMeasure::Pose => &[DataColumn::Position, DataColumn::Orientation],
            PlatformMeasure::Point => &[DataColumn::Position],
            PlatformMeasure::Distance => &[DataColumn::Pair, DataColumn::Distance],
            PlatformMeasure::Leg => &[DataColumn::Distance],
        }
    }

    /// Equations an observation gives `model`: its closure equations for a
    /// pose, a coordinate each for a point, one for a distance or a leg's
    /// reading.
    pub fn rows_per_observation(self, model: &impl ParallelModel) -> usize {
        match self {
            PlatformMeasure::Pose => model.actuator_count(),
            PlatformMeasure::Point => 3,
            PlatformMeasure::Distance | PlatformMeasure::Leg => 1,
        }
    }

    /// Equations `samples` samples give `model`.
    pub fn rows_for(self, model: &impl ParallelModel, samples: usize) -> usize {
        samples / self.samples_per_observation() * self.rows_per_observation(model)
    }

    /// Whether the tool point's parameters are in the equations.
    pub fn measures_tool(self) -> bool {
        matches!(self, PlatformMeasure::Point | PlatformMeasure::Distance)
    }

    /// Whether the data are in an instrument's frame (a pose, a point),
    /// which may be registered; distances and a leg's readings have none.
    pub fn has_frame(self) -> bool {
        matches!(self, PlatformMeasure::Pose | PlatformMeasure::Point)
    }

    /// Samples one observation takes: a pair for a distance, else one.
    pub fn samples_per_observation(self) -> usize {
        match self {
            PlatformMeasure::Distance => 2,
            _ => 1,
        }
    }

    /// Refuses a measure a structure cannot take: a pose of a platform
    /// that only translates (a Delta's plate) says nothing of its
    /// orientation, and its equations have no noise to weigh.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the measure that fits.
    pub fn check_for(self, model: &impl ParallelModel) -> Result<(), Error> {
        if self == PlatformMeasure::Leg && model.frame_parameters().is_empty() {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: format!(
                    "a measuring leg sees no frame, and {} has no convention of joints that \
                     would hold its frames: measure its tool point (method `position`)",
                    model.name()
                ),
            });
        }
        if self == PlatformMeasure::Pose && model.pose_freedom() < 6 {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: format!(
                    "{}'s platform only translates: measure the position of a point on it \
                     (method `position`), not its pose",
                    model.name()
                ),
            });
        }
        Ok(())
    }

    /// A sample's measured pose (the point's for [`Point`](Self::Point),
    /// level; none for a [`Distance`](Self::Distance), whose pairs are
    /// read by [`check_pairs`]).
    ///
    /// # Errors
    /// [`Error::InvalidData`] naming the sample's line when a column is
    /// missing.
    pub(super) fn measured(self, sample: &Sample) -> Result<Isometry3<f64>, Error> {
        let missing = |what: &str| Error::InvalidData {
            line: sample.line,
            message: format!("the {} measure needs the {what}", self.name()),
        };
        if self == PlatformMeasure::Leg {
            return Err(Error::InvalidData {
                line: sample.line,
                message: "a measuring leg reads a length, not a pose".into(),
            });
        }
        let position = sample.position.ok_or_else(|| missing("position x, y, z"))?;
        let rotation = match self {
            PlatformMeasure::Pose => sample
                .orientation
                .ok_or_else(|| missing("orientation qw, qx, qy, qz"))?,
            PlatformMeasure::Point | PlatformMeasure::Distance | PlatformMeasure::Leg => {
                nalgebra::UnitQuaternion::identity()
            }
        };
        Ok(Isometry3::from_parts(
            Translation3::from(position),
            rotation,
        ))
    }

    /// What the sensor reads of `model` at `pose`, as a sample with the
    /// actuator values `actuators`.
    pub fn reading(
        self,
        model: &impl ParallelModel,
        pose: &Isometry3<f64>,
        actuators: &[f64],
    ) -> Sample {
        let mut sample = Sample::new(actuators.to_vec());
        match self {
            PlatformMeasure::Pose => {
                sample.position = Some(pose.translation.vector);
                sample.orientation = Some(pose.rotation);
            }
            PlatformMeasure::Point => sample.position = Some(model.tool_point(pose)),
            // A distance is read of a pair ([`simulate_platform`]), a leg's
            // reading of its mount ([`super::simulate_leg`]).
            PlatformMeasure::Distance | PlatformMeasure::Leg => {}
        }
        sample
    }
}

/// The measured distance of each pair of `samples` (two consecutive rows
/// with one `pair` id and one distance, m), checked.
///
/// # Errors
/// [`Error::InvalidData`] naming the line of a row without a pair or a
/// distance, an odd row out, two rows of a pair with other ids or
/// distances, a negative distance.
pub(super) fn check_pairs(samples: &[Sample]) -> Result<Vec<f64>, Error> {
    let at = |sample: &Sample, message: String| Error::InvalidData {
        line: sample.line,
        message,
    };
    if !samples.len().is_multiple_of(2) {
        return Err(at(
            &samples[samples.len() - 1],
            format!(
                "a distance is measured between two configurations: the last of {} rows has \
                 no pair",
                samples.len()
            ),
        ));
    }
    samples
        .chunks_exact(2)
        .map(|pair| {
            let (first, second) = (&pair[0], &pair[1]);
            for sample in pair {
                if sample.group.is_none() || sample.distance.is_none() {
                    return Err(at(
                        sample,
                        "the distance measure needs the pair id and the distance".into(),
                    ));
                }
            }
            if first.group != second.group {
                return Err(at(
                    second,
                    format!(
                        "pair {} has one row: the two rows of a pair follow each other with one \
                         pair id (this one is {})",
                        first.group.unwrap_or(0),
                        second.group.unwrap_or(0)
                    ),
                ));
            }
            let (a, b) = (
                first.distance.unwrap_or(f64::NAN),
                second.distance.unwrap_or(f64::NAN),
            );
            if (a - b).abs() > 1e-9 * a.abs().max(1.0) {
                return Err(at(
                    second,
                    format!(
                        "pair {} gives two different distances ({a} and {b}); both rows of a \
                         pair carry the same measured distance",
                        first.group.unwrap_or(0)
                    ),
                ));
            }
            if !a.is_finite() || a < 0.0 {
                return Err(at(
                    first,
                    format!("a distance is a length of 0 or more, not {a}"),
                ));
            }
            Ok(a)
        })
        .collect()
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
    /// The variance a measured pose's noise gives a closure equation whose
    /// row of `∂F/∂x` is `row` (`[position; rotation]`):
    /// `σ_p²·‖row_p‖² + σ_r²·‖row_r‖²`.
    pub(super) fn closure_variance(self, row: impl IntoIterator<Item = f64>) -> f64 {
        row.into_iter()
            .enumerate()
            .map(|(index, value)| {
                let sigma = if index < 3 { self.length } else { self.angle };
                (sigma * value).powi(2)
            })
            .sum()
    }
}
