//! A measuring leg: a passive leg whose length is read at every
//! configuration — a redundant leg sensor built into the platform, or a
//! telescoping ballbar mounted for the calibration between a socket on the
//! base and one on the platform. No instrument outside the robot: the
//! platform calibrates itself from its own actuators and this one reading
//! (the autonomous way of Khalil's group and of Zhuang's redundant
//! sensors).
//!
//! # The equation
//! With the platform at pose (p, R), solved by the direct model from the
//! actuators, the leg from `a` (base frame) to `b` (platform frame) reads
//! `s` where
//!
//! ```text
//! G = ‖p + R·b − a‖ − l − K·s = 0
//! ```
//!
//! (`l` its length at reading 0, `K` its gain, stated: a calibrated encoder
//! or ballbar is the length standard, so the scale is measured). Linearised
//! through the direct model as the tool point is (the implicit function
//! theorem): `∂G/∂ξ = −∂G/∂x·J_x⁻¹·∂F/∂ξ` on the platform's parameters, with
//! `∂G/∂x = [u; R·b × u]` (`u` the leg's unit vector, `[u]` for a platform
//! that only translates), and on the leg's own unknowns `a, b, l` (7, after
//! the platform's parameters and any station's correction)
//! `[−u, Rᵀ·u, −1]`.
//!
//! # What it cannot see
//! Nothing outside the robot measures the base or the platform frame, nor
//! the tool point: the frames are held by the structure's convention
//! ([`frame_parameters`](gecaro_core::parallel_model::ParallelModel::frame_parameters),
//! a 3-2-1 convention on three
//! joints for a Gough–Stewart platform) and the tool point keeps its
//! stated place.

use gecaro_data::sample::Sample;
use nalgebra::{Isometry3, Point3, Vector3};

use crate::Error;

/// The unknowns of a measuring leg: `a` (3), `b` (3), `l`.
pub const LEG_UNKNOWNS: usize = 7;

/// The largest gain a leg's reading has (and the inverse, the smallest): a
/// micrometre a unit, or a kilometre.
const MAX_GAIN: f64 = 1e6;

/// A measuring leg's mount and reading (module docs). Lengths in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasuringLeg {
    /// `a`: its base socket's centre, in the base frame (m).
    pub base: Vector3<f64>,
    /// `b`: its platform socket's centre, in the platform frame (m).
    pub platform: Vector3<f64>,
    /// `l`: its length at reading 0 (m).
    pub length: f64,
    /// `K`: metres of length per unit of reading (stated, not identified).
    pub gain: f64,
}

impl MeasuringLeg {
    /// A leg mounted at `base` and `platform` whose reading makes `gain`
    /// metres a unit, its length at reading 0 not known yet (0: the data
    /// give it).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a socket not finite or beyond a cell,
    /// or a gain no sensor has (0, not finite, beyond 10⁶ either way).
    pub fn new(base: Vector3<f64>, platform: Vector3<f64>, gain: f64) -> Result<Self, Error> {
        let in_a_cell = |point: &Vector3<f64>| {
            point
                .iter()
                .all(|value| value.is_finite() && value.abs() <= gecaro_core::MAX_MAGNITUDE)
        };
        if !in_a_cell(&base) || !in_a_cell(&platform) {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: "a measuring leg's sockets are points of the cell (finite, within \
                          1 km)"
                    .into(),
            });
        }
        if !(gain.is_finite() && (1.0 / MAX_GAIN..=MAX_GAIN).contains(&gain.abs())) {
            return Err(Error::InvalidOption {
                setting: crate::Setting::LegGain,
                message: format!(
                    "{gain} is not the metres of length a unit of the leg's reading makes: 1 \
                     for a reading in the data's length unit, never 0"
                ),
            });
        }
        Ok(Self {
            base,
            platform,
            length: 0.0,
            gain,
        })
    }

    /// The leg's length `‖p + R·b − a‖` with the platform at `pose`.
    pub fn length_at(&self, pose: &Isometry3<f64>) -> f64 {
        (pose * Point3::from(self.platform) - Point3::from(self.base)).norm()
    }

    /// What it reads with the platform at `pose`: `(‖p + R·b − a‖ − l)/K`.
    pub fn reading_at(&self, pose: &Isometry3<f64>) -> f64 {
        (self.length_at(pose) - self.length) / self.gain
    }

    /// Its unknowns `[a, b, l]`.
    pub fn unknowns(&self) -> [f64; LEG_UNKNOWNS] {
        [
            self.base.x,
            self.base.y,
            self.base.z,
            self.platform.x,
            self.platform.y,
            self.platform.z,
            self.length,
        ]
    }

    /// The same leg with the unknowns `values` (`[a, b, l]`), its gain kept.
    pub fn with_unknowns(&self, values: &[f64]) -> Self {
        Self {
            base: Vector3::new(values[0], values[1], values[2]),
            platform: Vector3::new(values[3], values[4], values[5]),
            length: values[6],
            gain: self.gain,
        }
    }

    /// The leg's length at reading 0 that best explains `readings` at the
    /// platform's `poses` (their mean difference): its mount as stated,
    /// its zero found.
    pub fn zeroed(&self, poses: &[Isometry3<f64>], readings: &[f64]) -> Self {
        let count = poses.len().min(readings.len());
        if count == 0 {
            return *self;
        }
        let length = poses
            .iter()
            .zip(readings)
            .map(|(pose, reading)| self.length_at(pose) - self.gain * reading)
            .sum::<f64>()
            / count as f64;
        Self { length, ..*self }
    }

    /// The equation at `pose` for the reading `reading`: its residual `G`,
    /// its row of `∂G/∂x` (`[u; R·b × u]`, the first `freedom` of them) and
    /// its coefficients on `[a, b, l]` (module docs).
    pub(super) fn equation(
        &self,
        pose: &Isometry3<f64>,
        reading: f64,
        freedom: usize,
    ) -> (f64, [f64; 6], [f64; LEG_UNKNOWNS]) {
        let arm = pose.rotation * self.platform;
        let vector = pose.translation.vector + arm - self.base;
        let length = vector.norm();
        let unit = vector / length.max(f64::MIN_POSITIVE);
        let turn = if freedom == 6 {
            arm.cross(&unit)
        } else {
            Vector3::zeros()
        };
        let turned = pose.rotation.inverse() * unit;
        (
            length - self.length - self.gain * reading,
            [unit.x, unit.y, unit.z, turn.x, turn.y, turn.z],
            [
                -unit.x, -unit.y, -unit.z, turned.x, turned.y, turned.z, -1.0,
            ],
        )
    }
}

/// A sample's reading of the measuring leg, its `distance` column.
///
/// # Errors
/// [`Error::InvalidData`] naming the line of a sample without it.
pub(super) fn leg_reading(sample: &Sample) -> Result<f64, Error> {
    sample.distance.ok_or_else(|| Error::InvalidData {
        line: sample.line,
        message: "the leg measure needs the leg's reading, `distance`".into(),
    })
}
