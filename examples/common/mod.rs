//! What the simulation examples (`noise_floor`, `judge`) share: their
//! arguments (robots, methods, levels of error, seeds) and one simulated
//! case (a ready robot, a real robot drawn at a level of error, a method and
//! the sampler that draws its measurements).

// Each example compiles this module and uses part of it.
#![allow(dead_code)]

use gecaro_calib::prelude::*;
use gecaro_core::Robot;

/// Any error of an example.
pub(crate) type Failure = Box<dyn std::error::Error>;

/// The simulated sensors' σ: 0.01 mm (0.01 mrad for orientations).
pub(crate) const NOISE: f64 = 1e-5;

/// The examples' arguments, all optional, in order: robots, methods,
/// levels, seeds (each comma-separated).
pub(crate) struct Cases {
    pub(crate) robots: Vec<String>,
    pub(crate) methods: Vec<String>,
    pub(crate) levels: Vec<f64>,
    pub(crate) seeds: Vec<u64>,
}

impl Cases {
    /// The command line's, each list defaulting to the one given here.
    pub(crate) fn from_arguments(defaults: [&str; 4]) -> Result<Cases, Failure> {
        let arguments: Vec<String> = std::env::args().skip(1).collect();
        let list = |index: usize| -> Vec<String> {
            arguments
                .get(index)
                .map_or(defaults[index], String::as_str)
                .split(',')
                .map(str::to_owned)
                .collect()
        };
        Ok(Cases {
            robots: list(0),
            methods: list(1),
            levels: list(2)
                .iter()
                .map(|l| l.parse())
                .collect::<Result<_, _>>()?,
            seeds: list(3)
                .iter()
                .map(|s| s.parse())
                .collect::<Result<_, _>>()?,
        })
    }
}

/// A ready robot, the real robot drawn from it at a level of error, a
/// method, and the sampler that drew the robot and draws the measurements.
pub(crate) struct Case {
    pub(crate) nominal: Robot,
    pub(crate) real: Robot,
    pub(crate) method: Box<dyn CalibrationMethod>,
    pub(crate) sampler: Sampler,
}

impl Case {
    pub(crate) fn new(
        robot: &str,
        method_name: &str,
        level: f64,
        seed: u64,
    ) -> Result<Case, Failure> {
        let nominal = gecaro_io::load_robot(robot)?.robot;
        // Plane methods: the Table 2 normal through the middle of the
        // workspace, known (the paper's plane link 1 and 2).
        let options = MethodOptions {
            plane: method_name
                .starts_with("plane")
                .then(|| gecaro_calib::table2::default_plane(&nominal))
                .transpose()?,
            ..MethodOptions::default()
        };
        let method = method(method_name, &options)?;
        let mut sampler = Sampler::new(seed);
        let real = perturbed_robot(&nominal, level, &mut sampler)?;
        Ok(Case {
            nominal,
            real,
            method,
            sampler,
        })
    }

    /// `count` configurations of the method measured on the real robot
    /// (σ 0.01 mm, 0.01 mrad).
    pub(crate) fn measure(&mut self, count: usize) -> Result<Study, Failure> {
        let samples = simulate_measurements(
            &self.real,
            self.method.as_ref(),
            count,
            NOISE,
            &mut self.sampler,
            &mut Quiet,
        )?;
        Ok(Study::single(
            self.method.clone_method(),
            samples,
            "simulated",
        ))
    }

    /// The same with the sensor's σ stated, as a user who knows it would:
    /// the verdict then tests the residuals against it.
    pub(crate) fn measure_with_sigma(&mut self, count: usize) -> Result<Study, Failure> {
        let mut study = self.measure(count)?;
        for set in &mut study.sets {
            set.sigma = Some(NOISE);
        }
        Ok(study)
    }

    /// The nominal robot identified from `study` with the default options.
    pub(crate) fn identify(&self, study: &Study) -> Result<Identification, Failure> {
        Ok(identify(
            &self.nominal,
            study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )?)
    }
}
