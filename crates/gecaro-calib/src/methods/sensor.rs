//! Sensors of the simulation: what a position or frame sensor reads on a
//! robot, with Gaussian noise (points generation and measurements at planned
//! configurations share them, so both draw the noise in the same order).

use gecaro_core::{ChainBuffer, KinematicModel, Robot};
use nalgebra::UnitQuaternion;

use crate::Error;
use crate::sample::Sample;
use crate::sampler::Sampler;

/// A robot's terminal frame, read with noise.
pub(super) struct Sensor {
    model: KinematicModel,
    chain: ChainBuffer,
}

impl Sensor {
    pub(super) fn new(robot: &Robot) -> Self {
        Sensor {
            model: KinematicModel::new(robot),
            chain: ChainBuffer::default(),
        }
    }

    /// The origin of frame n+1, each coordinate with noise σ = `noise`.
    pub(super) fn point(
        &mut self,
        motor_positions: Vec<f64>,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Sample, Error> {
        let pose = self
            .model
            .terminal_pose(&motor_positions, &mut self.chain)?;
        Ok(Sample {
            position: Some(pose.translation.vector + sampler.gaussian_vector(noise)),
            ..Sample::new(motor_positions)
        })
    }

    /// The pose of frame n+1: orientation with a random rotation of σ =
    /// `noise` rad, then the position with σ = `noise` m per coordinate.
    pub(super) fn frame(
        &mut self,
        motor_positions: Vec<f64>,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Sample, Error> {
        let pose = self
            .model
            .terminal_pose(&motor_positions, &mut self.chain)?;
        let rotation = sampler.gaussian_rotation(noise) * pose.rotation;
        Ok(Sample {
            position: Some(pose.translation.vector + sampler.gaussian_vector(noise)),
            orientation: Some(UnitQuaternion::from_rotation_matrix(&rotation)),
            ..Sample::new(motor_positions)
        })
    }
}
