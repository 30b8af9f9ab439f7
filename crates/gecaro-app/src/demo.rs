//! The demo as a job ([`DemoRequest`]; `gecaro demo`): a "real" Stanford
//! arm drawn at an error level, each of the paper's seven methods simulated
//! on it and identified, and every calibrated robot judged where a user
//! meets it — against the real robot on held-out configurations no method
//! saw, after the rigid registration that best maps them (link and plane
//! methods do not observe the base).

use std::time::{Duration, Instant};

use gecaro_calib::Quiet;
use gecaro_calib::identification::Identification;
use gecaro_calib::progress::{Observer, Progress};
use gecaro_calib::simulation::{
    DEFAULT_SEED, Sampler, held_out_configurations, judge, perturbed_robot, simulate_measurements,
};

use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::identify::IdentifyRequest;
use crate::measurements::Measurements;
use crate::method::MethodSpec;
use crate::robot_files::simulated_robot_file;
use crate::sources::{DataSource, RobotSource};

/// Configurations of the real robot each calibration is judged on.
pub const DEMO_HELD_OUT: usize = 300;

/// Configurations per method: enough for a clean identification.
pub const DEMO_COUNTS: [(&str, usize); 7] = [
    ("position", 50),
    ("frame", 30),
    ("point-link", 80),
    ("frame-link", 60),
    ("plane1", 120),
    ("plane2", 120),
    ("distance", 200),
];

/// The demo's settings.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DemoRequest {
    /// The real robot's error level (1 = ±1 cm, ±1°, ±1 %).
    pub error_level: f64,
    /// Sensor noise, standard deviation (m, rad).
    pub noise: f64,
    /// Seed of every draw.
    pub seed: u64,
}

impl Default for DemoRequest {
    fn default() -> Self {
        DemoRequest {
            error_level: 3.0,
            noise: 5e-5,
            seed: DEFAULT_SEED,
        }
    }
}

/// One method's calibration in the demo.
#[derive(Debug)]
pub struct DemoRun {
    /// The method's title.
    pub title: &'static str,
    /// Configurations simulated.
    pub configurations: usize,
    /// The identification.
    pub identification: Identification,
    /// The calibrated robot's RMS error on the held-out configurations (m).
    pub held_out: f64,
    /// The identification's time.
    pub elapsed: Duration,
}

/// The demo's results.
#[derive(Debug)]
pub struct Demo {
    /// The robot's name.
    pub robot: String,
    /// The nominal robot's RMS error on the held-out configurations (m).
    pub nominal_held_out: f64,
    /// Per method, in the paper's order.
    pub runs: Vec<DemoRun>,
}

impl DemoRequest {
    /// Runs the demo; `observer` hears of each method (a phase named by its
    /// title, then the methods done).
    ///
    /// # Errors
    /// Settings out of range, a method that fails to identify, an
    /// interruption.
    pub fn run(&self, files: &dyn Files, observer: &mut dyn Observer) -> Result<Demo, AppError> {
        let stanford = RobotSource::Named("stanford".into()).load(files)?;
        let robot = &stanford.robot;
        let mut sampler = Sampler::new(self.seed);
        let real = perturbed_robot(robot, self.error_level, &mut sampler)?;
        let real = simulated_robot_file(&stanford, real, self.error_level, self.seed);
        let held_out = held_out_configurations(&real.robot, DEMO_HELD_OUT, &mut sampler);
        let nominal_held_out = judge(robot, &real.robot, &held_out)?.rms;
        let mut runs = Vec::with_capacity(DEMO_COUNTS.len());
        for (done, (method_name, count)) in DEMO_COUNTS.into_iter().enumerate() {
            let method = MethodSpec {
                plane_normal: Some(gecaro_calib::table2::TABLE2_PLANE_NORMAL),
                plane_point: Some(gecaro_calib::table2::STANFORD_PLANE_POINT),
                ..MethodSpec::named(method_name)
            };
            let chosen = method.build()?;
            let title = chosen.title();
            let interrupted =
                || AppError::plain(ErrorKind::NotConverged, "the demo was interrupted");
            if observer.observe(Progress::Phase(title)).is_break() {
                return Err(interrupted());
            }
            let started = Instant::now();
            let samples = simulate_measurements(
                &real.robot,
                chosen.as_ref(),
                count,
                self.noise,
                &mut sampler,
                &mut Quiet,
            )?;
            // The sensor's σ is known here: the verdict tests the fit against it.
            let mut measurements = Measurements::single(
                RobotSource::Loaded(Box::new(stanford.clone())),
                method,
                Some(DataSource::Samples {
                    samples: samples.into(),
                    label: method_name.to_owned(),
                }),
            );
            measurements.sigma =
                (self.noise > 0.0).then_some(gecaro_io::StandardDeviation::Number(self.noise));
            // Each method's identification alone, as its time says: the
            // comparison with the neighbouring models is not the demo's subject.
            let mut request = IdentifyRequest::new(measurements);
            request.check_model = Some(false);
            let identified = request.run(files, &mut Quiet)?;
            let elapsed = started.elapsed();
            let held = judge(&identified.result.calibrated, &real.robot, &held_out)?;
            runs.push(DemoRun {
                title,
                configurations: count,
                identification: identified.result,
                held_out: held.rms,
                elapsed,
            });
            let step = Progress::Step {
                done: done + 1,
                total: DEMO_COUNTS.len(),
            };
            if observer.observe(step).is_break() {
                return Err(interrupted());
            }
        }
        Ok(Demo {
            robot: robot.name().to_owned(),
            nominal_held_out,
            runs,
        })
    }
}
