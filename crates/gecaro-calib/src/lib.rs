//! # gecaro-calib
//!
//! The calibration methods of GECARO (Khalil et al.) and the three functions
//! each of them offers: identifiable parameters (Appendix III), points
//! generation (simulation with a "real" robot and sensor noise) and
//! identification (iterative linearised least squares, eq. 10).
//!
//! The API by topic:
//!
//! | module | what |
//! |---|---|
//! | [`methods`] | [`CalibrationMethod`](methods::CalibrationMethod), the shared trait (eq. 5–6), one implementation per method of paper §3 ([`METHODS`](methods::METHODS)), each with its simulated [`Sensor`](methods::Sensor) |
//! | [`study`] | measurements: [`Sample`](study::Sample)s, and a [`Study`](study::Study) of one or more measurement sets stacked into one system |
//! | [`observation`] | the linearised system `Δy = W Δη` (eq. 6, 8) as methods write it |
//! | [`identifiability`] | the base parameters, regrouping relations and condition number (Appendix III, [`RankReport`](identifiability::RankReport)); [`table2`] the paper's Table 2 |
//! | [`identification`] | [`identify`](identification::identify): iterative linearised least squares (eq. 10–11), robust losses and priors; [`evaluate`](identification::evaluate) |
//! | [`validation`] | cross-validation and the choice of model |
//! | [`simulation`] | points generation: a simulated "real" robot and noisy sensors; [`cell`] the configurations a cell can measure (floor, tracker station) |
//! | [`planning`], [`prediction`], [`curve`] | before measuring: configurations chosen from a pool by a criterion, the predicted accuracy of a plan, how many configurations are enough |
//! | [`compensation`] | what a calibration is for: the joint values for which the calibrated robot reaches a nominal program's targets |
//! | [`progress`] | watching long work ([`Observer`]) and stopping it |
//!
//! [`prelude`] holds the names most calibrations use.
//!
//! ## Example
//!
//! The identifiable parameters of the position measure method for a
//! two-joint planar arm, on random configurations: the link lengths and joint
//! offsets, not everything.
//!
//! ```
//! use gecaro_core::{Frame, FrameType, Joint, Robot, RobotSpec};
//! use gecaro_calib::prelude::*;
//!
//! let link = |d: f64| Frame { d, ..Frame::new(FrameType::Revolute) };
//! let robot = Robot::new(RobotSpec::rigid(
//!     "planar RR",
//!     vec![
//!         Frame::new(FrameType::Fixed),
//!         link(0.0),
//!         link(0.4),
//!         Frame { d: 0.3, ..Frame::new(FrameType::Fixed) },
//!     ],
//!     vec![Joint::default_for(FrameType::Revolute); 2],
//! ))?;
//! let position = method("position", &MethodOptions::default())?;
//! let random = Study::single(position, Vec::new(), "random configurations");
//! let report = identifiability(&robot, &random, &robot.priority(), None, 1, &mut Quiet)?.report;
//! assert_eq!(report.status("d2"), Some(ParameterStatus::Identifiable));
//! assert!(report.count() < robot.parameters().len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod axis_circles;
pub mod cell;
pub mod compensation;
mod continuation;
pub mod curve;
pub mod elastic;
mod error;
mod fold;
pub mod frames;
pub mod identifiability;
pub mod identification;
pub mod iso9283;
mod linalg;
mod linearise;
mod method;
pub mod methods;
pub mod observability;
pub mod observation;
pub mod parallel_robots;
pub use gecaro_data::parallel;
mod plane;
pub mod planning;
pub mod prediction;
mod prior;
pub mod progress;
pub mod registration;
mod robust;
mod rows;
use gecaro_data::sample;
mod sampler;
use gecaro_data::samples;
mod selection;
pub mod simulation;
mod states;
pub mod study;
pub mod table2;
pub mod tool_point;
pub mod validation;

pub use error::{Error, Setting};
pub use progress::{
    Observer, Progress, Quiet, each_iteration, each_step, report_phase, report_step,
};

/// The names most calibrations use, to import at once:
/// `use gecaro_calib::prelude::*;`.
pub mod prelude {
    pub use crate::identifiability::{ParameterStatus, RankReport, identifiability};
    pub use crate::identification::{
        ErrorSummary, Identification, IdentificationOptions, Loss, LossKind, Prior, Solver,
        StopReason, evaluate, identify,
    };
    pub use crate::methods::{CalibrationMethod, METHODS, MethodOptions, Plane, Sensor, method};
    pub use crate::progress::{Observer, Progress, Quiet, each_iteration, each_step};
    pub use crate::simulation::{Sampler, perturbed_robot, simulate_at, simulate_measurements};
    pub use crate::study::{
        DataColumn, MotorPositions, Sample, SampleLoads, SampleRef, SampleSlice, Samples, Study,
    };
    pub use crate::{Error, Setting};
}
