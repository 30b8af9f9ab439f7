//! # gecaro-app
//!
//! The jobs of gecaro as typed requests and results, beneath its three
//! front ends: the command line (`gecaro`), the web page (`gecaro-web`) and
//! the Python package (`gecaro-py`). A front end maps its input onto a
//! request (from clap arguments, a JSON body, keyword arguments), runs it,
//! and renders the result; reading files, parsing and checking settings, the
//! bounds of a request, the prior merge, the limit checks and the wording of
//! errors happen here, once, so that the three front ends compute and say
//! the same.
//!
//! | job | request | result |
//! |---|---|---|
//! | identification (eq. 10–11) | [`IdentifyRequest`] | [`Identified`] |
//! | cross-validated models | [`CompareModelsRequest`] | [`ModelComparison`] |
//! | errors on held-out data | [`EvaluateRequest`] | [`Evaluation`] |
//! | identifiable parameters (Appendix III) | [`IdentifiableRequest`] | [`IdentifiabilityAnalysis`] |
//! | points generation | [`GenerateRequest`] | [`Generated`] |
//! | a plan, an accuracy curve | [`PlanRequest`] | [`Planning`] |
//! | a plan for a whole cell (a study) | [`PlanStudyRequest`] | [`PlannedStudy`] |
//! | predicted precision of a plan | [`PredictRequest`] | [`Predicted`] |
//! | predicted precision of a whole cell (a study) | [`PredictStudyRequest`] | [`PredictedStudy`] |
//! | a program corrected for the calibrated robot | [`CompensateRequest`] | [`Compensated`] |
//! | a robot from another format | [`ImportRequest`] | [`Imported`] |
//! | a robot to another format | [`ExportRequest`] | [`ExportedRobot`] |
//! | a calibrated robot in its own base frame | [`RebaseRequest`] | [`Rebased`] |
//! | ISO 9283's test planned | [`Iso9283PlanRequest`] | [`PlannedTest`] |
//! | ISO 9283's test evaluated | [`Iso9283EvaluateRequest`] | [`EvaluatedTest`] |
//!
//! Requests deserialise from the JSON of the web API (`docs/api.md`);
//! results give the JSON documents of [`documents`]. Files are read and
//! written through [`Files`]. Errors are [`AppError`]s, worded for each front
//! end by its [`Dialect`].
//!
//! ## Example
//!
//! Points generation and identification as the web page asks for them:
//!
//! ```
//! use gecaro_app::{DataSource, Dialect, GenerateRequest, IdentifyRequest, LocalFiles};
//!
//! let generate: GenerateRequest = serde_json::from_str(
//!     r#"{"robot": "stanford", "method": {"name": "position"}, "count": 40,
//!         "error_level": 0.5, "noise": 1e-5, "seed": 3}"#,
//! )?;
//! let generated = generate.run(&LocalFiles, &mut gecaro_calib::Quiet)?;
//!
//! let mut identify: IdentifyRequest = serde_json::from_str(
//!     r#"{"robot": "stanford", "method": {"name": "position"}, "loss": "huber"}"#,
//! )?;
//! identify.measurements.data = Some(DataSource::Samples {
//!     samples: generated.samples.into(),
//!     label: "generated".into(),
//! });
//! let identified = identify.run(&LocalFiles, &mut gecaro_calib::Quiet)?;
//! assert!(identified.converged());
//! assert_eq!(identified.document().loss.kind, "huber");
//!
//! // A bad setting, in each front end's words.
//! let bad: IdentifyRequest = serde_json::from_str(r#"{"robot": "stanford", "cv": 1}"#)?;
//! let error = bad.prepare(&LocalFiles).expect_err("one fold");
//! assert_eq!(error.message(Dialect::CommandLine), "--cv 1: between 2 and 20 folds");
//! assert_eq!(error.message(Dialect::Python), "folds=1: between 2 and 20 folds");
//! assert_eq!(error.message(Dialect::Web), "cv 1: between 2 and 20 folds");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod base_circles;
mod base_frame;
mod cell;
mod compensate;
mod demo;
mod deviations;
pub mod documents;
mod error;
mod evaluation_frame;
mod files;
mod generate;
mod identifiable;
mod identify;
mod interchange;
mod iso9283;
mod join;
mod kinematics;
pub mod limits;
mod loads;
mod measurements;
mod method;
mod model_advice;
mod nearest_table;
mod output;
pub mod parallel;
mod plan;
mod rebase;
mod repeatability;
mod residuals;
mod robot_files;
mod set_errors;
mod settings;
mod sources;
mod study_editing;
mod study_file;
mod study_files;
mod study_parts;
mod study_plan;
mod study_prediction;
mod study_spec;
mod tool_point;
mod uncertainty;
mod user_frame;

pub use base_circles::HELD;
pub use base_frame::{
    BaseBy, BasePointJson, BasePointsSource, BaseRegistration, BaseRegistrationJson,
    RegisteredPoint,
};
pub use cell::CellSpec;
pub use compensate::{
    CompensateRequest, Compensated, CompensatedFile, CompensationSummary, DEFAULT_MAX_TOOL_TURN,
    LargestCorrection, ProgramSource,
};
pub use demo::{DEMO_COUNTS, DEMO_HELD_OUT, Demo, DemoRequest, DemoRun};
pub use deviations::{PointDeviation, point_deviations};
pub use error::{AppError, Dialect, ErrorKind};
pub use evaluation_frame::RegisterShare;
pub use files::{Files, LocalFiles, Opened, OpenedBytes};
pub use generate::{GenerateRequest, Generated, data_file_name};
pub use identifiable::{IdentifiabilityAnalysis, IdentifiableRequest};
pub use identify::{
    CompareModelsRequest, EvaluateRequest, Evaluation, EvaluationPlots, Identified,
    IdentifyRequest, ModelComparison, Plots, PreparedIdentification,
};
pub use interchange::{
    ExportRequest, ExportedRobot, ImportRequest, Imported, format_name, joint_calibration_name,
    write_export,
};
pub use iso9283::{
    EvaluatedTest, Iso9283EvaluateRequest, Iso9283PlanRequest, MAX_CYCLES, MeasuredTestJson,
    PlannedTest, PoseResultJson, TestConditions, TestEvaluationJson, TestPlanJson, TestWarning,
};
pub use join::{JoinRequest, JoinedData, JoinedJson, MAX_SHIFT, SHIFT_RATIO, UnmeasuredJson};
pub use kinematics::inverse_model;
pub use measurements::{Data, Loaded, LoadedStudy, Measurements, Note, StudySource};
pub use method::{MethodSpec, parse_name};
pub use model_advice::{BETTER, CHEAP_EQUATIONS, ModelAdvice, ModelCheck};
pub use nearest_table::{CHECK_POSES, FIT_POSES, MAX_TABLE_ERROR, NearestTable};
pub use output::Output;
pub use plan::{
    AccuracyCurve, PlanRequest, Planned, Planning, PredictRequest, Predicted, TestPoses,
};
pub use rebase::{RebaseRequest, Rebased, check_same_frame, rebased_file};
pub use residuals::residuals_csv;
pub use robot_files::{calibrated_robot_file, simulated_robot_file};
pub use set_errors::GroupErrorsJson;
pub use settings::{FitSettings, PrioritySource};
pub use sources::{
    DataFormatSpec, DataRead, DataSource, PointsSource, RobotSource, angle_unit, delimiter,
    length_unit, robot_of_document, rotation_format,
};
pub use study_editing::{SaveStudyRequest, open_study};
pub use study_file::{StudyText, read_study_file, read_study_file_for};
pub use study_parts::{FrameSpec, PriorSpec};
pub use study_plan::{
    PlanStudyJson, PlanStudyRequest, PlannedSetJson, PlannedStudy, PreparedStudyPlan,
};
pub use study_prediction::{
    PredictStudyJson, PredictStudyRequest, PredictedSetJson, PredictedStudy,
};
pub use study_spec::{
    MethodChoice, SetData, SetSpec, SpecField, StudyData, StudyFile, StudyFiles, StudySpec,
};
pub use tool_point::{SMALL_SPREAD, TaughtToolPoint, ToolPointJson, ToolPointRequest};
pub use uncertainty::{Correlation, correlation, frame_covariances};
pub use user_frame::{FramePointsSource, UserFrame, UserFrameJson, UserFrameRequest};
