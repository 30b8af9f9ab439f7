//! # gecaro-calib
//!
//! The calibration methods of GECARO (Khalil et al.) and the three functions
//! each of them offers: identifiable parameters (Appendix III), points
//! generation (simulation with a "real" robot and sensor noise) and
//! identification (iterative linearised least squares, eq. 10).
//!
//! - [`CalibrationMethod`]: the shared trait (eq. 5–6), one implementation
//!   per method of paper §3, listed in [`METHODS`].
//! - [`Study`]: one or more measurement sets stacked into one system.
//! - [`identifiable_parameters`]: the base parameters, regrouping relations,
//!   condition number ([`RankReport`]).
//! - [`compensate`]: what a calibration is for — the joint values for which
//!   the calibrated robot reaches the targets of a nominal program.
//! - Before measuring: [`CandidatePool`] and [`plan_configurations`] (optimal
//!   configurations from a pool, by a [`Criterion`]), [`predict`] (the calibrated robot's accuracy
//!   from a plan and the sensor's σ, checked by [`monte_carlo`]) and
//!   [`accuracy_curve`] (how many configurations are enough).
//!
//! ## Example
//!
//! The identifiable parameters of the position measure method for a
//! two-joint planar arm: the link lengths and joint offsets, not everything.
//!
//! ```
//! use gecaro_core::{Frame, FrameType, Joint, Robot, RobotSpec};
//! use gecaro_calib::{identifiable_parameters_random, MethodOptions, ParameterStatus};
//!
//! let link = |d: f64| Frame { d, ..Frame::new(FrameType::Revolute) };
//! let robot = Robot::new(RobotSpec {
//!     name: "planar RR".into(),
//!     frames: vec![Frame::new(FrameType::Fixed), link(0.0), link(0.4), Frame { d: 0.3, ..Frame::new(FrameType::Fixed) }],
//!     joints: vec![Joint::default_for(FrameType::Revolute); 2],
//!     motor_coupling: None,
//!     joint_coupling: None,
//!     priority: None,
//! })?;
//! let report = identifiable_parameters_random(&robot, "position", &MethodOptions::default(), None, 1)?;
//! assert_eq!(report.status("d2"), Some(ParameterStatus::Identifiable));
//! assert!(report.count() < robot.parameters().len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod compensation;
mod curve;
mod error;
mod identifiability;
mod identification;
mod linalg;
mod method;
mod methods;
mod observability;
mod observation;
mod parallel;
mod plane;
mod planning;
mod prediction;
mod prior;
mod robust;
mod rows;
mod sample;
mod sampler;
mod simulation;
mod states;
mod study;
mod table2;
mod validation;

pub use compensation::{
    CompensatedPoint, CompensationStatus, Match, ProgramPoint, ProgramTarget, compensate,
};
pub use curve::{CurvePoint, RANDOM_DRAWS, accuracy_curve};
pub use error::{Error, Setting};
pub use identifiability::{
    Classified, Excitation, Identifiability, ParameterStatus, RELATIVE_ZERO_FLOOR, RankReport,
    Relation, excitation, identifiability, identifiable_parameters, identifiable_parameters_random,
    random_counterpart, random_samples, structural_parameters,
};
pub use identification::{
    DEFAULT_OUTLIER_THRESHOLD, ErrorSummary, Identification, IdentificationOptions,
    IdentifiedParameter, IterationRecord, MAX_REWEIGHTINGS, Outlier, POOR_CONDITIONING, Route,
    Solver, StopReason, evaluate, identify, identify_with_progress,
};
pub use method::{CalibrationMethod, CloneMethod, MethodInfo, MethodOptions, Sensor};
pub use methods::{METHODS, method, method_info, units};
pub use observability::{AUXILIARY_UNIT, Observability};
pub use observation::ObservationSystem;
pub use plane::Plane;
pub use planning::{
    CandidatePool, Criterion, DesignQuality, Plan, PlanRequest, assess_design, plan_configurations,
};
pub use prediction::{MonteCarlo, PoseErrors, Prediction, monte_carlo, predict, random_test_poses};
pub use prior::Prior;
pub use robust::{Loss, LossKind, robust_sigma};
pub use rows::{ColumnLayout, RowKind, RowWriter};
pub use sample::{DataColumn, Sample};
pub use sampler::{RANDOM_STARTS, Sampler, solve_from_starts};
pub use simulation::{
    error_unit, perturbed_robot, simulate_at, simulate_measurements, terminal_displacement,
};
pub use states::{TerminalState, evaluate_poses, evaluate_states};
pub use study::{LimitViolation, MeasurementSet, Study, StudyStates};
pub use table2::{
    STANFORD_PLANE_POINT, TABLE2_COLUMNS, TABLE2_PLANE_NORMAL, Table2Column, default_plane, table2,
};
pub use validation::{
    CrossValidation, Fold, Model, ModelScore, compare_models, cross_validate, cross_validate_with,
};
