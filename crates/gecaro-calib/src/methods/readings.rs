//! The sensors of the measure methods, simulated: what a position or frame
//! sensor reads of frame n+1 on a robot, with Gaussian noise. Points
//! generation (random configurations) and measurements at planned
//! configurations read through the same [`Reader`], so both draw the noise in
//! the same order.

use gecaro_core::{ChainBuffer, KinematicModel, Robot};
use nalgebra::UnitQuaternion;

use crate::error::Error;
use crate::method::Sensor;
use crate::progress::{Observer, report_step};
use crate::sample::{Sample, SampleLoads};
use crate::sampler::Sampler;
use crate::samples::SampleSlice;

/// What a sensor reads of frame n+1; the simulated session of the position
/// and frame measure methods.
#[derive(Copy, Clone, Debug)]
pub(super) enum Reading {
    /// Its origin, each coordinate with noise σ.
    Point,
    /// Its pose: the orientation turned by a random rotation of σ rad, then
    /// the origin with σ m per coordinate.
    Frame,
}

/// A sensor on a robot.
struct Reader {
    model: KinematicModel,
    chain: ChainBuffer,
    reading: Reading,
}

impl Reader {
    fn new(robot: &Robot, reading: Reading) -> Self {
        Reader {
            model: KinematicModel::new(robot),
            chain: ChainBuffer::default(),
            reading,
        }
    }

    /// The sample `planned` (its configuration, and the payload and joint
    /// torques an elastic robot yields to) with what the sensor reads there.
    fn read(
        &mut self,
        planned: Sample,
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Sample, Error> {
        self.model
            .forward_loaded(&planned.motor_positions, planned.torques(), &mut self.chain)?;
        let pose = *self.chain.world_from_tool();
        let orientation = match self.reading {
            Reading::Point => None,
            Reading::Frame => Some(UnitQuaternion::from_rotation_matrix(
                &(sampler.gaussian_rotation(noise) * pose.rotation),
            )),
        };
        Ok(Sample {
            position: Some(pose.translation.vector + sampler.gaussian_vector(noise)),
            orientation,
            // The loads go on with the reading: a plan's nominal readings
            // keep the compliances' columns (planning::columns).
            loads: planned.loads,
            ..Sample::new(planned.motor_positions)
        })
    }
}

/// `count` random configurations of `robot` (within the joint limits), read
/// by the sensor: points generation of the position and frame methods.
fn random_readings(
    robot: &Robot,
    reading: Reading,
    count: usize,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    let mut sensor = Reader::new(robot, reading);
    let mut samples = Vec::with_capacity(count);
    for done in 0..count {
        report_step(observer, done, count)?;
        let motor_positions = sampler.configuration(robot);
        samples.push(sensor.read(Sample::new(motor_positions), noise, sampler)?);
    }
    Ok(samples)
}

/// The planned configurations, read by the sensor on `real`.
fn readings_at(
    real: &Robot,
    reading: Reading,
    planned: SampleSlice<'_>,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    let mut sensor = Reader::new(real, reading);
    let mut samples = Vec::with_capacity(planned.len());
    for (done, sample) in planned.iter().enumerate() {
        report_step(observer, done, planned.len())?;
        let planned = Sample {
            loads: sample.loads().as_ref().map(|loads| {
                Box::new(SampleLoads {
                    payload: loads.payload,
                    torques: loads.torques.clone(),
                    tilt_torques: None,
                })
            }),
            ..Sample::new(sample.motor_positions())
        };
        samples.push(sensor.read(planned, noise, sampler)?);
    }
    Ok(samples)
}

impl Sensor for Reading {
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        random_readings(robot, *self, count, noise, sampler, observer)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: SampleSlice<'_>,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        readings_at(real, *self, planned, noise, sampler, observer)
    }

    fn yields_to_loads(&self) -> bool {
        true
    }
}
